#include "estimation/ekf/landmark_candidates.h"

#include <gtest/gtest.h>

#include <cmath>

namespace splam::estimation {
namespace {

TEST(LandmarkCandidates, PromotesAfterEnoughSightingsAndForgetsOldOnes) {
  LandmarkCandidates<double> candidates(/*min_observations=*/3, /*max_age_scans=*/2);
  const auto close = [](double a, double b) { return std::abs(a - b) < 0.1; };
  EXPECT_FALSE(candidates.Observe(1.0, 0, close));
  EXPECT_FALSE(candidates.Observe(1.05, 0, close));  // same scan: a second candidate
  EXPECT_EQ(candidates.size(), 2u);
  EXPECT_FALSE(candidates.Observe(1.08, 1, close));  // matches the first (now at 1.08)
  EXPECT_TRUE(candidates.Observe(1.15, 2, close));   // third sighting, tracked value: promoted
  candidates.Prune(2);
  EXPECT_EQ(candidates.size(), 1u);  // the promoted one left; the second (seen at 0) stays
  candidates.Prune(3);
  EXPECT_EQ(candidates.size(), 0u);  // not seen for 3 scans > 2
  EXPECT_FALSE(candidates.Observe(5.0, 4, close));
  EXPECT_FALSE(candidates.Observe(5.0, 7, close));  // a gap does not matter until pruned
}

TEST(LandmarkCandidates, OneSightingIsEnoughWhenAskedFor) {
  LandmarkCandidates<int> candidates(1, 10);
  EXPECT_TRUE(candidates.Observe(3, 0, [](int, int) { return true; }));
}

}  // namespace
}  // namespace splam::estimation
