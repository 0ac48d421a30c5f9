#include "exploration/perception.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "kernel/angle.h"

namespace splam::exploration {

namespace {

// Gaps narrower than this between the free sets along a beam are bridged: from the laser's
// origin, the sectors of neighbouring sonars (whose apexes sit 0.2 m off the centre) leave
// slivers of a few centimetres that no obstacle between two echoes could fill, m.
constexpr double kGapTolerance = 0.05;

// The interval [t_in, t_out] of the ray t * u (t >= 0) inside the sector at `sonar` (apex,
// axis) of radius R and half angle `half_cone` (< 90 deg, so the sector is convex); empty
// (t_in > t_out) when the ray misses it.
std::pair<double, double> RayInSector(const Eigen::Vector2d& u, const kernel::Pose2& sonar,
                                      double radius, double half_cone) {
  const Eigen::Vector2d s = sonar.translation();
  double t_in = 0.0, t_out = std::numeric_limits<double>::infinity();
  // The disc |t u - s| <= R.
  const double su = s.dot(u);
  const double disc = su * su - s.squaredNorm() + radius * radius;
  if (disc < 0.0) return {1.0, 0.0};
  t_in = std::max(t_in, su - std::sqrt(disc));
  t_out = std::min(t_out, su + std::sqrt(disc));
  // The two sides: n . (t u - s) <= 0 with n the outward normals of the cone's edges.
  for (const double side : {1.0, -1.0}) {
    const double edge = sonar.theta() + side * half_cone;
    const Eigen::Vector2d n = side * Eigen::Vector2d(-std::sin(edge), std::cos(edge));
    const double nu = n.dot(u), ns = n.dot(s);
    if (std::abs(nu) < 1e-12) {
      if (ns < 0.0) return {1.0, 0.0};
    } else if (nu > 0.0) {
      t_out = std::min(t_out, ns / nu);
    } else {
      t_in = std::max(t_in, ns / nu);
    }
  }
  return {t_in, t_out};
}

}  // namespace

kernel::Scan SafeRegionScan(const Perception& perception, const RobotDescription& robot) {
  const kernel::Scan& laser = perception.scan;
  if (robot.robot_T_sonar.empty() || laser.size() == 0 || !(laser.angular_step_rad > 0.0))
    return laser;
  const int full = static_cast<int>(std::lround(2.0 * kernel::kPi / laser.angular_step_rad));
  if (full <= static_cast<int>(laser.size())) return laser;
  kernel::Scan scan = laser;
  scan.angular_step_rad = 2.0 * kernel::kPi / full;  // closes the circle exactly
  const kernel::Pose2 laser_T_robot = robot.robot_T_laser.Inverse();
  const double body = std::max(0.0, robot.radius_m - robot.robot_T_laser.translation().norm());
  std::vector<kernel::Pose2> sonars;
  for (const kernel::Pose2& robot_T_sonar : robot.robot_T_sonar)
    sonars.push_back(laser_T_robot * robot_T_sonar);
  std::vector<std::pair<double, double>> intervals;
  for (int i = static_cast<int>(laser.size()); i < full; ++i) {
    const double angle = scan.start_angle_rad + i * scan.angular_step_rad;  // laser frame
    const Eigen::Vector2d u(std::cos(angle), std::sin(angle));
    intervals.assign(1, {0.0, body});  // the robot's own disc
    bool echo = false;
    for (std::size_t j = 0; j < sonars.size() && j < perception.sonar_ranges_m.size(); ++j) {
      const double reading = perception.sonar_ranges_m[j];
      if (std::isnan(reading)) continue;
      const auto interval =
          RayInSector(u, sonars[j], std::isinf(reading) ? robot.sonar_max_range_m : reading,
                      robot.sonar_cone_half_angle_rad);
      if (interval.first > interval.second) continue;
      intervals.push_back(interval);
      echo = echo || !std::isinf(reading);
    }
    // The free run from the sensor: the union of the intervals connected to t = 0.
    std::sort(intervals.begin(), intervals.end());
    double reach = 0.0;
    for (const auto& [t_in, t_out] : intervals) {
      if (t_in > reach + kGapTolerance) break;
      reach = std::max(reach, t_out);
    }
    scan.ranges_m.push_back(reach >= laser.max_range_m && !echo ? kernel::Scan::kNoReturn
                            : reach > 0.0                       ? reach
                                          : std::numeric_limits<double>::quiet_NaN());
  }
  return scan;
}

kernel::LocalSafeRegion SafeRegionAt(const kernel::Scan& safe_region_scan,
                                     const kernel::Pose2& world_T_robot,
                                     const RobotDescription& robot, double radius_m) {
  return kernel::LocalSafeRegion::FromScan(safe_region_scan, world_T_robot * robot.robot_T_laser,
                                           radius_m);
}

}  // namespace splam::exploration
