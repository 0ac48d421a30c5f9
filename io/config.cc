#include "io/config.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include "io/result.h"
#include "io/text.h"
#include "io/trajectory.h"

namespace splam::io {
namespace {

std::string Quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string Number(double v) {
  if (std::isnan(v)) return ".nan";
  if (std::isinf(v)) return v > 0 ? ".inf" : "-.inf";
  return FormatDouble(v);
}

// Writes `key: value  # doc` lines, groups indented under their key.
class YamlWriter : public kernel::FieldVisitor {
 public:
  explicit YamlWriter(std::string* out) : out_(out) {}
  void Field(std::string_view key, double* v, std::string_view doc) override {
    Line(key, Number(*v), doc);
  }
  void Field(std::string_view key, int* v, std::string_view doc) override {
    Line(key, std::to_string(*v), doc);
  }
  void Field(std::string_view key, std::uint64_t* v, std::string_view doc) override {
    Line(key, std::to_string(*v), doc);
  }
  void Field(std::string_view key, bool* v, std::string_view doc) override {
    Line(key, *v ? "true" : "false", doc);
  }
  void Field(std::string_view key, std::string* v, std::string_view doc) override {
    Line(key, Quoted(*v), doc);
  }
  void Field(std::string_view key, std::vector<double>* v, std::string_view doc) override {
    std::string list = "[";
    for (std::size_t i = 0; i < v->size(); ++i) list += (i ? ", " : "") + Number((*v)[i]);
    Line(key, list + "]", doc);
  }
  void Field(std::string_view key, kernel::Pose2* v, std::string_view doc) override {
    Line(key, "[" + Number(v->x()) + ", " + Number(v->y()) + ", " + Number(v->theta()) + "]", doc);
  }
  void Choice(std::string_view key, int* index, std::initializer_list<std::string_view> choices,
              std::string_view doc) override {
    std::string names;
    for (const std::string_view c : choices) names += (names.empty() ? "" : ", ") + std::string(c);
    Line(key, Quoted(std::string(choices.begin()[*index])), std::string(doc) + " (" + names + ")");
  }
  void Group(std::string_view key, std::string_view doc,
             const std::function<void(FieldVisitor&)>& fields) override {
    *out_ +=
        indent_ + std::string(key) + ":" + (doc.empty() ? "" : "  # " + std::string(doc)) + "\n";
    indent_ += "  ";
    fields(*this);
    indent_.resize(indent_.size() - 2);
  }

 private:
  void Line(std::string_view key, const std::string& value, std::string_view doc) {
    *out_ += indent_ + std::string(key) + ": " + value +
             (doc.empty() ? "" : "  # " + std::string(doc)) + "\n";
  }
  std::string* out_;
  std::string indent_;
};

int LineOf(const YAML::Node& node) { return node.Mark().line + 1; }

// Reads the keys of one YAML map into the visited fields; the first problem is kept.
class YamlReader : public kernel::FieldVisitor {
 public:
  // `lines`: the messages name the line of the problem (false for a --set, which has none).
  YamlReader(const YAML::Node& map, std::string path, std::string prefix, bool allow_unknown,
             bool lines, kernel::Status* status)
      : map_(map),
        path_(std::move(path)),
        prefix_(std::move(prefix)),
        allow_unknown_(allow_unknown),
        lines_(lines),
        status_(status) {
    // yaml-cpp looks a key up by decoding every key of the map into a new node, so a file's
    // fields cost (fields x keys) decodings; one pass builds an index instead. As in yaml-cpp's
    // own lookup, the first of duplicate keys is the one read.
    for (const auto& entry : map_)
      if (entry.first.IsScalar()) index_.emplace(entry.first.Scalar(), entry.second);
  }

  void Field(std::string_view key, double* v, std::string_view) override {
    Scalar(
        key,
        [&](const YAML::Node& n) {
          const double d = n.as<double>();
          if (!std::isfinite(d)) return std::string("must be a finite number");
          *v = d;
          return std::string();
        },
        "a number");
  }
  void Field(std::string_view key, int* v, std::string_view) override {
    Scalar(
        key,
        [&](const YAML::Node& n) {
          *v = n.as<int>();
          return std::string();
        },
        "an integer");
  }
  void Field(std::string_view key, std::uint64_t* v, std::string_view) override {
    Scalar(
        key,
        [&](const YAML::Node& n) {
          if (n.Scalar().starts_with("-")) return std::string("must not be negative");
          *v = n.as<std::uint64_t>();
          return std::string();
        },
        "a non-negative integer");
  }
  void Field(std::string_view key, bool* v, std::string_view) override {
    Scalar(
        key,
        [&](const YAML::Node& n) {
          *v = n.as<bool>();
          return std::string();
        },
        "true or false");
  }
  void Field(std::string_view key, std::string* v, std::string_view) override {
    Scalar(
        key,
        [&](const YAML::Node& n) {
          *v = n.as<std::string>();
          return std::string();
        },
        "a string");
  }
  void Field(std::string_view key, std::vector<double>* v, std::string_view) override {
    Numbers(key, [&](std::vector<double> values) {
      *v = std::move(values);
      return std::string();
    });
  }
  void Field(std::string_view key, kernel::Pose2* v, std::string_view) override {
    Numbers(key, [&](const std::vector<double>& values) {
      if (values.size() != 3) return std::string("expected [x, y, theta]");
      *v = kernel::Pose2(values[0], values[1], values[2]);
      return std::string();
    });
  }
  void Choice(std::string_view key, int* index, std::initializer_list<std::string_view> choices,
              std::string_view) override {
    Scalar(
        key,
        [&](const YAML::Node& n) {
          const std::string value = n.as<std::string>();
          std::string names;
          int i = 0;
          for (const std::string_view c : choices) {
            if (c == value) {
              *index = i;
              return std::string();
            }
            names += (names.empty() ? "" : ", ") + std::string(c);
            ++i;
          }
          return "'" + value + "' is not one of " + names;
        },
        "a string");
  }
  void Group(std::string_view key, std::string_view,
             const std::function<void(FieldVisitor&)>& fields) override {
    const YAML::Node n = Find(key);
    if (!n || !status_->ok()) return;
    if (!n.IsMap()) return Fail(n, key, "expected a map of keys");
    YamlReader nested(n, path_, Qualified(key) + ".", allow_unknown_, lines_, status_);
    fields(nested);
    nested.CheckUnknown();
  }

  void Moved(std::string_view old_key, std::string_view new_key) override {
    const YAML::Node n = Find(old_key);
    if (n && status_->ok()) Fail(n, old_key, "this key is now " + Qualified(new_key));
  }

  // An error for the first key of the map that no field visited.
  void CheckUnknown() {
    if (allow_unknown_ || !status_->ok()) return;
    for (const auto& entry : map_) {
      if (!entry.first.IsScalar())
        return Fail(entry.first, "[...]", "a key must be a plain word, not a list or a map");
      const std::string key = entry.first.as<std::string>();
      if (!seen_.contains(key)) return Fail(entry.first, key, "unknown key");
    }
  }

 private:
  std::string Qualified(std::string_view key) const { return prefix_ + std::string(key); }
  // The value of `key`, marked as seen; an invalid node when the map has no such key.
  YAML::Node Find(std::string_view key) {
    seen_.insert(std::string(key));
    const auto it = index_.find(key);
    return it == index_.end() ? YAML::Node(YAML::NodeType::Undefined) : it->second;
  }
  void Fail(const YAML::Node& at, std::string_view key, const std::string& message) {
    if (status_->ok())
      *status_ = FileError(path_, lines_ ? LineOf(at) : 0, Qualified(key) + ": " + message);
  }
  template <class Convert>
  void Scalar(std::string_view key, Convert convert, const char* expected) {
    const YAML::Node n = Find(key);
    if (!n || !status_->ok()) return;
    if (!n.IsScalar()) return Fail(n, key, std::string("expected ") + expected);
    try {
      if (const std::string problem = convert(n); !problem.empty()) Fail(n, key, problem);
    } catch (const YAML::Exception&) {
      Fail(n, key, "'" + n.Scalar() + "' is not " + expected);
    }
  }
  template <class Use>
  void Numbers(std::string_view key, Use use) {
    const YAML::Node n = Find(key);
    if (!n || !status_->ok()) return;
    if (!n.IsSequence()) return Fail(n, key, "expected a list of numbers");
    std::vector<double> values;
    for (const YAML::Node& item : n) {
      double d = NAN;
      try {
        d = item.as<double>();
      } catch (const YAML::Exception&) {
      }
      if (!item.IsScalar() || !std::isfinite(d)) return Fail(item, key, "expected finite numbers");
      values.push_back(d);
    }
    if (const std::string problem = use(std::move(values)); !problem.empty()) Fail(n, key, problem);
  }

  YAML::Node map_;
  std::string path_, prefix_;
  bool allow_unknown_, lines_;
  kernel::Status* status_;
  std::set<std::string> seen_;
  std::map<std::string, YAML::Node, std::less<>> index_;
};

kernel::Status ReadInto(const YAML::Node& map, const std::string& path, const ConfigRoot& root,
                        bool allow_unknown, bool lines = true) {
  kernel::Status status;
  YamlReader reader(map, path, "", allow_unknown, lines, &status);
  root(reader);
  reader.CheckUnknown();
  return status;
}

}  // namespace

std::string ConfigToYaml(const ConfigRoot& root, const std::string& header) {
  std::string out;
  std::istringstream lines(header);
  for (std::string line; std::getline(lines, line);) out += "# " + OneLine(line) + "\n";
  YamlWriter writer(&out);
  root(writer);
  return out;
}

kernel::Status WriteConfig(const std::string& path, const ConfigRoot& root,
                           const std::string& header) {
  return WriteTextFile(path, ConfigToYaml(root, header));
}

struct ConfigFile::Impl {
  YAML::Node root;
  std::string path;
};

ConfigFile::ConfigFile(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ConfigFile::ConfigFile(ConfigFile&&) noexcept = default;
ConfigFile& ConfigFile::operator=(ConfigFile&&) noexcept = default;
ConfigFile::~ConfigFile() = default;

kernel::Result<ConfigFile> ConfigFile::Parse(const std::string& text, const std::string& path) {
  auto impl = std::make_unique<Impl>();
  impl->path = path;
  try {
    impl->root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    return kernel::Result<ConfigFile>::Fail(FileError(path, e.mark.line + 1, e.msg));
  }
  if (impl->root.IsNull()) impl->root = YAML::Node(YAML::NodeType::Map);  // an empty file
  if (!impl->root.IsMap())
    return kernel::Result<ConfigFile>::Fail(
        FileError(path, LineOf(impl->root), "expected a map of keys at the top"));
  return kernel::Result<ConfigFile>::Ok(ConfigFile(std::move(impl)));
}

kernel::Result<ConfigFile> ConfigFile::Load(const std::string& path) {
  std::string text;
  if (std::filesystem::is_directory(path) || !ReadTextFile(path, &text).ok())
    return kernel::Result<ConfigFile>::Fail(FileError(path, 0, "cannot read the file"));
  return Parse(text, path);
}

std::optional<std::string> ConfigFile::TopLevelString(const std::string& key) const {
  const YAML::Node n = impl_->root[key];
  if (!n || !n.IsScalar()) return std::nullopt;
  return n.Scalar();
}

kernel::Status ConfigFile::Read(const ConfigRoot& root, bool allow_unknown) const {
  return ReadInto(impl_->root, impl_->path, root, allow_unknown);
}

kernel::Status SetConfigValue(const ConfigRoot& root, const std::string& assignment) {
  const std::size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    return kernel::Status::Error("--set " + assignment + ": expected key=value");
  // key.sub=value as the YAML map {key: {sub: value}}, read like a file.
  const std::string key = assignment.substr(0, eq);
  YAML::Node value;
  try {
    value = YAML::Load(assignment.substr(eq + 1));
  } catch (const YAML::Exception&) {
    value = YAML::Node(assignment.substr(eq + 1));
  }
  YAML::Node map(YAML::NodeType::Map);
  std::vector<std::string> parts;
  for (std::size_t begin = 0; begin <= key.size();) {
    const std::size_t dot = std::min(key.find('.', begin), key.size());
    parts.push_back(key.substr(begin, dot - begin));
    begin = dot + 1;
  }
  YAML::Node leaf = value;
  for (auto it = parts.rbegin(); it != parts.rend(); ++it) {
    YAML::Node level(YAML::NodeType::Map);
    level[*it] = leaf;
    leaf = level;
  }
  return ReadInto(leaf, "--set", root, /*allow_unknown=*/false, /*lines=*/false);
}

}  // namespace splam::io
