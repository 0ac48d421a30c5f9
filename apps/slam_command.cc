// splam slam: run a SLAM method over a CARMEN log (simulated or real).
#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "apps/interrupt.h"
#include "apps/log_input.h"
#include "apps/output_paths.h"
#include "apps/run_config.h"
#include "estimation/evaluation/metrics.h"
#include "estimation/slam_state.h"
#include "io/carmen.h"
#include "io/config.h"
#include "io/relations.h"
#include "io/slam_state_file.h"
#include "io/text.h"
#include "io/world_file.h"
#include "kernel/angle.h"
#include "runtime/json_text.h"
#include "runtime/log_replay.h"
#include "runtime/slam_run.h"

namespace splam::apps {
namespace {

struct SlamArgs {
  SlamConfig config;  // method, local region, the method's options
  std::string config_file;
  std::vector<std::string> sets;
  std::string association;        // shortcut for --set <method>.association=
  double max_curve_range_m = -1;  // shortcut for --set <method>.max_curve_range_m=
  std::string log;
  std::string out;
  std::string world;
  std::string relations;  // a relations file: the relations metric goes into summary.json
  int max_scans = 0;
  bool trace = false;
  LogInput input;
  // The sensors' noise; negative: chosen from the log's laser type (runtime::SensorNoiseOf).
  runtime::SensorNoiseOverrides noise;
  bool method_given = false;
  std::string save_state;  // write the method's state here after the run
  std::string load_state;  // start from this saved state
  bool localize_only = false;
  std::vector<double> initial_pose;  // x y theta in the map's frame; empty: the log's first pose
};

// --save-state, --load-state and --localize-only on the method just made: the state read and
// loaded, the method told to keep what saving needs. Writes the problem to stderr and returns
// false on failure.
bool PrepareState(const SlamArgs& args, const std::string& method_name,
                  estimation::SlamMethod* method) {
  if (args.save_state.empty() && args.load_state.empty()) return true;
  estimation::PersistentSlam* persistent = estimation::PersistenceOf(method);
  if (persistent == nullptr) {
    fmt::print(stderr,
               "splam slam: method '{}' cannot save or load its state (the graph method can)\n",
               method_name);
    return false;
  }
  if (!args.save_state.empty()) persistent->KeepStateForSaving();
  if (args.load_state.empty()) return true;
  const io::Result<estimation::SlamState> state = io::ReadSlamState(args.load_state);
  if (!state.ok()) {
    fmt::print(stderr, "splam slam: {}\n", state.error);
    return false;
  }
  if (const kernel::Status loaded = persistent->LoadState(*state, args.localize_only);
      !loaded.ok()) {
    fmt::print(stderr, "splam slam: {}: {}\n", args.load_state, loaded.message());
    return false;
  }
  return true;
}

// The method and its options: the defaults for the log's sensors, then the configuration file,
// then the command line. Writes the problem to stderr and returns false on failure.
bool Configure(const SlamArgs& args, const io::LaserMessage& first, SlamConfig* config,
               estimation::SensorNoise* noise) {
  std::optional<io::ConfigFile> file;
  if (!args.config_file.empty()) {
    io::Result<io::ConfigFile> loaded = io::ConfigFile::Load(args.config_file);
    if (!loaded.ok()) {
      fmt::print(stderr, "splam slam: {}\n", loaded.error);
      return false;
    }
    file = std::move(*loaded.value);
  }
  config->method = args.config.method;
  if (!args.method_given && file)
    config->method = file->TopLevelString("method").value_or(config->method);
  const estimation::SlamMethodInfo* info = estimation::SlamRegistry::Global().Find(config->method);
  if (info == nullptr) {
    fmt::print(stderr, "splam slam: unknown SLAM method '{}' ({})\n", config->method,
               estimation::SlamRegistry::Global().NameList());
    return false;
  }
  *noise = runtime::SensorNoiseOf(first);
  config->options = info->default_options(*noise);
  std::vector<std::string> sets = args.sets;
  if (!args.association.empty())
    sets.push_back(config->method + ".association=" + args.association);
  if (args.max_curve_range_m >= 0)
    sets.push_back(config->method +
                   ".max_curve_range_m=" + io::FormatDouble(args.max_curve_range_m));
  // The whole file, then the method as decided above (--method wins), then --set.
  const std::string method = config->method;
  kernel::Status status = file ? file->Read(SlamConfigRoot(config)) : kernel::Status::Ok();
  config->method = method;
  if (status.ok()) status = ApplySets(SlamConfigRoot(config), sets);
  if (status.ok() && config->method != method) {
    status = kernel::Status::Error("--set method: choose the method with --method");
  }
  if (status.ok() && args.noise.any()) {
    *noise = runtime::SensorNoiseOf(first, args.noise);
    info->adapt_to_sensors(*noise, config->options.get());
  }
  if (status.ok()) status = config->options->Validate().Prefixed(config->method);
  if (!status.ok()) {
    fmt::print(stderr, "splam slam: {}\n", status.message());
    return false;
  }
  if (const kernel::Status problem = config->region.Validate(); !problem.ok()) {
    fmt::print(stderr, "splam slam: local_region: {}\n", problem.message());
    return false;
  }
  if (const kernel::Status grid = kernel::OptionsOf(config->grid).Validate(); !grid.ok()) {
    fmt::print(stderr, "splam slam: occupancy_grid: {}\n", grid.message());
    return false;
  }
  return true;
}

// Prints the run's figures; false when an error against the truth is not finite (an estimate
// that diverged): never "RMSE inf m" with a successful exit.
bool PrintSlamSummary(const std::string& label, const estimation::SlamMethod& slam,
                      const runtime::ReplayResult& run, const nlohmann::ordered_json& summary) {
  fmt::print(
      "{} scans ({:.0f} s of data) in {:.1f} s: {:.1f}x real time, {:.2f} ms per scan (median "
      "{:.2f}, slowest {:.1f}); peak memory {:.0f} MB\n",
      run.estimate.size(), run.data_s(), run.wall_s, summary["real_time_factor"].get<double>(),
      summary["time_per_scan_ms"]["mean"].get<double>(),
      summary["time_per_scan_ms"]["median"].get<double>(),
      summary["time_per_scan_ms"]["max"].get<double>(), summary["peak_memory_mb"].get<double>());
  if (run.backward_time_stamps() > 0)
    fmt::print(
        "{} scans are stamped earlier than the scan before them (not counted in the data's "
        "time span)\n",
        run.backward_time_stamps());
  fmt::print("map: {}; associations: {}\n", slam.MapDescription(),
             runtime::JsonText(summary["associations"]));
  const nlohmann::ordered_json& c = summary["consistency"];
  fmt::print(
      "self-consistency: {:.1f} % of the points of {} scans checked against other passes lie in "
      "their free space; {} scans ({:.1f} %) above {:.0f} %\n",
      100 * c["mean_contradicting"].get<double>(), c["scans_checked"].get<int>(),
      c["inconsistent_scans"].get<int>(), 100 * c["inconsistent_share"].get<double>(),
      100 * c["inconsistent_above"].get<double>());
  if (c["flagged"].get<bool>())
    fmt::print(
        "self-consistency: more than {:.0f} % of the scans contradict other passes: the map may "
        "hold a place twice or a local failure (marked in map.png, listed in consistency.csv)\n",
        100 * c["flagged_above"].get<double>());
  if (!run.truth.empty()) {
    const auto e = evaluation::CompareToTruth(run.truth, run.estimate);
    const auto o = evaluation::CompareToTruth(run.truth, run.odometry);
    if (!std::isfinite(e.rmse_position_m) || !std::isfinite(e.rmse_heading_rad)) {
      fmt::print(stderr, "splam slam: the {} estimate's error against the truth is not finite\n",
                 label);
      return false;
    }
    fmt::print(
        "position RMSE: {} {:.3f} m, odometry {:.3f} m; heading RMSE: {:.2f} deg, {:.2f} "
        "deg\n",
        label, e.rmse_position_m, o.rmse_position_m, kernel::RadToDeg(e.rmse_heading_rad),
        kernel::RadToDeg(o.rmse_heading_rad));
  }
  return true;
}

// Every file `slam` may write into its output directory (checked against its inputs first).
const std::vector<std::string> kSlamFiles = {
    "config.yaml", "trajectory.txt", "trajectory.tum", "odometry.txt",    "truth.txt",
    "truth.tum",   "map.txt",        "map.dxf",        "loops.csv",       "map.svg",
    "map.png",     "errors.svg",     "errors.png",     "consistency.csv", "map.yaml",
    "map.pgm",     "grid.png",       "steps.csv",      "summary.json",    "report.html"};

// The world to draw under the map: --world, or world.yaml beside a simulated log; none for a
// real log.
io::Result<std::optional<sim::World>> WorldToDraw(const SlamArgs& args) {
  using R = io::Result<std::optional<sim::World>>;
  std::string source = args.world;
  const std::filesystem::path beside = std::filesystem::path(args.log).parent_path() / "world.yaml";
  if (source.empty() && std::filesystem::exists(beside)) source = beside.string();
  if (source.empty()) return R::Ok(std::nullopt);
  io::Result<sim::World> w = io::LoadWorld(source);
  if (!w.ok()) return R::Fail(w.error);
  return R::Ok(std::move(w.value));
}

int RunSlam(const SlamArgs& args) {
  if (args.log.empty()) {
    fmt::print(stderr, "splam slam: no log: give one, `splam slam LOG` (a CARMEN log or a .bag)\n");
    return kExitBadInput;
  }
  const std::string out =
      args.out.empty() ? "runs/slam-" + std::filesystem::path(args.log).stem().string() : args.out;
  CommandFiles files;
  files.inputs = {{"the log", args.log},
                  {"the world", args.world},
                  {"--relations", args.relations},
                  {"--load-state", args.load_state}};
  files.config_in = args.config_file;
  files.config_out = out + "/config.yaml";
  files.outputs = {args.save_state};
  files.AddOutputs(out, kSlamFiles);
  if (const kernel::Status s = OutputOverwritesInput(files); !s.ok()) {
    fmt::print(stderr, "splam slam: {}\n", s.message());
    return kExitBadInput;
  }
  const io::CarmenReadResult read = ReadLogInput(args.log, args.input);
  if (!read.log.ok()) {
    fmt::print(stderr, "splam slam: {}\n", read.log.error);
    if (read.before_error.Lasers().empty()) return kExitBadInput;
    fmt::print(stderr,
               "splam slam: running on the {} scans before that line; the results are written "
               "and the exit status is 3\n",
               read.before_error.Lasers().size());
  }
  const bool truncated = !read.log.ok();
  const io::CarmenLog& log = truncated ? read.before_error : *read.log.value;
  const auto lasers = log.Lasers();
  if (lasers.empty()) {
    fmt::print(stderr, "splam slam: {}: the log has no laser scans\n", args.log);
    return kExitBadInput;
  }
  const io::Result<std::optional<sim::World>> world = WorldToDraw(args);
  if (!world.ok()) {
    fmt::print(stderr, "splam slam: {}\n", world.error);
    return kExitBadInput;
  }
  SlamConfig config;
  estimation::SensorNoise noise;
  if (!Configure(args, *lasers[0], &config, &noise)) return kExitBadInput;
  std::vector<evaluation::Relation> relations;
  if (!args.relations.empty()) {
    io::Result<std::vector<evaluation::Relation>> read_relations =
        io::ReadRelations(args.relations);
    if (!read_relations.ok()) {
      fmt::print(stderr, "splam slam: {}\n", read_relations.error);
      return kExitBadInput;
    }
    relations = std::move(*read_relations.value);
  }
  if (args.localize_only && args.load_state.empty()) {
    fmt::print(stderr, "splam slam: --localize-only needs --load-state (the map to localise in)\n");
    return kExitBadInput;
  }
  // The estimate starts at the first odometric pose: the map frame is the odometry frame (for
  // simulated runs, the true frame); --initial-pose places the log in a loaded map's frame.
  const kernel::Pose2 start =
      args.initial_pose.size() == 3
          ? kernel::Pose2(args.initial_pose[0], args.initial_pose[1], args.initial_pose[2])
          : lasers[0]->robot_pose;
  auto made = estimation::SlamRegistry::Global().Make(config.method, config.options.get(),
                                                      {start, config.region});
  if (!made.ok()) {
    fmt::print(stderr, "splam slam: {}\n", made.error);
    return kExitBadInput;
  }
  if (!PrepareState(args, config.method, made.value->get())) return kExitBadInput;
  if (const kernel::Status s = CreateOutputDirectory(out); !s.ok()) {
    fmt::print(stderr, "splam slam: {}\n", s.message());
    return kExitWriteFailed;
  }
  // From here a Ctrl-C stops the run with what is done written (config.yaml marks the moment).
  CatchInterrupts();
  std::vector<kernel::Status> errors = {
      io::WriteConfig(out + "/config.yaml", SlamConfigRoot(&config),
                      "splam slam " + args.log + "\nrepeat with: splam slam --config " + out +
                          "/config.yaml " + args.log)};

  runtime::SlamDriver driver(std::move(*made.value));
  driver.RecordSteps(args.trace);
  runtime::ReplayOptions replay_options;
  replay_options.max_scans = static_cast<std::size_t>(args.max_scans);
  const estimation::SlamMethod& slam = driver.method();
  replay_options.progress = [&slam](std::size_t done, std::size_t total) {
    fmt::print("  {}/{} scans, {} in the map\n", done, total, slam.MapDescription());
    std::fflush(stdout);
  };
  replay_options.stop = Interrupted;
  const runtime::ReplayResult run = runtime::ReplayLog(log, &driver, replay_options);
  const WritingResults writing;  // a second signal from here on does not cut the files short
  if (run.stopped_at) {
    fmt::print(stderr,
               "splam slam: interrupted before scan {} of {}: the results so far are written and "
               "the exit status is 3\n",
               *run.stopped_at + 1, run.scans_in_log);
  }
  if (run.failed_at) {
    fmt::print(stderr, "splam slam: the filter failed at scan {} (t = {} s): {}\n", *run.failed_at,
               run.failed_at_time_s, slam.health().message());
  }
  runtime::SlamRunFiles run_files;
  run_files.method = config.method;
  run_files.out = out;
  run_files.log = args.log;
  run_files.world = *world.value ? &**world.value : nullptr;
  if (!args.relations.empty()) run_files.relations = relations;
  run_files.relations_file = args.relations;
  run_files.grid = config.grid;
  run_files.save_state = args.save_state;
  run_files.trace = args.trace;
  run_files.noise = noise;
  run_files.read_stats = read.stats;
  if (truncated) run_files.stopped_early = read.log.error;
  const runtime::SlamRunReport report = runtime::WriteSlamRun(log, driver, run, run_files);
  errors.push_back(report.written);
  const std::string& label = report.label;
  const nlohmann::ordered_json& summary = report.summary;
  if (report.grid_error) fmt::print(stderr, "splam slam: no map.pgm: {}\n", *report.grid_error);
  if (report.relations) {
    const evaluation::RelationsError& r = *report.relations;
    if (report.scored) {
      fmt::print(
          "relations metric ({} of {} relations): translation {:.4f} +- {:.4f} m, rotation "
          "{:.3f} +- {:.3f} deg\n",
          r.used, relations.size(), r.translation_mean, r.translation_std,
          kernel::RadToDeg(r.rotation_mean), kernel::RadToDeg(r.rotation_std));
    } else {
      fmt::print(stderr, "splam slam: no relation of {} matches a time of the estimate\n",
                 args.relations);
    }
  }
  if (const kernel::Status e = kernel::FirstError(errors); !e.ok()) {
    fmt::print(stderr, "splam slam: {}\n", e.message());
    return kExitWriteFailed;
  }
  const bool finite = PrintSlamSummary(label, slam, run, summary);
  fmt::print(
      "wrote {}/{{config.yaml, trajectory.txt, trajectory.tum, odometry.txt, map.txt, map.dxf, "
      "map.svg, map.png, {}summary.json, report.html{}{}}}\n",
      out, report.grid_error ? "" : "map.yaml, map.pgm, grid.png, ",
      run.truth.empty() ? "" : ", truth.txt, truth.tum, errors.svg, errors.png",
      args.trace ? ", steps.csv" : "");
  if (!slam.healthy() || !finite || !report.scored || truncated || run.stopped_at)
    return kExitIncomplete;
  return kExitOk;
}

}  // namespace

void AddSlamCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<SlamArgs>();
  CLI::App* cmd = app->add_subcommand("slam",
                                      "Run a SLAM method over a CARMEN log; write the trajectory, "
                                      "the map, pictures, config.yaml and a summary.");
  CLI::Option* method =
      cmd->add_option("--method", args->config.method,
                      "SLAM method:\n" + estimation::SlamRegistry::Global().Describe())
          ->check(CLI::IsMember(estimation::SlamRegistry::Global().Names()))
          ->capture_default_str();
  cmd->add_option("--config", args->config_file,
                  "YAML options (splam config print --method M); command-line flags override it");
  AddSetOption(cmd, &args->sets, "topological.correction_gain=0.5");
  cmd->add_option("--association", args->association,
                  "ekf-bspline data association: pedraza (end points) or curvature (paper 000)")
      ->check(CLI::IsMember({"pedraza", "curvature"}));
  cmd->add_option("log", args->log,
                  "CARMEN log or ROS 1 bag (.bag), simulated or real (also as --log LOG)");
  cmd->add_option("--log", args->log)->group("");  // the same, by name; one entry in --help
  cmd->add_option("--max-curve-range", args->max_curve_range_m,
                  "B-spline methods: beams longer than this (metres) are not used for curves; 0 = "
                  "the laser's maximum range")
      ->check(FiniteNonNegative());
  cmd->add_option("--out", args->out, "Output directory (default runs/slam-<log>)");
  cmd->add_option("--world", args->world,
                  "World to draw under the map (default: world.yaml beside the log, if any)");
  cmd->add_option("--relations", args->relations,
                  "Relations file (Kuemmerle et al. 2009) of the log: score the estimate with the "
                  "relations metric in summary.json, as `splam eval --relations` does");
  cmd->add_option("--max-scans", args->max_scans, "Process only the first N scans (0 = all)")
      ->check(FiniteNonNegative());
  cmd->add_flag("--trace", args->trace,
                "Also write steps.csv: every step's predicted and corrected pose, their errors "
                "against the truth when the log has it, and what the method's update did");
  AddLogInputOptions(cmd, &args->input);
  cmd->add_option("--range-sigma", args->noise.range_sigma_m,
                  "Laser range noise, metres (constant part); default from the log's laser type: "
                  "3 mm for a Hokuyo URG, 1 cm for SICK and FLASER logs")
      ->check(FiniteNonNegative());
  cmd->add_option(
         "--range-sigma-fraction", args->noise.range_sigma_fraction,
         "Laser range noise, fraction of the range; default 0.01 for a Hokuyo URG, 0 otherwise")
      ->check(FiniteNonNegative());
  cmd->add_option("--odometry-noise", args->noise.odometry_noise_scale,
                  "Scale of the default odometry noise model (3 % of distance and rotation); "
                  "default 1 for simulated logs and 3 for real FLASER logs")
      ->check(OdometryNoiseScale());
  cmd->add_option("--save-state", args->save_state,
                  "After the run, write the method's map and its keyframes' scans to FILE (graph "
                  "method), for --load-state");
  cmd->add_option("--load-state", args->load_state,
                  "Start from a state saved by --save-state: go on mapping from its map, or, "
                  "with --localize-only, localise the log in it without changing it");
  cmd->add_flag("--localize-only", args->localize_only,
                "With --load-state: localise in the saved map, which stays as it is");
  cmd->add_option("--initial-pose", args->initial_pose,
                  "Where the log starts in the map's frame, x y theta (m, m, rad); default: the "
                  "log's first odometric pose (right when both logs share their odometry frame)")
      ->expected(3)
      ->check(FiniteRange(-kernel::kMaxCoordinateM, kernel::kMaxCoordinateM));
  cmd->callback([args, exit_code, method] {
    args->method_given = method->count() > 0;
    *exit_code = RunSlam(*args);
  });
}

}  // namespace splam::apps
