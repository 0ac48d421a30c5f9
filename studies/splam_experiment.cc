#include "studies/splam_experiment.h"

#include <fmt/core.h>
#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "estimation/evaluation/metrics.h"
#include "io/plot.h"
#include "kernel/angle.h"
#include "runtime/exit_status.h"
#include "runtime/json_text.h"
#include "runtime/run_html.h"
#include "sim/builtin_worlds.h"
#include "studies/experiment_trials.h"
#include "studies/sweep.h"

namespace splam::studies {

using runtime::JsonText;
using runtime::kExitBadInput;
using runtime::kExitIncomplete;
using runtime::kExitOk;
using runtime::WriteRunHtml;
namespace {

struct Strategy {
  std::string figure, explorer, method, label;
  io::Rgb color;
  // Options of the method's defaults changed, "key=value" under the method's name (empty: none).
  std::vector<std::string> set;
};

const std::vector<Strategy>& Strategies() {
  static const std::vector<Strategy> strategies = {
      {"fig19", "srt", "ekf-lines", "SRT + ekf-lines", {0.90, 0.45, 0.05}, {}},
      {"fig20", "srt", "ekf-bspline", "SRT + ekf-bspline", {0.10, 0.60, 0.25}, {}},
      {"fig21", "reg", "topological", "REG + topological", {0.10, 0.35, 0.85}, {}},
      {"fig21-paper",
       "reg",
       "topological",
       "REG + topological (paper)",
       {0.35, 0.65, 0.95},
       {"topological.prediction=odometry", "topological.correction=paper"}},
      {"graph", "reg", "graph", "REG + graph", {0.55, 0.15, 0.60}, {}},
      // The topological SLAM with the graph SLAM as its scan matcher and back end.
      {"topological-graph",
       "reg",
       "topological-graph",
       "REG + topological-graph",
       {0.85, 0.20, 0.20},
       {}},
  };
  return strategies;
}

// One trial's numbers, read from its report.json.
struct Trial {
  bool explored = false, healthy = false;
  double rmse_m = 0, max_error_m = 0, rmse_heading_deg = 0;
  double odometry_rmse_m = 0, odometry_rmse_heading_deg = 0;
  double map_size = 0;         // control points (spline maps) or landmarks (line maps)
  double map_curves = 0;       // 0 for line maps
  double map_accuracy_m = -1;  // mean distance of the map curves to the obstacles; -1: no curves
  double curves_per_obstacle = 0;  // runtime::CurvesPerObstacle; 0 for line maps
  double ms_per_step = 0, wall_s = 0, coverage_percent = 0;
  std::string map;  // the method's description
};

Trial TrialOf(const nlohmann::json& report) {
  Trial t;
  t.explored = report["termination"] == "explored";
  const nlohmann::json& e = report["trajectory_error"];
  t.rmse_m = e["estimate"]["rmse_position_m"];
  t.max_error_m = e["estimate"]["max_position_m"];
  t.rmse_heading_deg = kernel::RadToDeg(e["estimate"]["rmse_heading_rad"].get<double>());
  t.odometry_rmse_m = e["odometry"]["rmse_position_m"];
  t.odometry_rmse_heading_deg = kernel::RadToDeg(e["odometry"]["rmse_heading_rad"].get<double>());
  const nlohmann::json& slam = report["slam"];
  t.healthy = slam["healthy"];
  t.map = slam["map"]["description"];
  t.map_size = slam["map"]["size"];
  t.map_curves = slam["map"].value("curves", 0.0);
  t.map_accuracy_m = slam["map"].value("mean_distance_to_obstacles_m", -1.0);
  t.curves_per_obstacle = slam["map"].value("curves_per_obstacle", 0.0);
  t.ms_per_step = slam["ms_per_step"]["median"];
  t.wall_s = report["wall_s"];
  t.coverage_percent = 100.0 * report["coverage_fraction"].get<double>();
  return t;
}

std::string MeanStdText(const std::vector<double>& v, int digits) {
  const auto [mean, std] = evaluation::MeanStd(v);
  return fmt::format("{:.{}f} +- {:.{}f}", mean, digits, std, digits);
}

// One number of every trial.
std::vector<double> Values(const std::vector<Trial>& trials, double Trial::*field) {
  std::vector<double> out;
  for (const Trial& t : trials) out.push_back(t.*field);
  return out;
}

// The numbers summary.json keeps per trial.
const std::vector<std::pair<std::string, double Trial::*>>& SummaryFields() {
  static const std::vector<std::pair<std::string, double Trial::*>> fields = {
      {"rmse_position_m", &Trial::rmse_m},
      {"max_position_m", &Trial::max_error_m},
      {"rmse_heading_deg", &Trial::rmse_heading_deg},
      {"odometry_rmse_position_m", &Trial::odometry_rmse_m},
      {"odometry_rmse_heading_deg", &Trial::odometry_rmse_heading_deg},
      {"map_curves", &Trial::map_curves},
      {"map_size", &Trial::map_size},
      {"map_accuracy_m", &Trial::map_accuracy_m},
      {"curves_per_obstacle", &Trial::curves_per_obstacle},
      {"ms_per_step_median", &Trial::ms_per_step},
      {"wall_s", &Trial::wall_s},
      {"coverage_percent", &Trial::coverage_percent}};
  return fields;
}

// What a figure takes from a trial: its map and its errors over time.
const std::vector<std::string>& Pictures() {
  static const std::vector<std::string> pictures = {"map.svg", "map.png", "errors.svg",
                                                    "errors.png"};
  return pictures;
}

// A trial's run directory: the cell of its strategy and seed.
std::string TrialDir(const std::string& out, const Strategy& strategy, std::uint64_t seed) {
  return fmt::format("{}/cells/strategy-{}_seed-{}", out, strategy.figure, seed);
}

}  // namespace

io::Grid SplamExperimentGrid(const SplamExperimentArgs& args) {
  io::Grid grid;
  grid.command = {"explore"};
  grid.options = {{"world", args.world_name, false}};
  if (args.resolution_m_per_px != SplamExperimentArgs().resolution_m_per_px)
    grid.options.push_back({"resolution", fmt::format("{}", args.resolution_m_per_px), false});
  io::GridAxis strategy{"strategy", {}};
  for (const Strategy& s : Strategies()) {
    io::GridValue value{s.figure,
                        {{"explorer", s.explorer, false}, {"localization", s.method, false}}};
    for (const std::string& change : s.set) {
      const std::size_t equals = change.find('=');
      value.options.push_back({change.substr(0, equals), change.substr(equals + 1), true});
    }
    strategy.values.push_back(std::move(value));
  }
  grid.axes = {std::move(strategy), io::SeedAxis(args.seed, args.runs)};
  grid.figures = {"trajectory_error.estimate.rmse_position_m",
                  "trajectory_error.estimate.max_position_m",
                  "trajectory_error.estimate.rmse_heading_rad",
                  "trajectory_error.odometry.rmse_position_m",
                  "slam.map.curves",
                  "slam.map.size",
                  "slam.map.mean_distance_to_obstacles_m",
                  "slam.ms_per_step.median",
                  "wall_s",
                  "coverage_fraction",
                  "slam.healthy"};
  return grid;
}

int RunSplamExperiment(const SplamExperimentArgs& args) {
  if (const int status = RunExperimentTrials(args.out, SplamExperimentGrid(args), args.splam_binary,
                                             args.jobs, args.stop);
      status != kExitOk)
    return status;
  const sim::World& world = args.world;
  const std::vector<Strategy>& strategies = Strategies();
  std::vector<std::vector<Trial>> trials(strategies.size());
  bool all_good = true;
  for (std::size_t s = 0; s < strategies.size(); ++s) {
    for (int i = 0; i < args.runs; ++i) {
      const std::uint64_t seed = args.seed + static_cast<std::uint64_t>(i);
      const std::string dir = TrialDir(args.out, strategies[s], seed);
      const std::optional<nlohmann::json> report = TrialReport(dir);
      if (!report) return kExitBadInput;
      const Trial trial = TrialOf(*report);
      all_good &= trial.explored && trial.healthy;
      fmt::print(
          "{} seed {}: {}, {:.1f} % explored; position RMSE {:.3f} m (odometry {:.3f} m), "
          "heading {:.2f} deg; map {}; {:.1f} s wall\n",
          strategies[s].label, seed, (*report)["termination"].get<std::string>(),
          trial.coverage_percent, trial.rmse_m, trial.odometry_rmse_m, trial.rmse_heading_deg,
          trial.map, trial.wall_s);
      if (i == 0) {  // Figs. 19-21: the first seed's pictures
        if (kernel::Status error =
                CopyTrialFiles(dir, args.out, Pictures(), strategies[s].figure + "-");
            !error.ok()) {
          fmt::print(stderr, "splam experiment: {}\n", error.message());
          return kExitBadInput;
        }
      }
      trials[s].push_back(trial);
    }
  }
  std::fflush(stdout);

  for (std::size_t s = 0; s < strategies.size(); ++s) {
    // The trial with the largest position RMSE: its pictures too.
    const auto worst =
        std::max_element(trials[s].begin(), trials[s].end(),
                         [](const Trial& a, const Trial& b) { return a.rmse_m < b.rmse_m; });
    const std::string dir = TrialDir(
        args.out, strategies[s], args.seed + static_cast<std::uint64_t>(worst - trials[s].begin()));
    if (kernel::Status error =
            CopyTrialFiles(dir, args.out, Pictures(), strategies[s].figure + "-worst-");
        !error.ok()) {
      fmt::print(stderr, "splam experiment: {}\n", error.message());
      return kExitBadInput;
    }
  }

  // Fig. 22: every trial's numbers, one bar per strategy.
  const std::vector<std::pair<std::string, double Trial::*>> figure22 = {
      {"position RMSE (m)", &Trial::rmse_m},
      {"heading RMSE (deg)", &Trial::rmse_heading_deg},
      {"odometry RMSE (m)", &Trial::odometry_rmse_m},
      {"map size", &Trial::map_size},
      {"wall time (s)", &Trial::wall_s}};
  std::vector<io::PlotPanel> panels;
  for (const auto& [label, field] : figure22) {
    io::PlotPanel panel{label, {}};
    for (std::size_t s = 0; s < strategies.size(); ++s) {
      io::PlotSeries series{
          strategies[s].label, strategies[s].color, {}, Values(trials[s], field), true};
      for (int i = 0; i < args.runs; ++i) series.x.push_back(i + 1);
      panel.series.push_back(std::move(series));
    }
    panels.push_back(std::move(panel));
  }
  io::PlotOptions plot;
  plot.title =
      fmt::format("{}: SPLAM strategies, {} trials (paper 003 Fig. 22)", world.name, args.runs);
  plot.x_label = "trial";
  plot.panel_height_px = 150.0;
  if (kernel::Status error =
          io::SavePlot(panels, plot, {args.out + "/fig22.svg", args.out + "/fig22.png"});
      !error.ok()) {
    fmt::print(stderr, "splam experiment: {}\n", error.message());
    return kExitBadInput;
  }

  // The table and the summary.
  std::string table = fmt::format(
      "# SPLAM strategies in `{}` (paper 003 Figs. 19-22): {} trials each, seeds {}-{}\n\n",
      args.world_name, args.runs, args.seed, args.seed + static_cast<std::uint64_t>(args.runs) - 1);
  table +=
      "| strategy | explored | position RMSE (m) | max position error (m) | heading RMSE (deg) | "
      "odometry RMSE (m) | odometry heading RMSE (deg) | map curves | curves per obstacle | map "
      "control points or landmarks | map accuracy (m) | ms per step (median) | wall time (s) |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  nlohmann::ordered_json summary;
  summary["experiment"] = "splam (paper 003 section 4.2, Figs. 19-22)";
  summary["world"] = args.world_name;
  summary["seeds"] = {args.seed, args.seed + static_cast<std::uint64_t>(args.runs) - 1};
  for (std::size_t s = 0; s < strategies.size(); ++s) {
    const std::vector<Trial>& v = trials[s];
    int explored = 0;
    for (const Trial& t : v) explored += t.explored && t.healthy;
    const auto text = [&v](double Trial::*field, int digits) {
      return MeanStdText(Values(v, field), digits);
    };
    table +=
        fmt::format("| {} | {}/{} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
                    strategies[s].label, explored, v.size(), text(&Trial::rmse_m, 3),
                    text(&Trial::max_error_m, 3), text(&Trial::rmse_heading_deg, 2),
                    text(&Trial::odometry_rmse_m, 3), text(&Trial::odometry_rmse_heading_deg, 2),
                    v.front().map_curves > 0 ? text(&Trial::map_curves, 1) : "-",
                    v.front().map_curves > 0 ? text(&Trial::curves_per_obstacle, 2) : "-",
                    text(&Trial::map_size, 0),
                    v.front().map_accuracy_m >= 0 ? text(&Trial::map_accuracy_m, 3) : "-",
                    text(&Trial::ms_per_step, 2), text(&Trial::wall_s, 1));
    nlohmann::ordered_json& j = summary["strategies"][strategies[s].label];
    j["explorer"] = strategies[s].explorer;
    j["method"] = strategies[s].method;
    if (!strategies[s].set.empty()) j["options"] = strategies[s].set;
    j["explored_and_healthy"] = explored;
    for (const auto& [key, field] : SummaryFields()) j[key] = Values(v, field);
  }
  if (const int status =
          WriteExperimentFiles({{args.out + "/table.md", table},
                                {args.out + "/summary.json", JsonText(summary, 2) + "\n"}});
      status != kExitOk)
    return status;
  if (kernel::Status s = WriteRunHtml(
          args.out, "splam experiment splam (paper 003 Figs. 19-22) in " + args.world_name);
      !s.ok()) {
    fmt::print(stderr, "splam experiment: {}\n", s.message());
    return kExitBadInput;
  }
  fmt::print(
      "{}wrote {}/{{table.md, summary.json, report.html, fig22.png, <figure>-map.png and "
      "<figure>-errors.png "
      "(first seed) and <figure>-worst-map.png and -errors.png (largest position RMSE) for "
      "fig19, fig20, fig21, fig21-paper, graph and topological-graph, one directory per trial}}\n",
      table, args.out);
  return all_good ? kExitOk : kExitIncomplete;
}

}  // namespace splam::studies
