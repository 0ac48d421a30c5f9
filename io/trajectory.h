#ifndef SPLAM_IO_TRAJECTORY_H_
#define SPLAM_IO_TRAJECTORY_H_

#include <cstddef>
#include <string>
#include <vector>

#include "io/result.h"
#include "kernel/pose2.h"
#include "kernel/trajectory.h"

namespace splam::io {

using kernel::Poses;
using kernel::StampedPose;
using kernel::Trajectory;

// Trajectory files, one pose per line, values separated by white space, '#' starting a comment
// line, in one of three formats:
//   splam  "time_s x_m y_m theta_rad" (4 values; .txt and any other extension)
//   TUM    "time_s x y z qx qy qz qw" (8 values; .tum), as evo and the TUM RGB-D benchmark
//          read it: the planar pose is written with z = 0 and the heading as a rotation about
//          z; read back, the heading is the quaternion's yaw (roll and pitch and z are dropped)
//   KITTI  "r00 r01 r02 x r10 r11 r12 y r20 r21 r22 z" (12 values; .kitti), the 3x4 pose
//          matrix of the KITTI odometry benchmark, row by row, with the robot's plane as its
//          x-y plane; KITTI has no times: pose k is given time k s, so KITTI trajectories are
//          compared with each other pose by pose
// Readers tell the format by the count of values on the first pose's line, whatever the
// extension. Poses are kept in file order: the timestamps of real logs can jitter backwards
// (intel.clf does 631 times, by a few milliseconds).
enum class TrajectoryFormat { kSplam, kTum, kKitti };
// By the file's extension: .tum, .kitti, else splam's.
TrajectoryFormat TrajectoryFormatOf(const std::string& path);
const char* TrajectoryFormatName(TrajectoryFormat format);

Result<Trajectory> ReadTrajectory(const std::string& path);
Result<Trajectory> ParseTrajectory(const std::string& text, const std::string& name);
// `comment` becomes a '#' line at the top (not in KITTI files, which numpy-style readers take
// whole).
std::string FormatTrajectory(const Trajectory& trajectory, const std::string& comment = "",
                             TrajectoryFormat format = TrajectoryFormat::kSplam);
// In the format of the path's extension (TrajectoryFormatOf).
kernel::Status WriteTrajectory(const std::string& path, const Trajectory& trajectory,
                               const std::string& comment = "");

// The most a text file (a log, a world, options, a trajectory) may hold: 4 GiB, about 13 hours
// of a 181-beam SICK logged at its full 75 Hz as CARMEN text (1.2 kB a scan), 500 hours at MIT
// Killian's 2.3 scans a second; reading and parsing it needs about twice that in memory. A larger
// file, or a device that never ends (/dev/zero, /dev/full read back), is refused rather than read
// until memory runs out.
inline constexpr std::size_t kMaxTextFileBytes = std::size_t{4} << 30;

// Reads a whole file (or a pipe) into *text; ok, else "path: cannot open ...",
// "is a device", or, past max_bytes, "holds more than N bytes".
kernel::Status ReadTextFile(const std::string& path, std::string* text,
                            std::size_t max_bytes = kMaxTextFileBytes);
// Writes text to a file; ok, else why it could not.
kernel::Status WriteTextFile(const std::string& path, const std::string& text);

}  // namespace splam::io

#endif  // SPLAM_IO_TRAJECTORY_H_
