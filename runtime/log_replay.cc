#include "runtime/log_replay.h"

#include <algorithm>
#include <chrono>

#include "estimation/evaluation/metrics.h"
#include "io/simulation_log.h"

namespace splam::runtime {

estimation::SensorNoise SensorNoiseOf(const io::LaserMessage& first,
                                      const SensorNoiseOverrides& given) {
  const bool urg = first.format == io::LaserMessage::Format::kRobotLaser1 &&
                   first.laser_type == io::kCarmenHokuyoUrg;
  const bool real = first.format == io::LaserMessage::Format::kFlaser;
  estimation::SensorNoise noise;
  noise.range_sigma_m = given.range_sigma_m >= 0 ? given.range_sigma_m : (urg ? 0.003 : 0.01);
  noise.range_sigma_fraction =
      given.range_sigma_fraction >= 0 ? given.range_sigma_fraction : (urg ? 0.01 : 0.0);
  noise.odometry_noise_scale = given.odometry_noise_scale >= 0 ? given.odometry_noise_scale
                                                               : (real ? kRealOdometryScale : 1.0);
  // The simulator's URG noise has no constant part; a --range-sigma given is used as it is.
  noise.beam_sigma_floor_m =
      given.range_sigma_m >= 0 ? given.range_sigma_m : (urg ? 0.0 : noise.range_sigma_m);
  return noise;
}

namespace {

// The one replay loop: `reading(i)` gives time, odometry pose, scan and laser mounting of
// reading i.
template <class Reading>
void Replay(std::size_t count, const Reading& reading, SlamDriver* driver,
            const ReplayOptions& options, ReplayResult* result) {
  const std::size_t n = options.max_scans > 0 ? std::min(options.max_scans, count) : count;
  estimation::SlamMethod& slam = driver->method();
  const auto begin = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < n; ++i) {
    if (options.stop && options.stop()) {
      result->stopped_at = i;
      break;
    }
    const auto [t, odometry, scan, robot_T_laser] = reading(i);
    if (!driver->Step(odometry, scan, robot_T_laser)) {
      result->failed_at = i;
      result->failed_at_time_s = t;
      break;
    }
    result->estimate.push_back({t, slam.pose()});
    result->odometry.push_back({t, odometry});
    const auto truth = kernel::PoseAt(result->truth, t, 0.0, 1e-3);
    if (const auto covariance =
            truth && slam.PoseCovarianceEveryScan() ? slam.PoseCovariance() : std::nullopt;
        covariance)
      result->nees.push_back(evaluation::PoseNees(*truth, slam.pose(), *covariance));
    if (options.progress && (i + 1) % 1000 == 0) options.progress(i + 1, n);
  }
  slam.Finish();
  // A method that revises the past (a pose graph) gives its final estimate of every pose; the
  // poses it gave while running are kept as `online`.
  if (const auto revised = slam.Trajectory(); revised.size() == result->estimate.size()) {
    result->online = result->estimate;
    for (std::size_t i = 0; i < revised.size(); ++i) result->estimate[i].pose = revised[i];
  }
  result->wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
}

struct Reading {
  double time_s;
  kernel::Pose2 odometry_pose;
  const kernel::Scan* scan;
  kernel::Pose2 robot_T_laser;
};

}  // namespace

ReplayResult ReplayLog(const io::CarmenLog& log, SlamDriver* driver, const ReplayOptions& options) {
  ReplayResult result;
  const auto lasers = log.Lasers();
  result.scans_in_log = lasers.size();
  result.truth = io::TrueTrajectory(log);
  Replay(
      lasers.size(),
      [&](std::size_t i) {
        const io::LaserMessage& m = *lasers[i];
        return Reading{m.stamp.ipc_timestamp_s, m.robot_pose, &m.scan,
                       m.robot_pose.Between(m.laser_pose)};
      },
      driver, options, &result);
  return result;
}

std::vector<evaluation::PlacedScan> PlacedScans(const io::CarmenLog& log,
                                                const kernel::Trajectory& estimate) {
  const auto lasers = log.Lasers();
  std::vector<evaluation::PlacedScan> placed;
  for (std::size_t i = 0; i < lasers.size() && i < estimate.size(); ++i) {
    const io::LaserMessage& m = *lasers[i];
    placed.push_back({estimate[i].pose, m.robot_pose.Between(m.laser_pose), &m.scan});
  }
  return placed;
}

std::vector<evaluation::PlacedScan> PlacedScansAt(const io::CarmenLog& log,
                                                  const kernel::Trajectory& trajectory) {
  const kernel::Trajectory sorted = kernel::SortedByTime(trajectory);
  std::vector<evaluation::PlacedScan> placed;
  for (const io::LaserMessage* m : log.Lasers()) {
    if (const std::optional<kernel::Pose2> pose = kernel::PoseAt(sorted, m->scan.timestamp_s))
      placed.push_back({*pose, m->robot_pose.Between(m->laser_pose), &m->scan});
  }
  return placed;
}

ReplayResult ReplayFrames(const std::vector<sim::SensorFrame>& frames,
                          const kernel::Pose2& robot_T_laser, SlamDriver* driver,
                          const ReplayOptions& options) {
  ReplayResult result;
  result.scans_in_log = frames.size();
  for (const sim::SensorFrame& f : frames) result.truth.push_back({f.time_s, f.true_pose});
  Replay(
      frames.size(),
      [&](std::size_t i) {
        return Reading{frames[i].time_s, frames[i].odometry_pose, &frames[i].scan, robot_T_laser};
      },
      driver, options, &result);
  return result;
}

}  // namespace splam::runtime
