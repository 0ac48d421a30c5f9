// Frontier bookkeeping: subtracting covered parts from a frontier arc.
#include "graph/frontiers.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "kernel/random.h"

namespace splam::graph {
namespace {

bool InAny(double angle, const std::vector<kernel::FrontierArc>& arcs) {
  for (const kernel::FrontierArc& a : arcs) {
    if (angle >= a.start_angle_rad && angle <= a.end_angle_rad) return true;
  }
  return false;
}

TEST(Frontiers, PropertySubtractKeepsExactlyTheUncoveredAngles) {
  kernel::Random random(5);
  for (int trial = 0; trial < 200; ++trial) {
    const kernel::FrontierArc arc{random.Uniform(-3, 0), random.Uniform(0.1, 3)};
    std::vector<kernel::FrontierArc> covered;
    for (int k = 0; k < 3; ++k) {
      const double a = random.Uniform(-4, 4);
      covered.push_back({a, a + random.Uniform(0, 1)});
    }
    const double margin = random.Uniform(0, 0.05);
    const std::vector<kernel::FrontierArc> pieces = Subtract(arc, covered, margin);
    for (std::size_t k = 1; k < pieces.size(); ++k)
      EXPECT_LT(pieces[k - 1].end_angle_rad, pieces[k].start_angle_rad);
    for (int s = 0; s <= 500; ++s) {
      const double angle =
          std::min(arc.end_angle_rad, arc.start_angle_rad + arc.AngularWidth() * s / 500.0);
      std::vector<kernel::FrontierArc> widened = covered;
      for (auto& c : widened) {
        c.start_angle_rad -= margin;
        c.end_angle_rad += margin;
      }
      const bool is_covered = InAny(angle, widened);
      // Boundaries may go either way; test only angles clearly inside or outside.
      bool near_boundary = false;
      for (const auto& c : widened) {
        near_boundary |=
            std::abs(angle - c.start_angle_rad) < 1e-9 || std::abs(angle - c.end_angle_rad) < 1e-9;
      }
      if (!near_boundary) {
        EXPECT_EQ(InAny(angle, pieces), !is_covered) << "trial " << trial << " angle " << angle;
      }
    }
  }
}

TEST(Frontiers, LeadingPieceStartsAtTheArcStart) {
  EXPECT_DOUBLE_EQ(LeadingPiece({0.0, 1.0}, 2.0).end_angle_rad, 1.0);
  const kernel::FrontierArc piece = LeadingPiece({0.5, 3.0}, 1.0);
  EXPECT_DOUBLE_EQ(piece.start_angle_rad, 0.5);
  EXPECT_DOUBLE_EQ(piece.end_angle_rad, 1.5);
}

}  // namespace
}  // namespace splam::graph
