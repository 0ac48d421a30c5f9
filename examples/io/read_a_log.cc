// Tutorial: read a CARMEN log, look at its contents, draw the raw odometry with the scans, and
// write it as a ROS 1 bag. Usage: example_io [picture.png] [log.clf or log.bag]
// Without a log it reads ../shared/datasets/intel.clf (or $SPLAM_DATA/intel.clf) when present,
// else it simulates a short log of its own first.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "io/carmen.h"
#include "io/render.h"
#include "io/ros_bag.h"
#include "io/simulation_log.h"
#include "sim/builtin_worlds.h"

namespace {

// A short simulated log in the office world, written next to the picture.
std::string SimulateSmallLog(const std::string& path) {
  namespace sim = splam::sim;
  const sim::World world = *sim::BuiltinWorld("office");
  const sim::RayCaster caster(world);
  sim::SimulatorOptions options;
  sim::Simulator simulator(caster, options, *world.start, 1);
  const sim::RouteRun run =
      sim::FollowRoute(&simulator, {world.route[0], world.route[1]}, sim::RouteOptions());
  const splam::kernel::Status error =
      splam::io::WriteCarmenLog(path, splam::io::MakeCarmenLog(run.frames, options));
  return error.ok() ? path : "";
}

}  // namespace

int main(int argc, char** argv) {
  namespace io = splam::io;
  const std::string picture = argc > 1 ? argv[1] : "example_io.png";
  std::string log_path = argc > 2 ? argv[2] : "";
  if (log_path.empty()) {
    const char* data = std::getenv("SPLAM_DATA");
    log_path = std::string(data != nullptr ? data : SPLAM_DEFAULT_DATA_DIR) + "/intel.clf";
    if (!std::filesystem::exists(log_path)) {
      std::printf("%s not found: simulating a small log instead\n", log_path.c_str());
      log_path = SimulateSmallLog(
          (std::filesystem::path(picture).parent_path() / "example_io.clf").string());
    }
  }

  // 1. Read. FLASER lines carry no beam geometry: CarmenReadOptions says how to assume it (the
  //    defaults fit the Freiburg logs). Errors come back as "file:line: message", never a crash.
  //    A ROS 1 bag is read into the same CarmenLog (RosBagOptions chooses topics and frames).
  io::CarmenReadOptions options;
  io::CarmenReadResult read;
  if (io::IsRosBagPath(log_path)) {
    read.log = io::ReadRosBag(log_path).log;
  } else {
    read = io::ReadCarmenLog(log_path, options);
  }
  if (!read.log.ok()) {
    std::fprintf(stderr, "%s\n", read.log.error.c_str());
    return 2;
  }
  const io::CarmenLog& log = *read.log.value;

  // 2. What is in it.
  const auto lasers = log.Lasers();
  std::printf("%s: %d lines, %zu scans, %zu odometry messages, %zu ground-truth poses\n",
              log_path.c_str(), read.stats.lines, lasers.size(), log.Odometry().size(),
              log.TruePoses().size());
  std::printf("readings: %d no-return, %d invalid\n", read.stats.no_return_readings,
              read.stats.invalid_readings);
  for (const auto& [type, count] : read.stats.skipped_messages)
    std::printf("skipped %d %s lines\n", count, type.c_str());
  if (lasers.empty()) return 0;
  const double duration =
      lasers.back()->stamp.ipc_timestamp_s - lasers.front()->stamp.ipc_timestamp_s;
  std::printf("%zu beams per scan over %.1f deg, %.0f s of data\n", lasers[0]->scan.size(),
              lasers[0]->scan.FieldOfView() * 180.0 / M_PI, duration);

  // 3. Odometry and scans placed with it: the raw, uncorrected map every SLAM method improves on.
  const io::Trajectory odometry = io::OdometryTrajectory(log);
  std::vector<Eigen::Vector2d> points;
  splam::kernel::Box2 area;
  for (std::size_t i = 0; i < lasers.size(); i += 20) {
    for (const Eigen::Vector2d& p : lasers[i]->laser_pose* lasers[i]->scan.HitPoints()) {
      points.push_back(p);
      area.Extend(p);
    }
  }
  for (const io::StampedPose& p : odometry) area.Extend(p.pose.translation());
  io::FigureOptions figure_options;
  figure_options.title = std::filesystem::path(log_path).filename().string() + ": raw odometry";
  figure_options.pixels_per_meter = 20;
  io::Figure figure(area, figure_options);
  figure.DrawPoints(points, io::palette::kScan, 0.8, "scans (every 20th)");
  figure.DrawPath(io::Poses(odometry), io::palette::kOdometry, 1.0, "odometry");
  if (const splam::kernel::Status error = figure.Save(picture); !error.ok()) {
    std::fprintf(stderr, "%s\n", error.message().c_str());
    return 2;
  }
  std::printf("wrote %s\n", picture.c_str());

  // 4. The same log as a ROS 1 bag: /scan, /odom, /tf_static and /ground_truth.
  const std::string bag =
      (std::filesystem::path(picture).parent_path() / "example_io.bag").string();
  io::RosBagWriteStats written;
  if (const splam::kernel::Status error = io::WriteRosBag(log, bag, {}, &written); !error.ok()) {
    std::fprintf(stderr, "%s\n", error.message().c_str());
    return 2;
  }
  std::printf("wrote %s: %d scans, %d odometry poses\n", bag.c_str(), written.scans,
              written.odometry);
  return 0;
}
