#include "studies/sweep_merge.h"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <functional>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>

#include "estimation/evaluation/metrics.h"
#include "io/html.h"
#include "io/plot.h"
#include "io/text.h"
#include "io/trajectory.h"
#include "kernel/version.h"
#include "runtime/run_html.h"

namespace splam::studies {

using runtime::RunFigures;
namespace {

// "a, b" of a group's axis values; "all" without any.
std::string GroupLabel(const MergedGroup& g) {
  std::string label;
  for (const auto& [axis, value] : g.values) label += (label.empty() ? "" : ", ") + value;
  return label.empty() ? "all" : label;
}

std::string Number(double v) { return fmt::format("{:.6g}", v); }

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

// The shortest end of a figure's name ("rmse_position_m", else "estimate.rmse_position_m") that
// no other of `figures` ends with: the y label of its panel.
std::string ShortName(const std::string& figure, const std::vector<std::string>& figures) {
  for (std::size_t at = figure.rfind('.'); at != std::string::npos;
       at = at == 0 ? std::string::npos : figure.rfind('.', at - 1)) {
    const std::string end = figure.substr(at + 1);
    const auto ends_so = [&](const std::string& other) {
      return other != figure && (other == end || other.ends_with("." + end));
    };
    if (std::none_of(figures.begin(), figures.end(), ends_so)) return end;
  }
  return figure;
}

// Strip plot of the figures against one axis: a panel per figure, a dot per successful cell at
// its value of the axis (spread sideways by its index in the group), the medians in red.
kernel::Status AxisPlot(const MergedSweep& m, const std::vector<std::string>& figures,
                        std::size_t axis, const std::string& path) {
  const io::GridAxis& a = m.plan.grid.axes[axis];
  io::PlotOptions options;
  options.title = fmt::format("figures against {} ({} cells)", a.name, m.cells.size());
  options.x_label = a.name;
  options.panel_height_px = 150.0;
  for (const io::GridValue& v : a.values) options.x_labels.push_back(v.label);
  std::vector<io::PlotPanel> panels;
  for (const std::string& figure : figures) {
    io::PlotSeries dots{"cells", {0.15, 0.35, 0.75}, {}, {}, false, true};
    io::PlotSeries medians{"median", {0.85, 0.1, 0.1}, {}, {}, false, true};
    for (std::size_t k = 0; k < a.values.size(); ++k) {
      std::vector<double> values;
      for (const MergedCell& c : m.cells) {
        const auto f = c.figures.find(figure);
        if (c.cell.values[axis].second != a.values[k].label || f == c.figures.end()) continue;
        values.push_back(f->second);
      }
      for (std::size_t i = 0; i < values.size(); ++i) {
        const double spread = values.size() > 1
                                  ? static_cast<double>(i) / static_cast<double>(values.size() - 1)
                                  : 0.5;
        dots.x.push_back(static_cast<double>(k) - 0.2 + 0.4 * spread);
        dots.y.push_back(values[i]);
      }
      if (!values.empty()) {
        medians.x.push_back(static_cast<double>(k));
        medians.y.push_back(StatsOf(values).median);
      }
    }
    panels.push_back({ShortName(figure, figures), {dots, medians}});
  }
  return io::SavePlot(panels, options, {path});
}

std::string RelativeTo(const std::string& path, const std::string& dir) {
  return std::filesystem::path(path).lexically_relative(dir).string();
}

void AddCellRows(const MergedSweep& m, io::HtmlPage* page) {
  std::vector<std::string> header = {"cell"};
  for (const io::GridAxis& a : m.plan.grid.axes) header.push_back(a.name);
  header.insert(header.end(), {"exit status", "wall (s)", "message", "pictures"});
  std::vector<std::vector<io::HtmlCell>> rows;
  for (const MergedCell& c : m.cells) {
    const std::string cell_dir = CellDir(m.dir, c.cell);
    const std::string rel = RelativeTo(cell_dir, m.dir);
    const bool has_report = std::filesystem::exists(cell_dir + "/report.html");
    std::vector<io::HtmlCell> row = {
        io::HtmlCell(c.cell.name, has_report ? rel + "/report.html" : rel + "/")};
    for (const auto& [axis, value] : c.cell.values) row.emplace_back(value);
    row.emplace_back(c.record ? std::to_string(c.record->exit_status) : "not run");
    row.emplace_back(c.record ? fmt::format("{:.1f}", c.record->wall_s) : "");
    row.emplace_back(c.record && !c.record->ok() ? c.record->message : "");
    std::vector<std::string> pictures;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(cell_dir, ec))
      if (entry.path().extension() == ".png") pictures.push_back(entry.path().filename().string());
    std::sort(pictures.begin(), pictures.end());
    rows.push_back(std::move(row));
    for (const std::string& p : pictures) rows.back().emplace_back(p, rel + "/" + p);
  }
  page->Table(header, rows);
}

}  // namespace

FigureStats StatsOf(std::vector<double> values) {
  FigureStats s;
  s.n = static_cast<int>(values.size());
  if (values.empty()) return s;
  std::tie(s.mean, s.std) = evaluation::MeanStd(values);
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  s.median = n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
  s.min = values.front();
  s.max = values.back();
  return s;
}

kernel::Result<MergedSweep> MergeSweep(const std::string& dir) {
  kernel::Result<SweepPlan> plan = ReadSweepPlan(dir);
  if (!plan.ok()) return kernel::Result<MergedSweep>::Fail(plan.error);
  MergedSweep m;
  m.dir = dir;
  m.plan = std::move(*plan.value);
  const io::Grid& grid = m.plan.grid;
  std::vector<bool> grouped;
  for (const io::GridAxis& a : grid.axes) {
    grouped.push_back(a.name != grid.replicate);
    if (grouped.back()) m.group_axes.push_back(a.name);
  }
  std::set<std::string> seen;
  std::map<std::vector<std::pair<std::string, std::string>>, std::size_t> group_of;
  std::vector<std::size_t> cell_group;  // per cell, its index in m.groups
  for (const SweepCell& cell : m.plan.cells) {
    MergedCell c{cell, ReadCellRecord(CellDir(dir, cell)), {}};
    if (c.record && c.record->ok()) {
      c.figures = RunFigures(CellDir(dir, cell));
      c.figures["cell.wall_s"] = c.record->wall_s;
      c.figures["cell.exit_status"] = c.record->exit_status;
      for (const auto& [name, value] : c.figures) seen.insert(name);
    }
    std::vector<std::pair<std::string, std::string>> key;
    for (std::size_t a = 0; a < cell.values.size(); ++a)
      if (grouped[a]) key.push_back(cell.values[a]);
    if (!group_of.contains(key)) {
      group_of[key] = m.groups.size();
      m.groups.push_back({key, 0, 0, 0, {}});
    }
    cell_group.push_back(group_of[key]);
    MergedGroup& g = m.groups[group_of[key]];
    ++g.cells;
    g.failed += c.record && !c.record->ok();
    g.missing += !c.record;
    m.cells.push_back(std::move(c));
  }
  if (grid.figures.empty()) {
    m.figures.assign(seen.begin(), seen.end());
  } else {
    m.figures = grid.figures;
    // A figure no finished cell reports is a misspelling (or another command's): a "-" column
    // and an empty panel would hide it. Unknowable before a cell has finished.
    std::vector<std::string> unknown;
    for (const std::string& f : seen.empty() ? std::vector<std::string>{} : grid.figures)
      if (!seen.contains(f)) unknown.push_back(f);
    if (!unknown.empty())
      return kernel::Result<MergedSweep>::Fail(fmt::format(
          "{}/grid.yaml: figures: {} {} not among the figures the cells report: {}", dir,
          fmt::join(unknown, ", "), unknown.size() == 1 ? "is" : "are", fmt::join(seen, ", ")));
  }
  for (std::size_t k = 0; k < m.groups.size(); ++k) {
    for (const std::string& figure : m.figures) {
      std::vector<double> values;
      for (std::size_t c = 0; c < m.cells.size(); ++c) {
        const auto f = m.cells[c].figures.find(figure);
        if (cell_group[c] == k && f != m.cells[c].figures.end()) values.push_back(f->second);
      }
      m.groups[k].figures[figure] = StatsOf(std::move(values));
    }
  }
  return kernel::Result<MergedSweep>::Ok(std::move(m));
}

kernel::Result<std::vector<std::string>> WriteMergedSweep(const MergedSweep& m) {
  using R = kernel::Result<std::vector<std::string>>;
  std::vector<std::string> written;
  // table.csv: one row per group and figure.
  std::string csv;
  for (const std::string& a : m.group_axes) csv += CsvField(a) + ",";
  csv += "figure,n,mean,std,median,min,max,cells,failed,not_run\n";
  for (const MergedGroup& g : m.groups) {
    for (const std::string& figure : m.figures) {
      const FigureStats& s = g.figures.at(figure);
      for (const auto& [axis, value] : g.values) csv += CsvField(value) + ",";
      csv += fmt::format("{},{},{},{},{},{},{},{},{},{}\n", CsvField(figure), s.n, Number(s.mean),
                         Number(s.std), Number(s.median), Number(s.min), Number(s.max), g.cells,
                         g.failed, g.missing);
    }
  }
  // table.md and the report's table: a row per figure, a column per group.
  std::vector<std::string> header = {"figure"};
  for (const MergedGroup& g : m.groups) header.push_back(GroupLabel(g));
  std::vector<std::vector<io::HtmlCell>> rows;
  std::string md = "|";
  for (const std::string& h : header) md += " " + h + " |";
  md += "\n|";
  for (std::size_t i = 0; i < header.size(); ++i) md += "---|";
  md += "\n";
  const auto add_row = [&](const std::string& name,
                           const std::function<std::string(const MergedGroup&)>& text) {
    rows.push_back({name});
    md += "| " + name + " |";
    for (const MergedGroup& g : m.groups) {
      rows.back().emplace_back(text(g));
      md += " " + rows.back().back().text + " |";
    }
    md += "\n";
  };
  add_row("cells (failed, not run)", [](const MergedGroup& g) {
    return fmt::format("{} ({}, {})", g.cells, g.failed, g.missing);
  });
  for (const std::string& figure : m.figures) {
    add_row(figure, [&](const MergedGroup& g) {
      const FigureStats& s = g.figures.at(figure);
      return s.n == 0
                 ? std::string("-")
                 : fmt::format("{} +- {} (median {}; {} to {}; n {})", Number(s.mean),
                               Number(s.std), Number(s.median), Number(s.min), Number(s.max), s.n);
    });
  }
  for (const auto& [name, text] : {std::pair{"table.csv", &csv}, std::pair{"table.md", &md}}) {
    if (kernel::Status error = io::WriteTextFile(m.dir + "/" + name, *text); !error.ok())
      return R::Fail(error);
    written.push_back(m.dir + "/" + name);
  }

  // report.html
  int done = 0, failed = 0, not_run = 0;
  for (const MergedCell& c : m.cells) {
    done += c.record && c.record->ok();
    failed += c.record && !c.record->ok();
    not_run += !c.record;
  }
  io::HtmlPage page("splam sweep: " + std::filesystem::path(m.dir).filename().string());
  std::string command = "splam";
  for (const std::string& w : m.plan.grid.command) command += " " + w;
  std::string axes;
  for (const std::string& a : m.group_axes) axes += (axes.empty() ? "" : ", ") + a;
  page.Paragraph(fmt::format(
      "{} cells of `{}`: {} done, {} failed, {} not run. Grouped by: {}; replicate axis: {}.",
      m.cells.size(), command, done, failed, not_run, axes.empty() ? "nothing" : axes,
      m.plan.grid.replicate.empty() ? "none" : m.plan.grid.replicate));
  page.Heading("Table");
  page.Paragraph(
      "Every figure the cells report, per group of the varied axes: mean +- standard "
      "deviation (of the population), median, range and number of cells with it.");
  page.Table(header, rows);
  page.Heading("Figures against each axis");
  // The grid's figures, else those that differ between cells.
  std::vector<std::string> plotted = m.plan.grid.figures;
  for (const std::string& figure : m.plan.grid.figures.empty() ? m.figures : plotted) {
    if (!m.plan.grid.figures.empty()) break;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const MergedCell& c : m.cells) {
      if (const auto f = c.figures.find(figure); f != c.figures.end())
        lo = std::min(lo, f->second), hi = std::max(hi, f->second);
    }
    if (lo < hi && figure != "cell.exit_status") plotted.push_back(figure);
  }
  page.Paragraph("A dot per cell (spread sideways within its value), the medians in red; " +
                 std::to_string(plotted.size()) +
                 " figures (the grid's `figures`, else those that "
                 "differ between cells).");
  for (std::size_t a = 0; a < m.plan.grid.axes.size() && !plotted.empty(); ++a) {
    const std::string path = m.dir + "/plot-" + std::to_string(a + 1) + ".svg";
    if (kernel::Status error = AxisPlot(m, plotted, a, path); !error.ok()) return R::Fail(error);
    if (kernel::Status s = page.EmbedImage(path, "figures against " + m.plan.grid.axes[a].name);
        !s.ok())
      return R::Fail(s.message());
    written.push_back(path);
  }
  page.Heading("Cells");
  AddCellRows(m, &page);
  page.Heading("Grid");
  page.Preformatted(io::GridToYaml(m.plan.grid));
  page.Heading("Version");
  page.Paragraph(
      fmt::format("Merged by splam at git commit {}; each cell's commit and options are in its "
                  "report.json and config.yaml.",
                  kernel::GitCommit()));
  if (kernel::Status s = page.Save(m.dir + "/report.html"); !s.ok()) return R::Fail(s.message());
  written.push_back(m.dir + "/report.html");
  return R::Ok(written);
}

}  // namespace splam::studies
