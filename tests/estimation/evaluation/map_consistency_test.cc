// The map's self-consistency check without ground truth.
#include "estimation/evaluation/map_consistency.h"

#include <gtest/gtest.h>

#include <iostream>
#include <vector>

#include "kernel/angle.h"
#include "kernel/random.h"
#include "sim/builtin_worlds.h"
#include "sim/laser.h"
#include "sim/ray_caster.h"

namespace splam::evaluation {
namespace {

using kernel::Pose2;

// Two passes along the office corridor, scans ray-cast every 0.5 m: with the true poses almost no
// point of one pass lies in the other's free space; with the second pass shifted 1 m across the
// corridor (a loop that did not close: the corridor drawn twice) 29 % of its points on average
// lie in the first pass's free space, 17 of its 42 scans contradict it by more than a fifth, and
// the map is flagged.
TEST(MapConsistency, FlagsACorridorDrawnTwiceAndNotTheTruth) {
  const sim::World world = *sim::BuiltinWorld("office");
  const sim::RayCaster caster(world);
  const sim::LaserOptions laser;
  kernel::Random random(5);
  std::vector<Pose2> truth;
  for (int i = 0; i <= 20; ++i) truth.emplace_back(1.0 + 0.5 * i, 6.0, 0.0);          // east
  for (int i = 20; i >= 0; --i) truth.emplace_back(1.0 + 0.5 * i, 6.0, kernel::kPi);  // back
  std::vector<kernel::Scan> scans;
  for (const Pose2& p : truth) scans.push_back(sim::SimulateLaser(caster, laser, p, 0.0, &random));
  const auto check = [&](const Pose2& second_pass_error) {
    std::vector<PlacedScan> placed;
    for (std::size_t i = 0; i < truth.size(); ++i)
      placed.push_back(
          {i > 20 ? second_pass_error * truth[i] : truth[i], laser.robot_T_laser, &scans[i]});
    ConsistencyOptions options;
    options.scan_spacing_m = 0.5;
    options.min_path_gap_m = 3.0;
    return CheckMapConsistency(placed, options);
  };
  const ConsistencyReport right = check(Pose2());
  const ConsistencyReport doubled = check(Pose2(0.0, 1.0, 0.0));
  ASSERT_GT(right.scans_checked, 20);
  EXPECT_LT(right.mean_contradicting, 0.03);
  EXPECT_EQ(right.inconsistent, 0);
  EXPECT_FALSE(right.flagged);
  EXPECT_GT(doubled.mean_contradicting, 0.2);
  EXPECT_GT(doubled.inconsistent_share, 0.3);
  EXPECT_TRUE(doubled.flagged);
  std::cout << "contradicting: " << right.mean_contradicting << " right, "
            << doubled.mean_contradicting << " with the second pass 1 m off ("
            << doubled.inconsistent << " of " << doubled.scans_checked << " scans flagged)\n";
}

}  // namespace
}  // namespace splam::evaluation
