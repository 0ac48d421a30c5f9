#ifndef SPLAM_RUNTIME_LOG_REPLAY_H_
#define SPLAM_RUNTIME_LOG_REPLAY_H_

#include <algorithm>
#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "estimation/evaluation/map_consistency.h"
#include "estimation/slam_method.h"
#include "io/carmen.h"
#include "kernel/trajectory.h"
#include "runtime/slam_driver.h"
#include "sim/simulator.h"

namespace splam::runtime {

// Real FLASER logs: their odometry is much worse than the simulator's model, so the methods'
// odometry noise is scaled by this.
inline constexpr double kRealOdometryScale = 3.0;

// The sensors' noise a log implies, from its first laser message: a Hokuyo URG (ROBOTLASER1
// type URG) has sigma = 3 mm + 1 % of the range and no constant part in the beam model; SICK and
// FLASER logs 1 cm; the odometry model is scaled by kRealOdometryScale for FLASER logs.
// `given` fields (>= 0) replace the choice: -1 means "from the log".
struct SensorNoiseOverrides {
  double odometry_noise_scale = -1.0;
  double range_sigma_m = -1.0;
  double range_sigma_fraction = -1.0;
  bool any() const {
    return odometry_noise_scale >= 0 || range_sigma_m >= 0 || range_sigma_fraction >= 0;
  }
};
estimation::SensorNoise SensorNoiseOf(const io::LaserMessage& first,
                                      const SensorNoiseOverrides& given = {});

struct ReplayOptions {
  std::size_t max_scans = 0;  // 0: every scan
  // Called every 1000 scans with the scans done and the total.
  std::function<void(std::size_t done, std::size_t total)> progress;
  // Asked before every scan; true ends the replay there (Ctrl-C), as if the log ended. May be
  // empty.
  std::function<bool()> stop;
};

struct ReplayResult {
  kernel::Trajectory estimate, odometry;  // one pose per processed scan
  // For methods that revise the past (SlamMethod::Trajectory): the poses as estimated while
  // running, before the last optimisations moved them (`estimate` holds the final ones).
  kernel::Trajectory online;
  kernel::Trajectory truth;  // the log's TRUEPOS, if any
  std::vector<double> nees;  // pose NEES where the method has a covariance and truth exists
  std::size_t scans_in_log = 0;
  double wall_s = 0.0;
  // The scan at which the method became unhealthy (not in `estimate`), if it did.
  std::optional<std::size_t> failed_at;
  // The scan before which ReplayOptions::stop ended the replay, if it did.
  std::optional<std::size_t> stopped_at;
  double failed_at_time_s = 0.0;
  // Time span of the processed data, latest minus earliest time stamp, s. Real logs have time
  // stamps that go backwards (intel: 631 scans, together 237 s back): last minus first could be
  // negative ("-12 s of data"), and the sum of the forward steps counted intel's 2691 s as 2928.
  double data_s() const {
    if (estimate.empty()) return 0.0;
    const auto [earliest, latest] =
        std::minmax_element(estimate.begin(), estimate.end(),
                            [](const auto& a, const auto& b) { return a.time_s < b.time_s; });
    return latest->time_s - earliest->time_s;
  }
  // Scans whose time stamp is earlier than the previous scan's.
  int backward_time_stamps() const {
    int count = 0;
    for (std::size_t i = 1; i < estimate.size(); ++i)
      count += estimate[i].time_s < estimate[i - 1].time_s;
    return count;
  }
};

// Replays the laser messages of a CARMEN log through `driver` (the method starts at the first
// message's odometric pose): odometry increments between scans predict, every scan updates with
// the laser's mounting pose from the message.
ReplayResult ReplayLog(const io::CarmenLog& log, SlamDriver* driver,
                       const ReplayOptions& options = {});

// The log's scans placed by a trajectory of the replay (`estimate`: one pose per scan processed,
// in order), for CheckMapConsistency; the log must outlive the result.
std::vector<evaluation::PlacedScan> PlacedScans(const io::CarmenLog& log,
                                                const kernel::Trajectory& estimate);
// The log's scans placed by any trajectory of the log's time (a file from another tool): each
// scan at the trajectory's pose at its time stamp (kernel::PoseAt: interpolated across gaps up to
// 1 s); scans outside the trajectory are left out.
std::vector<evaluation::PlacedScan> PlacedScansAt(const io::CarmenLog& log,
                                                  const kernel::Trajectory& trajectory);
// The same for simulated frames (a route the simulator drove) seen by a laser at robot_T_laser;
// the truth is the frames' true poses.
ReplayResult ReplayFrames(const std::vector<sim::SensorFrame>& frames,
                          const kernel::Pose2& robot_T_laser, SlamDriver* driver,
                          const ReplayOptions& options = {});

}  // namespace splam::runtime

#endif  // SPLAM_RUNTIME_LOG_REPLAY_H_
