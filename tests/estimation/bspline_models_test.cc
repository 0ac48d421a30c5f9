// The ray-spline observation model: ranges and analytic Jacobians against numeric ones.
#include "estimation/bspline_models.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernel/angle.h"
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

}  // namespace
}  // namespace splam::estimation
