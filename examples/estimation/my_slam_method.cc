// Tutorial: write a SLAM variant, register it in one line, and run it exactly as `splam slam`
// and `splam explore` run the published methods: through the library's log-replay driver and
// through the SPLAM loop of an exploration.
// Usage: example_my_slam_method
#include <cstdio>

#include "estimation/evaluation/metrics.h"
#include "estimation/slam_method.h"
#include "examples/estimation/scan_matcher.h"
#include "io/simulation_log.h"
#include "runtime/exploration_run.h"
#include "runtime/log_replay.h"
#include "sim/builtin_worlds.h"
#include "sim/simulator.h"

int main() {
  namespace estimation = splam::estimation;
  namespace evaluation = splam::evaluation;
  namespace sim = splam::sim;

  // 1. Register the method: its name, a line for --help, and how to build it from its options.
  //    From here on the registry lists it beside ekf-lines, ekf-bspline and topological.
  estimation::RegisterSlamMethod<my_lab::ScanMatcherOptions>(
      "scan-matcher", "odometry corrected by scan-to-previous-scan ICP (tutorial)",
      [](const my_lab::ScanMatcherOptions& o, const estimation::SlamContext& c) {
        return std::make_unique<my_lab::ScanMatcher>(o, c);
      });

  // 2. A log to replay: the `complex` route with a URG-04LX, recorded as a CARMEN log (the same
  //    log `splam simulate --world complex --route built-in` writes).
  const sim::World world = *sim::BuiltinWorld("complex");
  const sim::RayCaster caster(world);
  const sim::SimulatorOptions sim_options;
  sim::Simulator simulator(caster, sim_options, *world.start, /*seed=*/1);
  const sim::RouteRun route = sim::FollowRoute(&simulator, world.route, sim::RouteOptions());
  const splam::io::CarmenLog log = splam::io::MakeCarmenLog(route.frames, sim_options);

  // 3. Replay it through the method, by name, with its default options: the driver predicts with
  //    every odometry increment and updates with every scan, as `splam slam` does.
  const estimation::SlamRegistry& registry = estimation::SlamRegistry::Global();
  auto made = registry.Make("scan-matcher", nullptr, {log.Lasers()[0]->robot_pose, {}});
  if (!made.ok()) {
    std::fprintf(stderr, "%s\n", made.error.c_str());
    return 1;
  }
  splam::runtime::SlamDriver driver(std::move(*made.value));
  const splam::runtime::ReplayResult replay = splam::runtime::ReplayLog(log, &driver);
  const auto e = evaluation::CompareToTruth(replay.truth, replay.estimate);
  const auto o = evaluation::CompareToTruth(replay.truth, replay.odometry);
  std::printf("log replay: %zu scans, position RMSE %.3f m (odometry %.3f m), %.2f ms per scan\n",
              replay.estimate.size(), e.rmse_position_m, o.rmse_position_m,
              1e3 * replay.wall_s / static_cast<double>(replay.estimate.size()));

  // 4. The same method as the explorer's localisation: REG plans with its estimate.
  splam::runtime::ExploreSetup setup;
  setup.explorer = "reg";
  setup.localization = "scan-matcher";
  const splam::runtime::ExploreOutcome outcome = splam::runtime::RunExploration(world, setup);
  if (!outcome.error.empty()) {
    std::fprintf(stderr, "%s\n", outcome.error.c_str());
    return 1;
  }
  const splam::runtime::Trajectories t = splam::runtime::TrajectoriesOf(outcome.run);
  const auto xe = evaluation::CompareToTruth(t.truth, t.estimate);
  const auto xo = evaluation::CompareToTruth(t.truth, t.odometry);
  std::printf("exploration: %s, %.1f %% explored, position RMSE %.3f m (odometry %.3f m)\n",
              splam::exploration::TerminationName(outcome.run.termination).c_str(),
              100.0 * outcome.coverage(), xe.rmse_position_m, xo.rmse_position_m);
  // 5. What the method counted (its SlamStatistics), as `splam slam` writes into summary.json.
  for (const auto& [name, count] : driver.method().Statistics().associations)
    std::printf("  %s: %ld\n", name.c_str(), count);
  // The example fails (and CI with it) when the replay stops early or REG does not finish.
  const bool ok = replay.estimate.size() == replay.scans_in_log &&
                  outcome.run.termination == splam::exploration::Termination::kExplored;
  return ok ? 0 : 1;
}
