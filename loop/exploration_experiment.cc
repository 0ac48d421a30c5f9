#include "loop/exploration_experiment.h"

#include <fmt/core.h>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "estimation/metrics.h"
#include "io/plot.h"
#include "loop/exit_status.h"
#include "loop/exploration_report.h"
#include "loop/run_html.h"
#include "sim/builtin_worlds.h"

namespace splam::loop {
namespace {

struct Metric {
  std::string name, unit;
  double (*get)(const ExploreOutcome&);
};

const std::vector<Metric>& Metrics() {
  static const std::vector<Metric> metrics = {
      {"nodes", "",
       [](const ExploreOutcome& o) {
         return static_cast<double>(boost::num_vertices(o.run.graph));
       }},
      {"distance", "m", [](const ExploreOutcome& o) { return o.run.distance_m; }},
      {"time", "s", [](const ExploreOutcome& o) { return o.run.time_s; }},
      {"coverage", "%", [](const ExploreOutcome& o) { return 100.0 * o.coverage(); }},
  };
  return metrics;
}

}  // namespace

int RunExplorationExperiment(const ExplorationExperimentArgs& args) {
  std::error_code ec;
  std::filesystem::create_directories(args.out, ec);
  if (ec) {
    fmt::print(stderr, "splam experiment: cannot create {}: {}\n", args.out, ec.message());
    return kExitBadInput;
  }
  const std::vector<std::string> explorers = {"srt", "reg"};
  std::string table = fmt::format(
      "# SRT vs REG (paper 003 Fig. 18): {} trials per world, seeds {}-{}, ground-truth "
      "localisation, alpha {}\n\n",
      args.runs, args.seed, args.seed + static_cast<std::uint64_t>(args.runs) - 1, args.alpha);
  table += "| world | metric | SRT mean +- std | REG mean +- std | REG lower in |\n";
  table += "|---|---|---|---|---|\n";
  nlohmann::json summary;
  bool all_explored = true;
  for (const std::string world_name : {"office", "office-long", "office-doors", "complex"}) {
    const sim::World world = *sim::BuiltinWorld(world_name);
    std::vector<std::vector<ExploreOutcome>> outcomes(explorers.size());
    for (std::size_t e = 0; e < explorers.size(); ++e) {
      for (int i = 0; i < args.runs; ++i) {
        ExploreSetup setup;
        setup.localization = "ground-truth";  // Fig. 18 studies exploration alone
        setup.explorer = explorers[e];
        setup.seed = args.seed + static_cast<std::uint64_t>(i);
        setup.options.alpha = args.alpha;
        ExploreOutcome outcome = RunExploration(world, setup);
        if (!outcome.error.empty()) {
          fmt::print(stderr, "splam experiment: {}\n", outcome.error);
          return kExitBadInput;
        }
        all_explored &= outcome.run.termination == exploration::Termination::kExplored;
        const std::string dir =
            fmt::format("{}/{}-{}-seed{}", args.out, world_name, explorers[e], setup.seed);
        std::filesystem::create_directories(dir, ec);
        std::ofstream(dir + "/report.json")
            << ExplorationReport(world, setup, outcome).dump(2) << "\n";
        if (i == 0) {
          if (std::string error = SaveExplorationPicture(
                  world, outcome,
                  fmt::format("{} | {} | seed {}", world_name, explorers[e], setup.seed),
                  {dir + "/graph.svg", dir + "/graph.png"});
              !error.empty()) {
            fmt::print(stderr, "splam experiment: {}\n", error);
            return kExitBadInput;
          }
        }
        fmt::print("{} {} seed {}: {} nodes, {:.1f} m, {:.1f} s, {:.1f} % explored, {}\n",
                   world_name, explorers[e], setup.seed, boost::num_vertices(outcome.run.graph),
                   outcome.run.distance_m, outcome.run.time_s, 100.0 * outcome.coverage(),
                   exploration::TerminationName(outcome.run.termination));
        std::fflush(stdout);
        outcomes[e].push_back(std::move(outcome));
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
      const auto [srt_mean, srt_std] = estimation::MeanStd(values[0]);
      const auto [reg_mean, reg_std] = estimation::MeanStd(values[1]);
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
    if (std::string error = io::SavePlot(panels, plot,
                                         {fmt::format("{}/fig18-{}.svg", args.out, world_name),
                                          fmt::format("{}/fig18-{}.png", args.out, world_name)});
        !error.empty()) {
      fmt::print(stderr, "splam experiment: {}\n", error);
      return kExitBadInput;
    }
  }
  std::ofstream(args.out + "/table.md") << table;
  std::ofstream(args.out + "/summary.json") << summary.dump(2) << "\n";
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

}  // namespace splam::loop
