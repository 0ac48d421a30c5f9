#include "studies/exploration_experiment.h"

#include <fmt/core.h>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <vector>

#include "estimation/evaluation/metrics.h"
#include "io/plot.h"
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

struct Metric {
  std::string name, unit;
  double (*get)(const nlohmann::json& report);
};

const std::vector<Metric>& Metrics() {
  static const std::vector<Metric> metrics = {
      {"nodes", "", [](const nlohmann::json& r) { return r["nodes"].get<double>(); }},
      {"distance", "m", [](const nlohmann::json& r) { return r["distance_m"].get<double>(); }},
      {"time", "s", [](const nlohmann::json& r) { return r["time_s"].get<double>(); }},
      {"coverage", "%",
       [](const nlohmann::json& r) { return 100.0 * r["coverage_fraction"].get<double>(); }},
  };
  return metrics;
}

const std::vector<std::string>& Worlds() {
  static const std::vector<std::string> worlds = {"office", "office-long", "office-doors",
                                                  "complex"};
  return worlds;
}
const std::vector<std::string>& Explorers() {
  static const std::vector<std::string> explorers = {"srt", "reg"};
  return explorers;
}

std::string TrialDir(const std::string& out, const std::string& world, const std::string& explorer,
                     std::uint64_t seed) {
  return fmt::format("{}/cells/world-{}_explorer-{}_seed-{}", out, world, explorer, seed);
}

}  // namespace

io::Grid ExplorationExperimentGrid(const ExplorationExperimentArgs& args) {
  io::Grid grid;
  grid.command = {"explore"};
  grid.options = {{"localization", "ground-truth", false}};  // Fig. 18 studies exploration alone
  if (args.alpha != ExplorationExperimentArgs().alpha)
    grid.options.push_back({"alpha", fmt::format("{}", args.alpha), false});
  io::GridAxis worlds{"world", {}}, explorers{"explorer", {}};
  for (const std::string& w : Worlds()) worlds.values.push_back({w, {{"world", w, false}}});
  for (const std::string& e : Explorers())
    explorers.values.push_back({e, {{"explorer", e, false}}});
  grid.axes = {std::move(worlds), std::move(explorers), io::SeedAxis(args.seed, args.runs)};
  grid.figures = {"nodes", "distance_m", "time_s", "coverage_fraction", "wall_s"};
  return grid;
}

int RunExplorationExperiment(const ExplorationExperimentArgs& args) {
  if (const int status = RunExperimentTrials(args.out, ExplorationExperimentGrid(args),
                                             args.splam_binary, args.jobs, args.stop);
      status != kExitOk)
    return status;
  const std::vector<std::string>& explorers = Explorers();
  std::string table = fmt::format(
      "# SRT vs REG (paper 003 Fig. 18): {} trials per world, seeds {}-{}, ground-truth "
      "localisation, alpha {}\n\n",
      args.runs, args.seed, args.seed + static_cast<std::uint64_t>(args.runs) - 1, args.alpha);
  table += "| world | metric | SRT mean +- std | REG mean +- std | REG lower in |\n";
  table += "|---|---|---|---|---|\n";
  nlohmann::json summary;
  bool all_explored = true;
  for (const std::string& world_name : Worlds()) {
    std::vector<std::vector<nlohmann::json>> outcomes(explorers.size());
    for (std::size_t e = 0; e < explorers.size(); ++e) {
      for (int i = 0; i < args.runs; ++i) {
        const std::uint64_t seed = args.seed + static_cast<std::uint64_t>(i);
        const std::string dir = TrialDir(args.out, world_name, explorers[e], seed);
        std::optional<nlohmann::json> trial = TrialReport(dir);
        if (!trial) return kExitBadInput;
        nlohmann::json& report = *trial;
        all_explored &= report["termination"] == "explored";
        fmt::print("{} {} seed {}: {} nodes, {:.1f} m, {:.1f} s, {:.1f} % explored, {}\n",
                   world_name, explorers[e], seed, report["nodes"].get<int>(),
                   report["distance_m"].get<double>(), report["time_s"].get<double>(),
                   100.0 * report["coverage_fraction"].get<double>(),
                   report["termination"].get<std::string>());
        outcomes[e].push_back(std::move(report));
      }
    }
    std::vector<io::PlotPanel> panels;
    for (const Metric& metric : Metrics()) {
      io::PlotPanel panel{metric.name + (metric.unit.empty() ? "" : " (" + metric.unit + ")"), {}};
      std::vector<std::vector<double>> values(explorers.size());
      for (std::size_t e = 0; e < explorers.size(); ++e) {
        io::PlotSeries series{e == 0 ? "SRT" : "REG",
                              e == 0 ? io::Rgb{0.90, 0.45, 0.05} : io::Rgb{0.10, 0.35, 0.85},
                              {},
                              {},
                              true};
        for (int i = 0; i < args.runs; ++i) {
          values[e].push_back(metric.get(outcomes[e][static_cast<std::size_t>(i)]));
          series.x.push_back(i + 1);
          series.y.push_back(values[e].back());
        }
        panel.series.push_back(std::move(series));
      }
      int reg_lower = 0;
      for (int i = 0; i < args.runs; ++i)
        reg_lower +=
            values[1][static_cast<std::size_t>(i)] < values[0][static_cast<std::size_t>(i)];
      const auto [srt_mean, srt_std] = evaluation::MeanStd(values[0]);
      const auto [reg_mean, reg_std] = evaluation::MeanStd(values[1]);
      table +=
          fmt::format("| {} | {} | {:.1f} +- {:.1f} | {:.1f} +- {:.1f} | {}/{} |\n", world_name,
                      panel.y_label, srt_mean, srt_std, reg_mean, reg_std, reg_lower, args.runs);
      summary[world_name][metric.name] = {
          {"srt", values[0]}, {"reg", values[1]}, {"reg_lower", reg_lower}};
      panels.push_back(std::move(panel));
    }
    io::PlotOptions plot;
    plot.title =
        fmt::format("{}: SRT vs REG, {} trials (paper 003 Fig. 18)", world_name, args.runs);
    plot.x_label = "trial";
    plot.panel_height_px = 150.0;
    if (kernel::Status error = io::SavePlot(panels, plot,
                                            {fmt::format("{}/fig18-{}.svg", args.out, world_name),
                                             fmt::format("{}/fig18-{}.png", args.out, world_name)});
        !error.ok()) {
      fmt::print(stderr, "splam experiment: {}\n", error.message());
      return kExitBadInput;
    }
  }
  if (const int status =
          WriteExperimentFiles({{args.out + "/table.md", table},
                                {args.out + "/summary.json", JsonText(summary, 2) + "\n"}});
      status != kExitOk)
    return status;
  if (kernel::Status s = WriteRunHtml(args.out, "splam experiment exploration (paper 003 Fig. 18)");
      !s.ok()) {
    fmt::print(stderr, "splam experiment: {}\n", s.message());
    return kExitBadInput;
  }
  fmt::print(
      "{}wrote {}/{{table.md, summary.json, report.html, fig18-office.png, fig18-complex.png, "
      "...}}\n",
      table, args.out);
  return all_explored ? kExitOk : kExitIncomplete;
}

}  // namespace splam::studies
