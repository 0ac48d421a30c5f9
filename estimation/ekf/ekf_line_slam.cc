#include "estimation/ekf/ekf_line_slam.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "estimation/chi_square.h"
#include "estimation/ekf/joint_compatibility.h"
#include "kernel/angle.h"

namespace splam::estimation {
namespace {

using kernel::WrapAngle;
using Matrix5d = Eigen::Matrix<double, 5, 5>;
using Matrix25 = Eigen::Matrix<double, 2, 5>;

}  // namespace

struct EkfLineSlam::Observation {
  bool is_line = true;
  Eigen::Vector2d z = Eigen::Vector2d::Zero();  // (rho, theta) or (x, y), robot frame
  Eigen::Matrix2d r = Eigen::Matrix2d::Zero();  // measurement covariance
  Eigen::Vector2d a = Eigen::Vector2d::Zero();  // segment end points, robot frame (lines)
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  std::size_t points = 0;  // supporting points (lines)
};

kernel::Status EkfLineSlamOptions::Validate() const {
  if (kernel::Status s = kernel::FirstError(odometry.Validate(), extraction.Validate()); !s.ok())
    return s;
  if (!(line_rho_floor_m > 0) || !(line_theta_floor_rad > 0) || !(corner_sigma_m > 0)) {
    return kernel::Status::Error("measurement noise floors must be positive");
  }
  if (!(gate_probability > 0 && gate_probability < 1) ||
      !(new_landmark_probability >= gate_probability && new_landmark_probability < 1)) {
    return kernel::Status::Error("need 0 < gate_probability <= new_landmark_probability < 1");
  }
  if (!(min_new_line_length_m >= 0) || min_new_line_points < 2)
    return kernel::Status::Error("bad new-line thresholds");
  if (!(corner_max_distance_m > 0) || !(max_extension_gap_m >= 0))
    return kernel::Status::Error("bad association distances");
  return kernel::Status::Ok();
}

EkfLineSlam::EkfLineSlam(const kernel::Pose2& initial_pose,
                         const Eigen::Matrix3d& initial_covariance,
                         const EkfLineSlamOptions& options)
    : options_(options),
      gate_(ChiSquareQuantile(options.gate_probability, 2)),
      new_gate_(ChiSquareQuantile(options.new_landmark_probability, 2)),
      ekf_(initial_pose, initial_covariance),
      candidates_(options.min_observations_to_add, options.candidate_max_age_scans) {}

void EkfLineSlam::Predict(const kernel::Pose2& u) {
  ekf_.Predict(u, options_.odometry.Covariance(u));
}

void EkfLineSlam::NormaliseLine(LineLandmark* landmark) {
  const Eigen::Index i = landmark->index;
  Eigen::VectorXd& x = ekf_.mutable_state();
  if (x(i) < 0.0) {
    // (rho, theta) -> (-rho, theta + pi): the rho row and column of P change sign, and the
    // direction (-sin theta, cos theta) reverses, so the extent flips too.
    ekf_.Negate(i);
    x(i + 1) += kernel::kPi;
    std::swap(landmark->s_min, landmark->s_max);
    landmark->s_min = -landmark->s_min;
    landmark->s_max = -landmark->s_max;
  }
  x(i + 1) = WrapAngle(x(i + 1));
}

void EkfLineSlam::ExtendLine(LineLandmark* landmark, const Eigen::Vector2d& a,
                             const Eigen::Vector2d& b) {
  const double rho = ekf_.state()(landmark->index), theta = ekf_.state()(landmark->index + 1);
  const Eigen::Vector2d normal(std::cos(theta), std::sin(theta)), dir(-normal.y(), normal.x());
  // Only a segment that lies on the line extends it: an association accepted through a large
  // covariance must not stretch the drawn extent along the line.
  if (std::isfinite(landmark->s_min) &&
      (std::abs(normal.dot(a) - rho) > options_.max_extension_offset_m ||
       std::abs(normal.dot(b) - rho) > options_.max_extension_offset_m)) {
    return;
  }
  landmark->s_min = std::min({landmark->s_min, dir.dot(a), dir.dot(b)});
  landmark->s_max = std::max({landmark->s_max, dir.dot(a), dir.dot(b)});
}

UpdateReport EkfLineSlam::Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) {
  return Update(kernel::ExtractLines(scan, options_.extraction), robot_T_laser);
}

UpdateReport EkfLineSlam::Update(const kernel::LineExtraction& features,
                                 const kernel::Pose2& robot_T_laser) {
  UpdateReport report;
  if (!healthy()) return report;

  // Observations in the robot frame.
  std::vector<Observation> observations;
  for (const kernel::LineFeature& f : features.lines) {
    Observation o;
    const Line line = TransformLine(robot_T_laser, {f.rho_m, f.theta_rad});
    o.z = {line.rho, line.theta};
    o.r = f.covariance +
          Eigen::Vector2d(options_.line_rho_floor_m * options_.line_rho_floor_m,
                          options_.line_theta_floor_rad * options_.line_theta_floor_rad)
              .asDiagonal()
              .toDenseMatrix();
    o.a = robot_T_laser * f.start;
    o.b = robot_T_laser * f.end;
    o.points = f.point_indices.size();
    observations.push_back(o);
    ++report.line_observations;
  }
  if (options_.use_corners) {
    for (const kernel::LineCorner& c : features.corners) {
      Observation o;
      o.is_line = false;
      o.z = robot_T_laser * c.position;
      const Eigen::Matrix2d rotation = robot_T_laser.Rotation();
      o.r = rotation * c.covariance * rotation.transpose() +
            options_.corner_sigma_m * options_.corner_sigma_m * Eigen::Matrix2d::Identity();
      observations.push_back(o);
      ++report.corner_observations;
    }
  }

  // Mahalanobis distance of every observation to every compatible landmark.
  const kernel::Pose2 x = pose();
  struct Pairing {
    double d2;
    std::size_t observation, landmark;
  };
  std::vector<Pairing> pairings;
  // With association: jcbb, each pairing as joint compatibility takes it (pairings' order).
  const bool jcbb = options_.association == EkfAssociation::kJointCompatibility;
  std::vector<CompatibilityItem> items;
  std::vector<double> nearest(observations.size(), std::numeric_limits<double>::infinity());
  for (std::size_t o = 0; o < observations.size(); ++o) {
    const Observation& obs = observations[o];
    const std::size_t count = obs.is_line ? lines_.size() : corners_.size();
    for (std::size_t l = 0; l < count; ++l) {
      const Eigen::Index i = obs.is_line ? lines_[l].index : corners_[l].index;
      Matrix23 h_r;
      Eigen::Matrix2d h_l;
      Eigen::Vector2d nu;
      if (obs.is_line) {
        const LineLandmark& lm = lines_[l];
        // The observed segment must overlap the landmark's extent or continue it closely.
        const Eigen::Vector2d dir(-std::sin(ekf_.state()(i + 1)), std::cos(ekf_.state()(i + 1)));
        const double sa = dir.dot(x * obs.a), sb = dir.dot(x * obs.b);
        const double gap =
            std::max({0.0, std::min(sa, sb) - lm.s_max, lm.s_min - std::max(sa, sb)});
        if (gap > options_.max_extension_gap_m) continue;
        const Eigen::Vector2d h =
            PredictLine(x, {ekf_.state()(i), ekf_.state()(i + 1)}, &h_r, &h_l);
        nu = LineInnovation(obs.z, h, &h_r, &h_l);
      } else {
        if ((x * obs.z - ekf_.state().segment<2>(i)).norm() > options_.corner_max_distance_m)
          continue;
        nu = obs.z - PredictPoint(x, ekf_.state().segment<2>(i), &h_r, &h_l);
      }
      Matrix25 h;
      h << h_r, h_l;
      Matrix5d p_local;
      p_local << ekf_.covariance().topLeftCorner<3, 3>(), ekf_.covariance().block(0, i, 3, 2),
          ekf_.covariance().block(i, 0, 2, 3), ekf_.covariance().block<2, 2>(i, i);
      const Eigen::Matrix2d s = h * p_local * h.transpose() + obs.r;
      const double d2 = nu.dot(s.ldlt().solve(nu));
      nearest[o] = std::min(nearest[o], d2);
      if (d2 < gate_) {
        pairings.push_back({d2, o, l});
        if (jcbb)
          items.push_back({static_cast<int>(o), nu, h_r, {JacobianBlock{i, h_l, 0}}, obs.r});
      }
    }
  }

  if (jcbb) {
    // JCBB: each observation's pairings, nearest first; the largest jointly compatible set, no
    // landmark paired twice.
    std::vector<std::size_t> order(pairings.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      const Pairing& pa = pairings[a];
      const Pairing& pb = pairings[b];
      return pa.observation != pb.observation ? pa.observation < pb.observation : pa.d2 < pb.d2;
    });
    std::vector<CompatibilityItem> ordered;
    for (const std::size_t k : order) ordered.push_back(std::move(items[k]));
    const auto same_landmark = [&](int a, int b) {
      const Pairing& pa = pairings[order[static_cast<std::size_t>(a)]];
      const Pairing& pb = pairings[order[static_cast<std::size_t>(b)]];
      return pa.landmark == pb.landmark &&
             observations[pa.observation].is_line == observations[pb.observation].is_line;
    };
    const JointCompatibilityResult joint =
        JointCompatibility(ordered, same_landmark, ekf_.covariance(), options_.gate_probability);
    std::vector<Pairing> kept;
    for (const int c : joint.chosen) kept.push_back(pairings[order[static_cast<std::size_t>(c)]]);
    report.jcbb_nodes = joint.nodes;
    pairings = std::move(kept);
  }
  // Greedy one-to-one assignment by increasing distance (with jcbb: the jointly compatible set,
  // one to one already), then sequential corrections.
  std::sort(pairings.begin(), pairings.end(),
            [](const Pairing& a, const Pairing& b) { return a.d2 < b.d2; });
  std::vector<bool> obs_used(observations.size(), false);
  std::vector<bool> line_used(lines_.size(), false), corner_used(corners_.size(), false);
  for (const Pairing& c : pairings) {
    const Observation& obs = observations[c.observation];
    std::vector<bool>& used = obs.is_line ? line_used : corner_used;
    if (obs_used[c.observation] || used[c.landmark]) continue;
    obs_used[c.observation] = true;
    used[c.landmark] = true;
    const Eigen::Index i = obs.is_line ? lines_[c.landmark].index : corners_[c.landmark].index;
    Matrix23 h_r;
    Eigen::Matrix2d h_l;
    if (obs.is_line) {
      const Eigen::Vector2d h =
          PredictLine(pose(), {ekf_.state()(i), ekf_.state()(i + 1)}, &h_r, &h_l);
      const Eigen::Vector2d nu = LineInnovation(obs.z, h, &h_r, &h_l);
      ekf_.Correct(h_r, {JacobianBlock{i, h_l}}, nu, obs.r);
      LineLandmark& lm = lines_[c.landmark];
      NormaliseLine(&lm);
      ExtendLine(&lm, pose() * obs.a, pose() * obs.b);
      ++lm.observations;
    } else {
      const Eigen::Vector2d h = PredictPoint(pose(), ekf_.state().segment<2>(i), &h_r, &h_l);
      ekf_.Correct(h_r, {JacobianBlock{i, h_l}}, obs.z - h, obs.r);
      ++corners_[c.landmark].observations;
    }
    ++report.associated;
  }

  // New landmarks from what is clearly new: after enough sightings as a candidate.
  ++scans_;
  for (std::size_t o = 0; o < observations.size(); ++o) {
    if (obs_used[o]) continue;
    const Observation& obs = observations[o];
    if (nearest[o] < new_gate_) {
      ++report.ambiguous;
      continue;
    }
    if (obs.is_line && ((obs.b - obs.a).norm() < options_.min_new_line_length_m ||
                        static_cast<int>(obs.points) < options_.min_new_line_points)) {
      ++report.too_small;
      continue;
    }
    Matrix23 g_r;
    Eigen::Matrix2d g_z;
    Eigen::Vector2d g;
    if (obs.is_line) {
      const Line line = InitializeLine(pose(), {obs.z(0), obs.z(1)}, &g_r, &g_z);
      g = {line.rho, line.theta};
    } else {
      g = InitializePoint(pose(), obs.z, &g_r, &g_z);
    }
    // Match a candidate of the same kind; promote it when it has been seen often enough.
    const bool promoted =
        candidates_.Observe({obs.is_line, g}, scans_, [&](const Candidate& c, const Candidate& n) {
          if (c.is_line != n.is_line) return false;
          return n.is_line
                     ? std::abs(c.value(0) - n.value(0)) <= options_.candidate_rho_tolerance_m &&
                           std::abs(WrapAngle(c.value(1) - n.value(1))) <=
                               options_.candidate_theta_tolerance_rad
                     : (c.value - n.value).norm() <= options_.corner_max_distance_m;
        });
    if (!promoted) {
      ++report.candidates;
      continue;
    }
    if (obs.is_line) {
      const Eigen::Index i = ekf_.Append(g, g_r, g_z * obs.r * g_z.transpose());
      LineLandmark lm{i, std::numeric_limits<double>::infinity(),
                      -std::numeric_limits<double>::infinity(), 1};
      ExtendLine(&lm, pose() * obs.a, pose() * obs.b);
      lines_.push_back(lm);
    } else {
      corners_.push_back({ekf_.Append(g, g_r, g_z * obs.r * g_z.transpose()), 1});
    }
    ++report.new_landmarks;
  }
  candidates_.Prune(scans_);
  return report;
}

std::vector<MapLine> EkfLineSlam::MapLines() const {
  std::vector<MapLine> out;
  for (const LineLandmark& lm : lines_) {
    const Eigen::Index i = lm.index;
    const Line line{ekf_.state()(i), ekf_.state()(i + 1)};
    const Eigen::Vector2d n(std::cos(line.theta), std::sin(line.theta)), dir(-n.y(), n.x());
    out.push_back({line, line.rho * n + lm.s_min * dir, line.rho * n + lm.s_max * dir,
                   ekf_.covariance().block<2, 2>(i, i), lm.observations});
  }
  return out;
}

std::vector<MapCorner> EkfLineSlam::MapCorners() const {
  std::vector<MapCorner> out;
  for (const CornerLandmark& c : corners_) {
    out.push_back({ekf_.state().segment<2>(c.index),
                   ekf_.covariance().block<2, 2>(c.index, c.index), c.observations});
  }
  return out;
}

void EkfLineSlamOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Nested("odometry", "odometry noise model", &odometry);
  v.Nested("extraction", "lines and corners from a scan", &extraction);
  v.Field("use_corners", &use_corners, "corners as point landmarks");
  v.Field("line_rho_floor_m", &line_rho_floor_m, "line measurement noise floor (rho), m");
  v.Field("line_theta_floor_rad", &line_theta_floor_rad,
          "line measurement noise floor (theta), rad");
  v.Field("corner_sigma_m", &corner_sigma_m, "corner measurement noise floor, m");
  int rule = static_cast<int>(association);
  v.Choice("association", &rule, {"nearest", "jcbb"},
           "nearest neighbour (paper 001) or joint compatibility branch and bound (Neira and "
           "Tardos 2001) over the pairings inside the gate");
  association = static_cast<EkfAssociation>(rule);
  v.Field("gate_probability", &gate_probability, "association gate, chi-square probability");
  v.Field("new_landmark_probability", &new_landmark_probability,
          "new landmarks only outside this larger gate");
  v.Field("min_observations_to_add", &min_observations_to_add,
          "a candidate becomes a landmark after this many sightings");
  v.Field("candidate_max_age_scans", &candidate_max_age_scans,
          "... none more than this many scans after the previous");
  v.Field("candidate_rho_tolerance_m", &candidate_rho_tolerance_m, "candidates match within, m");
  v.Field("candidate_theta_tolerance_rad", &candidate_theta_tolerance_rad,
          "candidates match within, rad");
  v.Field("min_new_line_length_m", &min_new_line_length_m, "new line landmarks at least, m");
  v.Field("min_new_line_points", &min_new_line_points, "new line landmarks at least, points");
  v.Field("corner_max_distance_m", &corner_max_distance_m,
          "corners compared only with corner landmarks within, m");
  v.Field("max_extension_gap_m", &max_extension_gap_m,
          "a segment associates across a gap of at most, m");
  v.Field("max_extension_offset_m", &max_extension_offset_m,
          "... and extends a line when its ends lie within, m");
}

}  // namespace splam::estimation
