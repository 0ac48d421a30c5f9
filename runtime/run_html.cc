#include "runtime/run_html.h"

#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "io/html.h"
#include "io/trajectory.h"
#include "kernel/version.h"
#include "runtime/json_text.h"

namespace splam::runtime {
namespace {

void Flatten(const nlohmann::json& j, const std::string& path, std::map<std::string, double>* out) {
  if (j.is_object()) {
    for (const auto& [key, value] : j.items()) {
      if (path.empty() && (key == "options" || key == "seed")) continue;
      Flatten(value, path.empty() ? key : path + "." + key, out);
    }
  } else if (j.is_boolean()) {
    (*out)[path] = j.get<bool>() ? 1.0 : 0.0;
  } else if (j.is_number()) {
    (*out)[path] = j.get<double>();
  }
}

}  // namespace

std::map<std::string, double> RunFigures(const std::string& run_dir) {
  std::map<std::string, double> figures;
  for (const char* name : {"report.json", "summary.json"}) {
    std::ifstream in(run_dir + "/" + name);
    if (!in) continue;
    const nlohmann::json j = ReadJson(in);
    if (j.is_discarded()) continue;
    Flatten(j, "", &figures);
    break;
  }
  return figures;
}

kernel::Status WriteRunHtml(const std::string& dir, const std::string& title,
                            const std::vector<std::string>& headline) {
  io::HtmlPage page(title);
  if (!headline.empty()) page.List(headline);
  page.Paragraph(fmt::format(
      "Written by splam at git commit {}. The numbers come from {}.", kernel::GitCommit(),
      std::filesystem::exists(dir + "/report.json") ? "report.json" : "summary.json"));
  std::vector<std::string> pictures, files;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    if (!entry.is_regular_file()) continue;
    const std::string name = entry.path().filename().string();
    (entry.path().extension() == ".png" ? pictures : files).push_back(name);
  }
  // The map, the exploration graph or the simulated run first, then the plots by name.
  const auto rank = [](const std::string& name) {
    const std::vector<std::string> first = {"map.png", "graph.png", "run.png"};
    return std::find(first.begin(), first.end(), name) - first.begin();
  };
  std::sort(pictures.begin(), pictures.end(), [&](const std::string& a, const std::string& b) {
    return std::pair(rank(a), a) < std::pair(rank(b), b);
  });
  std::sort(files.begin(), files.end());
  page.Heading("Pictures");
  for (const std::string& p : pictures) page.Image(p, p);
  page.Heading("Numbers");
  std::vector<std::vector<io::HtmlCell>> rows;
  for (const auto& [name, value] : RunFigures(dir))
    rows.push_back({name, fmt::format("{:.6g}", value)});
  page.Table({"figure", "value"}, rows);
  page.Heading("Files");
  rows.clear();
  for (const std::string& f : files)
    if (f != "report.html") rows.push_back({io::HtmlCell(f, f)});
  page.Table({"file"}, rows);
  // Shown in the page when they are small; a file that failed to be written may be anything
  // (config.yaml a link to /dev/full read back without end before this bound).
  constexpr std::size_t kMaxShownBytes = std::size_t{1} << 20;
  for (const char* table_file : {"table.md", "table1.md"}) {
    std::string table;
    if (!io::ReadTextFile(dir + "/" + table_file, &table, kMaxShownBytes).ok()) continue;
    page.Heading(std::string("Table (") + table_file + ")");
    page.Preformatted(table);
  }
  std::string config;
  if (io::ReadTextFile(dir + "/config.yaml", &config, kMaxShownBytes).ok()) {
    page.Heading("Options (config.yaml)");
    page.Preformatted(config);
  }
  return page.Save(dir + "/report.html");
}

}  // namespace splam::runtime
