#include "runtime/exploration_run.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "exploration/coverage.h"
#include "exploration/perception.h"
#include "runtime/simulated_robot.h"
#include "sim/ray_caster.h"

namespace splam::runtime {
namespace {

constexpr double kCoverageCell = 0.1;  // m
// A larger world gets coarser coverage cells (its grid would take 1.6e13 cells of 0.1 m over 400
// km): about 2^22 cells (at most twice), 4 MB a mask and a flood of that many clearance queries
// (seconds).
constexpr double kMaxCoverageCells = 1 << 22;

std::shared_ptr<exploration::Localization> MakeLocalization(const ExploreSetup& setup) {
  const std::string& name = setup.localization;
  if (name == "ground-truth") return std::make_shared<exploration::GroundTruthLocalization>();
  if (name == "odometry") return std::make_shared<exploration::OdometryLocalization>();
  if (estimation::SlamRegistry::Global().Find(name) == nullptr) return nullptr;
  std::shared_ptr<const estimation::SlamOptions> options = setup.slam_options;
  if (!options) options = DefaultSlamOptions(setup);
  auto slam = std::make_shared<SlamLocalization>(name, options, setup.region);
  slam->RecordSteps(setup.trace_steps);
  return slam;
}

// The free space reachable from the world's start (ExploreOutcome::reachable_area_m2), on a grid
// over the obstacles' bounds and 0.5 m beyond.
exploration::CoverageGrid ReachableSpace(const sim::World& world, const sim::RayCaster& caster) {
  kernel::Box2 bounds = world.Bounds();
  bounds.min -= Eigen::Vector2d::Constant(0.5);
  bounds.max += Eigen::Vector2d::Constant(0.5);
  // (w/c + 1)(h/c + 1) <= 2 kMaxCoverageCells + 1 with c^2 >= w h / max and c >= (w + h) / max:
  // the second keeps a long thin world (200 km x 1 m) bounded too.
  const Eigen::Vector2d size = bounds.Size();
  const double cell = std::max({kCoverageCell, std::sqrt(size.x() * size.y() / kMaxCoverageCells),
                                (size.x() + size.y()) / kMaxCoverageCells});
  const double half_diagonal = cell * std::sqrt(0.5);
  return exploration::CoverageGrid(
      bounds, cell, world.start->translation(), [&](const Eigen::Vector2d& c) {
        return !caster.IsInsideObstacle(c) && caster.Nearest(c, half_diagonal).obstacle < 0;
      });
}

// The explored fraction after every node: the LSRs at the nodes' true poses over the free
// space reachable from the start.
void EvaluateCoverage(exploration::CoverageGrid grid, const exploration::RobotDescription& robot,
                      double lsr_radius_m, ExploreOutcome* outcome) {
  outcome->reachable_area_m2 = grid.reachable_cells() * grid.cell_m() * grid.cell_m();
  for (const exploration::NodeRecord& node : outcome->run.nodes) {
    grid.Cover(
        exploration::SafeRegionAt(node.safe_region_scan, node.true_pose, robot, lsr_radius_m));
    outcome->coverage_time_s.push_back(node.time_s);
    outcome->coverage_fraction.push_back(grid.CoveredFraction());
  }
  if (!outcome->coverage_time_s.empty() && outcome->run.time_s > outcome->coverage_time_s.back()) {
    outcome->coverage_time_s.push_back(outcome->run.time_s);  // the way home adds no area
    outcome->coverage_fraction.push_back(outcome->coverage_fraction.back());
  }
}

}  // namespace

sim::SimulatorOptions DefaultSimulator(const ExploreSetup& setup) {
  sim::SimulatorOptions options;
  options.enable_sonar = setup.sonar;
  options.odometry = options.odometry.Scaled(setup.odometry_noise_scale);
  return options;
}

std::unique_ptr<estimation::SlamOptions> DefaultSlamOptions(const ExploreSetup& setup) {
  const estimation::SlamMethodInfo* info =
      estimation::SlamRegistry::Global().Find(setup.localization);
  if (info == nullptr) return nullptr;
  estimation::SensorNoise noise;  // the simulated URG-04LX
  noise.odometry_noise_scale = std::max(setup.odometry_noise_scale, 0.05);
  return info->default_options(noise);
}

std::vector<std::string> LocalizationChoices() {
  std::vector<std::string> choices = {"ground-truth", "odometry"};
  for (const std::string& n : estimation::SlamRegistry::Global().Names()) choices.push_back(n);
  return choices;
}

bool IsLocalization(const std::string& name) {
  const std::vector<std::string> choices = LocalizationChoices();
  return std::find(choices.begin(), choices.end(), name) != choices.end();
}

std::string LocalizationNames() {
  return "ground-truth, odometry, " + estimation::SlamRegistry::Global().NameList();
}

Trajectories TrajectoriesOf(const exploration::ExplorationRun& run) {
  Trajectories t;
  for (const exploration::TraceSample& s : run.trace) {
    t.truth.push_back({s.time_s, s.truth});
    t.odometry.push_back({s.time_s, s.odometry});
    t.estimate.push_back({s.time_s, s.estimate});
  }
  return t;
}

ExploreOutcome RunExploration(const sim::World& world, const ExploreSetup& setup) {
  ExploreOutcome outcome;
  const auto begin = std::chrono::steady_clock::now();
  exploration::ExplorerOptions options = setup.options;
  options.seed = setup.seed;
  options.lsr_radius_m = setup.region.radius_m;
  options.alpha = setup.region.alpha;
  kernel::Result<std::unique_ptr<exploration::Explorer>> made =
      exploration::ExplorerRegistry::Global().Make(setup.explorer, options,
                                                   setup.explorer_options.get());
  if (!made.ok()) {
    outcome.error = made.error;
    return outcome;
  }
  const std::unique_ptr<exploration::Explorer> explorer = std::move(*made.value);
  std::shared_ptr<exploration::Localization> localization = MakeLocalization(setup);
  if (!localization) {
    outcome.error =
        "unknown localisation '" + setup.localization + "' (" + LocalizationNames() + ")";
    return outcome;
  }
  if (!world.start) {
    outcome.error = "world '" + world.name + "' has no start pose";
    return outcome;
  }
  const sim::SimulatorOptions sim_options = setup.simulator.value_or(DefaultSimulator(setup));
  if (const kernel::Status problem = sim_options.Validate(); !problem.ok()) {
    outcome.error = problem.message();
    return outcome;
  }
  const sim::RayCaster caster(world);
  sim::Simulator simulator(caster, sim_options, *world.start, setup.seed);
  simulator.SetPeople(world.people);
  if (!simulator.IsFree(*world.start)) {
    outcome.error = "the start pose of '" + world.name + "' collides with an obstacle";
    return outcome;
  }
  // An exploration ends when nothing is left to explore: the start must be enclosed.
  exploration::CoverageGrid reachable = ReachableSpace(world, caster);
  if (reachable.reachable_cells() == 0) {
    outcome.error = "the start pose of '" + world.name +
                    "' lies outside the world (beyond its obstacles' bounds) or in no free space";
    if (reachable.cell_m() > kCoverageCell)
      outcome.error += fmt::format(
          " of the coverage grid, whose cells are {:.3g} m in a world of {:.0f} m x {:.0f} m (at "
          "most {:.0f} cells)",
          reachable.cell_m(), world.Bounds().Size().x(), world.Bounds().Size().y(),
          kMaxCoverageCells);
    return outcome;
  }
  if (reachable.reaches_border()) {
    outcome.error = "the free space around the start pose of '" + world.name +
                    "' is not enclosed by walls (it reaches the border of the world's bounds): "
                    "nothing would end the exploration";
    return outcome;
  }
  SimulatedRobot robot(&simulator);
  outcome.robot_radius_m = robot.description().radius_m;
  outcome.run = explorer->Run(&robot, localization.get());
  outcome.slam = std::dynamic_pointer_cast<SlamLocalization>(localization);
  // A method that revises the past optimises what is pending, so that its map and the graph
  // reported (its nodes moved once more) are final; the trajectory scored stays the one the
  // explorer used.
  if (outcome.slam && outcome.slam->driver() != nullptr) {
    outcome.slam->Finish();
    outcome.run.graph.MoveNodes(outcome.slam->NodePoses());
  }
  if (outcome.run.termination == exploration::Termination::kInvalidInput) {
    outcome.error = outcome.run.message;
    return outcome;
  }
  EvaluateCoverage(std::move(reachable), robot.description(), options.lsr_radius_m, &outcome);
  outcome.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return outcome;
}

}  // namespace splam::runtime
