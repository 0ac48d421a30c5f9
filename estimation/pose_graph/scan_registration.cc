// Scan-to-submap registration (scan_registration.h): the points' distances to the map and a
// prior on the pose, solved by Ceres.
#include "estimation/pose_graph/scan_registration.h"

#include <ceres/ceres.h>
#include <ceres/cubic_interpolation.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <set>
#include <utility>

#include "estimation/pose_graph/ceres_solve.h"
#include "estimation/pose_graph/pose_graph.h"
#include "kernel/angle.h"

namespace splam::estimation {
namespace {

using Interpolator = ceres::BiCubicInterpolator<ceres::Grid2D<double, 1>>;

// D(q), a point's distance to the map: the grid's exact distance to its nearest outline piece
// (DistanceGrid::Distance) or, with `bicubic`, the bicubic interpolation of the cell values
// (Hess et al. 2016); dD/dq in *gradient when not null.
struct MapDistance {
  const DistanceGrid& grid;
  const Interpolator& field;
  bool bicubic;
  double operator()(const Eigen::Vector2d& q, Eigen::Vector2d* gradient = nullptr) const {
    if (!bicubic) return grid.Distance(q, gradient);
    const Eigen::Vector2d cell = grid.CellCoordinates(q);
    double d = 0.0, d_row = 0.0, d_col = 0.0;
    field.Evaluate(cell.x(), cell.y(), &d, &d_row, &d_col);
    if (gradient != nullptr) *gradient = Eigen::Vector2d(d_col, d_row) / grid.resolution();
    return d;
  }
};

// The distances of all the scan's points to the map in one block (one block of n rows costs far
// less in Ceres than n blocks of one), D a MapDistance. Residual i is the Huber-robustified
// distance
//   r_i = sqrt(rho(e_i^2)),  e_i = D(T p_i) / sigma,  rho(s) = s (s <= k^2), 2 k sqrt(s) - k^2,
// so that sum r_i^2 is the robust cost, with the analytic Jacobian
//   dr_i/dT = rho'(e_i^2) e_i / r_i * dD/dq * [I, R'(theta) p_i] / sigma.
class PointsToMapCost : public ceres::CostFunction {
 public:
  PointsToMapCost(const MapDistance& distance, const std::vector<Eigen::Vector2d>& points,
                  double sigma, double scale, bool cauchy)
      : distance_(distance),
        points_(points),
        inv_sigma_(1.0 / sigma),
        huber_(scale),
        cauchy_(cauchy) {
    set_num_residuals(static_cast<int>(points.size()));
    mutable_parameter_block_sizes()->push_back(3);
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* pose = parameters[0];
    const double c = std::cos(pose[2]), s = std::sin(pose[2]);
    const double k = huber_;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      const Eigen::Vector2d& p = points_[i];
      const Eigen::Vector2d q(pose[0] + c * p.x() - s * p.y(), pose[1] + s * p.x() + c * p.y());
      Eigen::Vector2d gradient;  // dD/dq
      const double e = distance_(q, &gradient) * inv_sigma_;
      double r = e, dr_de = 1.0;
      const double a = std::abs(e);
      if (cauchy_) {
        // r = sign(e) k sqrt(log(1 + e^2 / k^2)), dr/de = e / ((1 + e^2 / k^2) r).
        const double u = e * e / (k * k);
        r = std::copysign(k * std::sqrt(std::log1p(u)), e);
        if (std::abs(r) > 1e-9) dr_de = e / ((1 + u) * r);
      } else if (a > k) {
        // Huber: r = sign(e) sqrt(2 k |e| - k^2), dr/de = k / |r|.
        r = std::copysign(std::sqrt(2 * k * a - k * k), e);
        dr_de = k / std::max(std::abs(r), 1e-12);
      }
      residuals[i] = r;
      if (jacobians == nullptr || jacobians[0] == nullptr) continue;
      const double scale = dr_de * inv_sigma_;
      const double dx = gradient.x() * scale, dy = gradient.y() * scale;
      double* row = jacobians[0] + 3 * i;
      row[0] = dx;
      row[1] = dy;
      row[2] = dx * (-s * p.x() - c * p.y()) + dy * (c * p.x() - s * p.y());
    }
    return true;
  }

 private:
  const MapDistance& distance_;
  const std::vector<Eigen::Vector2d>& points_;
  double inv_sigma_, huber_;
  bool cauchy_;
};

// A prior on a pose: an edge from a fixed `anchor` to it (EdgeResidual).
class PriorCost : public ceres::SizedCostFunction<3, 3> {
 public:
  PriorCost(const kernel::Pose2& anchor, const Eigen::Matrix3d& information)
      : anchor_(anchor.ToVector()), residual_(Identity(information)) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    Eigen::Matrix3d d_pose;
    const bool want = jacobians != nullptr && jacobians[0] != nullptr;
    Eigen::Map<Eigen::Vector3d> out(residuals);
    out = residual_(anchor_.data(), parameters[0], nullptr, want ? &d_pose : nullptr);
    if (want) Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>{jacobians[0]} = d_pose;
    return true;
  }

 private:
  // The identity measurement with this information.
  static PoseGraphEdge Identity(const Eigen::Matrix3d& information) {
    PoseGraphEdge edge;
    edge.information = information;
    return edge;
  }
  Eigen::Vector3d anchor_;
  EdgeResidual residual_;
};

// J^T J of a cost function of one 3-parameter block at `pose`, accumulated row by row. Evaluated
// directly: Problem::Evaluate sets up an evaluator on every call, most of a registration's
// covariance.
Eigen::Matrix3d GaussNewtonHessian(const ceres::CostFunction& cost, const double* pose) {
  const auto rows = static_cast<std::size_t>(cost.num_residuals());
  std::vector<double> residuals(rows), jacobian(3 * rows);
  const double* parameters[] = {pose};
  double* jacobians[] = {jacobian.data()};
  cost.Evaluate(parameters, residuals.data(), jacobians);
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  for (std::size_t r = 0; r < rows; ++r) {
    const Eigen::Vector3d row(jacobian[3 * r], jacobian[3 * r + 1], jacobian[3 * r + 2]);
    h += row * row.transpose();
  }
  return h;
}

}  // namespace

bool Matchable(const DistanceGrid& grid, const OrientedPoint& placed,
               const RegistrationOptions& options) {
  if (!grid.Known(placed.point)) return false;
  const OrientedPoint* piece = grid.NearestPiece(placed.point);
  if (piece == nullptr || piece->normal.isZero()) return true;
  const Eigen::Vector2d tangent(-piece->normal.y(), piece->normal.x());
  if (options.skip_past_outline_ends &&
      std::abs(tangent.dot(placed.point - piece->point)) > grid.PieceHalfLength() &&
      !grid.SeenFree(placed.point))
    return false;
  if (options.max_normal_angle_rad >= M_PI || placed.normal.isZero()) return true;
  const double min_cos = std::cos(options.max_normal_angle_rad);
  if (placed.normal.dot(piece->normal) >= min_cos) return true;
  if (!options.two_sided_outlines) return false;
  // An outline seen from both sides (a thin wall) matches a point facing either side.
  const Eigen::Vector2d back = grid.BackNormal(placed.point);
  return !back.isZero() && placed.normal.dot(back) >= min_cos;
}

bool TellsApart(const DistanceGrid& target, const std::vector<OrientedPoint>& query,
                const kernel::Pose2& best, const kernel::Pose2& rival,
                const RegistrationOptions& options, double cell_m, double alpha) {
  const std::vector<OrientedPoint> at_best = Placed(best, query), at_rival = Placed(rival, query);
  const auto fits = [&](const OrientedPoint& p) {
    return Matchable(target, p, options) &&
           std::abs(target.Distance(p.point)) < options.inlier_distance_m;
  };
  const auto cell = [&](const OrientedPoint& p) {
    return std::pair<long, long>(std::lround(std::floor(p.point.x() / cell_m)),
                                 std::lround(std::floor(p.point.y() / cell_m)));
  };
  std::set<std::pair<long, long>> for_best, for_rival;
  for (std::size_t i = 0; i < query.size(); ++i) {
    const bool b = fits(at_best[i]), r = fits(at_rival[i]);
    if (b && !r) for_best.insert(cell(at_best[i]));
    if (r && !b) for_rival.insert(cell(at_rival[i]));
  }
  // P(X >= k) for X ~ Binomial(n, 1/2), summed in logs.
  const int k = static_cast<int>(for_best.size());
  const int n = k + static_cast<int>(for_rival.size());
  double tail = 0.0;
  for (int x = k; x <= n; ++x)
    tail += std::exp(std::lgamma(n + 1.0) - std::lgamma(x + 1.0) - std::lgamma(n - x + 1.0) -
                     n * std::log(2.0));
  return 2 * k > n && tail < alpha;
}

std::vector<OrientedPoint> Placed(const kernel::Pose2& pose,
                                  const std::vector<OrientedPoint>& points) {
  const Eigen::Matrix2d rotation = pose.Rotation();
  std::vector<OrientedPoint> placed;
  placed.reserve(points.size());
  for (const OrientedPoint& o : points)
    placed.push_back({rotation * o.point + pose.translation(), rotation * o.normal});
  return placed;
}

RegistrationResult RegisterPoints(const std::vector<Eigen::Vector2d>& points,
                                  const DistanceGrid& grid, const kernel::Pose2& prior,
                                  const RegistrationOptions& options,
                                  const Eigen::Matrix3d* prior_covariance) {
  std::vector<OrientedPoint> oriented;
  oriented.reserve(points.size());
  for (const auto& p : points) oriented.push_back({p, Eigen::Vector2d::Zero()});
  return RegisterPoints(oriented, grid, prior, options, prior_covariance);
}

RegistrationResult RegisterPoints(const std::vector<OrientedPoint>& points,
                                  const DistanceGrid& grid, const kernel::Pose2& prior,
                                  const RegistrationOptions& options,
                                  const Eigen::Matrix3d* prior_covariance) {
  RegistrationResult result;
  result.pose = prior;
  // Points the map never saw around (at the prior) carry no information: a wall the submap saw
  // to where its range ended goes on, and its new points must not pull the scan back. Nor do
  // points facing away from their nearest piece (options.max_normal_angle_rad).
  std::vector<Eigen::Vector2d> seen;
  const std::vector<OrientedPoint> placed = Placed(prior, points);
  for (std::size_t i = 0; i < points.size(); ++i)
    if (Matchable(grid, placed[i], options)) seen.push_back(points[i].point);
  if (grid.empty() || static_cast<int>(seen.size()) < options.min_points) {
    result.reason = "too few points where the map has seen";
    return result;
  }
  const ceres::Grid2D<double, 1> data(grid.values().data(), 0, grid.rows(), 0, grid.cols());
  const Interpolator field(data);
  const MapDistance distance{grid, field, options.bicubic_field};
  double pose[3] = {prior.x(), prior.y(), prior.theta()};
  ceres::Problem problem;
  auto* points_cost =
      new PointsToMapCost(distance, seen, options.point_sigma_m,
                          options.loss_scale_m / options.point_sigma_m, options.cauchy_loss);
  problem.AddResidualBlock(points_cost, nullptr, pose);
  const Eigen::Matrix3d prior_information =
      prior_covariance != nullptr
          ? Eigen::Matrix3d(prior_covariance->inverse())
          : Eigen::Matrix3d(
                Eigen::Vector3d(1.0 / (options.prior_sigma_m * options.prior_sigma_m),
                                1.0 / (options.prior_sigma_m * options.prior_sigma_m),
                                1.0 / (options.prior_sigma_rad * options.prior_sigma_rad))
                    .asDiagonal());
  auto* prior_cost = new PriorCost(prior, prior_information);
  const ceres::ResidualBlockId prior_block = problem.AddResidualBlock(prior_cost, nullptr, pose);
  const ceres::Solver::Summary summary =
      SolveSilently(&problem, ceres::DENSE_NORMAL_CHOLESKY, options.max_iterations);
  result.iterations = static_cast<int>(summary.iterations.size());
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  result.pose = kernel::Pose2(pose[0], pose[1], pose[2]);
  // The points' errors are not independent: the map's pieces and the scan's noise are shared by
  // the neighbours in a cell, so the points count once per cell they fall in (a dense laser's
  // 5-10 points per 0.1 m otherwise make the scan overconfident by as much, and a gate that
  // compares it with the odometry refuses the odometry where the scan slides along a corridor).
  std::vector<long long> cells;
  cells.reserve(seen.size());
  for (const auto& p : seen) {
    const Eigen::Vector2d cell = grid.CellCoordinates(result.pose * p);
    cells.push_back(static_cast<long long>(std::floor(cell.x())) * 1000003LL +
                    static_cast<long long>(std::floor(cell.y())));
  }
  std::sort(cells.begin(), cells.end());
  const auto distinct = std::unique(cells.begin(), cells.end()) - cells.begin();
  const double independent = static_cast<double>(distinct) / static_cast<double>(seen.size());
  const Eigen::Matrix3d prior_hessian = GaussNewtonHessian(*prior_cost, pose);
  const Eigen::Matrix3d information =
      independent * GaussNewtonHessian(*points_cost, pose) + prior_hessian;
  result.covariance = information.inverse();

  int inliers = 0;
  double sum_sq = 0.0;
  for (const auto& p : seen) {
    const double d = distance(result.pose * p);
    const double capped = std::min(std::abs(d), options.inlier_distance_m) / options.point_sigma_m;
    result.points_cost += capped * capped;
    if (std::abs(d) < options.inlier_distance_m) {
      ++inliers;
      sum_sq += d * d;
    }
  }
  result.points_cost *= independent;
  // Laplace's approximation of the evidence: the cost at the solution plus
  // log det(I + S H) = log det(S^-1 + H) - log det(S^-1), S the prior's covariance (its
  // Hessian S^-1), H the points' Hessian.
  double prior_half_cost = 0.0;
  problem.EvaluateResidualBlock(prior_block, false, &prior_half_cost, nullptr, nullptr);
  result.evidence_cost = result.points_cost + 2.0 * prior_half_cost +
                         std::log(information.determinant() / prior_hessian.determinant());
  // Of the whole scan: a scan mostly outside what the map saw is not trusted (the recovery
  // search or the odometry take over).
  result.inlier_fraction = static_cast<double>(inliers) / static_cast<double>(points.size());
  result.misfit_fraction = static_cast<double>(static_cast<int>(seen.size()) - inliers) /
                           static_cast<double>(points.size());
  result.rms_m = inliers > 0 ? std::sqrt(sum_sq / inliers) : 0.0;
  const kernel::Pose2 correction = prior.Between(result.pose);
  if (!std::isfinite(pose[0] + pose[1] + pose[2]) || !result.covariance.allFinite())
    result.reason = "the solution is not finite";
  else if (result.inlier_fraction < options.min_inlier_fraction)
    result.reason = "too few points near the map";
  else if (correction.translation().norm() > options.max_correction_m ||
           std::abs(correction.theta()) > options.max_correction_rad)
    result.reason = "the correction is larger than the odometry can be off";
  result.accepted = result.reason.empty();
  return result;
}

bool OdometryIsInlier(const RegistrationResult& fused, const RegistrationResult& alone,
                      double outlier_probability) {
  const double p = outlier_probability;
  return fused.accepted &&
         fused.evidence_cost - alone.evidence_cost <= 2.0 * std::log((1.0 - p) / p);
}

void RegistrationOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("point_sigma_m", &point_sigma_m, "scale of a point's distance to the map, m");
  v.Field("bicubic_field", &bicubic_field,
          "interpolate the distance field bicubically instead of the exact distance");
  v.Field("cauchy_loss", &cauchy_loss, "Cauchy loss instead of Huber");
  v.Field("loss_scale_m", &loss_scale_m, "robust loss scale: farther points count less, m");
  v.Field("prior_sigma_m", &prior_sigma_m, "prior on the translation from odometry, m");
  v.Field("prior_sigma_rad", &prior_sigma_rad, "prior on the heading from odometry, rad");
  v.Field("max_iterations", &max_iterations, "Ceres iterations");
  v.Field("inlier_distance_m", &inlier_distance_m, "a point this near the map is an inlier, m");
  v.Field("min_inlier_fraction", &min_inlier_fraction, "quality test: inliers at least");
  v.Field("min_points", &min_points, "quality test: points at least");
  v.Field("max_correction_m", &max_correction_m, "quality test: moved from the prior at most, m");
  v.Field("max_correction_rad", &max_correction_rad,
          "quality test: turned from the prior at most, rad");
  v.Field("skip_past_outline_ends", &skip_past_outline_ends,
          "points past the end of their nearest outline piece are not matched");
  v.Field("max_normal_angle_rad", &max_normal_angle_rad,
          "a point turned from its nearest piece's normal by more is not matched (pi: off), rad");
  v.Field("two_sided_outlines", &two_sided_outlines,
          "where the map saw an outline from both sides, a point facing either side is matched");
}

kernel::Status RegistrationOptions::Validate() const {
  // Weights are 1 / sigma^2: beyond these they underflow or overflow, and the solve is no
  // longer one.
  if (!(point_sigma_m >= 1e-6 && point_sigma_m <= 10) ||
      !(loss_scale_m > 0 && loss_scale_m <= 100) || !(prior_sigma_m > 0 && prior_sigma_m <= 1e4) ||
      !(prior_sigma_rad > 0 && prior_sigma_rad <= 100))
    return kernel::Status::Error(
        "registration point_sigma_m must be in [1e-6, 10] m, loss_scale_m in (0, 100] m, "
        "prior_sigma_m in (0, 1e4] m and prior_sigma_rad in (0, 100] rad");
  if (max_iterations < 1 || max_iterations > 1000 || min_points < 3)
    return kernel::Status::Error(
        "registration needs max_iterations in [1, 1000] and min_points >= 3");
  if (!(inlier_distance_m > 0) || !(min_inlier_fraction >= 0 && min_inlier_fraction <= 1) ||
      !(max_correction_m > 0) || !(max_correction_rad > 0) ||
      !(max_normal_angle_rad > 0 && max_normal_angle_rad <= M_PI))
    return kernel::Status::Error(
        "registration quality test: positive distances, inlier fraction in [0, 1], normal angle "
        "in (0, pi]");
  return kernel::Status::Ok();
}

}  // namespace splam::estimation
