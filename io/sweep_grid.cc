#include "io/sweep_grid.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <iomanip>
#include <set>
#include <sstream>

#include "io/text.h"
#include "io/trajectory.h"

namespace splam::io {
namespace {

constexpr int kMaxRangeValues = 100000;
constexpr int kMaxCells = 1000000;
constexpr char kSetPrefix[] = "set.";

int LineOf(const YAML::Node& node) { return node.Mark().line + 1; }

// Reading fails by throwing this; ParseGrid turns it into "path:line: message".
struct GridError {
  int line;
  std::string message;
};
[[noreturn]] void Fail(const YAML::Node& at, const std::string& message) {
  throw GridError{LineOf(at), message};
}

// A value becomes one argument of a cell's command line and one field of cells.tsv: a tab or a
// line break in it would read back as more (a `log:` value "small.clf\t--method\tgraph" ran
// graph).
void CheckPlain(const YAML::Node& node, const std::string& what, const std::string& text) {
  for (const char c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      Fail(node, what + " must not hold a tab, a line break or another control character");
}

std::string Scalar(const YAML::Node& node, const std::string& what) {
  if (!node.IsScalar()) Fail(node, what + " must be a single value, not a list or a map");
  CheckPlain(node, what, node.Scalar());
  return node.Scalar();
}

// A map's key: a plain word (YAML allows lists and maps as keys; their Scalar() is empty).
std::string Key(const YAML::Node& key) {
  if (!key.IsScalar()) Fail(key, "a key must be a plain word, not a list or a map");
  CheckPlain(key, "a key", key.Scalar());
  return key.Scalar();
}

// The option `key` (`set.KEY` for a --set value) with the scalar `value`.
GridOption OptionOf(const std::string& key, const YAML::Node& value) {
  GridOption option;
  const std::string text = Scalar(value, key);
  if (key.starts_with(kSetPrefix)) {
    option.name = key.substr(sizeof(kSetPrefix) - 1);
    option.set = true;
    option.value = text;
    if (option.name.empty()) Fail(value, "'set.' needs the key of a --set value after it");
    return option;
  }
  option.name = key;
  option.value = text;
  return option;
}

// The numbers from `from` to `to` (inclusive) by `step`, written as the shortest text (integers
// without a decimal point).
std::vector<GridValue> RangeValues(const std::string& axis, const YAML::Node& node) {
  const auto number = [&](const char* key, std::optional<double> fallback) {
    const YAML::Node n = node[key];
    if (!n) {
      if (!fallback) Fail(node, axis + ": a range needs '" + key + "'");
      return *fallback;
    }
    const std::optional<double> v = ParseDouble(Scalar(n, axis + "." + key));
    if (!v || !std::isfinite(*v)) Fail(n, axis + "." + key + " is not a finite number");
    return *v;
  };
  for (const auto& entry : node) {
    const std::string key = Key(entry.first);
    if (key != "from" && key != "to" && key != "step")
      Fail(entry.first, axis + ": a range has from, to and step, not '" + key + "'");
  }
  const double from = number("from", std::nullopt), to = number("to", std::nullopt);
  const double step = number("step", 1.0);
  if (!(step > 0.0)) Fail(node, axis + ": the step of a range must be above 0");
  if (to < from) Fail(node, axis + ": a range's 'to' is below its 'from'");
  if ((to - from) / step >= kMaxRangeValues)
    Fail(node, axis + ": a range of more than " + std::to_string(kMaxRangeValues) + " values");
  std::vector<GridValue> values;
  const long n = std::lround(std::floor((to - from) / step + 1e-9));
  for (long i = 0; i <= n; ++i) {
    const double v = from + static_cast<double>(i) * step;
    std::ostringstream text;
    text.precision(12);
    text << v;  // %g with 12 digits: 0.30000000000000004 is written 0.3
    YAML::Node scalar(text.str());
    values.push_back({text.str(), {OptionOf(axis, scalar)}});
  }
  return values;
}

GridAxis AxisOf(const std::string& name, const YAML::Node& node) {
  GridAxis axis{name, {}};
  if (node.IsMap()) {
    axis.values = RangeValues(name, node);
  } else if (node.IsSequence()) {
    std::set<std::string> labels;
    for (const YAML::Node& v : node) {
      GridValue value;
      if (v.IsMap()) {  // a bundle
        if (!v["name"]) Fail(v, name + ": a value that sets several options needs a 'name'");
        value.label = Scalar(v["name"], name + ".name");
        for (const auto& entry : v) {
          const std::string key = Key(entry.first);
          if (key != "name") value.options.push_back(OptionOf(key, entry.second));
        }
      } else {
        value.label = Scalar(v, name);
        value.options.push_back(OptionOf(name, v));
      }
      if (!labels.insert(value.label).second)
        Fail(v, name + ": the value '" + value.label + "' is given twice");
      axis.values.push_back(std::move(value));
    }
  } else {
    Fail(node, name + ": an axis is a list of values or a range {from, to, step}");
  }
  if (axis.values.empty()) Fail(node, name + ": an axis without values");
  return axis;
}

Grid GridOf(const YAML::Node& root) {
  if (!root.IsMap()) Fail(root, "a grid is a map with command, options, set and axes");
  Grid grid;
  for (const auto& entry : root) {
    const std::string key = Key(entry.first);
    const YAML::Node& v = entry.second;
    if (key == "command") {
      std::istringstream words(Scalar(v, "command"));
      for (std::string w; words >> w;) grid.command.push_back(w);
    } else if (key == "options" || key == "set") {
      if (!v.IsMap() && !v.IsNull()) Fail(v, key + " is a map of option names to values");
      for (const auto& option : v)
        grid.options.push_back(
            OptionOf((key == "set" ? kSetPrefix : "") + Key(option.first), option.second));
    } else if (key == "axes") {
      if (!v.IsMap()) Fail(v, "axes is a map of axis names to values");
      std::set<std::string> names;
      for (const auto& axis : v) {
        const std::string name = Key(axis.first);
        if (!names.insert(name).second) Fail(axis.first, "the axis '" + name + "' is given twice");
        grid.axes.push_back(AxisOf(name, axis.second));
      }
    } else if (key == "replicate") {
      grid.replicate = v.IsNull() ? "" : Scalar(v, "replicate");
    } else if (key == "figures") {
      if (!v.IsSequence()) Fail(v, "figures is a list of figure names");
      for (const YAML::Node& f : v) grid.figures.push_back(Scalar(f, "figures"));
    } else {
      Fail(entry.first, "unknown key '" + key +
                            "' (a grid has command, options, set, axes, replicate, figures)");
    }
  }
  if (grid.command.empty()) Fail(root, "a grid needs a command (slam, explore, experiment NAME)");
  // A cell runs one splam command that writes figures; `sweep` would start sweeps of itself.
  static const std::set<std::string> kCommands = {"slam", "explore", "simulate", "experiment"};
  if (!kCommands.contains(grid.command.front()))
    Fail(root["command"], "a cell runs slam, explore, simulate or experiment NAME, not '" +
                              grid.command.front() + "'");
  double cells = 1;
  for (const GridAxis& a : grid.axes) cells *= static_cast<double>(a.values.size());
  if (cells > kMaxCells) {
    std::ostringstream message;
    message << "the axes make " << std::fixed << std::setprecision(0) << cells
            << " cells, more than " << kMaxCells << " (split the grid)";
    Fail(root["axes"], message.str());
  }
  if (!grid.replicate.empty()) {
    bool found = false;
    for (const GridAxis& a : grid.axes) found = found || a.name == grid.replicate;
    // The default names an axis only when the grid has one of that name.
    if (!found && root["replicate"])
      Fail(root["replicate"], "replicate names no axis: '" + grid.replicate + "'");
    if (!found) grid.replicate.clear();
  }
  return grid;
}

std::string KeyOf(const GridOption& o) { return (o.set ? kSetPrefix : "") + o.name; }

}  // namespace

Result<Grid> ParseGrid(const std::string& text, const std::string& path) {
  try {
    return Result<Grid>::Ok(GridOf(YAML::Load(text.substr(TextStart(text)))));
  } catch (const GridError& e) {
    return Result<Grid>::Fail(FileError(path, e.line, e.message));
  } catch (const YAML::Exception& e) {
    return Result<Grid>::Fail(FileError(path, e.mark.line + 1, e.msg));
  }
}

Result<Grid> ReadGrid(const std::string& path) {
  std::string text;
  if (kernel::Status error = ReadTextFile(path, &text); !error.ok())
    return Result<Grid>::Fail(error);
  return ParseGrid(text, path);
}

GridAxis SeedAxis(std::uint64_t first, int count) {
  GridAxis seeds{"seed", {}};
  for (int i = 0; i < count; ++i) {
    const std::string seed = std::to_string(first + static_cast<std::uint64_t>(i));
    seeds.values.push_back({seed, {{"seed", seed, false}}});
  }
  return seeds;
}

std::string GridToYaml(const Grid& grid) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  std::string command;
  for (const std::string& w : grid.command) command += (command.empty() ? "" : " ") + w;
  out << YAML::Key << "command" << YAML::Value << command;
  for (const bool set : {false, true}) {
    bool any = false;
    for (const GridOption& o : grid.options) any = any || o.set == set;
    if (!any) continue;
    out << YAML::Key << (set ? "set" : "options") << YAML::Value << YAML::BeginMap;
    for (const GridOption& o : grid.options)
      if (o.set == set) out << YAML::Key << o.name << YAML::Value << o.value;
    out << YAML::EndMap;
  }
  out << YAML::Key << "axes" << YAML::Value << YAML::BeginMap;
  for (const GridAxis& axis : grid.axes) {
    out << YAML::Key << axis.name << YAML::Value << YAML::BeginSeq;
    for (const GridValue& v : axis.values) {
      const bool plain = v.options.size() == 1 && KeyOf(v.options[0]) == axis.name &&
                         (v.options[0].value == v.label);
      if (plain) {
        out << v.options[0].value;
        continue;
      }
      out << YAML::Flow << YAML::BeginMap << YAML::Key << "name" << YAML::Value << v.label;
      for (const GridOption& o : v.options) out << YAML::Key << KeyOf(o) << YAML::Value << o.value;
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
  }
  out << YAML::EndMap;
  out << YAML::Key << "replicate" << YAML::Value;
  if (grid.replicate.empty()) {
    out << YAML::Null;
  } else {
    out << grid.replicate;
  }
  if (!grid.figures.empty()) out << YAML::Key << "figures" << YAML::Value << grid.figures;
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace splam::io
