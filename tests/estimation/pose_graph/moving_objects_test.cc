#include "estimation/pose_graph/moving_objects.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "kernel/angle.h"
#include "kernel/random.h"
#include "sim/laser.h"
#include "sim/ray_caster.h"
#include "sim/world.h"

namespace splam::estimation {
namespace {

using kernel::Pose2;

// A 20 m x 12 m hall with columns from 3 cm (a chair's leg, one beam) to 0.4 m across and short
// free-standing walls: the small static things a moving-object test could take for people.
sim::World Hall(kernel::Random* random) {
  sim::World world;
  world.obstacles.push_back(sim::Polyline{{{0, 0}, {20, 0}, {20, 12}, {0, 12}}, true});
  for (int i = 0; i < 12; ++i)
    world.obstacles.push_back(kernel::Circle2{{random->Uniform(1, 19), random->Uniform(1, 11)},
                                              random->Uniform(0.015, 0.2)});
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d a(random->Uniform(2, 18), random->Uniform(2, 10));
    const double heading = random->Uniform(-kernel::kPi, kernel::kPi),
                 length = random->Uniform(0.5, 3);
    world.obstacles.push_back(
        sim::Polyline{{a, a + length * Eigen::Vector2d(std::cos(heading), std::sin(heading))}});
  }
  return world;
}

// The distance from p to the nearest obstacle.
double Clearance(const sim::World& world, const Eigen::Vector2d& p) {
  sim::Primitives primitives;
  for (std::size_t i = 0; i < world.obstacles.size(); ++i) world.AppendPrimitives(i, &primitives);
  double clearance = std::numeric_limits<double>::infinity();
  for (const kernel::Segment2& s : primitives.segments)
    clearance = std::min(clearance, s.Distance(p));
  for (const kernel::Circle2& c : primitives.circles)
    clearance = std::min(clearance, (p - c.center).norm() - c.radius);
  return clearance;
}

// A point of the hall at least `clearance_m` from every obstacle.
Eigen::Vector2d FreePoint(const sim::World& world, double clearance_m, kernel::Random* random) {
  for (;;) {
    const Eigen::Vector2d p(random->Uniform(1, 19), random->Uniform(1, 11));
    if (Clearance(world, p) >= clearance_m) return p;
  }
}

// Two sweeps of a SICK at 1 deg (80 m) from nearby poses, the second's pose as a front end would
// know it relative to the first: off by a few centimetres and a few tenths of a degree.
struct TwoScans {
  kernel::Scan first, second;
  Pose2 first_pose, second_pose, second_estimate;
  std::vector<int> first_obstacles;  // per beam of `first`: the obstacle hit, -1 a person or none
};

TwoScans Sweep(const sim::World& world, const std::vector<kernel::Circle2>& person_then,
               const std::vector<kernel::Circle2>& person_now, kernel::Random* random) {
  sim::LaserOptions laser = sim::LaserOptions::Lms200(1.0);
  laser.max_range_m = 80.0;
  const sim::RayCaster caster(world);
  TwoScans s;
  do {
    s.first_pose = Pose2(FreePoint(world, 0.5, random), random->Uniform(-kernel::kPi, kernel::kPi));
    s.second_pose = s.first_pose * Pose2(random->Uniform(0.1, 1.0), random->Uniform(-0.1, 0.1),
                                         random->Uniform(-0.4, 0.4));
  } while (Clearance(world, s.second_pose.translation()) < 0.3);
  s.second_estimate = s.second_pose * Pose2(random->Gaussian(0.02), random->Gaussian(0.02),
                                            random->Gaussian(0.005));
  s.first =
      sim::SimulateLaser(caster, laser, s.first_pose, 0.0, random, &s.first_obstacles, person_then);
  s.second = sim::SimulateLaser(caster, laser, s.second_pose, 0.5, random, nullptr, person_now);
  return s;
}

// The hall alone, two sweeps 0.1-1 m apart with a wrong relative pose: nothing moved, and no
// beam of either is taken for a moving object, one-beam legs and wall ends included.
TEST(MovingObjects, PropertyNothingStaticIsSeenThrough) {
  kernel::Random random(11);
  const MovingObjectOptions options;
  int candidates = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const sim::World world = Hall(&random);
    const TwoScans s = Sweep(world, {}, {}, &random);
    candidates += static_cast<int>(ForegroundObjects(s.first, options).size());
    EXPECT_TRUE(
        SeenThroughBeams(s.first, s.first_pose, s.second, s.second_estimate, options).empty())
        << "trial " << trial;
    EXPECT_TRUE(
        SeenThroughBeams(s.second, s.second_estimate, s.first, s.first_pose, options).empty())
        << "trial " << trial;
  }
  EXPECT_GT(candidates, 1500);  // the columns and wall ends were candidates, and stood
}

// A person (a disc of 0.2-0.3 m) in the open walks 0.5-2 m between the sweeps. The beams taken
// for a moving object are always the person's, and the person's beams are taken in nearly every
// trial where the second sweep's view of where the person stood is clear.
TEST(MovingObjects, PropertyAPersonWhoWalkedOnIsSeenThroughAndNothingElse) {
  kernel::Random random(12);
  const MovingObjectOptions options;
  int clear = 0, found = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const sim::World world = Hall(&random);
    const double radius = random.Uniform(0.2, 0.3);
    const Eigen::Vector2d then = FreePoint(world, 1.0, &random);
    const double heading = random.Uniform(-kernel::kPi, kernel::kPi);
    const Eigen::Vector2d now =
        then + random.Uniform(0.5, 2.0) * Eigen::Vector2d(std::cos(heading), std::sin(heading));
    const TwoScans s = Sweep(world, {{then, radius}}, {{now, radius}}, &random);
    const std::vector<std::size_t> moving =
        SeenThroughBeams(s.first, s.first_pose, s.second, s.second_estimate, options);
    std::vector<std::size_t> person;
    for (std::size_t i = 0; i < s.first.size(); ++i)
      if (s.first.IsHit(i) && s.first_obstacles[i] < 0) person.push_back(i);
    for (std::size_t i : moving)
      EXPECT_TRUE(std::binary_search(person.begin(), person.end(), i))
          << "trial " << trial << ", beam " << i;
    // Clear: the person was a candidate of the first sweep, 3 beams or more, and the second
    // sweep, were the person still standing there, would see them with 2 or more, not behind
    // where they are now.
    const auto objects = ForegroundObjects(s.first, options);
    const bool candidate = person.size() >= 3 &&
                           std::find(objects.begin(), objects.end(),
                                     std::pair{person.front(), person.back() + 1}) != objects.end();
    sim::LaserOptions exact = sim::LaserOptions::Lms200(1.0);
    exact.max_range_m = 80.0;
    exact.noise_floor_m = 0.0;
    const sim::RayCaster caster(world);
    const kernel::Scan empty = sim::SimulateLaser(caster, exact, s.second_pose, 0.0, &random);
    const kernel::Scan ghost =
        sim::SimulateLaser(caster, exact, s.second_pose, 0.0, &random, nullptr,
                           std::vector<kernel::Circle2>{{then, radius}});
    int seen = 0;
    for (std::size_t i = 0; i < ghost.size(); ++i)
      seen += ghost.IsHit(i) && !(empty.IsHit(i) && empty.ranges_m[i] <= ghost.ranges_m[i]);
    const Eigen::Vector2d was = s.second_pose.Inverse() * then, is = s.second_pose.Inverse() * now;
    const bool behind =
        is.norm() < was.norm() &&
        std::abs(kernel::WrapAngle(std::atan2(is.y(), is.x()) - std::atan2(was.y(), was.x()))) <
            std::asin(radius / is.norm()) + std::asin(radius / was.norm()) + 0.02;
    if (!candidate || seen < 2 || behind) continue;
    ++clear;
    found += !moving.empty() && moving.size() == person.size();
  }
  std::cout << "person seen through in " << found << " of " << clear << " clear trials\n";
  EXPECT_GT(clear, 100);
  EXPECT_GE(found, 0.9 * clear);
}

// A scan of 1 deg beams whose ranges are `ranges`, the first beam straight ahead.
kernel::Scan Beams(std::vector<double> ranges) {
  kernel::Scan scan;
  scan.angular_step_rad = kernel::DegToRad(1.0);
  scan.max_range_m = 80.0;
  scan.ranges_m = std::move(ranges);
  return scan;
}

// A person overtaking the robot enters the view at its edge, close by: half outside the field of
// view, they are a candidate (the edge counts as open); a wall running out of the view is not (it
// is longer than max_size_m).
TEST(MovingObjects, APersonHalfOutsideTheViewIsACandidate) {
  const MovingObjectOptions options;
  std::vector<double> person(40, 5.0), wall(60, 5.0);
  for (std::size_t i = 36; i < 40; ++i) person[i] = 0.6;  // 4 beams, 3 deg: 3 cm apart
  EXPECT_EQ(ForegroundObjects(Beams(person), options),
            (std::vector<std::pair<std::size_t, std::size_t>>{{36, 40}}));
  for (std::size_t i = 20; i < 60; ++i) wall[i] = 2.0;  // 39 deg of an arc at 2 m: 1.3 m
  EXPECT_TRUE(ForegroundObjects(Beams(wall), options).empty());
}

// Where the other scan left a moving object out (its beams read NaN), what lay behind the object
// is unknown: a point there is not seen through, though the beams beside it passed.
TEST(MovingObjects, WhatAMovingObjectHidIsUnknown) {
  const MovingObjectOptions options;
  std::vector<double> ranges(60, 10.0);
  for (std::size_t i = 28; i < 33; ++i) ranges[i] = 3.0;  // an object at 3 m, 5 beams
  const kernel::Scan scan = Beams(ranges);
  const kernel::Scan clear = Beams(std::vector<double>(60, 10.0));
  EXPECT_EQ(SeenThroughBeams(scan, Pose2(), clear, Pose2(), options).size(), 5u);
  const kernel::Scan hid = WithoutBeams(clear, {27, 28, 29, 30, 31, 32, 33});
  EXPECT_TRUE(SeenThroughBeams(scan, Pose2(), hid, Pose2(), options).empty());
  EXPECT_TRUE(SeenThroughBeams(scan, Pose2(), scan, Pose2(), options).empty());  // still there
}

// A pose that is not finite (a NaN from an option the option fuzzer made huge) puts every point
// nowhere: nothing is seen through, and no NaN becomes a beam index (UBSan).
TEST(MovingObjects, APoseThatIsNotFiniteSeesNothingThrough) {
  const MovingObjectOptions options;
  std::vector<double> ranges(60, 10.0);
  for (std::size_t i = 28; i < 33; ++i) ranges[i] = 3.0;
  const kernel::Scan scan = Beams(ranges);
  const kernel::Scan clear = Beams(std::vector<double>(60, 10.0));
  const double nan = std::nan("");
  EXPECT_TRUE(SeenThroughBeams(scan, Pose2(nan, 0, 0), clear, Pose2(), options).empty());
  EXPECT_TRUE(SeenThroughBeams(scan, Pose2(), clear, Pose2(0, 0, nan), options).empty());
}

}  // namespace
}  // namespace splam::estimation
