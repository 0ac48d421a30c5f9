// A SLAM run's evaluation and files from one call (runtime::RunSlam), as `splam slam` writes them.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "estimation/slam_method.h"
#include "io/simulation_log.h"
#include "runtime/slam_run.h"
#include "sim/builtin_worlds.h"
#include "sim/ray_caster.h"
#include "sim/simulator.h"

namespace splam::runtime {
namespace {

int Lines(const std::string& path) {
  std::ifstream in(path);
  int n = 0;
  for (std::string line; std::getline(in, line);) n += !line.empty() && line[0] != '#';
  return n;
}

// The graph SLAM over the first 400 steps of the `complex` route, scored against its truth and
// against relations made from the truth every 20 scans: every file of the command line,
// summary.json's figures those of the report, the relations metric equal to the error of the
// relative motions.
TEST(RunSlam, WritesTheFilesAndFiguresOfTheCommandLineFromOneCall) {
  const sim::World world = *sim::BuiltinWorld("complex");
  const sim::RayCaster caster(world);
  sim::Simulator simulator(caster, sim::SimulatorOptions(), *world.start, 1);
  sim::RouteOptions route;
  route.max_steps = 399;
  const sim::RouteRun run = sim::FollowRoute(&simulator, world.route, route);
  ASSERT_GT(run.frames.size(), 390u);
  const io::CarmenLog log = io::MakeCarmenLog(run.frames, simulator.options());
  auto made =
      estimation::SlamRegistry::Global().Make("graph", nullptr, {run.frames[0].odometry_pose, {}});
  ASSERT_TRUE(made.ok()) << made.error;

  SlamRunFiles files;
  files.method = "graph";
  files.out = ::testing::TempDir() + "/run_slam";
  std::filesystem::remove_all(files.out);
  files.log = "simulated complex";
  files.world = &world;
  files.relations.emplace();
  for (std::size_t i = 20; i < run.frames.size(); i += 20)
    files.relations->push_back({run.frames[i - 20].time_s, run.frames[i].time_s,
                                run.frames[i - 20].true_pose.Between(run.frames[i].true_pose)});
  files.relations_file = "from the truth";
  ReplayResult replay;
  const SlamRunReport report = RunSlam(log, std::move(*made.value), {}, files, &replay);

  ASSERT_TRUE(report.written.ok()) << report.written.message();
  for (const char* name :
       {"trajectory.txt", "trajectory.tum", "odometry.txt", "truth.txt", "map.txt", "map.dxf",
        "map.png", "map.svg", "errors.png", "consistency.csv", "map.yaml", "map.pgm", "grid.png",
        "summary.json", "report.html"})
    EXPECT_TRUE(std::filesystem::exists(files.out + "/" + name)) << name;
  EXPECT_EQ(Lines(files.out + "/trajectory.txt"), static_cast<int>(run.frames.size()));
  EXPECT_FALSE(report.grid_error);
  EXPECT_EQ(report.label.rfind("graph", 0), 0u);

  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(files.out + "/summary.json"));
  EXPECT_EQ(summary["method"], "graph");
  EXPECT_EQ(summary["log"], "simulated complex");
  const double rmse = summary["error"]["estimate"]["rmse_position_m"].get<double>();
  EXPECT_LT(rmse, 0.1);
  EXPECT_LT(rmse, summary["error"]["odometry"]["rmse_position_m"].get<double>());
  EXPECT_EQ(summary["relations"]["relations_used"].get<int>(), 19);
  ASSERT_TRUE(report.scored && report.relations);
  EXPECT_LT(report.relations->translation_mean, 0.05);
  EXPECT_EQ(summary["relations"]["translation_m"]["mean"].get<double>(),
            report.relations->translation_mean);
  EXPECT_EQ(replay.estimate.size(), run.frames.size());
  // The typed counters (SlamStatistics::registration and loop_closure) under their keys: every
  // scan but the first registered against a submap, none left at the odometry, and no loop
  // search yet (fewer keyframes than loop.min_gap_keyframes).
  const nlohmann::json& counts = summary["associations"];
  EXPECT_EQ(counts["registrations"].get<long>(), static_cast<long>(run.frames.size()) - 1);
  EXPECT_EQ(counts["registration_fallbacks"].get<long>(), 0);
  EXPECT_LE(counts["registration_recovered"].get<long>(),
            counts["registration_recovery_searches"].get<long>());
  EXPECT_EQ(counts["loop_searches"].get<long>(), 0);
  EXPECT_EQ(counts["loop_accepted"].get<long>(), 0);
}

}  // namespace
}  // namespace splam::runtime
