#include "kernel/trajectory.h"

#include <algorithm>
#include <cmath>

#include "kernel/angle.h"

namespace splam::kernel {

std::vector<Pose2> Poses(const Trajectory& trajectory) {
  std::vector<Pose2> poses;
  poses.reserve(trajectory.size());
  for (const StampedPose& p : trajectory) poses.push_back(p.pose);
  return poses;
}

Trajectory SortedByTime(Trajectory trajectory) {
  std::stable_sort(trajectory.begin(), trajectory.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.time_s < b.time_s; });
  return trajectory;
}

std::optional<Pose2> PoseAt(const Trajectory& trajectory, double t, double max_gap_s,
                            double match_tolerance_s) {
  if (trajectory.empty()) return std::nullopt;
  const auto after =
      std::lower_bound(trajectory.begin(), trajectory.end(), t,
                       [](const StampedPose& p, double time) { return p.time_s < time; });
  const double tolerance = match_tolerance_s;
  if (after != trajectory.end() && std::abs(after->time_s - t) <= tolerance) return after->pose;
  if (after != trajectory.begin() && std::abs(std::prev(after)->time_s - t) <= tolerance) {
    return std::prev(after)->pose;
  }
  if (after == trajectory.end() || after == trajectory.begin()) return std::nullopt;
  const StampedPose& a = *std::prev(after);
  const StampedPose& b = *after;
  if (b.time_s - a.time_s > max_gap_s) return std::nullopt;
  const double f = (t - a.time_s) / (b.time_s - a.time_s);
  return Pose2(a.pose.translation() + f * (b.pose.translation() - a.pose.translation()),
               a.pose.theta() + f * WrapAngle(b.pose.theta() - a.pose.theta()));
}

}  // namespace splam::kernel
