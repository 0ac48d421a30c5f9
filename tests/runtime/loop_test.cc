// The SPLAM loop library: the one predict/update driver, log and frame replay, explorations with
// any registered method, and the scoring of runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "estimation/evaluation/metrics.h"
#include "estimation/exploration_nodes.h"
#include "estimation/topological/topological_slam.h"
#include "exploration/explorer.h"
#include "exploration/reg.h"
#include "io/config.h"
#include "io/simulation_log.h"
#include "kernel/angle.h"
#include "runtime/exploration_run.h"
#include "runtime/log_replay.h"
#include "runtime/scoring.h"
#include "runtime/slam_driver.h"
#include "runtime/step_trace.h"
#include "sim/builtin_worlds.h"
#include "studies/association_scoring.h"
#include "studies/corridor_experiment.h"

namespace splam::runtime {
namespace {

using kernel::Pose2;

// Records what the driver calls.
class Recorder : public estimation::SlamMethod {
 public:
  void Predict(const Pose2& u) override {
    increments.push_back(u);
    pose_ = pose_ * u;
  }
  void Update(const kernel::Scan& scan, const Pose2& robot_T_laser) override {
    updates.push_back(scan.size());
    mounting = robot_T_laser;
    if (fail_after_updates > 0 && static_cast<int>(updates.size()) >= fail_after_updates)
      health_ = kernel::Status::Error("diverged");
  }
  Pose2 pose() const override { return pose_; }
  kernel::Status health() const override { return health_; }
  std::size_t MapSize() const override { return updates.size(); }
  std::size_t MapCurves() const override { return 2 * updates.size(); }
  std::string MapDescription() const override { return ""; }
  estimation::SlamMap Map() const override { return {}; }
  estimation::SlamStatistics Statistics() const override { return {}; }

  std::vector<Pose2> increments;
  std::vector<std::size_t> updates;
  Pose2 mounting;
  int fail_after_updates = 0;

 private:
  Pose2 pose_;
  kernel::Status health_;
};

kernel::Scan ScanOf(std::size_t beams) {
  kernel::Scan scan;
  scan.ranges_m.assign(beams, 1.0);
  return scan;
}

TEST(SlamDriver, PredictsIncrementsAndUpdatesWithScans) {
  auto owned = std::make_unique<Recorder>();
  Recorder* r = owned.get();
  SlamDriver driver(std::move(owned));
  const kernel::Scan scan = ScanOf(5), empty;
  const Pose2 mount(0.1, 0, 0);
  EXPECT_TRUE(driver.Step(Pose2(1, 0, 0), &scan, mount));  // first reading: nothing to predict
  EXPECT_TRUE(r->increments.empty());
  EXPECT_TRUE(driver.Step(Pose2(2, 0, kernel::kPi / 2), &empty, mount));  // odometry only
  EXPECT_TRUE(driver.Step(Pose2(2, 1, kernel::kPi / 2), nullptr, mount));
  ASSERT_EQ(r->increments.size(), 2u);
  EXPECT_NEAR(r->increments[0].x(), 1.0, 1e-12);
  EXPECT_NEAR(r->increments[1].x(), 1.0, 1e-12);  // robot frame: straight ahead after the turn
  EXPECT_NEAR(r->increments[1].y(), 0.0, 1e-12);
  EXPECT_EQ(r->updates, std::vector<std::size_t>{5});
  EXPECT_EQ(r->mounting.x(), 0.1);
  EXPECT_EQ(driver.update_ms().size(), 1u);
  EXPECT_EQ(driver.map_size(), std::vector<std::size_t>{1});
  EXPECT_EQ(driver.map_curves(), std::vector<std::size_t>{2});
  // An origin makes the first reading predict too (the SPLAM loop's zero increment).
  auto second = std::make_unique<Recorder>();
  Recorder* s = second.get();
  SlamDriver origin(std::move(second));
  origin.SetOdometryOrigin(Pose2(1, 0, 0));
  origin.Step(Pose2(1, 0, 0), &scan, mount);
  ASSERT_EQ(s->increments.size(), 1u);
  EXPECT_EQ(s->increments[0].translation().norm(), 0.0);
}

TEST(SlamDriver, StopsUpdatingAnUnhealthyMethod) {
  auto owned = std::make_unique<Recorder>();
  owned->fail_after_updates = 2;
  Recorder* r = owned.get();
  SlamDriver driver(std::move(owned));
  const kernel::Scan scan = ScanOf(3);
  EXPECT_TRUE(driver.Step(Pose2(), &scan, Pose2()));
  EXPECT_FALSE(driver.Step(Pose2(), &scan, Pose2()));
  EXPECT_FALSE(driver.Step(Pose2(), &scan, Pose2()));
  EXPECT_EQ(r->updates.size(), 2u);
}

// A short drive along the complex route with the URG-04LX.
sim::RouteRun Drive(std::uint64_t seed, int scans) {
  static const sim::World world = *sim::BuiltinWorld("complex");
  static const sim::RayCaster caster(world);
  sim::Simulator simulator(caster, sim::SimulatorOptions(), *world.start, seed);
  sim::RouteOptions route;
  route.max_steps = scans - 1;
  return sim::FollowRoute(&simulator, world.route, route);
}

TEST(ReplayFrames, IsExactlyTheMethodsOwnLoop) {
  const sim::RouteRun run = Drive(3, 300);
  auto made = estimation::SlamRegistry::Global().Make("topological", nullptr,
                                                      {run.frames[0].odometry_pose, {}});
  ASSERT_TRUE(made.ok());
  SlamDriver driver(std::move(*made.value));
  const ReplayResult replay = ReplayFrames(run.frames, Pose2(), &driver);
  // The same method driven by hand: predict with each increment, update with each scan.
  estimation::TopologicalSlam slam(run.frames[0].odometry_pose);
  ASSERT_EQ(replay.estimate.size(), run.frames.size());
  for (std::size_t i = 0; i < run.frames.size(); ++i) {
    if (i > 0) slam.Predict(run.frames[i - 1].odometry_pose.Between(run.frames[i].odometry_pose));
    slam.Update(run.frames[i].scan);
    ASSERT_EQ(replay.estimate[i].pose.x(), slam.pose().x()) << i;
    ASSERT_EQ(replay.estimate[i].pose.theta(), slam.pose().theta()) << i;
  }
  EXPECT_EQ(replay.truth.size(), run.frames.size());
  EXPECT_TRUE(replay.nees.empty());  // no covariance
  EXPECT_FALSE(replay.failed_at);
}

TEST(ReplayLog, ReplaysARecordedLogLikeItsFrames) {
  const sim::RouteRun run = Drive(4, 200);
  const sim::SimulatorOptions options;
  const io::CarmenLog log = io::MakeCarmenLog(run.frames, options);
  const auto make = [&] {
    return SlamDriver(std::move(*estimation::SlamRegistry::Global()
                                     .Make("ekf-lines", nullptr, {run.frames[0].odometry_pose, {}})
                                     .value));
  };
  SlamDriver a = make(), b = make();
  ReplayOptions half;
  half.max_scans = 100;
  const ReplayResult from_log = ReplayLog(log, &a, half);
  const ReplayResult from_frames = ReplayFrames(run.frames, Pose2(), &b, half);
  ASSERT_EQ(from_log.estimate.size(), 100u);
  EXPECT_EQ(from_log.scans_in_log, run.frames.size());
  for (std::size_t i = 0; i < 100; ++i) {
    // The log stores poses as text: equal to a few ulps of the written precision.
    EXPECT_NEAR(from_log.estimate[i].pose.x(), from_frames.estimate[i].pose.x(), 1e-6) << i;
  }
  EXPECT_EQ(from_log.nees.size(), 100u);  // truth (TRUEPOS) and covariance at every scan
  const auto e = evaluation::CompareToTruth(from_log.truth, from_log.estimate);
  EXPECT_LT(e.rmse_position_m, 0.05);
}

TEST(SensorNoiseOf, FollowsTheLaserTypeUnlessGiven) {
  io::LaserMessage urg;
  urg.format = io::LaserMessage::Format::kRobotLaser1;
  urg.laser_type = io::kCarmenHokuyoUrg;
  io::LaserMessage flaser;
  flaser.format = io::LaserMessage::Format::kFlaser;
  EXPECT_EQ(SensorNoiseOf(urg).range_sigma_m, 0.003);
  EXPECT_EQ(SensorNoiseOf(urg).beam_sigma_floor_m, 0.0);
  EXPECT_EQ(SensorNoiseOf(urg).odometry_noise_scale, 1.0);
  EXPECT_EQ(SensorNoiseOf(flaser).range_sigma_m, 0.01);
  EXPECT_EQ(SensorNoiseOf(flaser).range_sigma_fraction, 0.0);
  EXPECT_EQ(SensorNoiseOf(flaser).odometry_noise_scale, kRealOdometryScale);
  SensorNoiseOverrides given;
  given.range_sigma_m = 0.02;
  given.odometry_noise_scale = 2.0;
  EXPECT_EQ(SensorNoiseOf(urg, given).beam_sigma_floor_m, 0.02);
  EXPECT_EQ(SensorNoiseOf(flaser, given).odometry_noise_scale, 2.0);
}

TEST(Scoring, PercentileAndTimeBins) {
  EXPECT_EQ(Percentile({}, 0.5), 0.0);
  EXPECT_EQ(Percentile({5, 1, 3}, 0.5), 3.0);
  EXPECT_EQ(Percentile({5, 1, 3}, 1.0), 5.0);
  EXPECT_EQ(Percentile({5, 1, 3}, 0.0), 1.0);
  // Map sizes 0..15 with time = size: 8 bins of width 2, medians the upper value of each.
  std::vector<double> ms;
  std::vector<std::size_t> size;
  for (std::size_t k = 0; k < 16; ++k) ms.push_back(static_cast<double>(k)), size.push_back(k);
  const std::vector<TimeBin> bins = TimeByMapSize(ms, size);
  ASSERT_EQ(bins.size(), 8u);
  EXPECT_EQ(bins[3].map_size_from, 6u);
  EXPECT_EQ(bins[3].map_size_to, 7u);
  EXPECT_EQ(bins[3].steps, 2u);
  EXPECT_EQ(bins[3].median_ms, 7.0);
  EXPECT_TRUE(TimeByMapSize({}, {}).empty());
}

TEST(Scoring, MapDistanceToObstaclesMeasuresAnOffset) {
  sim::World world;
  world.obstacles.push_back(sim::Polyline{{{0, 0}, {10, 0}}, false});
  const sim::RayCaster caster(world);
  for (const double offset : {0.0, 0.1, 0.35}) {
    const estimation::MapSpline s{
        0,
        *kernel::CubicBSpline::ClampedUniform({{1, offset}, {3, offset}, {5, offset}, {7, offset}}),
        1};
    EXPECT_NEAR(MeanDistanceToObstacles(caster, {s}), offset, 1e-6);
  }
  const estimation::MapSpline far{
      0, *kernel::CubicBSpline::ClampedUniform({{1, 5}, {3, 5}, {5, 5}, {7, 5}}), 1};
  EXPECT_NEAR(MeanDistanceToObstacles(caster, {far}), 2.0, 1e-12);  // capped
  EXPECT_EQ(MeanDistanceToObstacles(caster, {}), 0.0);
}

// One curve per wall scores 1; a wall built twice (a second copy 0.1 m off), or in two pieces,
// 1.5; a curve far from every obstacle counts against the map without adding an obstacle.
TEST(Scoring, CurvesPerObstacleCountsCopiesAndPieces) {
  sim::World world;
  world.obstacles.push_back(sim::Polyline{{{0, 0}, {10, 0}}, false});
  world.obstacles.push_back(sim::Polyline{{{0, 4}, {10, 4}}, false});
  const sim::RayCaster caster(world);
  const auto along = [](double y, double x0, double x1) {
    const double d = (x1 - x0) / 3;
    return estimation::MapSpline{
        0, *kernel::CubicBSpline::ClampedUniform({{x0, y}, {x0 + d, y}, {x0 + 2 * d, y}, {x1, y}}),
        1};
  };
  EXPECT_EQ(CurvesPerObstacle(caster, {}), 0.0);
  EXPECT_DOUBLE_EQ(CurvesPerObstacle(caster, {along(0.02, 1, 9), along(3.98, 1, 9)}), 1.0);
  EXPECT_DOUBLE_EQ(
      CurvesPerObstacle(caster, {along(0.0, 1, 9), along(0.1, 1, 9), along(4.0, 1, 9)}), 1.5);
  EXPECT_DOUBLE_EQ(
      CurvesPerObstacle(caster, {along(0.0, 1, 4), along(0.0, 5, 9), along(4.0, 1, 9)}), 1.5);
  EXPECT_DOUBLE_EQ(CurvesPerObstacle(caster, {along(0.0, 1, 9), along(2.0, 1, 9)}), 2.0);
}

TEST(RunExploration, NamesWhatCannotStart) {
  const sim::World world = *sim::BuiltinWorld("complex");
  ExploreSetup setup;
  setup.localization = "fastslam";
  EXPECT_EQ(RunExploration(world, setup).error,
            "unknown localisation 'fastslam' (" + LocalizationNames() + ")");
  EXPECT_NE(LocalizationNames().find("ground-truth, odometry, ekf-lines"), std::string::npos);
  setup.localization = "ground-truth";
  setup.explorer = "dfs";
  EXPECT_EQ(RunExploration(world, setup).error,
            "unknown explorer 'dfs' (" + exploration::ExplorerRegistry::Global().NameList() + ")");
  EXPECT_EQ(exploration::ExplorerRegistry::Global().NameList().rfind("srt, reg", 0), 0u);
  setup.localization = "topological";
  EXPECT_NE(DefaultSlamOptions(setup), nullptr);
  setup.localization = "odometry";
  EXPECT_EQ(DefaultSlamOptions(setup), nullptr);
}

// An explorer registered by a static object in a translation unit of its own
// (explorer_registration_elsewhere.cc) is listed after SRT and REG and runs like them.
TEST(RunExploration, RunsAnExplorerRegisteredInAnotherUnit) {
  const std::vector<std::string> names = exploration::ExplorerRegistry::Global().Names();
  ASSERT_EQ(std::find(names.begin(), names.end(), "reg-again") - names.begin(), 2);
  const sim::World world = *sim::BuiltinWorld("corridor");
  ExploreSetup setup;
  setup.explorer = "reg-again";
  setup.localization = "ground-truth";
  setup.options.max_nodes = 4;
  const ExploreOutcome outcome = RunExploration(world, setup);
  ASSERT_TRUE(outcome.error.empty()) << outcome.error;
  EXPECT_EQ(outcome.run.explorer, "reg-again");
  EXPECT_EQ(outcome.run.graph.num_nodes(), 4u);
  // Its own options, set as `--set exploration.reg-again.node_cap=3` would set them.
  std::unique_ptr<kernel::AnyOptions> own =
      exploration::ExplorerRegistry::Global().Find("reg-again")->default_options();
  ASSERT_TRUE(
      io::SetConfigValue([&](kernel::FieldVisitor& v) { own->VisitFields(v); }, "node_cap=3").ok());
  setup.explorer_options = own->Clone();
  EXPECT_EQ(RunExploration(world, setup).run.graph.num_nodes(), 3u);
  ASSERT_TRUE(
      io::SetConfigValue([&](kernel::FieldVisitor& v) { own->VisitFields(v); }, "node_cap=0").ok());
  setup.explorer_options = std::move(own);
  EXPECT_EQ(RunExploration(world, setup).error, "invalid reg-again options: node_cap must be >= 1");
  // Another explorer's options are refused by name.
  setup.explorer_options = std::make_shared<kernel::OptionsOf<exploration::RegOptions>>();
  EXPECT_EQ(RunExploration(world, setup).error, "the options given are not reg-again's");
}

TEST(SlamContext, TheRegionReachesTheTopologicalSlam) {
  // The local region is set once (the explorer's r and alpha) and handed to the method: with a
  // region far smaller than the laser's range the method finds fewer map curves to localise on.
  const sim::RouteRun run = Drive(2, 400);
  const auto localized = [&](double radius_m) {
    auto made = estimation::SlamRegistry::Global().Make(
        "topological", nullptr, {run.frames[0].odometry_pose, {radius_m, 0.8}});
    SlamDriver driver(std::move(*made.value));
    ReplayFrames(run.frames, Pose2(), &driver);
    for (const auto& [name, count] : driver.method().Statistics().associations)
      if (name == "associated_curves") return count;
    return -1L;
  };
  EXPECT_LT(localized(0.5), localized(3.0) / 2);
}

TEST(RunExploration, TheLsrRadiusIsTheExplorersToo) {
  const sim::World world = *sim::BuiltinWorld("corridor");
  ExploreSetup setup;
  setup.region.radius_m = 2.0;
  setup.options.max_nodes = 6;
  const ExploreOutcome outcome = RunExploration(world, setup);
  ASSERT_TRUE(outcome.error.empty()) << outcome.error;
  ASSERT_NE(outcome.slam_method(), nullptr);
  ASSERT_GT(outcome.run.graph.num_nodes(), 1u);
  for (graph::Vertex v = 0; v < outcome.run.graph.num_nodes(); ++v)
    EXPECT_EQ(outcome.run.graph[v].lsr.radius(), 2.0);
}

// min_frontier_m 0 keeps every frontier, but a stretch that only the sonars saw is never empty:
// with 0 an empty one was as long as the minimum and was read at its middle (UBSan: an element
// of an empty vector; found by the option fuzzer with REG, an LSR of 30 m and -0).
TEST(RunExploration, AZeroMinimumFrontierGivesUpNoEmptyStretch) {
  const sim::World world = *sim::BuiltinWorld("complex");
  for (const char* explorer : {"reg", "srt"}) {
    ExploreSetup setup;
    setup.explorer = explorer;
    setup.options.min_frontier_m = 0.0;
    setup.region.radius_m = 30.0;
    setup.options.max_nodes = 2;
    const ExploreOutcome outcome = RunExploration(world, setup);
    ASSERT_TRUE(outcome.error.empty()) << outcome.error;
    for (const exploration::GivenUpFrontier& f : outcome.run.given_up)
      EXPECT_TRUE(f.unseen.empty() ? f.reason.find("sonars") == std::string::npos
                                   : f.midpoint.allFinite())
          << explorer << ": " << f.reason;
  }
}

// With the graph SLAM as localisation the explorer plans on the optimised graph: after the run
// (and its closures) every node sits where the pose graph puts it, and every stored path still
// joins its two nodes.
TEST(RunExploration, TheGraphSlamMovesTheExplorersNodes) {
  const sim::World world = *sim::BuiltinWorld("complex");
  ExploreSetup setup;
  setup.localization = "graph";
  const ExploreOutcome outcome = RunExploration(world, setup);
  ASSERT_TRUE(outcome.error.empty()) << outcome.error;
  const estimation::ExplorationNodes* exploration_nodes =
      estimation::NodesOf(*outcome.slam_method());
  ASSERT_NE(exploration_nodes, nullptr);
  const std::vector<Pose2> nodes = exploration_nodes->NodePoses();
  const graph::ExplorationGraph& g = outcome.run.graph;
  ASSERT_EQ(nodes.size(), g.num_nodes());
  // How far the optimisations moved the nodes from where they were placed (the online estimate
  // when each was perceived).
  double moved = 0.0;
  for (graph::Vertex v = 0; v < nodes.size(); ++v) {
    EXPECT_NEAR((g[v].configuration.translation() - nodes[v].translation()).norm(), 0.0, 1e-9);
    EXPECT_NEAR((g[v].lsr.center() - nodes[v].translation()).norm(), 0.0, 1e-9);
    const auto placed =
        std::find_if(outcome.run.trace.begin(), outcome.run.trace.end(),
                     [&](const auto& t) { return t.time_s >= outcome.run.nodes[v].time_s; });
    ASSERT_NE(placed, outcome.run.trace.end());
    moved = std::max(moved, (placed->estimate.translation() - nodes[v].translation()).norm());
  }
  EXPECT_GT(moved, 0.02);
  for (const auto& [a, b, edge] : g.Edges()) {
    const auto& path = edge->path;
    if (path.size() < 2) continue;
    EXPECT_NEAR((path.front() - nodes[a].translation()).norm(), 0.0, 1e-9);
    EXPECT_NEAR((path.back() - nodes[b].translation()).norm(), 0.0, 1e-9);
  }
}

}  // namespace
}  // namespace splam::runtime

namespace splam::runtime {
namespace {

// A built-in world's route driven with `laser` (at most max_steps steps) and replayed through
// the registry's `method` with its default options (steps recorded when asked).
struct RouteReplay {
  sim::RouteRun route;
  ReplayResult replay;
  std::unique_ptr<SlamDriver> driver;
};
RouteReplay ReplayRoute(const std::string& method, const std::string& world_name,
                        const sim::LaserOptions& laser, std::uint64_t seed,
                        int max_steps = sim::RouteOptions().max_steps, bool record_steps = false) {
  const sim::World world = *sim::BuiltinWorld(world_name);
  const sim::RayCaster caster(world);
  sim::SimulatorOptions options;
  options.laser = laser;
  sim::Simulator simulator(caster, options, *world.start, seed);
  sim::RouteOptions route;
  route.max_steps = max_steps;
  RouteReplay r;
  r.route = sim::FollowRoute(&simulator, world.route, route);
  const auto* info = estimation::SlamRegistry::Global().Find(method);
  auto made = estimation::SlamRegistry::Global().Make(
      method, info->default_options(estimation::SensorNoise()).get(),
      {r.route.frames[0].odometry_pose, {}});
  r.driver = std::make_unique<SlamDriver>(std::move(*made.value));
  r.driver->RecordSteps(record_steps);
  r.replay = ReplayFrames(r.route.frames, laser.robot_T_laser, r.driver.get());
  return r;
}

struct GraphRun {
  ReplayResult replay;
  long loops_accepted = 0;
};

// The graph SLAM with its default options over a world's built-in route.
GraphRun RunGraphOnRoute(const std::string& world_name, const sim::LaserOptions& laser,
                         std::uint64_t seed = 1) {
  RouteReplay run = ReplayRoute("graph", world_name, laser, seed);
  GraphRun result;
  result.replay = std::move(run.replay);
  const estimation::SlamStatistics statistics = run.driver->method().Statistics();
  if (statistics.loop_closure) result.loops_accepted = statistics.loop_closure->accepted;
  return result;
}

// A whole loop through the office with the LMS-200: the graph SLAM closes loops and ends with its
// final trajectory (every scan's pose after the last optimisation) more accurate than odometry.
TEST(GraphSlam, ClosesTheOfficeLoop) {
  const GraphRun run = RunGraphOnRoute("office", sim::LaserOptions::Lms200());
  EXPECT_GT(run.loops_accepted, 10);
  const ReplayResult& replay = run.replay;
  ASSERT_EQ(replay.online.size(), replay.estimate.size());  // the past was revised
  const auto error = evaluation::CompareToTruth(replay.truth, replay.estimate);
  const auto odometry = evaluation::CompareToTruth(replay.truth, replay.odometry);
  EXPECT_LT(error.rmse_position_m, 0.1);
  EXPECT_LT(error.rmse_position_m, odometry.rmse_position_m);
  EXPECT_LT(error.rmse_heading_rad, kernel::DegToRad(1.0));
}

// The step trace of `splam slam --trace`: one record per reading with the predicted and the
// corrected pose and the topological SLAM's own values; the CSV's errors are those of the
// recorded poses against the truth.
TEST(StepTrace, RecordsEachStepsPredictionCorrectionAndValuesWithTheirErrors) {
  const RouteReplay r =
      ReplayRoute("topological", "complex", sim::SimulatorOptions().laser, 3, 299, true);
  const sim::RouteRun& run = r.route;
  const SlamDriver& driver = *r.driver;
  const ReplayResult& replay = r.replay;
  ASSERT_EQ(driver.steps().size(), run.frames.size());
  int localized = 0;
  for (std::size_t i = 0; i < driver.steps().size(); ++i) {
    const StepRecord& s = driver.steps()[i];
    EXPECT_NEAR(s.corrected.x(), replay.estimate[i].pose.x(), 1e-12);
    ASSERT_FALSE(s.values.empty());
    const auto value = [&](const std::string& name) {
      for (const auto& [n, v] : s.values)
        if (n == name) return v;
      ADD_FAILURE() << "no value " << name;
      return 0.0;
    };
    localized += value("localized") > 0;
    // An update that neither registered the scan (the scan-matched prediction), localised nor
    // refined against the map leaves the odometry's prediction.
    if (value("scan_matched") == 0 && value("localized") == 0 && value("dense") == 0) {
      EXPECT_NEAR(s.predicted.theta(), s.corrected.theta(), 1e-12);
    }
  }
  EXPECT_GT(localized, 50);  // 91 of the 300
  const std::string path = ::testing::TempDir() + "/steps.csv";
  std::vector<double> times;
  for (const auto& p : replay.estimate) times.push_back(p.time_s);
  ASSERT_EQ(WriteStepTrace(path, driver.steps(), times, replay.truth).message(), "");
  std::ifstream in(path);
  std::string header, line;
  std::getline(in, header);
  EXPECT_NE(header.find("predicted_heading_error_deg,heading_error_deg"), std::string::npos);
  EXPECT_NE(header.find("verified_curves"), std::string::npos);
  int rows = 0;
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) v.push_back(std::stod(cell));
    const Pose2& truth = replay.truth[static_cast<std::size_t>(rows)].pose;
    EXPECT_NEAR(v[12], std::hypot(v[5] - truth.x(), v[6] - truth.y()), 1e-5);  // position_error_m
    ++rows;
  }
  EXPECT_EQ(rows, static_cast<int>(run.frames.size()));
}

// The office with a SICK at 1 deg: walls seen at grazing incidence give points metres apart.
// As isolated points, each an outline piece across its wall, and with the view's chords between
// them marking the wall itself seen free, they held the front end where the submap's scans had
// been: 0.20 m RMSE on seed 1 (0.19 +- 0.06 m over seeds 1-10), against 0.007 m now.
TEST(GraphSlam, FollowsAOneDegreeLaserAlongGrazingWalls) {
  const GraphRun run = RunGraphOnRoute("office", sim::LaserOptions::Lms200(1.0));
  const auto error = evaluation::CompareToTruth(run.replay.truth, run.replay.estimate);
  EXPECT_LT(error.rmse_position_m, 0.05);
  EXPECT_LT(error.rmse_heading_rad, kernel::DegToRad(0.5));
}

// The complex route with the URG's 4 m range returns to its start from the other side: the last
// keyframes see walls the first ones never saw, and their score counted over all their points
// stayed below 0.4 (no seed closed). Judged on the points where the target has seen, the loop
// closes in most seeds (9 of 10; the URG's noise leaves correct matches near the 0.55 score).
TEST(GraphSlam, ClosesTheComplexLoopSeenFromTheOtherSide) {
  int closed = 0;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const GraphRun run = RunGraphOnRoute("complex", sim::LaserOptions::Urg04lx(), seed);
    closed += run.loops_accepted > 0;
    const auto error = evaluation::CompareToTruth(run.replay.truth, run.replay.estimate);
    const auto odometry = evaluation::CompareToTruth(run.replay.truth, run.replay.odometry);
    EXPECT_LT(error.rmse_position_m, 0.7 * odometry.rmse_position_m) << "seed " << seed;
  }
  EXPECT_GE(closed, 3);
}

}  // namespace
}  // namespace splam::runtime

namespace splam::runtime {
namespace {

// Active loop closing with the graph SLAM in `complex`: REG (default options) and SRT (metres
// cheaper, 0.1 nats/m: its tree's revisits are longer) revisit a node once the pose's position
// sigma reaches 1 m, the graph closes loops there (the sigma is then a fraction of what it was),
// and the exploration still covers the world. SRT's revisit is a round trip: the robot is back at
// the node it left.
TEST(ActiveLoopClosing, RevisitsCloseLoopsAndExplorationGoesOn) {
  for (const std::string explorer : {"reg", "srt"}) {
    SCOPED_TRACE(explorer);
    const sim::World world = *sim::BuiltinWorld("complex");
    ExploreSetup setup;
    setup.explorer = explorer;
    setup.localization = "graph";
    setup.options.active_loop_closing.enabled = true;
    if (explorer == "srt") setup.options.active_loop_closing.cost_nats_per_m = 0.1;
    const ExploreOutcome outcome = RunExploration(world, setup);
    ASSERT_TRUE(outcome.error.empty()) << outcome.error;
    const exploration::ExplorationRun& run = outcome.run;
    ASSERT_GE(run.revisits.size(), 1u);
    for (const exploration::RevisitRecord& r : run.revisits) {
      EXPECT_TRUE(r.reached);
      EXPECT_GE(r.position_sigma_m, setup.options.active_loop_closing.min_position_sigma_m);
      EXPECT_GT(r.information_nats, setup.options.active_loop_closing.min_information_nats);
      EXPECT_LT(r.trace_begin, r.trace_end);
      if (explorer == "srt") {
        const Eigen::Vector2d left =
            run.graph[static_cast<graph::Vertex>(r.from)].configuration.translation();
        EXPECT_LT((run.trace[r.trace_end - 1].estimate.translation() - left).norm(), 0.3);
      }
    }
    EXPECT_LT(run.revisits.front().position_sigma_after_m,
              0.5 * run.revisits.front().position_sigma_m);
    EXPECT_GT(outcome.coverage(), 0.97);
    const Trajectories t = TrajectoriesOf(run);
    EXPECT_LT(evaluation::CompareToTruth(t.truth, t.estimate).rmse_position_m, 0.08);
  }
}

// Without a localisation that says how uncertain it is, the option changes nothing.
TEST(ActiveLoopClosing, GroundTruthNeverRevisits) {
  const sim::World world = *sim::BuiltinWorld("office");
  ExploreSetup setup;
  setup.options.max_nodes = 12;
  setup.options.active_loop_closing.enabled = true;
  const ExploreOutcome with = RunExploration(world, setup);
  setup.options.active_loop_closing.enabled = false;
  const ExploreOutcome without = RunExploration(world, setup);
  EXPECT_TRUE(with.run.revisits.empty());
  EXPECT_NEAR(with.run.distance_m, without.run.distance_m, 1e-9);
}

}  // namespace
}  // namespace splam::runtime

namespace splam::runtime {
namespace {

// Beside a round hall's wall every rotation about the hall's centre fits the wall: REG + graph
// in `halls`, seed 3, once took a recovery 16 deg and 0.67 m off that left 18 % of the scan in
// the submap's free space, and ended 0.53 m off (heading 6.7 deg). A recovery may not contradict
// the submap more than the registration it replaces
// (FrontEndOptions::Advanced::verify_misfit_fraction).
TEST(GraphSlam, ARotationAboutARoundHallsCentreIsNoRecovery) {
  const sim::World world = *sim::BuiltinWorld("halls");
  ExploreSetup setup;
  setup.localization = "graph";
  setup.seed = 3;
  const ExploreOutcome outcome = RunExploration(world, setup);
  ASSERT_TRUE(outcome.error.empty()) << outcome.error;
  const Trajectories t = TrajectoriesOf(outcome.run);
  const auto error = evaluation::CompareToTruth(t.truth, t.estimate);
  EXPECT_LT(error.rmse_position_m, 0.1);
  EXPECT_LT(error.rmse_heading_rad, kernel::DegToRad(1.0));
  EXPECT_GT(outcome.coverage(), 0.97);
}

// The topological SLAM's scan matcher registered against keyframes at its own poses, which knew
// nothing of the curve corrections, and its back end's closures did not move them: the heading
// stayed 0.5-1 deg off, and REG + topological-graph in `halls`, seed 3, ended 0.159 m RMSE as
// the second hall was mapped with the offset. With one graph SLAM as scan matcher and back end,
// its keyframes at the corrected poses (GraphFrontEnd::Settle), it is 0.065 m (worst 0.112).
TEST(TopologicalGraphSlam, TheCorrectedPosesHoldTheHeadingAcrossTheRoundHalls) {
  const sim::World world = *sim::BuiltinWorld("halls");
  ExploreSetup setup;
  setup.localization = "topological-graph";
  setup.seed = 3;
  const ExploreOutcome outcome = RunExploration(world, setup);
  ASSERT_TRUE(outcome.error.empty()) << outcome.error;
  const Trajectories t = TrajectoriesOf(outcome.run);
  const auto error = evaluation::CompareToTruth(t.truth, t.estimate);
  EXPECT_LT(error.rmse_position_m, 0.08);
  EXPECT_LT(error.max_position_m, 0.15);
  EXPECT_GT(outcome.coverage(), 0.97);
}

}  // namespace
}  // namespace splam::runtime
