#ifndef SPLAM_RUNTIME_RUN_HTML_H_
#define SPLAM_RUNTIME_RUN_HTML_H_

#include <map>
#include <string>
#include <vector>

#include "kernel/status.h"

// The report.html every run directory gets (slam, explore, simulate, the experiments) and the
// numbers sweeps merge.
namespace splam::runtime {

// The numbers a run reported: every number and boolean (as 0/1) of its report.json (else its
// summary.json), named by its path ("trajectory_error.estimate.rmse_position_m"); lists, the
// options and the seed left out. Empty when the run wrote neither file.
std::map<std::string, double> RunFigures(const std::string& run_dir);

// Writes <dir>/report.html: `title`, the run's headline figures (one line each, at the top: its
// error, how it ended), its numbers (RunFigures), its pictures (every PNG in the directory,
// linked by name), its config.yaml and the git commit of this splam. Opens in a browser without
// a network.
kernel::Status WriteRunHtml(const std::string& dir, const std::string& title,
                            const std::vector<std::string>& headline = {});

}  // namespace splam::runtime

#endif  // SPLAM_RUNTIME_RUN_HTML_H_
