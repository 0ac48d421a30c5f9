#ifndef SPLAM_IO_SLAM_STATE_FILE_H_
#define SPLAM_IO_SLAM_STATE_FILE_H_

#include <string>

#include "estimation/slam_state.h"
#include "io/result.h"

// A SLAM method's saved state (`splam slam --save-state FILE`) as text, every number written so
// that it reads back as exactly the same double:
//   splam_state 1
//   method graph
//   keyframe x y theta                                  (the map's keyframes, in order)
//   loop_edge a b                                       (keyframe indices)
//   spline id n x_0 y_0 ... x_n-1 y_n-1 knot_0 ... knot_n+3      (as map.txt)
//   scan x y theta lx ly ltheta time start step min_range max_range n r_0 ... r_n-1
// `scan` is a map scan: the robot's pose, the laser's mounting, then the reading (angles in rad,
// ranges in m, "inf" for no return). '#' starts a comment.
namespace splam::io {

std::string FormatSlamState(const estimation::SlamState& state);
kernel::Status WriteSlamState(const std::string& path, const estimation::SlamState& state);
// Errors name the file (`path`) and line.
Result<estimation::SlamState> ReadSlamState(const std::string& path);
Result<estimation::SlamState> ParseSlamState(const std::string& text, const std::string& path);

}  // namespace splam::io

#endif  // SPLAM_IO_SLAM_STATE_FILE_H_
