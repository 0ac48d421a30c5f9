#ifndef SPLAM_STUDIES_EXPERIMENT_TRIALS_H_
#define SPLAM_STUDIES_EXPERIMENT_TRIALS_H_

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io/sweep_grid.h"
#include "kernel/status.h"

// The experiments' trials as cells of a grid (experiments/*.yaml): run on the sweep engine, read
// back from their run directories.
namespace splam::studies {

// Writes the plan of `grid` into `dir` and runs its cells there, `jobs` at once (0: one per
// core), with `splam_binary`; cells finished before are skipped. Prints progress and a summary.
// kExitOk when every cell has run; else the exit status to stop with, the problem printed:
// kExitBadInput (another grid in `dir`), kExitWriteFailed (the plan could not be written),
// kExitIncomplete (interrupted by `stop`).
int RunExperimentTrials(const std::string& dir, const io::Grid& grid,
                        const std::string& splam_binary, int jobs,
                        const std::function<bool()>& stop);

// The report.json of a trial that succeeded; nullopt, the problem printed, when it failed or
// wrote none.
std::optional<nlohmann::json> TrialReport(const std::string& cell_dir);

// Writes each (path, text) of an experiment's results: kExitOk, or kExitWriteFailed with the
// first file that could not be written printed.
int WriteExperimentFiles(const std::vector<std::pair<std::string, std::string>>& files);

// Copies each of `names` from a trial's directory to <out>/<prefix><name> (a figure of the
// experiment from one of its trials); ok, else the first error.
kernel::Status CopyTrialFiles(const std::string& cell_dir, const std::string& out,
                              const std::vector<std::string>& names,
                              const std::string& prefix = "");

}  // namespace splam::studies

#endif  // SPLAM_STUDIES_EXPERIMENT_TRIALS_H_
