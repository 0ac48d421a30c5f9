// Global localisation: where do scans lie in a saved map, with no initial pose and any heading?
//
//   example_global_localization                       # the simulated `complex` route
//   example_global_localization LOG STATE TRAJECTORY [N] [SEED]
//
// With a real log: STATE is the map `splam slam --method graph --save-state STATE LOG` saved,
// TRAJECTORY that run's trajectory.txt (the reference pose of every scan). N scans drawn at
// random (default 1000) are located twice: the scan alone, and as a stretch (the scan and five
// before it, eight apart, placed as a front end maps them: by the run's trajectory with the
// real log, by the odometry in simulation; intel's odometry bends such a stretch by more than
// a fix may be off). A fix within 0.1 m and 2 deg of the reference is found, another one
// wrong; refused ones are neither.
#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "estimation/pose_graph/global_localizer.h"
#include "io/carmen.h"
#include "io/slam_state_file.h"
#include "io/trajectory.h"
#include "kernel/angle.h"
#include "kernel/random.h"
#include "sim/builtin_worlds.h"
#include "sim/ray_caster.h"
#include "sim/simulator.h"

namespace estimation = splam::estimation;
using splam::kernel::Pose2;

// A log's scans as the localiser takes them: reading, mounting, local pose, reference pose.
struct Frame {
  splam::kernel::Scan scan;
  Pose2 robot_T_laser;
  Pose2 local;  // where a front end puts it (a stretch's scans relative to each other)
  Pose2 reference;
};

struct Tally {
  int queries = 0, found = 0, wrong = 0;
  double ms = 0.0;
  std::string wrong_errors;  // how far off each wrong fix was
  void Add(const estimation::GlobalFix& fix, const Pose2& reference, double ms_taken) {
    ++queries;
    ms += ms_taken;
    if (!fix.found) return;
    const Pose2 e = reference.Between(fix.pose);
    const bool right = e.translation().norm() <= 0.1 &&
                       std::abs(splam::kernel::WrapAngle(e.theta())) <= splam::kernel::DegToRad(2);
    ++(right ? found : wrong);
    if (!right)
      wrong_errors += fmt::format(" {:.2f} m {:.1f} deg;", e.translation().norm(),
                                  splam::kernel::RadToDeg(std::abs(e.theta())));
  }
  void Print(const char* what) const {
    std::printf("%-10s %4d of %4d found (%.1f %%), %d wrong%s, %.1f ms per query\n", what, found,
                queries, 100.0 * found / queries, wrong,
                wrong_errors.empty() ? "" : (" (" + wrong_errors + ")").c_str(), ms / queries);
  }
};

// Locates `n` random frames (from the 41st on) alone and as stretches.
void Run(const estimation::GlobalLocalizer& localizer, const std::vector<Frame>& frames, int n,
         std::uint64_t seed) {
  const estimation::FrontEndOptions front_end;
  splam::kernel::Random random(seed);
  Tally one, stretch;
  for (int q = 0; q < n; ++q) {
    const std::size_t i = 40 + random.Index(frames.size() - 40);
    auto start = std::chrono::steady_clock::now();
    const auto ms = [&start] {
      const auto now = std::chrono::steady_clock::now();
      const double d = std::chrono::duration<double, std::milli>(now - start).count();
      start = now;
      return d;
    };
    const estimation::GlobalFix alone = localizer.Locate(frames[i].scan, frames[i].robot_T_laser);
    one.Add(alone, frames[i].reference, ms());
    std::vector<estimation::MapScan> scans;
    for (std::size_t j = i - 40; j <= i; j += 8)
      scans.push_back({frames[j].local, frames[j].robot_T_laser, frames[j].scan});
    const std::vector<estimation::OrientedPoint> points =
        estimation::StretchPoints(scans, front_end);
    const estimation::GlobalFix placed = localizer.Locate(points);
    stretch.Add(placed, frames[i].reference, ms());
  }
  one.Print("one scan");
  stretch.Print("a stretch");
}

int main(int argc, char** argv) {
  std::vector<Frame> frames;
  std::vector<estimation::MapScan> map;
  int n = 150;
  std::uint64_t seed = 1;
  if (argc >= 4) {
    const splam::io::CarmenReadResult log = splam::io::ReadCarmenLog(argv[1]);
    const auto state = splam::io::ReadSlamState(argv[2]);
    const auto trajectory = splam::io::ReadTrajectory(argv[3]);
    if (!log.log.ok() || !state.ok() || !trajectory.ok())
      return std::fprintf(stderr, "%s%s%s\n", log.log.error.c_str(), state.error.c_str(),
                          trajectory.error.c_str()),
             2;
    const auto lasers = log.log.value->Lasers();
    if (lasers.size() != trajectory->size() || lasers.size() < 50)
      return std::fprintf(stderr, "the trajectory must hold one pose per scan of the log\n"), 2;
    for (std::size_t i = 0; i < lasers.size(); ++i)
      frames.push_back({lasers[i]->scan, lasers[i]->robot_pose.Between(lasers[i]->laser_pose),
                        (*trajectory)[i].pose, (*trajectory)[i].pose});
    map = state->scans;
    n = argc >= 5 ? std::atoi(argv[4]) : 1000;
    seed = argc >= 6 ? std::strtoull(argv[5], nullptr, 10) : 1;
  } else {
    // The simulated `complex` route; the map: every tenth scan at its true pose.
    const splam::sim::World world = *splam::sim::BuiltinWorld("complex");
    const splam::sim::RayCaster caster(world);
    splam::sim::Simulator simulator(caster, splam::sim::SimulatorOptions(), *world.start, 1);
    const splam::sim::RouteRun run = splam::sim::FollowRoute(&simulator, world.route, {});
    const Pose2 robot_T_laser = simulator.options().laser.robot_T_laser;
    for (const auto& f : run.frames)
      frames.push_back({f.scan, robot_T_laser, f.odometry_pose, f.true_pose});
    for (std::size_t i = 0; i < frames.size(); i += 10)
      map.push_back({frames[i].reference, robot_T_laser, frames[i].scan});
  }
  const auto built = std::chrono::steady_clock::now();
  const estimation::GlobalLocalizer localizer(map, estimation::FrontEndOptions(),
                                              estimation::GlobalLocalizationOptions());
  std::printf(
      "map: %zu scans, field %d x %d cells, built in %.0f ms\n", map.size(),
      localizer.field().cols(), localizer.field().rows(),
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - built).count());
  Run(localizer, frames, n, seed);
  return 0;
}
