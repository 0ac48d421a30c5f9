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

// Trajectory files: one pose per line, "time_s x_m y_m theta_rad", separated by white space;
// '#' starts a comment line. Poses are kept in file order: the timestamps of real logs can jitter
// backwards (intel.clf does 631 times, by a few milliseconds).
Result<Trajectory> ReadTrajectory(const std::string& path);
Result<Trajectory> ParseTrajectory(const std::string& text, const std::string& name);
std::string FormatTrajectory(const Trajectory& trajectory, const std::string& comment = "");
// Ok, else why the file could not be written.
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
