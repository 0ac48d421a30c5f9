#include "kernel/lines.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "kernel/angle.h"

namespace splam::kernel {

Eigen::Vector2d LineFeature::Normal() const { return {std::cos(theta_rad), std::sin(theta_rad)}; }
Eigen::Vector2d LineFeature::Direction() const {
  return {-std::sin(theta_rad), std::cos(theta_rad)};
}

std::optional<LineFeature> FitLineTls(const std::vector<Eigen::Vector2d>& points) {
  if (points.size() < 2) return std::nullopt;
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) c += p;
  c /= static_cast<double>(points.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& p : points) scatter += (p - c) * (p - c).transpose();
  if (!(scatter.trace() > 0.0) || !scatter.allFinite()) return std::nullopt;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
  Eigen::Vector2d normal = eig.eigenvectors().col(0);  // smallest eigenvalue
  double rho = normal.dot(c);
  if (rho < 0.0) {
    normal = -normal;
    rho = -rho;
  }
  LineFeature line;
  line.rho_m = rho;
  line.theta_rad = WrapAngle(std::atan2(normal.y(), normal.x()));
  const Eigen::Vector2d foot = rho * line.Normal();
  const Eigen::Vector2d dir = line.Direction();
  line.start = foot + dir * dir.dot(points.front() - foot);
  line.end = foot + dir * dir.dot(points.back() - foot);
  return line;
}

Eigen::Matrix2d LineCovariance(const std::vector<Eigen::Vector2d>& points, const LineFeature& line,
                               const std::vector<double>& sigma2) {
  const double n = static_cast<double>(points.size());
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) c += p;
  c /= n;
  const Eigen::Vector2d dir = line.Direction();
  double spread = 0.0, var_e = 0.0, var_theta = 0.0, cov_e_theta = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double s = dir.dot(points[i] - c);
    spread += s * s;
    var_e += sigma2[i];
    var_theta += s * s * sigma2[i];
    cov_e_theta += s * sigma2[i];
  }
  spread = std::max(spread, 1e-12);
  var_e /= n * n;
  var_theta /= spread * spread;
  cov_e_theta /= n * spread;
  const double m = dir.dot(c);
  Eigen::Matrix2d cov;
  cov << var_e + 2.0 * m * cov_e_theta + m * m * var_theta, cov_e_theta + m * var_theta,
      cov_e_theta + m * var_theta, var_theta;
  return cov;
}

Status LineExtractionOptions::Validate() const {
  if (!(sef_c0_m >= 0.0)) return Status::Error("sef_c0_m must be >= 0");
  if (!(range_sigma_m >= 0.0) || !(range_sigma_fraction >= 0.0) ||
      !(range_sigma_m + range_sigma_fraction > 0.0)) {
    return Status::Error("the point noise model needs a positive sigma");
  }
  if (!(inlier_sigmas > 0.0)) return Status::Error("inlier_sigmas must be positive");
  if (!(max_residual_sigmas > 0.0)) return Status::Error("max_residual_sigmas must be positive");
  // Each draw scores every remaining point: 2e9 draws per line was a hang.
  if (ransac_iterations < 1 || ransac_iterations > 10000)
    return Status::Error("ransac_iterations must be in [1, 10000]");
  if (min_points < 2) return Status::Error("min_points must be at least 2");
  if (!(min_length_m >= 0.0) || !(max_point_gap_m > 0.0))
    return Status::Error("line lengths and gaps must be positive");
  if (!(corner_min_angle_rad > 0.0 && corner_min_angle_rad <= kPi / 2)) {
    return Status::Error("corner_min_angle_rad must be in (0, pi/2]");
  }
  if (!(corner_max_distance_m >= 0.0)) return Status::Error("corner_max_distance_m must be >= 0");
  return Status::Ok();
}

std::vector<LineFeature> RansacLines(const std::vector<Eigen::Vector2d>& points,
                                     const std::vector<double>& sigma2,
                                     const LineExtractionOptions& options, Random* random) {
  std::vector<LineFeature> lines;
  std::vector<std::size_t> remaining(points.size());
  std::iota(remaining.begin(), remaining.end(), 0);
  const double k2 = options.inlier_sigmas * options.inlier_sigmas;
  const double max_gap2 = options.max_point_gap_m * options.max_point_gap_m;
  // The longest run of consensus points of the line (normal, rho) without a gap larger than
  // max_point_gap_m, as positions [first, last] in `remaining` and its size; counted without
  // allocating, since it runs for every RANSAC sample.
  struct Run {
    std::size_t first = 0, last = 0, size = 0;
  };
  auto longest_run = [&](const Eigen::Vector2d& normal, double rho) {
    Run best, current;
    const Eigen::Vector2d* previous = nullptr;
    for (std::size_t pos = 0; pos < remaining.size(); ++pos) {
      const std::size_t i = remaining[pos];
      const double d = normal.dot(points[i]) - rho;
      if (d * d > k2 * sigma2[i]) continue;
      if (previous == nullptr || (points[i] - *previous).squaredNorm() > max_gap2)
        current = {pos, pos, 0};
      current.last = pos;
      ++current.size;
      previous = &points[i];
      if (current.size > best.size) best = current;
    }
    return best;
  };
  auto members = [&](const Run& run, const Eigen::Vector2d& normal, double rho) {
    std::vector<std::size_t> out;
    for (std::size_t pos = run.first; run.size > 0 && pos <= run.last; ++pos) {
      const std::size_t i = remaining[pos];
      const double d = normal.dot(points[i]) - rho;
      if (d * d <= k2 * sigma2[i]) out.push_back(i);
    }
    return out;
  };
  const std::size_t min_points = static_cast<std::size_t>(options.min_points);
  while (remaining.size() >= min_points) {
    Run best_run;
    Eigen::Vector2d best_normal = Eigen::Vector2d::UnitX();
    double best_rho = 0.0;
    for (int it = 0; it < options.ransac_iterations; ++it) {
      const std::size_t a = remaining[random->Index(remaining.size())];
      const std::size_t b = remaining[random->Index(remaining.size())];
      const Eigen::Vector2d d = points[b] - points[a];
      if (a == b || d.squaredNorm() == 0.0) continue;
      const Eigen::Vector2d normal = Eigen::Vector2d(-d.y(), d.x()).normalized();
      const double rho = normal.dot(points[a]);
      const Run run = longest_run(normal, rho);
      if (run.size > best_run.size) {
        best_run = run;
        best_normal = normal;
        best_rho = rho;
      }
    }
    if (best_run.size < min_points) break;
    std::vector<std::size_t> best = members(best_run, best_normal, best_rho);
    // Refit by TLS, then take the contiguous consensus of the refit line.
    std::vector<Eigen::Vector2d> support;
    for (std::size_t i : best) support.push_back(points[i]);
    std::optional<LineFeature> line = FitLineTls(support);
    if (line) {
      const Run refit = longest_run(line->Normal(), line->rho_m);
      if (refit.size >= min_points) best = members(refit, line->Normal(), line->rho_m);
      support.clear();
      for (std::size_t i : best) support.push_back(points[i]);
      line = FitLineTls(support);
    }
    std::erase_if(remaining,
                  [&](std::size_t i) { return std::binary_search(best.begin(), best.end(), i); });
    if (!line || line->Length() < options.min_length_m) continue;
    // Range noise acts along the beam: across the line it is sigma2 (n . u)^2 with u the beam
    // direction (points are in the sensor frame).
    std::vector<double> s2;
    double residual2 = 0.0, noise2 = 0.0;
    for (std::size_t i : best) {
      const double cos_incidence = line->Normal().dot(points[i].normalized());
      s2.push_back(sigma2[i] * cos_incidence * cos_incidence);
      residual2 += std::pow(line->SignedDistance(points[i]), 2);
      noise2 += s2.back();
    }
    if (residual2 > options.max_residual_sigmas * options.max_residual_sigmas * noise2)
      continue;  // not straight
    line->covariance = LineCovariance(support, *line, s2);
    line->point_indices = std::move(best);
    lines.push_back(std::move(*line));
  }
  return lines;
}

LineExtraction ExtractLines(const Scan& scan, const LineExtractionOptions& options) {
  LineExtraction out;
  SegmentationOptions sef;
  sef.method = SegmentationMethod::kDietmayer;
  sef.dietmayer_c0_m = options.sef_c0_m;
  sef.min_points = options.min_points;
  sef.min_length_m = options.min_length_m;
  Random random(options.seed);
  for (const ScanSegment& segment : SegmentScan(scan, sef)) {
    const std::size_t offset = out.points.size();
    std::vector<double> sigma2;
    for (std::size_t i = 0; i < segment.points.size(); ++i) {
      const double sigma =
          options.range_sigma_m + options.range_sigma_fraction * segment.points[i].norm();
      sigma2.push_back(sigma * sigma);
      out.points.push_back(segment.points[i]);
      out.beams.push_back(segment.beams[i]);
    }
    for (LineFeature& line : RansacLines(segment.points, sigma2, options, &random)) {
      for (std::size_t& i : line.point_indices) i += offset;
      out.lines.push_back(std::move(line));
    }
  }
  std::sort(out.lines.begin(), out.lines.end(), [](const LineFeature& a, const LineFeature& b) {
    return a.point_indices.front() < b.point_indices.front();
  });
  // Corners between neighbours in beam order.
  for (std::size_t i = 0; i + 1 < out.lines.size(); ++i) {
    const LineFeature& a = out.lines[i];
    const LineFeature& b = out.lines[i + 1];
    const double cross =
        a.Direction().x() * b.Direction().y() - a.Direction().y() * b.Direction().x();
    const double angle = std::asin(std::min(1.0, std::abs(cross)));
    if (angle < options.corner_min_angle_rad) continue;
    // Intersection: solve n_a . x = rho_a, n_b . x = rho_b.
    Eigen::Matrix2d n;
    n << a.Normal().transpose(), b.Normal().transpose();
    const Eigen::Vector2d x = n.inverse() * Eigen::Vector2d(a.rho_m, b.rho_m);
    if ((x - a.end).norm() > options.corner_max_distance_m ||
        (x - b.start).norm() > options.corner_max_distance_m) {
      continue;
    }
    // d x / d rho_k = N^-1 e_k; d x / d theta_k = -N^-1 e_k (t_k . x), t_k = d n_k / d theta_k.
    const Eigen::Matrix2d n_inv = n.inverse();
    Eigen::Matrix<double, 2, 4> j;
    j.col(0) = n_inv.col(0);
    j.col(1) = -n_inv.col(0) * a.Direction().dot(x);
    j.col(2) = n_inv.col(1);
    j.col(3) = -n_inv.col(1) * b.Direction().dot(x);
    Eigen::Matrix4d lines_cov = Eigen::Matrix4d::Zero();
    lines_cov.topLeftCorner<2, 2>() = a.covariance;
    lines_cov.bottomRightCorner<2, 2>() = b.covariance;
    out.corners.push_back({x, i, i + 1, angle, j * lines_cov * j.transpose()});
  }
  return out;
}

void LineExtractionOptions::VisitFields(FieldVisitor& v) {
  v.Field("sef_c0_m", &sef_c0_m, "successive edge following: split where points jump apart, m");
  v.Field("range_sigma_m", &range_sigma_m, "point noise: sigma = this + fraction * range, m");
  v.Field("range_sigma_fraction", &range_sigma_fraction, "point noise: fraction of the range");
  v.Field("inlier_sigmas", &inlier_sigmas, "a point supports a line within this many sigma");
  v.Field("ransac_iterations", &ransac_iterations, "minimal samples drawn per line");
  v.Field("min_points", &min_points, "consensus needed to accept a line");
  v.Field("min_length_m", &min_length_m, "shorter lines are dropped, m");
  v.Field("max_residual_sigmas", &max_residual_sigmas,
          "straightness: RMS residual at most this many times the noise RMS");
  v.Field("max_point_gap_m", &max_point_gap_m,
          "consensus points farther apart start a new line, m");
  v.Field("corner_min_angle_rad", &corner_min_angle_rad,
          "corners: lines crossing at least this, rad");
  v.Field("corner_max_distance_m", &corner_max_distance_m,
          "corners: crossing within this of both line ends, m");
  v.Field("seed", &seed, "RANSAC's generator seed");
}

}  // namespace splam::kernel
