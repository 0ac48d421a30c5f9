#ifndef SPLAM_KERNEL_TRAJECTORY_H_
#define SPLAM_KERNEL_TRAJECTORY_H_

#include <optional>
#include <vector>

#include "kernel/pose2.h"

namespace splam::kernel {

struct StampedPose {
  double time_s = 0.0;
  Pose2 pose;
};
// Poses in order of non-decreasing time.
using Trajectory = std::vector<StampedPose>;

std::vector<Pose2> Poses(const Trajectory& trajectory);

// The trajectory stably sorted by time (PoseAt needs time order).
Trajectory SortedByTime(Trajectory trajectory);

// The pose at time t: the pose stamped within match_tolerance_s of t when there is one, else the
// linear interpolation of position and (wrapped) heading between the two poses around t when
// they are at most max_gap_s apart; nullopt outside the trajectory or across a larger gap.
// (Unix timestamps near 1e9 s carry about 1e-7 s of double precision.)
std::optional<Pose2> PoseAt(const Trajectory& trajectory, double t, double max_gap_s = 1.0,
                            double match_tolerance_s = 1e-4);

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_TRAJECTORY_H_
