// splam simulate: drive the simulated robot along a route and record what it sensed.
#include <fmt/core.h>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "apps/interrupt.h"
#include "apps/output_paths.h"
#include "io/config.h"
#include "io/run_picture.h"
#include "io/simulation_log.h"
#include "io/world_file.h"
#include "kernel/angle.h"
#include "runtime/json_text.h"
#include "runtime/run_html.h"
#include "sim/ray_caster.h"
#include "sim/simulator.h"

namespace splam::apps {
namespace {

struct SimulateArgs {
  std::string world = "complex";
  std::string route = "built-in";
  std::uint64_t seed = 1;
  std::string out;
  std::string laser = "urg04lx";
  bool sonar = false;
  double odometry_noise_scale = 1.0;
  double resolution_m_per_px = 0.05;
  int max_steps = 20000;
  int scan_every = 5;
  std::string config_file;
  std::vector<std::string> sets;
  std::vector<std::string> given;  // the flags given: they override the file
};

// The document of `splam simulate --config`: the simulator and the route follower.
io::ConfigRoot SimulateConfigRoot(sim::SimulatorOptions* simulator, sim::RouteOptions* route) {
  return [simulator, route](kernel::FieldVisitor& v) {
    v.Nested("simulator", "the simulated robot and its sensors", simulator);
    v.Nested("route", "how the robot follows the route", route);
  };
}

// The simulator and route options: defaults, then the file, then the flags given and --set.
kernel::Status Configure(const SimulateArgs& args, sim::SimulatorOptions* options,
                         sim::RouteOptions* route_options) {
  const auto given = [&](const char* flag) {
    return std::find(args.given.begin(), args.given.end(), flag) != args.given.end();
  };
  if (!args.config_file.empty()) {
    const io::Result<io::ConfigFile> file = io::ConfigFile::Load(args.config_file);
    kernel::Status read = file.status();
    if (read.ok()) read = file.value->Read(SimulateConfigRoot(options, route_options));
    if (!read.ok()) return read;
  }
  if (given("laser") || args.config_file.empty()) {
    if (args.laser == "urg04lx")
      options->laser = sim::LaserOptions::Urg04lx();
    else if (args.laser == "lms200")
      options->laser = sim::LaserOptions::Lms200(0.5);
    else
      options->laser = sim::LaserOptions::Lms200(1.0);
  }
  if (given("sonar")) options->enable_sonar = args.sonar;
  if (given("odometry-noise"))
    options->odometry = sim::OdometryNoiseOptions().Scaled(args.odometry_noise_scale);
  if (given("max-steps")) route_options->max_steps = args.max_steps;
  for (const std::string& assignment : args.sets) {
    if (const kernel::Status s =
            io::SetConfigValue(SimulateConfigRoot(options, route_options), assignment);
        !s.ok())
      return s;
  }
  return kernel::Status::Ok();
}

int RunSimulate(const SimulateArgs& args) {
  io::FloorPlanOptions floor_plan;
  floor_plan.resolution_m_per_px = args.resolution_m_per_px;
  io::Result<sim::World> world = io::LoadValidWorld(args.world, floor_plan);
  if (!world.ok()) {
    fmt::print(stderr, "splam simulate: {}\n", world.error);
    return kExitBadInput;
  }

  io::Route route;
  if (args.route == "built-in") {
    if (!world.value->start || world.value->route.empty()) {
      fmt::print(stderr, "splam simulate: world '{}' has no built-in route; pass --route FILE\n",
                 args.world);
      return kExitBadInput;
    }
    route.start = *world.value->start;
    route.waypoints = world.value->route;
  } else {
    io::Result<io::Route> read = io::ReadRoute(args.route);
    if (!read.ok()) {
      fmt::print(stderr, "splam simulate: {}\n", read.error);
      return kExitBadInput;
    }
    route = *read.value;
  }

  sim::SimulatorOptions options;
  sim::RouteOptions route_options;
  if (const kernel::Status s = Configure(args, &options, &route_options); !s.ok()) {
    fmt::print(stderr, "splam simulate: {}\n", s.message());
    return kExitBadInput;
  }
  if (const kernel::Status s = kernel::FirstError(options.Validate(), route_options.Validate());
      !s.ok()) {
    fmt::print(stderr, "splam simulate: {}\n", s.message());
    return kExitBadInput;
  }

  if (kernel::Status problem = io::StartProblem(args.world, floor_plan, route.start);
      !problem.ok()) {
    fmt::print(stderr, "splam simulate: {}\n", problem.message());
    return kExitBadInput;
  }
  const sim::RayCaster caster(*world.value);
  sim::Simulator simulator(caster, options, route.start, args.seed);
  simulator.SetPeople(world.value->people);
  if (!simulator.IsFree(route.start)) {
    fmt::print(stderr,
               "splam simulate: the start pose ({}, {}) collides with an obstacle of '{}'\n",
               route.start.x(), route.start.y(), args.world);
    return kExitBadInput;
  }
  const std::string out = args.out.empty() ? "runs/simulate-" + world.value->name : args.out;
  CommandFiles files;
  files.inputs = {{"the world", args.world}, {"the route", args.route}};
  files.config_in = args.config_file;
  files.config_out = out + "/config.yaml";
  files.AddOutputs(out, {"log.clf", "truth.txt", "odometry.txt", "world.yaml", "run.svg", "run.png",
                         "summary.json", "report.html"});
  if (const kernel::Status s = OutputOverwritesInput(files); !s.ok()) {
    fmt::print(stderr, "splam simulate: {}\n", s.message());
    return kExitBadInput;
  }
  CatchInterrupts();
  int steps = 0;
  const auto progress_or_stop = [&steps, &simulator] {
    if (++steps % 500 == 0) {
      fmt::print("  {} steps, {:.0f} s simulated\n", steps, simulator.time_s());
      std::fflush(stdout);
    }
    return Interrupted();
  };
  const sim::RouteRun run =
      sim::FollowRoute(&simulator, route.waypoints, route_options, progress_or_stop);
  const WritingResults writing;  // a second signal from here on does not cut the files short

  // Write everything, also after an early stop.
  if (const kernel::Status s = CreateOutputDirectory(out); !s.ok()) {
    fmt::print(stderr, "splam simulate: {}\n", s.message());
    return kExitWriteFailed;
  }
  if (const kernel::Status s = io::WriteConfig(
          out + "/config.yaml", SimulateConfigRoot(&options, &route_options),
          "splam simulate --world " + args.world + " --seed " + std::to_string(args.seed) +
              "\nrepeat with --config " + out + "/config.yaml");
      !s.ok()) {
    fmt::print(stderr, "splam simulate: {}\n", s.message());
    return kExitWriteFailed;
  }
  const std::vector<std::string> comments = {
      " splam simulate: world " + world.value->name + ", laser " + options.laser.model + ", seed " +
          std::to_string(args.seed),
      " ODOM: noisy odometry; TRUEPOS: ground truth; ROBOTLASER1: scans (odometric poses)"};
  const io::CarmenLog log = io::MakeCarmenLog(run.frames, options, comments);
  const io::Trajectory truth = io::TrueTrajectory(log);
  const io::Trajectory odometry = io::OdometryTrajectory(log);
  io::RunPicture picture;
  picture.title = fmt::format("{} | {} | seed {} | {} scans, {:.1f} m", world.value->name,
                              options.laser.model, args.seed, run.frames.size(), run.distance_m);
  picture.world = &*world.value;
  picture.truth = truth;
  picture.odometry = odometry;
  picture.scan_points = io::ScanPointsInWorld(log, args.scan_every);
  picture.robot_radius_m = options.robot.radius_m;

  const kernel::Pose2 drift = run.frames.back().true_pose.Between(run.frames.back().odometry_pose);
  nlohmann::ordered_json summary;
  summary["world"] = world.value->name;
  summary["laser"] = options.laser.model;
  summary["seed"] = args.seed;
  summary["completed"] = run.completed;
  summary["message"] = run.message;
  summary["waypoints_reached"] = run.waypoints_reached;
  summary["waypoints"] = route.waypoints.size();
  summary["scans"] = run.frames.size();
  summary["duration_s"] = run.frames.back().time_s;
  summary["distance_m"] = run.distance_m;
  summary["final_odometry_error"] = {{"position_m", drift.translation().norm()},
                                     {"heading_rad", std::abs(drift.theta())}};
  summary["files"] = {"log.clf", "truth.txt", "odometry.txt", "world.yaml", "run.svg", "run.png"};

  std::vector<kernel::Status> errors = {
      io::WriteCarmenLog(out + "/log.clf", log),
      io::WriteTrajectory(out + "/truth.txt", truth, "ground truth of " + world.value->name),
      io::WriteTrajectory(out + "/odometry.txt", odometry, "odometry of " + world.value->name),
      io::WriteWorldFile(out + "/world.yaml", *world.value),
      io::SaveRunPicture(picture, {out + "/run.svg", out + "/run.png"}),
  };
  errors.push_back(io::WriteTextFile(out + "/summary.json", runtime::JsonText(summary, 2) + "\n"));
  errors.push_back(runtime::WriteRunHtml(out, "splam simulate: " + world.value->name + " world"));
  if (const kernel::Status e = kernel::FirstError(errors); !e.ok()) {
    fmt::print(stderr, "splam simulate: {}\n", e.message());
    return kExitWriteFailed;
  }
  fmt::print(
      "{} scans over {:.1f} s, {:.1f} m travelled, {}/{} waypoints; odometry drift at the end "
      "{:.3f} m, "
      "{:.2f} deg\nwrote {}/{{log.clf, truth.txt, odometry.txt, world.yaml, run.svg, run.png, "
      "summary.json, report.html}}\n",
      run.frames.size(), run.frames.back().time_s, run.distance_m, run.waypoints_reached,
      route.waypoints.size(), drift.translation().norm(), kernel::RadToDeg(std::abs(drift.theta())),
      out);
  if (!run.completed) {
    fmt::print(stderr, "splam simulate: the route was not completed: {}\n", run.message);
    return kExitIncomplete;
  }
  return kExitOk;
}

}  // namespace

void AddSimulateCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* cmd = app->add_subcommand("simulate",
                                      "Drive the simulated robot along a route; write a CARMEN log "
                                      "with ground truth, trajectories and "
                                      "pictures into --out.");
  cmd->add_option("--world", args->world,
                  "Built-in world (corridor, office, office-long, office-doors, complex, loop, "
                  "curves, halls), a YAML "
                  "world file or a floor-plan image")
      ->capture_default_str();
  cmd->add_option("--route", args->route,
                  "'built-in' (the world's own route) or a route file: lines 'x y', the first may "
                  "be 'x y theta'")
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "Seed of all noise; the same seed gives the same files")
      ->check(Seed())
      ->capture_default_str();
  cmd->add_option("--out", args->out, "Output directory (default runs/simulate-<world>)");
  std::vector<std::pair<std::string, CLI::Option*>> flags;
  cmd->add_option("--config", args->config_file,
                  "YAML options (the config.yaml of a run: simulator, route); flags override it");
  AddSetOption(cmd, &args->sets, "simulator.laser.noise_fraction=0.02");
  flags.emplace_back("laser", cmd->add_option("--laser", args->laser, "Laser model"));
  flags.back()
      .second->check(CLI::IsMember({"urg04lx", "lms200", "lms200-1deg"}))
      ->capture_default_str();
  flags.emplace_back(
      "sonar", cmd->add_flag("--sonar", args->sonar, "Also simulate and log the 16-sonar ring"));
  flags.emplace_back("odometry-noise",
                     cmd->add_option("--odometry-noise", args->odometry_noise_scale,
                                     "Scale of the default odometry noise (0 = perfect odometry)"));
  flags.back().second->check(OdometryNoiseScale())->capture_default_str();
  cmd->add_option("--resolution", args->resolution_m_per_px,
                  "Metres per pixel of a floor-plan image world")
      ->check(FloorPlanResolution())
      ->capture_default_str();
  flags.emplace_back("max-steps",
                     cmd->add_option("--max-steps", args->max_steps, "Cap on 0.1 s time steps"));
  flags.back().second->check(FinitePositive())->capture_default_str();
  cmd->add_option("--scan-every", args->scan_every, "Draw the points of every N-th scan")
      ->check(FinitePositive())
      ->capture_default_str();
  cmd->callback([args, exit_code, flags] {
    args->given.clear();
    for (const auto& [name, option] : flags)
      if (option->count() > 0) args->given.push_back(name);
    *exit_code = RunSimulate(*args);
  });
}

}  // namespace splam::apps
