#include "apps/output_paths.h"

#include <filesystem>

#include "io/text.h"

namespace splam::apps {

void CommandFiles::AddOutputs(const std::string& dir, const std::vector<std::string>& names) {
  for (const std::string& name : names)
    outputs.push_back((std::filesystem::path(dir) / name).string());
}

kernel::Status OutputOverwritesInput(const CommandFiles& files) {
  std::vector<std::string> outputs = files.outputs;
  outputs.push_back(files.config_out);
  std::vector<std::pair<std::string, std::string>> inputs = files.inputs;
  inputs.emplace_back("--config", files.config_in);
  for (const std::string& output : outputs) {
    if (output.empty()) continue;
    for (const auto& [what, input] : inputs) {
      std::error_code error;  // a path that does not exist yet is no input
      if (input.empty() || (input == files.config_in && output == files.config_out) ||
          !std::filesystem::equivalent(output, input, error))
        continue;
      return kernel::Status::Error(io::Quoted(output) + " would overwrite " + what + " " +
                                   io::Quoted(input) +
                                   ": give the results another path (nothing was written)");
    }
  }
  return {};
}

kernel::Status CreateOutputDirectory(const std::string& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) return kernel::Status::Error("cannot create " + dir + ": " + error.message());
  return {};
}

}  // namespace splam::apps
