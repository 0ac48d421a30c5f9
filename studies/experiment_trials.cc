#include "studies/experiment_trials.h"

#include <fmt/core.h>

#include <filesystem>
#include <fstream>

#include "io/trajectory.h"
#include "runtime/exit_status.h"
#include "runtime/json_text.h"
#include "studies/sweep.h"

namespace splam::studies {

using runtime::kExitBadInput;
using runtime::kExitIncomplete;
using runtime::kExitOk;
using runtime::kExitWriteFailed;
using runtime::ReadJson;

int RunExperimentTrials(const std::string& dir, const io::Grid& grid,
                        const std::string& splam_binary, int jobs,
                        const std::function<bool()>& stop) {
  bool write_failed = false;
  if (kernel::Status s = WriteSweepPlan(dir, grid, &write_failed); !s.ok()) {
    fmt::print(stderr, "splam experiment: {}\n", s.message());
    return write_failed ? kExitWriteFailed : kExitBadInput;
  }
  SweepRunOptions options;
  options.splam_binary = splam_binary;
  options.jobs = jobs;
  options.stop = stop;
  options.progress = PrintSweepProgress();
  const kernel::Result<SweepRunSummary> run = RunSweepLocally(dir, options);
  if (!run.ok()) {
    fmt::print(stderr, "splam experiment: {}\n", run.error);
    return kExitBadInput;
  }
  const SweepRunSummary& r = *run.value;
  fmt::print("\n{} trials: {} run now in {:.1f} s wall for {:.1f} s of trials, {} done before\n",
             r.cells, r.done + r.failed, r.wall_s, r.cells_wall_s, r.skipped);
  if (r.interrupted) {
    fmt::print("interrupted: the {} trials left run when the same command is given again\n",
               r.left);
    return kExitIncomplete;
  }
  return kExitOk;
}

std::optional<nlohmann::json> TrialReport(const std::string& cell_dir) {
  const std::optional<CellRecord> record = ReadCellRecord(cell_dir);
  std::ifstream in(cell_dir + "/report.json");
  nlohmann::json report = ReadJson(in);
  if (!record || !record->ok() || report.is_discarded()) {
    fmt::print(stderr, "splam experiment: the trial in {} failed: {}\n", cell_dir,
               record ? record->message : "it has no result");
    return std::nullopt;
  }
  return report;
}

kernel::Status CopyTrialFiles(const std::string& cell_dir, const std::string& out,
                              const std::vector<std::string>& names, const std::string& prefix) {
  for (const std::string& name : names) {
    std::error_code ec;
    std::filesystem::copy_file(cell_dir + "/" + name, out + "/" + prefix + name,
                               std::filesystem::copy_options::overwrite_existing, ec);
    if (ec)
      return kernel::Status::Error(
          fmt::format("cannot copy {}/{}: {}", cell_dir, name, ec.message()));
  }
  return {};
}

int WriteExperimentFiles(const std::vector<std::pair<std::string, std::string>>& files) {
  for (const auto& [path, text] : files) {
    if (kernel::Status error = io::WriteTextFile(path, text); !error.ok()) {
      fmt::print(stderr, "splam experiment: {}\n", error.message());
      return kExitWriteFailed;
    }
  }
  return kExitOk;
}

}  // namespace splam::studies
