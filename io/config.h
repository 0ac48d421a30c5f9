#ifndef SPLAM_IO_CONFIG_H_
#define SPLAM_IO_CONFIG_H_

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "kernel/options.h"
#include "kernel/status.h"

// Options structs as YAML: their VisitFields lists become keys (the field names), values and
// comments (unit and meaning). A configuration document is described by one function that visits
// its top-level keys (a "root"); the same function writes it, reads it and applies
// `key.sub=value` overrides, so the three can never disagree.
namespace splam::io {

using ConfigRoot = std::function<void(kernel::FieldVisitor&)>;

// The document `root` describes, every key with its value and comment, under `header` (comment
// lines). Doubles are written so that they read back exactly: a run's config.yaml repeats it.
std::string ConfigToYaml(const ConfigRoot& root, const std::string& header);
// Writes ConfigToYaml to `path`; an error names the file.
kernel::Status WriteConfig(const std::string& path, const ConfigRoot& root,
                           const std::string& header);

// A parsed YAML configuration file.
class ConfigFile {
 public:
  // "path:line: ..." when the file cannot be read or is not YAML with a map at its top.
  static kernel::Result<ConfigFile> Load(const std::string& path);
  static kernel::Result<ConfigFile> Parse(const std::string& text, const std::string& path);
  ConfigFile(ConfigFile&&) noexcept;
  ConfigFile& operator=(ConfigFile&&) noexcept;
  ~ConfigFile();

  // The string at top-level `key`, if the file has one (before the whole document is read:
  // e.g. the method, which decides what the rest of the document holds).
  std::optional<std::string> TopLevelString(const std::string& key) const;
  // Reads every key the file has into the fields `root` visits. The first problem comes back as
  // "path:line: key.sub: what is wrong": an unknown key (unless allow_unknown), a wrong type, a
  // value out of an enum's choices. Fields the file does not name keep their values.
  kernel::Status Read(const ConfigRoot& root, bool allow_unknown = false) const;

 private:
  struct Impl;
  explicit ConfigFile(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// Applies "key.sub=value" (a command-line override) to the field `root` visits under that key;
// an error names the key when no field has it or the value has the wrong type.
kernel::Status SetConfigValue(const ConfigRoot& root, const std::string& assignment);

}  // namespace splam::io

#endif  // SPLAM_IO_CONFIG_H_
