// The ray-spline observation model: ranges and analytic Jacobians against numeric ones.
#include "estimation/ekf/bspline_models.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernel/angle.h"
#include "kernel/bspline_fit.h"
#include "kernel/random.h"

namespace splam::estimation {
namespace {

using kernel::CubicBSpline;
using kernel::Pose2;
using kernel::Random;

CubicBSpline RandomCurve(Random* random) {
  std::vector<Eigen::Vector2d> control;
  Eigen::Vector2d p(random->Uniform(-1, 1), random->Uniform(-1, 1));
  const int n = 4 + static_cast<int>(random->Index(6));
  for (int i = 0; i < n; ++i) {
    control.push_back(p);
    p += Eigen::Vector2d(random->Uniform(0.3, 0.8), random->Uniform(-0.4, 0.4));
  }
  return *CubicBSpline::ClampedUniform(control);
}

TEST(PredictBeam, RangeIsTheDistanceToTheCurveAlongTheBeam) {
  // A straight curve along x = 3 seen head on from the origin, laser 0.2 m ahead.
  const CubicBSpline wall = *CubicBSpline::ClampedUniform({{3, -2}, {3, -0.5}, {3, 0.5}, {3, 2}});
  const auto p = PredictBeam(Pose2(), Pose2(0.2, 0, 0), 0.0, wall, 10.0);
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(p->range_m, 2.8, 1e-12);
  // Moving the robot by dx shortens the range by dx; turning it by dth lengthens it by
  // about 2.8 dth^2 (second order): dr/dx = -1, dr/dy = 0, dr/dth = 0.
  EXPECT_NEAR(p->d_range_d_pose(0), -1.0, 1e-9);
  EXPECT_NEAR(p->d_range_d_pose(1), 0.0, 1e-9);
  EXPECT_NEAR(p->d_range_d_pose(2), 0.0, 1e-9);
  // Missing and grazing beams have no prediction.
  EXPECT_FALSE(PredictBeam(Pose2(), Pose2(), kernel::kPi, wall, 10.0).has_value());
  EXPECT_FALSE(PredictBeam(Pose2(), Pose2(), 0.0, wall, 2.0).has_value());
  EXPECT_FALSE(
      PredictBeam(Pose2(3, -3, kernel::kPi / 2 - 0.01), Pose2(), 0.0, wall, 10.0).has_value());
}

TEST(PredictBeam, PropertyJacobiansMatchNumericDifferentiation) {
  Random random(131);
  int checked = 0;
  for (int trial = 0; trial < 400 && checked < 150; ++trial) {
    const CubicBSpline curve = RandomCurve(&random);
    // A laser 1-3 m from a random point of the curve, looking at it.
    const Eigen::Vector2d target = curve.Point(random.Uniform(0.05, 0.95));
    const double bearing = random.Uniform(-kernel::kPi, kernel::kPi);
    const Eigen::Vector2d origin =
        target - random.Uniform(1, 3) * Eigen::Vector2d(std::cos(bearing), std::sin(bearing));
    const Pose2 mount(random.Uniform(-0.2, 0.2), random.Uniform(-0.1, 0.1),
                      random.Uniform(-0.3, 0.3));
    const double beam = random.Uniform(-0.2, 0.2);
    const Pose2 robot(origin, bearing - mount.theta() - beam);
    const auto p = PredictBeam(robot, mount, beam, curve, 10.0, 0.3);
    if (!p) continue;
    ++checked;
    auto range = [&](const Pose2& x, const CubicBSpline& c) {
      const auto q = PredictBeam(x, mount, beam, c, 10.0, 0.0);
      return q ? q->range_m : NAN;
    };
    const double h = 1e-6;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d a = robot.ToVector(), b = robot.ToVector();
      a(k) += h;
      b(k) -= h;
      const double numeric =
          (range(Pose2(a(0), a(1), a(2)), curve) - range(Pose2(b(0), b(1), b(2)), curve)) / (2 * h);
      EXPECT_NEAR(p->d_range_d_pose(k), numeric, 1e-5 * (1 + std::abs(numeric)))
          << "trial " << trial << " pose " << k;
    }
    for (int k = 0; k < 8; ++k) {
      std::vector<Eigen::Vector2d> plus = curve.control_points(), minus = plus;
      plus[p->first_control + k / 2](k % 2) += h;
      minus[p->first_control + k / 2](k % 2) -= h;
      const double numeric = (range(robot, *CubicBSpline::Create(plus, curve.knots())) -
                              range(robot, *CubicBSpline::Create(minus, curve.knots()))) /
                             (2 * h);
      EXPECT_NEAR(p->d_range_d_controls(k), numeric, 1e-5 * (1 + std::abs(numeric)))
          << "trial " << trial << " control " << k;
    }
  }
  EXPECT_GE(checked, 100);
}

TEST(CubicBSplineBasis, MatchesTheCurveAndSumsToOne) {
  Random random(132);
  for (int trial = 0; trial < 50; ++trial) {
    const CubicBSpline curve = RandomCurve(&random);
    for (double t : {0.0, 0.13, 0.5, 0.77, 1.0}) {
      const CubicBSpline::Basis b = curve.BasisAt(t);
      Eigen::Vector2d point = Eigen::Vector2d::Zero();
      double sum = 0.0;
      for (int k = 0; k < 4; ++k) {
        point += b.values[k] * curve.control_points()[b.first + k];
        sum += b.values[k];
      }
      EXPECT_NEAR(sum, 1.0, 1e-12);
      EXPECT_LT((point - curve.Point(t)).norm(), 1e-9);
    }
  }
}

TEST(AddBeamColumns, PropertyNewControlPointJacobiansMatchNumericDifferentiation) {
  // A new map spline X = (M (x) I2) D(pose, ranges) from the beams that see a curved wall.
  Random random(19);
  for (int trial = 0; trial < 30; ++trial) {
    const Pose2 pose(random.Uniform(-3, 3), random.Uniform(-3, 3), random.Uniform(-3, 3));
    const Pose2 laser(random.Uniform(-0.2, 0.2), random.Uniform(-0.1, 0.1),
                      random.Uniform(-0.1, 0.1));
    std::vector<double> ranges, angles;
    for (int k = 0; k < 40; ++k) {
      angles.push_back(-0.6 + 0.03 * k);
      ranges.push_back(2.0 + 0.3 * std::sin(0.1 * k) + random.Uniform(0, 0.5) * 0.01 * k);
    }
    auto controls_at = [&](const Pose2& x, const std::vector<double>& r, const Eigen::MatrixXd* m,
                           Eigen::MatrixXd* d_pose, Eigen::MatrixXd* d_ranges) {
      const BeamPoints b = BeamPointsInWorld(x, laser, r, angles);
      const Eigen::MatrixXd op = m != nullptr ? *m : kernel::CubicBSplineFitOperator(b.points)->m;
      std::vector<Eigen::Index> columns(r.size());
      for (std::size_t k = 0; k < r.size(); ++k) columns[k] = static_cast<Eigen::Index>(k);
      Eigen::VectorXd g = Eigen::VectorXd::Zero(2 * op.rows());
      Eigen::MatrixXd g_r = Eigen::MatrixXd::Zero(2 * op.rows(), 3);
      const Eigen::MatrixXd g_z = AddBeamColumns(op, columns, b, &g, &g_r);
      if (d_pose != nullptr) *d_pose = g_r;
      if (d_ranges != nullptr) *d_ranges = g_z;
      return std::pair{g, op};
    };
    Eigen::MatrixXd d_pose, d_ranges;
    const auto [g, m] = controls_at(pose, ranges, nullptr, &d_pose, &d_ranges);
    // The fit reproduces the points: the control points are those of FitCubicBSpline.
    const auto fit = kernel::FitCubicBSpline(BeamPointsInWorld(pose, laser, ranges, angles).points);
    ASSERT_TRUE(fit.ok());
    for (std::size_t i = 0; i < fit->control_points().size(); ++i)
      EXPECT_LT((g.segment<2>(2 * static_cast<Eigen::Index>(i)) - fit->control_points()[i]).norm(),
                1e-9);
    // Pose: exact, since the fit's parameters are invariant under rigid motion (M recomputed).
    const double h = 1e-6;
    for (int j = 0; j < 3; ++j) {
      Eigen::Vector3d dp = Eigen::Vector3d::Zero();
      dp(j) = h;
      const Eigen::Vector3d xp = pose.ToVector() + dp, xm = pose.ToVector() - dp;
      const Eigen::VectorXd plus =
          controls_at(Pose2(xp(0), xp(1), xp(2)), ranges, nullptr, nullptr, nullptr).first;
      const Eigen::VectorXd minus =
          controls_at(Pose2(xm(0), xm(1), xm(2)), ranges, nullptr, nullptr, nullptr).first;
      EXPECT_LT(((plus - minus) / (2 * h) - d_pose.col(j)).cwiseAbs().maxCoeff(), 1e-6) << j;
    }
    // Ranges: with M held fixed, as documented.
    for (std::size_t k = 0; k < ranges.size(); k += 7) {
      std::vector<double> plus_r = ranges, minus_r = ranges;
      plus_r[k] += h;
      minus_r[k] -= h;
      const Eigen::VectorXd plus = controls_at(pose, plus_r, &m, nullptr, nullptr).first;
      const Eigen::VectorXd minus = controls_at(pose, minus_r, &m, nullptr, nullptr).first;
      EXPECT_LT(((plus - minus) / (2 * h) - d_ranges.col(static_cast<Eigen::Index>(k)))
                    .cwiseAbs()
                    .maxCoeff(),
                1e-6)
          << k;
    }
  }
}

}  // namespace
}  // namespace splam::estimation
