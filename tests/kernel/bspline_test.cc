#include "kernel/bspline.h"

#include <gtest/gtest.h>

#include "kernel/random.h"

namespace splam::kernel {
namespace {

std::vector<Eigen::Vector2d> RandomPoints(Random* random, int n) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < n; ++i) points.emplace_back(random->Uniform(-5, 5), random->Uniform(-5, 5));
  return points;
}

TEST(CubicBSpline, ClampedUniformPassesThroughItsEnds) {
  const std::vector<Eigen::Vector2d> control = {{0, 0}, {1, 2}, {2, -1}, {3, 1}, {4, 0}};
  const auto spline = CubicBSpline::ClampedUniform(control);
  ASSERT_TRUE(spline.ok());
  EXPECT_TRUE(spline->PointDeBoor(spline->DomainStart()).isApprox(control.front()));
  EXPECT_TRUE(spline->Point(spline->DomainStart()).isApprox(control.front()));
  EXPECT_TRUE(spline->Point(spline->DomainEnd()).isApprox(control.back()));
  EXPECT_EQ(spline->knots(), (std::vector<double>{0, 0, 0, 0, 0.5, 1, 1, 1, 1}));
}

TEST(CubicBSpline, FourPointsIsOneBezier) {
  const std::vector<Eigen::Vector2d> control = {{0, 0}, {1, 2}, {2, -1}, {3, 1}};
  const auto spline = CubicBSpline::ClampedUniform(control);
  const auto& pieces = spline->pieces();
  ASSERT_EQ(pieces.size(), 1u);
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(pieces[0].p[i].isApprox(control[i]));
}

TEST(CubicBSpline, PropertyBezierPiecesReproduceDeBoor) {
  Random random(12);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 4 + static_cast<int>(random.Index(10));
    // Random clamped knots, some interior knots repeated.
    std::vector<double> interior;
    for (int i = 0; i < n - 4; ++i) interior.push_back(random.Uniform(0.05, 0.95));
    std::sort(interior.begin(), interior.end());
    if (interior.size() >= 2 && random.Uniform() < 0.3) interior[1] = interior[0];
    std::vector<double> knots = {0, 0, 0, 0};
    knots.insert(knots.end(), interior.begin(), interior.end());
    knots.insert(knots.end(), {1, 1, 1, 1});
    const auto spline = CubicBSpline::Create(RandomPoints(&random, n), knots);
    ASSERT_TRUE(spline.ok());
    const auto& pieces = spline->pieces();
    // Distinct spans in order.
    std::vector<double> spans = {0.0};
    for (double k : interior) {
      if (k > spans.back()) spans.push_back(k);
    }
    spans.push_back(1.0);
    ASSERT_EQ(pieces.size(), spans.size() - 1) << "trial " << trial;
    for (std::size_t s = 0; s < pieces.size(); ++s) {
      for (double u : {0.0, 0.25, 0.5, 0.75, 1.0}) {
        const double t = spans[s] + u * (spans[s + 1] - spans[s]);
        EXPECT_LT((pieces[s].Point(u) - spline->PointDeBoor(t)).norm(), 1e-9) << "trial " << trial;
        EXPECT_LT((spline->Point(t) - spline->PointDeBoor(t)).norm(), 1e-9) << "trial " << trial;
      }
    }
  }
}

TEST(CubicBSpline, CreateRejectsBadInput) {
  const auto few = CubicBSpline::ClampedUniform({{0, 0}, {1, 1}, {2, 2}});
  EXPECT_FALSE(few);
  EXPECT_NE(few.error.find("at least 4"), std::string::npos);
  const std::vector<Eigen::Vector2d> four = {{0, 0}, {1, 1}, {2, 2}, {3, 3}};
  const auto says = [](const Result<CubicBSpline>& made, const std::string& why) {
    return !made && made.error.find(why) != std::string::npos;
  };
  EXPECT_TRUE(says(CubicBSpline::Create(four, {0, 0, 0, 0, 1, 1, 1}), "expected 8 knots"));
  EXPECT_TRUE(says(CubicBSpline::Create(four, {0, 0, 0, 0.5, 1, 1, 1, 1}), "clamped"));
  EXPECT_TRUE(says(CubicBSpline::Create(four, {0, 0, 0, 0, 1, 1, 1, 0.5}), "non-decreasing"));
  EXPECT_TRUE(
      says(CubicBSpline::Create({{0, 0}, {NAN, 1}, {2, 2}, {3, 3}}, {0, 0, 0, 0, 1, 1, 1, 1}),
           "not finite"));
  EXPECT_TRUE(CubicBSpline::Create(four, {0, 0, 0, 0, 1, 1, 1, 1}));
}

TEST(ClosedUniformBSpline, PiecesJoinWithContinuousTangents) {
  const std::vector<Eigen::Vector2d> square = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  const auto pieces = ClosedUniformBSplineToBezier(square);
  ASSERT_EQ(pieces.size(), 4u);
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const auto& a = pieces[i];
    const auto& b = pieces[(i + 1) % pieces.size()];
    EXPECT_LT((a.Point(1) - b.Point(0)).norm(), 1e-12);
    EXPECT_LT((a.Derivative(1) - b.Derivative(0)).norm(), 1e-12);
    EXPECT_LT((a.SecondDerivative(1) - b.SecondDerivative(0)).norm(), 1e-12);
  }
  // The curve is strictly inside the control polygon of a square.
  EXPECT_TRUE(
      pieces[0].Point(0).isApprox(Eigen::Vector2d(5.0 / 3.0, 1.0 / 3.0)));  // (P0 + 4 P1 + P2) / 6
}

}  // namespace
}  // namespace splam::kernel
