#ifndef SPLAM_STUDIES_SLURM_H_
#define SPLAM_STUDIES_SLURM_H_

#include <string>
#include <vector>

#include "kernel/status.h"

// A sweep as a Slurm job array (docs/sweeps.md): task i runs cells i*K .. i*K+K-1 of the list of
// cells still to run, each with `splam sweep cell DIR INDEX`, the same command line a local worker
// runs. Nothing Slurm-specific runs inside a cell; the sweep directory must be on a filesystem
// every node sees, and the splam binary at the same path on every node.
namespace splam::studies {

struct SlurmOptions {
  std::string partition;          // --partition; empty: the cluster's default
  std::string time;               // --time per array task (e.g. "01:00:00"); empty: the partition's
  int cpus_per_task = 1;          // --cpus-per-task
  int array_chunk = 1;            // cells per array task (K)
  std::string sbatch = "sbatch";  // the submit command
  kernel::Status Validate() const;
};

// Whether `path` can go into a job script's #SBATCH lines: no control characters (a newline
// would end the comment and run the rest as a command when the job starts) and no double quotes
// (the lines quote the paths with them). The error names `what` and the path.
kernel::Status CheckScriptPath(const std::string& what, const std::string& path);
// CheckScriptPath of the sweep directory, the working directory and the binary (absolute): what
// `sweep --slurm` checks before it writes the sweep's plan.
kernel::Status CheckSlurmPaths(const std::string& dir, const std::string& splam_binary);

// The job script running `cells` cells of the sweep in `dir` (absolute paths) from `workdir`
// (where relative paths in the grid start: the directory the sweep was submitted from).
std::string SlurmScript(const std::string& dir, const std::string& splam_binary, int cells,
                        const std::string& workdir, const SlurmOptions& options);

// Writes <dir>/slurm-cells.txt (the cells to run, one index per line: array task i, cell j of its
// chunk reads line i*K+j+1) and <dir>/sweep.sbatch, submits it with `sbatch --parsable` and
// returns the job id. Errors carry sbatch's own message; paths that fail CheckSlurmPaths are
// refused before anything is written.
kernel::Result<std::string> SubmitSweepToSlurm(const std::string& dir,
                                               const std::string& splam_binary,
                                               const std::vector<int>& cells,
                                               const SlurmOptions& options);

}  // namespace splam::studies

#endif  // SPLAM_STUDIES_SLURM_H_
