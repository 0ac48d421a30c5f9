#ifndef SPLAM_EXPLORATION_PERCEPTION_H_
#define SPLAM_EXPLORATION_PERCEPTION_H_

#include "exploration/robot_interface.h"
#include "kernel/local_safe_region.h"
#include "kernel/pose2.h"
#include "kernel/scan.h"

namespace splam::exploration {

// The scan that bounds the robot's local safe region, in the laser frame: the laser sweep,
// completed around the full circle with the sonars when the robot has them (paper 003 §4.1: the
// rear sonars of the P3-DX cover the 120 deg the URG-04LX cannot see). The added beams keep the
// laser's angular step. A sonar echo at range R says that the sector of radius R at the sonar,
// over its cone, is free (the echo may come from anywhere in the cone; no echo: R = the sonar's
// maximum range); the robot's own disc is free too. Each added beam reads how far it runs from
// the laser through the union of these free sets (exact interval arithmetic on the convex
// sectors), no return when that is beyond the laser's range and no sonar on the way heard an
// echo, and NaN (unknown, never free) when the run is empty.
kernel::Scan SafeRegionScan(const Perception& perception, const RobotDescription& robot);

// The local safe region of radius `radius_m` of a robot at world_T_robot.
kernel::LocalSafeRegion SafeRegionAt(const kernel::Scan& safe_region_scan,
                                     const kernel::Pose2& world_T_robot,
                                     const RobotDescription& robot, double radius_m);

}  // namespace splam::exploration

#endif  // SPLAM_EXPLORATION_PERCEPTION_H_
