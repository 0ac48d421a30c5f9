// splam experiment: the published experiments, reproduced on the simulator.
//
// corridor-lines (paper 001 §6): EKF-SLAM with lines and corners on a straight run of 160 steps
// through the `corridor` world, started 2.7 deg off the corridor axis, with a SICK LMS-200.
// Reports, as 001 Table 1, nine distances between mapped corners next to their true values, and
// checks the filter's consistency: the average NEES of the robot pose over the seeded runs must
// stay inside the 95 % chi-square band for at least 90 % of the steps.
#include <fmt/core.h>
#include <Eigen/LU>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "apps/bspline_experiment.h"
#include "apps/commands.h"
#include "apps/exploration_experiment.h"
#include "apps/slam_report.h"
#include "apps/splam_experiment.h"
#include "estimation/chi_square.h"
#include "estimation/ekf_line_slam.h"
#include "estimation/metrics.h"
#include "io/plot.h"
#include "io/render.h"
#include "io/run_picture.h"
#include "kernel/angle.h"
#include "loop/corridor_experiment.h"
#include "sim/builtin_worlds.h"
#include "sim/simulator.h"

namespace splam::apps {
namespace {

struct ExperimentArgs {
  std::string name = "corridor-lines";
  int runs = 0;  // 0: the experiment's default (corridor-lines 20, complex-bspline 10)
  int max_scans = 0;
  double odometry_noise_scale = 1.0;            // complex-bspline
  double max_correspondence_distance_m = 0.15;  // complex-bspline
  int steps = 160;
  double speed_mps = 1.0;
  std::uint64_t seed = 1;
  std::string out;
  bool corners = true;
  double corner_floor_m = 0.01;
  double odometry_floor = 1e-4;
  double line_floor_scale = 1.0;  // scales the line floors of 1 mm and 0.5 mrad
};

int RunCorridorLines(const ExperimentArgs& args) {
  loop::CorridorOptions options;
  options.runs = args.runs;
  options.steps = args.steps;
  options.speed_mps = args.speed_mps;
  options.seed = args.seed;
  options.corners = args.corners;
  options.corner_floor_m = args.corner_floor_m;
  options.odometry_floor = args.odometry_floor;
  options.line_floor_scale = args.line_floor_scale;
  std::filesystem::create_directories(args.out);
  const loop::CorridorResult result = loop::RunCorridorExperiment(options);
  if (!result.error.empty()) {
    fmt::print(stderr, "splam experiment: {}\n", result.error);
    return kExitIncomplete;
  }
  // Pictures of the first run.
  const sim::World world = *sim::BuiltinWorld("corridor");
  RunPicture picture;
  picture.title =
      fmt::format("corridor, LMS-200, {} steps from 2.7 deg: {} lines, {} corners (seed {})",
                  args.steps, result.lines.size(), result.corners.size(), args.seed);
  picture.world = &world;
  picture.world_color = io::Rgb{0.75, 0.75, 0.75};
  picture.truth = result.truth;
  picture.odometry = result.odometry;
  picture.estimates = {{"estimate", result.estimate}};
  DrawMap({.lines = result.lines, .corners = result.corners, .splines = {}, .spline_features = {}},
          &picture);
  for (const std::string& e :
       {SaveRunPicture(picture, {args.out + "/map.svg", args.out + "/map.png"}),
        SaveErrorPlot("corridor run, seed " + std::to_string(args.seed), result.truth,
                      {{"odometry", io::palette::kOdometry, result.odometry},
                       {"ekf-lines", io::palette::kEstimate, result.estimate}},
                      {args.out + "/errors.svg", args.out + "/errors.png"})}) {
    if (!e.empty()) {
      fmt::print(stderr, "splam experiment: {}\n", e);
      return kExitBadInput;
    }
  }
  const auto& distances = loop::CorridorDistances();
  const std::vector<std::vector<double>>& measured = result.measured;

  // Table 1.
  nlohmann::ordered_json report;
  report["experiment"] = "corridor-lines (paper 001 section 6)";
  report["runs"] = args.runs;
  report["steps"] = args.steps;
  std::string table =
      "| distance | true (m) | SLAM (m), mean +- std over runs | error (%) | mapped in runs "
      "|\n|---|---|---|---|---|\n";
  fmt::print("{}", table);
  for (std::size_t k = 0; k < distances.size(); ++k) {
    const double truth = distances[k].TrueValue();
    const std::vector<double>& v = measured[k];
    std::string row;
    if (v.empty()) {
      row = fmt::format("| {} | {:.3f} | not mapped | - | 0/{} |\n", distances[k].name, truth,
                        args.runs);
      report["distances"].push_back(
          {{"name", distances[k].name}, {"true_m", truth}, {"mapped_runs", 0}});
    } else {
      const auto [mean, std] = estimation::MeanStd(v);
      const double error = 100.0 * std::abs(mean - truth) / truth;
      row = fmt::format("| {} | {:.3f} | {:.3f} +- {:.3f} | {:.2f} | {}/{} |\n", distances[k].name,
                        truth, mean, std, error, v.size(), args.runs);
      report["distances"].push_back({{"name", distances[k].name},
                                     {"true_m", truth},
                                     {"slam_mean_m", mean},
                                     {"slam_std_m", std},
                                     {"error_percent", error},
                                     {"mapped_runs", v.size()}});
    }
    table += row;
    fmt::print("{}", row);
  }
  // Consistency.
  const double n = args.runs;
  const double lo = estimation::ChiSquareQuantile(0.025, 3 * n) / n,
               hi = estimation::ChiSquareQuantile(0.975, 3 * n) / n;
  const std::vector<double>& average = result.average_nees;
  std::vector<double> steps;
  int inside = 0;
  for (int s = 0; s <= args.steps; ++s) {
    steps.push_back(s);
    inside += average[s] >= lo && average[s] <= hi;
  }
  const double fraction = static_cast<double>(inside) / (args.steps + 1);
  double mean_final = 0, mean_odometry = 0;
  for (std::size_t i = 0; i < result.final_error_m.size(); ++i)
    mean_final += result.final_error_m[i], mean_odometry += result.final_odometry_error_m[i];
  mean_final /= n;
  mean_odometry /= n;
  report["nees"] = {
      {"band", {lo, hi}}, {"fraction_of_steps_inside", fraction}, {"passed", fraction >= 0.9}};
  report["final_position_error_m"] = {{"ekf_lines_mean", mean_final},
                                      {"odometry_mean", mean_odometry}};
  io::PlotOptions plot_options;
  plot_options.title =
      fmt::format("average NEES over {} runs; 95 % band [{:.2f}, {:.2f}]: {:.0f} % of steps inside",
                  args.runs, lo, hi, 100 * fraction);
  plot_options.x_label = "step";
  const io::PlotPanel panel{
      "NEES (3 dof)",
      {{"average NEES", io::palette::kEstimate, steps, average},
       {"95 % band", io::palette::kOdometry, {0.0, static_cast<double>(args.steps)}, {lo, lo}},
       {"", io::palette::kOdometry, {0.0, static_cast<double>(args.steps)}, {hi, hi}}}};
  if (std::string e =
          io::SavePlot({panel}, plot_options, {args.out + "/nees.svg", args.out + "/nees.png"});
      !e.empty()) {
    fmt::print(stderr, "splam experiment: {}\n", e);
    return kExitBadInput;
  }
  std::ofstream(args.out + "/table1.md") << table;
  std::ofstream(args.out + "/report.json") << report.dump(2) << "\n";
  fmt::print("average NEES inside the 95 % band [{:.2f}, {:.2f}] for {:.1f} % of {} steps ({})\n",
             lo, hi, 100 * fraction, args.steps + 1,
             fraction >= 0.9 ? "consistent" : "NOT consistent");
  fmt::print("final position error: ekf-lines {:.3f} m, odometry {:.3f} m (mean of {} runs)\n",
             mean_final, mean_odometry, args.runs);
  fmt::print(
      "wrote {}/{{table1.md, report.json, nees.svg, nees.png, map.svg, map.png, errors.svg, "
      "errors.png}}\n",
      args.out);
  return kExitOk;
}

// An experiment's arguments with the shared ones (runs, seed, out) taken from the command line
// when given, else the experiment's defaults.
template <typename Args>
Args WithCommonArgs(const ExperimentArgs& given) {
  Args args;
  args.runs = given.runs > 0 ? given.runs : args.runs;
  args.seed = given.seed;
  args.out = given.out.empty() ? args.out : given.out;
  return args;
}

}  // namespace

void AddExperimentCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<ExperimentArgs>();
  CLI::App* cmd =
      app->add_subcommand("experiment", "Reproduce a published experiment on the simulator.");
  cmd->add_option("name", args->name,
                  "Experiment: corridor-lines (paper 001 section 6), complex-bspline (paper 000 "
                  "Figs. 15-17), exploration (paper 003 Fig. 18) or splam (paper 003 Figs. "
                  "19-22: SRT + ekf-lines, SRT + ekf-bspline, REG + topological)")
      ->check(CLI::IsMember({"corridor-lines", "complex-bspline", "exploration", "splam"}))
      ->capture_default_str();
  cmd->add_option("--runs", args->runs, "Seeded runs (default: 20 corridor-lines, 10 the others)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--max-scans", args->max_scans,
                  "complex-bspline: stop each route after this many scans (0 = the whole route)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--steps", args->steps, "Steps (scans) of the straight run")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--speed", args->speed_mps, "Forward speed, m/s (0.1 s per step)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "Seed of the first run; run i uses seed + i")
      ->capture_default_str();
  cmd->add_option("--out", args->out, "Output directory (default runs/experiment-<name>)");
  cmd->add_option("--odometry-noise", args->odometry_noise_scale,
                  "complex-bspline: scale of the odometry noise (simulated and modelled)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--max-correspondence", args->max_correspondence_distance_m,
                  "complex-bspline: largest distance (m) between a beam's predicted hit and the "
                  "map point its association paired it with; large values switch the test off")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("!--no-corners", args->corners, "Use lines only, no corner landmarks");
  cmd->add_option("--line-floor-scale", args->line_floor_scale,
                  "Scale of the line noise floors (1 mm, 0.5 mrad)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--corner-floor", args->corner_floor_m, "Corner measurement noise floor, m")
      ->capture_default_str();
  cmd->add_option("--odometry-floor", args->odometry_floor,
                  "Odometry noise floors per step (m and rad)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->callback([args, exit_code] {
    if (args->name == "splam") {
      *exit_code = RunSplamExperiment(WithCommonArgs<SplamExperimentArgs>(*args));
      return;
    }
    if (args->name == "exploration") {
      *exit_code = RunExplorationExperiment(WithCommonArgs<ExplorationExperimentArgs>(*args));
      return;
    }
    if (args->name == "complex-bspline") {
      BSplineExperimentArgs b = WithCommonArgs<BSplineExperimentArgs>(*args);
      b.max_scans = args->max_scans;
      b.odometry_noise_scale = args->odometry_noise_scale;
      b.max_correspondence_distance_m = args->max_correspondence_distance_m;
      *exit_code = RunComplexBSpline(b);
      return;
    }
    ExperimentArgs a = *args;
    a.runs = a.runs > 0 ? a.runs : 20;
    a.out = a.out.empty() ? "runs/experiment-corridor-lines" : a.out;
    *exit_code = RunCorridorLines(a);
  });
}

}  // namespace splam::apps
