#ifndef SPLAM_RUNTIME_EXPLORATION_RUN_H_
#define SPLAM_RUNTIME_EXPLORATION_RUN_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "estimation/slam_method.h"
#include "exploration/explorer.h"
#include "kernel/local_safe_region.h"
#include "kernel/trajectory.h"
#include "runtime/slam_localization.h"
#include "sim/simulator.h"
#include "sim/world.h"

namespace splam::runtime {

// One simulated exploration: which explorer, localisation and seed, and every option.
struct ExploreSetup {
  std::string explorer = "reg";  // a registered explorer (exploration::ExplorerRegistry)
  // "ground-truth", "odometry", or a registered SLAM method (the SPLAM loop).
  std::string localization = "topological";
  std::uint64_t seed = 1;             // simulator noise and the explorer's draws
  double odometry_noise_scale = 1.0;  // times the default odometry noise (simulated and modelled)
  bool sonar = true;                  // complete the LSR behind the robot with sonar
  kernel::LocalRegionOptions region;  // r and alpha, shared by the explorer and the SLAM
  // The options every explorer shares; lsr_radius_m, alpha and seed are overwritten by `region`
  // and `seed`.
  exploration::ExplorerOptions options;
  // The explorer's own options (ExplorerInfo::default_options, possibly edited); null: its
  // defaults.
  std::shared_ptr<const kernel::AnyOptions> explorer_options;
  // The simulator; null: DefaultSimulator(*this).
  std::optional<sim::SimulatorOptions> simulator;
  // The SLAM method's options; null: DefaultSlamOptions(*this).
  std::shared_ptr<const estimation::SlamOptions> slam_options;
  // Keep every SLAM step (SlamDriver::RecordSteps) for steps.csv (WriteExplorationRun).
  bool trace_steps = false;
};

// The simulator of a setup: defaults with the URG-04LX, the sonar ring when `sonar`, and the
// odometry noise scaled by odometry_noise_scale.
sim::SimulatorOptions DefaultSimulator(const ExploreSetup& setup);
// The SLAM method's defaults for the simulated sensors (URG-04LX ranges, the odometry model
// scaled like the simulation's, at least 0.05: an EKF needs some odometry noise); null when the
// localisation is not a registered SLAM method.
std::unique_ptr<estimation::SlamOptions> DefaultSlamOptions(const ExploreSetup& setup);
// "ground-truth", "odometry" and every registered SLAM method.
std::vector<std::string> LocalizationChoices();
// True for one of LocalizationChoices().
bool IsLocalization(const std::string& name);
// "ground-truth, odometry, ekf-lines, ..." for messages and help.
std::string LocalizationNames();

struct ExploreOutcome {
  std::string error;  // non-empty when the run could not start (nothing else is valid then)
  exploration::ExplorationRun run;
  double robot_radius_m = 0.0;
  // Explored fraction of the reachable free space (exploration::CoverageGrid, 10 cm cells) after
  // each node (and at the end of the run), from the LSRs placed at the nodes' true poses.
  std::vector<double> coverage_time_s, coverage_fraction;
  double reachable_area_m2 = 0.0;
  double wall_s = 0.0;  // whole run, simulation included
  // The SLAM method when the localisation is one (its map, timings); null otherwise.
  std::shared_ptr<SlamLocalization> slam;
  double coverage() const { return coverage_fraction.empty() ? 0.0 : coverage_fraction.back(); }
  const estimation::SlamMethod* slam_method() const {
    return slam && slam->driver() ? &slam->driver()->method() : nullptr;
  }
};

// The true, odometric and estimated trajectories of a run (from its trace).
struct Trajectories {
  kernel::Trajectory truth, odometry, estimate;
};
Trajectories TrajectoriesOf(const exploration::ExplorationRun& run);

// Runs the exploration in `world` from its start pose and evaluates its coverage.
ExploreOutcome RunExploration(const sim::World& world, const ExploreSetup& setup);

}  // namespace splam::runtime

#endif  // SPLAM_RUNTIME_EXPLORATION_RUN_H_
