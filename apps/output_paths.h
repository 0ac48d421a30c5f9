#ifndef SPLAM_APPS_OUTPUT_PATHS_H_
#define SPLAM_APPS_OUTPUT_PATHS_H_

#include <string>
#include <utility>
#include <vector>

#include "kernel/status.h"

namespace splam::apps {

// What a command reads and what it will write, checked before it writes anything.
struct CommandFiles {
  // The files read, each with what it is to the command ("the log", "--relations"); empty
  // paths are left out.
  std::vector<std::pair<std::string, std::string>> inputs;
  std::vector<std::string> outputs;  // the files written; empty paths are left out
  // The --config file read and the config.yaml written: the one may be the other (a run
  // repeated where it was written renews its record), but no other output may be the config.
  std::string config_in, config_out;
  // Adds dir/name for each name (the files a command writes into its output directory).
  void AddOutputs(const std::string& dir, const std::vector<std::string>& names);
};

// Ok when no output is one of the inputs: the same file by any name (a relative path, a link,
// a hard link: std::filesystem::equivalent). Else "--save-state LOG would overwrite the log LOG"
// (bad input, exit 2): `slam LOG --save-state LOG` overwrote its log.
kernel::Status OutputOverwritesInput(const CommandFiles& files);

// Creates the output directory `dir` and its parents; else "cannot create DIR: why" (a regular
// file in its way, no permission, a full disk): a failed write, exit 4.
kernel::Status CreateOutputDirectory(const std::string& dir);

}  // namespace splam::apps

#endif  // SPLAM_APPS_OUTPUT_PATHS_H_
