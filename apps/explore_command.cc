// splam explore: autonomous exploration of a simulated world with SRT or REG.
#include <fmt/core.h>
#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>

#include "apps/commands.h"
#include "apps/interrupt.h"
#include "apps/output_paths.h"
#include "apps/run_config.h"
#include "exploration/explorer.h"
#include "io/config.h"
#include "io/text.h"
#include "io/world_file.h"
#include "kernel/angle.h"
#include "runtime/exploration_report.h"

namespace splam::apps {
namespace {

struct ExploreArgs {
  runtime::ExploreSetup setup;  // what the command line gave
  std::string config_file;
  std::vector<std::string> sets;
  std::vector<std::string> given;  // the top-level flags given (explorer, localization, ...)
  std::string world = "complex";
  std::string out;
  double resolution_m_per_px = 0.05;
  std::vector<double> start;  // x, y, theta: overrides the world's start pose
  bool trace = false;
};

// The setup: defaults, then the configuration file, then the command line (flags and --set).
kernel::Status Configure(const ExploreArgs& args, ExploreConfig* config) {
  std::optional<io::ConfigFile> file;
  if (!args.config_file.empty()) {
    io::Result<io::ConfigFile> loaded = io::ConfigFile::Load(args.config_file);
    if (!loaded.ok()) return loaded.status();
    file = std::move(*loaded.value);
  }
  runtime::ExploreSetup& setup = config->setup;
  const runtime::ExploreSetup& flags = args.setup;
  const auto given = [&](const char* name) {
    return std::find(args.given.begin(), args.given.end(), name) != args.given.end();
  };
  // What decides the defaults of the rest: explorer, localisation, seed, odometry noise.
  const io::ConfigRoot top = [&](kernel::FieldVisitor& v) {
    v.Field("explorer", &setup.explorer, "");
    v.Field("localization", &setup.localization, "");
    v.Field("seed", &setup.seed, "");
    v.Field("odometry_noise_scale", &setup.odometry_noise_scale, "");
  };
  if (file) {
    if (kernel::Status s = file->Read(top, /*allow_unknown=*/true); !s.ok()) return s;
  }
  if (given("explorer")) setup.explorer = flags.explorer;
  if (given("localization")) setup.localization = flags.localization;
  if (given("seed")) setup.seed = flags.seed;
  if (given("odometry-noise")) setup.odometry_noise_scale = flags.odometry_noise_scale;
  if (given("no-sonar")) setup.sonar = false;
  if (exploration::ExplorerRegistry::Global().Find(setup.explorer) == nullptr)
    return kernel::Status::Error("unknown explorer '" + setup.explorer + "' (" +
                                 exploration::ExplorerRegistry::Global().NameList() + ")");
  if (!runtime::IsLocalization(setup.localization))
    return kernel::Status::Error("unknown localisation '" + setup.localization + "' (" +
                                 runtime::LocalizationNames() + ")");
  ResetExploreDefaults(config);
  std::vector<std::string> sets;
  if (given("lsr-radius"))
    sets.push_back("local_region.radius_m=" + io::FormatDouble(flags.region.radius_m));
  if (given("alpha")) sets.push_back("local_region.alpha=" + io::FormatDouble(flags.region.alpha));
  if (given("max-nodes"))
    sets.push_back("exploration.max_nodes=" + std::to_string(flags.options.max_nodes));
  if (given("max-time"))
    sets.push_back("exploration.max_time_s=" + io::FormatDouble(flags.options.max_time_s));
  if (given("no-sonar")) sets.push_back("simulator.enable_sonar=false");
  if (given("active-loop-closing")) sets.push_back("exploration.active_loop_closing.enabled=true");
  sets.insert(sets.end(), args.sets.begin(), args.sets.end());
  // The whole file, then the top-level values as decided above (the flags win), then --set.
  const runtime::ExploreSetup before = setup;
  const auto top_changed = [&] {
    return setup.explorer != before.explorer || setup.localization != before.localization ||
           setup.seed != before.seed || setup.odometry_noise_scale != before.odometry_noise_scale;
  };
  if (file) {
    if (kernel::Status s = file->Read(ExploreConfigRoot(config, /*other_explorers=*/true)); !s.ok())
      return s;
    setup.explorer = before.explorer;
    setup.localization = before.localization;
    setup.seed = before.seed;
    setup.odometry_noise_scale = before.odometry_noise_scale;
  }
  if (kernel::Status s = ApplySets(ExploreConfigRoot(config), sets); !s.ok()) return s;
  if (top_changed())
    return kernel::Status::Error(
        "--set cannot change explorer, localization, seed or odometry_noise_scale: use their "
        "flags");
  setup.sonar = config->simulator.enable_sonar;
  setup.simulator = config->simulator;
  setup.slam_options = config->slam_options ? config->slam_options->Clone() : nullptr;
  setup.explorer_options = config->explorer_options ? config->explorer_options->Clone() : nullptr;
  if (kernel::Status p = setup.region.Validate(); !p.ok()) return p.Prefixed("local_region");
  exploration::ExplorerOptions checked = setup.options;
  checked.lsr_radius_m = setup.region.radius_m;
  checked.alpha = setup.region.alpha;
  if (kernel::Status p = checked.Validate(); !p.ok()) return p;
  if (setup.explorer_options) {
    if (kernel::Status p = setup.explorer_options->Validate(); !p.ok())
      return p.Prefixed("exploration." + setup.explorer);
  }
  if (kernel::Status p = config->simulator.Validate(); !p.ok()) return p.Prefixed("simulator");
  if (setup.slam_options) return setup.slam_options->Validate().Prefixed(setup.localization);
  return kernel::Status::Ok();
}

int RunExplore(const ExploreArgs& args) {
  io::FloorPlanOptions floor_plan;
  floor_plan.resolution_m_per_px = args.resolution_m_per_px;
  io::Result<sim::World> world = io::LoadValidWorld(args.world, floor_plan);
  if (!world.ok()) {
    fmt::print(stderr, "splam explore: {}\n", world.error);
    return kExitBadInput;
  }
  if (args.start.size() == 3)
    world.value->start = kernel::Pose2(args.start[0], args.start[1], args.start[2]);
  if (!world.value->start) {
    fmt::print(stderr,
               "splam explore: world '{}' has no start pose: give one with --start X,Y,THETA\n",
               args.world);
    return kExitBadInput;
  }
  if (const kernel::Status problem = world.value->Validate(); !problem.ok()) {
    fmt::print(stderr, "splam explore: --start: {}\n", problem.message());
    return kExitBadInput;
  }
  if (kernel::Status problem = io::StartProblem(args.world, floor_plan, *world.value->start);
      !problem.ok()) {
    fmt::print(stderr, "splam explore: {}\n", problem.message());
    return kExitBadInput;
  }
  ExploreConfig config;
  if (kernel::Status s = Configure(args, &config); !s.ok()) {
    fmt::print(stderr, "splam explore: {}\n", s.message());
    return kExitBadInput;
  }
  runtime::ExploreSetup& setup = config.setup;
  setup.trace_steps = args.trace;
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
  const std::string out = args.out.empty()
                              ? fmt::format("runs/explore-{}-{}", setup.explorer, world.value->name)
                              : args.out;
  CommandFiles files;
  files.inputs = {{"the world", args.world}};
  files.config_in = args.config_file;
  files.config_out = out + "/config.yaml";
  files.AddOutputs(
      out, {"report.json", "graph.svg", "graph.png", "explored.svg", "explored.png", "errors.svg",
            "errors.png", "truth.txt", "odometry.txt", "estimate.txt", "map.txt", "map.dxf",
            "loops.csv", "map.svg", "map.png", "steps.csv", "report.html"});
  if (const kernel::Status s = OutputOverwritesInput(files); !s.ok()) {
    fmt::print(stderr, "splam explore: {}\n", s.message());
    return kExitBadInput;
  }
  setup.options.stop = Interrupted;
  CatchInterrupts();
  const runtime::ExploreOutcome outcome = RunExploration(*world.value, setup);
  const WritingResults writing;  // a second signal from here on does not cut the files short
  if (!outcome.error.empty()) {
    fmt::print(stderr, "splam explore: {}\n", outcome.error);
    return kExitBadInput;
  }
  if (const kernel::Status s = CreateOutputDirectory(out); !s.ok()) {
    fmt::print(stderr, "splam explore: {}\n", s.message());
    return kExitWriteFailed;
  }
  if (kernel::Status s = io::WriteConfig(
          out + "/config.yaml", ExploreConfigRoot(&config),
          "splam explore\nrepeat with: splam explore --config " + out + "/config.yaml");
      !s.ok()) {
    fmt::print(stderr, "splam explore: {}\n", s.message());
    return kExitWriteFailed;
  }
  const exploration::ExplorationRun& run = outcome.run;
  const int nodes = static_cast<int>(run.graph.num_nodes());
  const nlohmann::json report = runtime::ExplorationReport(*world.value, setup, outcome);
  std::vector<std::string> written;
  if (kernel::Status error =
          runtime::WriteExplorationRun(*world.value, setup, outcome, report, out, &written);
      !error.ok()) {
    fmt::print(stderr, "splam explore: {}\n", error.message());
    return kExitWriteFailed;
  }
  fmt::print(
      "{} nodes, {} edges, {:.1f} m, {:.1f} s simulated, {:.1f} % of {:.0f} m^2 reachable free "
      "space explored\nterminated: {} ({})\nplanning {:.2f} ms per node, wall time {:.2f} s\n",
      nodes, run.graph.num_edges(), run.distance_m, run.time_s, 100.0 * outcome.coverage(),
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
  fmt::print("wrote {}/{{config.yaml, {}}}\n", out, fmt::join(written, ", "));
  return run.termination == exploration::Termination::kExplored ? kExitOk : kExitIncomplete;
}

}  // namespace

void AddExploreCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<ExploreArgs>();
  runtime::ExploreSetup& setup = args->setup;
  exploration::ExplorerOptions& o = setup.options;
  CLI::App* cmd = app->add_subcommand(
      "explore",
      "Explore a simulated world autonomously with SRT or REG; write the graph with its local "
      "safe regions, the explored area over time, trajectories, config.yaml and report.json into "
      "--out.");
  std::vector<std::pair<std::string, CLI::Option*>> flags;
  const auto flag = [&](const std::string& name, CLI::Option* option) {
    flags.emplace_back(name, option);
    return option;
  };
  flag("explorer", cmd->add_option("--explorer", setup.explorer,
                                   "Exploration strategy:\n" +
                                       exploration::ExplorerRegistry::Global().Describe()))
      ->check(CLI::IsMember(exploration::ExplorerRegistry::Global().Names()))
      ->capture_default_str();
  cmd->add_option("--world", args->world,
                  "Built-in world (corridor, office, office-long, office-doors, complex, loop, "
                  "curves, halls), a YAML "
                  "world file or a floor-plan image")
      ->capture_default_str();
  flag("seed", cmd->add_option("--seed", setup.seed,
                               "Seed of the simulator's noise and the explorer's random draws"))
      ->check(Seed())
      ->capture_default_str();
  cmd->add_option("--out", args->out, "Output directory (default runs/explore-<explorer>-<world>)");
  flag(
      "localization",
      cmd->add_option("--localization", setup.localization,
                      "Where the explorer believes it is: a SLAM method (the SPLAM loop), odometry "
                      "alone, or the simulator's ground truth. SLAM methods:\n" +
                          estimation::SlamRegistry::Global().Describe()))
      ->check(CLI::IsMember(runtime::LocalizationChoices()))
      ->capture_default_str();
  cmd->add_option("--config", args->config_file,
                  "YAML options (splam config print --explorer E); command-line flags override it");
  AddSetOption(cmd, &args->sets, "exploration.min_frontier_m=0.6");
  flag("odometry-noise",
       cmd->add_option("--odometry-noise", setup.odometry_noise_scale,
                       "Scale of the default odometry noise (0 = perfect odometry)"))
      ->check(OdometryNoiseScale())
      ->capture_default_str();
  flag("lsr-radius", cmd->add_option("--lsr-radius", setup.region.radius_m,
                                     "LSR radius r, m (also the topological SLAM's region)"))
      ->check(FinitePositive())
      ->capture_default_str();
  flag("alpha", cmd->add_option("--alpha", setup.region.alpha,
                                "Step alpha * r to a new node, 0 < alpha < 1"))
      ->check(FiniteRange(0.0, 1.0))
      ->capture_default_str();
  flag("max-nodes", cmd->add_option("--max-nodes", o.max_nodes, "Cap on graph nodes"))
      ->check(FinitePositive())
      ->capture_default_str();
  flag("max-time",
       cmd->add_option("--max-time", o.max_time_s, "Cap on simulated exploration time, s"))
      ->check(FinitePositive())
      ->capture_default_str();
  flag(
      "no-sonar",
      cmd->add_flag("!--no-sonar", setup.sonar,
                    "LSRs from the laser only (240 deg), without the sonar ring behind the robot"));
  flag("active-loop-closing",
       cmd->add_flag("--active-loop-closing", o.active_loop_closing.enabled,
                     "Revisit known places to close loops when the pose grows uncertain (needs "
                     "a localisation that says how uncertain it is: graph); the same as --set "
                     "exploration.active_loop_closing.enabled=true"));
  cmd->add_option("--resolution", args->resolution_m_per_px,
                  "Metres per pixel of a floor-plan image world")
      ->check(FloorPlanResolution())
      ->capture_default_str();
  AddPoseOption(cmd, "--start", &args->start,
                "Start pose X,Y,THETA (m, m, rad), e.g. for a floor-plan image, which has none; "
                "default: the world's");
  cmd->add_flag("--trace", args->trace,
                "With a SLAM localisation, also write steps.csv: every step's predicted and "
                "corrected pose, their errors against the truth and what the method's update did");
  cmd->callback([args, exit_code, flags] {
    args->given.clear();
    for (const auto& [name, option] : flags)
      if (option->count() > 0) args->given.push_back(name);
    *exit_code = RunExplore(*args);
  });
}

}  // namespace splam::apps
