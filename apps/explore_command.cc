// splam explore: autonomous exploration of a simulated world with SRT or REG.
#include <fmt/core.h>
#include <fmt/format.h>
#include <chrono>
#include <filesystem>
#include <fstream>

#include "apps/commands.h"
#include "apps/exploration_run.h"
#include "io/world_file.h"
#include "kernel/angle.h"

namespace splam::apps {
namespace {

struct ExploreArgs {
  ExploreSetup setup;
  std::string world = "complex";
  std::string out;
  double resolution_m_per_px = 0.05;
};

int RunExplore(const ExploreArgs& args) {
  io::FloorPlanOptions floor_plan;
  floor_plan.resolution_m_per_px = args.resolution_m_per_px;
  io::Result<sim::World> world = io::LoadWorld(args.world, floor_plan);
  if (!world.ok()) {
    fmt::print(stderr, "splam explore: {}\n", world.error);
    return kExitBadInput;
  }
  if (std::string problem = world.value->Validate(); !problem.empty()) {
    fmt::print(stderr, "splam explore: {}: {}\n", args.world, problem);
    return kExitBadInput;
  }
  if (std::string problem = args.setup.options.Validate(); !problem.empty()) {
    fmt::print(stderr, "splam explore: {}\n", problem);
    return kExitBadInput;
  }
  ExploreSetup setup = args.setup;
  fmt::print("splam explore: {} with {} localisation in '{}', seed {}\n", setup.explorer,
             setup.localization, world.value->name, setup.seed);
  std::fflush(stdout);
  const auto begin = std::chrono::steady_clock::now();
  setup.options.on_node = [&begin](int nodes, double time_s) {
    if (nodes % 10 != 0) return;
    fmt::print("  {} nodes, {:.0f} s simulated, {:.1f} s wall\n", nodes, time_s,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count());
    std::fflush(stdout);
  };
  const ExploreOutcome outcome = RunExploration(*world.value, setup);
  if (!outcome.error.empty()) {
    fmt::print(stderr, "splam explore: {}\n", outcome.error);
    return kExitBadInput;
  }
  const std::string out = args.out.empty()
                              ? fmt::format("runs/explore-{}-{}", setup.explorer, world.value->name)
                              : args.out;
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) {
    fmt::print(stderr, "splam explore: cannot create {}: {}\n", out, ec.message());
    return kExitBadInput;
  }
  const exploration::ExplorationRun& run = outcome.run;
  const int nodes = static_cast<int>(boost::num_vertices(run.graph));
  const nlohmann::json report = ExplorationReport(*world.value, setup, outcome);
  std::vector<std::string> written;
  if (std::string error = WriteExplorationRun(*world.value, setup, outcome, report, out, &written);
      !error.empty()) {
    fmt::print(stderr, "splam explore: {}\n", error);
    return kExitBadInput;
  }
  fmt::print(
      "{} nodes, {} edges, {:.1f} m, {:.1f} s simulated, {:.1f} % of {:.0f} m^2 reachable free "
      "space explored\nterminated: {} ({})\nplanning {:.2f} ms per node, wall time {:.2f} s\n",
      nodes, boost::num_edges(run.graph), run.distance_m, run.time_s, 100.0 * outcome.coverage(),
      outcome.reachable_area_m2, exploration::TerminationName(run.termination), run.message,
      nodes > 0 ? 1e3 * run.planning_wall_s / nodes : 0.0, outcome.wall_s);
  const nlohmann::json& e = report["trajectory_error"];
  fmt::print(
      "position RMSE: estimate {:.3f} m, odometry {:.3f} m; heading RMSE: {:.2f} deg, {:.2f} "
      "deg\n",
      e["estimate"]["rmse_position_m"].get<double>(),
      e["odometry"]["rmse_position_m"].get<double>(),
      kernel::RadToDeg(e["estimate"]["rmse_heading_rad"].get<double>()),
      kernel::RadToDeg(e["odometry"]["rmse_heading_rad"].get<double>()));
  if (report.contains("slam")) {
    const nlohmann::json& map = report["slam"]["map"];
    fmt::print("map: {}", map["description"].get<std::string>());
    if (map.contains("mean_distance_to_obstacles_m"))
      fmt::print(", {:.3f} m mean distance to the true obstacles",
                 map["mean_distance_to_obstacles_m"].get<double>());
    fmt::print("; {:.2f} ms per localisation step (median)\n",
               report["slam"]["ms_per_step"]["median"].get<double>());
  }
  fmt::print("wrote {}/{{{}}}\n", out, fmt::join(written, ", "));
  return run.termination == exploration::Termination::kExplored ? kExitOk : kExitIncomplete;
}

}  // namespace

void AddExploreCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<ExploreArgs>();
  ExploreSetup& setup = args->setup;
  exploration::ExplorerOptions& o = setup.options;
  CLI::App* cmd = app->add_subcommand(
      "explore",
      "Explore a simulated world autonomously with SRT or REG; write the graph with its local "
      "safe regions, the explored area over time, trajectories and report.json into --out.");
  cmd->add_option("--explorer", setup.explorer, "Exploration strategy")
      ->check(CLI::IsMember({"srt", "reg"}))
      ->capture_default_str();
  cmd->add_option(
         "--world", args->world,
         "Built-in world (corridor, office, complex), a YAML world file or a floor-plan image")
      ->capture_default_str();
  cmd->add_option("--seed", setup.seed,
                  "Seed of the simulator's noise and the explorer's random draws")
      ->capture_default_str();
  cmd->add_option("--out", args->out, "Output directory (default runs/explore-<explorer>-<world>)");
  cmd->add_option("--localization", setup.localization,
                  "Where the explorer believes it is: a SLAM method (the SPLAM loop), odometry "
                  "alone, or the simulator's ground truth")
      ->check(
          CLI::IsMember({"topological", "ekf-lines", "ekf-bspline", "odometry", "ground-truth"}))
      ->capture_default_str();
  cmd->add_option("--odometry-noise", setup.odometry_noise_scale,
                  "Scale of the default odometry noise (0 = perfect odometry)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--lsr-radius", o.lsr_radius_m, "LSR radius r, m")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--alpha", o.alpha, "Step alpha * r to a new node, 0 < alpha < 1")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--max-nodes", o.max_nodes, "Cap on graph nodes")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--max-time", o.max_time_s, "Cap on simulated exploration time, s")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("!--no-sonar", setup.sonar,
                "LSRs from the laser only (240 deg), without the sonar ring behind the robot");
  cmd->add_option("--resolution", args->resolution_m_per_px,
                  "Metres per pixel of a floor-plan image world")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->callback([args, exit_code] { *exit_code = RunExplore(*args); });
}

}  // namespace splam::apps
