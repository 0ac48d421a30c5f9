// Tutorial: the kernel's basic types. A robot drives with odometry increments, takes a laser
// scan, and we place the scan's points in the world frame.
#include <cmath>
#include <cstdio>

#include "kernel/angle.h"
#include "kernel/pose2.h"
#include "kernel/scan.h"

using splam::kernel::DegToRad;
using splam::kernel::Pose2;
using splam::kernel::Scan;

int main() {
  // 1. A pose is world_T_robot = (x, y, theta); composing with an odometry increment (dx, dy,
  //    dtheta), expressed in the robot frame, gives the next pose (SPEC §2).
  Pose2 world_T_robot(1.0, 2.0, DegToRad(90));
  const Pose2 increment(0.5, 0.0, DegToRad(10));  // half a metre forward, turn 10 degrees
  for (int step = 0; step < 3; ++step) world_T_robot = world_T_robot * increment;
  std::printf("after 3 steps: x = %.3f m, y = %.3f m, theta = %.1f deg\n", world_T_robot.x(),
              world_T_robot.y(), splam::kernel::RadToDeg(world_T_robot.theta()));

  // 2. The motion between two poses, in the frame of the first, is what odometry measures.
  const Pose2 start(1.0, 2.0, DegToRad(90));
  const Pose2 moved = start.Between(world_T_robot);
  std::printf("motion seen from the start: (%.3f, %.3f, %.1f deg)\n", moved.x(), moved.y(),
              splam::kernel::RadToDeg(moved.theta()));

  // 3. A scan: beams from -90 to +90 degrees. Readings follow one convention everywhere:
  //    finite in [min, max) is a hit, +inf is "no return", NaN is an invalid reading.
  Scan scan;
  scan.start_angle_rad = DegToRad(-90);
  scan.angular_step_rad = DegToRad(45);
  scan.min_range_m = 0.02;
  scan.max_range_m = 8.0;
  scan.ranges_m = {1.0, 2.0, Scan::kNoReturn, NAN, 1.5};
  std::printf("scan: %zu beams, %zu hits\n", scan.size(), scan.HitIndices().size());

  // 4. Hit points are in the sensor frame; the pose maps them into the world.
  for (const Eigen::Vector2d& p : world_T_robot* scan.HitPoints()) {
    std::printf("  hit at world (%.3f, %.3f)\n", p.x(), p.y());
  }
  return 0;
}
