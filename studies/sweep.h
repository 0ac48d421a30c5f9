#ifndef SPLAM_STUDIES_SWEEP_H_
#define SPLAM_STUDIES_SWEEP_H_

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io/sweep_grid.h"
#include "kernel/status.h"

// The engine of experiment grids (docs/sweeps.md). A sweep directory holds
//   grid.yaml            the grid, as run
//   cells.tsv            one line per cell: index, name, the splam command line
//   cells/<name>/        each cell's run directory (--out), with cell.log (its output),
//                        cell.started (host, pid, time) and, once it ended, cell.json
// A cell is one `splam` command line and nothing else: the same cells run on a local worker pool
// (RunSweepLocally) or as a Slurm job array whose tasks call `splam sweep cell` (slurm.h).
namespace splam::studies {

struct SweepCell {
  std::string name;  // "<axis>-<value>_<axis>-<value>...", unique within the grid
  std::vector<std::pair<std::string, std::string>> values;  // axis name, value label
  std::vector<std::string> args;  // after the binary, without --out: {"explore", "--seed", "3"}
};

// Every combination of the axes' values, the last axis varying fastest; a grid without axes has
// one cell, "single".
std::vector<SweepCell> GridCells(const io::Grid& grid);

struct SweepPlan {
  io::Grid grid;
  std::vector<SweepCell> cells;
};

// Writes grid.yaml and cells.tsv into `dir` (created). When `dir` already holds a plan, it must
// be the same grid: a sweep resumes, it never mixes two grids in one directory. A file that
// cannot be written sets *write_failed (when given) besides the error naming it.
kernel::Status WriteSweepPlan(const std::string& dir, const io::Grid& grid,
                              bool* write_failed = nullptr);
kernel::Result<SweepPlan> ReadSweepPlan(const std::string& dir);

std::string CellDir(const std::string& dir, const SweepCell& cell);

// What a cell recorded when its command ended (cell.json).
struct CellRecord {
  int exit_status = 0;  // 128 + N when killed by signal N
  double wall_s = 0.0;
  std::string message;  // the last line the command printed
  std::string host;
  // 0 (done) and 3 (the run stopped early, its results written: e.g. explore's `incomplete`)
  // are results; anything else is a failure.
  bool ok() const { return exit_status == 0 || exit_status == 3; }
};
// A record whose fields are missing or of other types than splam writes (a number as the
// message, a string as the wall time), or whose exit status is not in [0, 255], is none.
std::optional<CellRecord> ReadCellRecord(const std::string& cell_dir);

// The indices of the plan's cells that have no successful cell.json in `dir`: what a run (local
// or Slurm) still has to do.
std::vector<int> CellsToRun(const std::string& dir, const SweepPlan& plan);

// Runs one cell to its end in the calling process's place (`splam sweep cell`): writes
// cell.started, runs `splam_binary args --out <cell dir>` with its output in cell.log, then
// cell.json.
CellRecord RunCell(const std::string& dir, const SweepCell& cell, const std::string& splam_binary);

struct SweepProgress {
  int total = 0, done = 0, failed = 0, running = 0, skipped = 0;
  double eta_s = -1.0;  // estimated time left; -1 before the first cell ends
  std::string event;    // "<name>: ok (12.3 s)" when a cell just ended, else empty
};

// Prints progress to stdout: a status line rewritten in place on a terminal (cells done, failed,
// running, skipped, the time left), plain lines, one per finished cell, otherwise.
std::function<void(const SweepProgress&)> PrintSweepProgress();

struct SweepRunOptions {
  std::string splam_binary;
  int jobs = 0;                // cells at once; 0: one per core
  std::function<bool()> stop;  // polled; true: no new cell starts and the running ones get SIGINT
  std::function<void(const SweepProgress&)> progress;  // after every start and end
};

struct SweepRunSummary {
  int cells = 0, skipped = 0, done = 0, failed = 0, left = 0;
  int write_failed = 0;  // of the failed: cells that exited 4 (a result that could not be written)
  bool interrupted = false;
  double wall_s = 0.0;        // of the whole sweep
  double cells_wall_s = 0.0;  // the sum of the cells run now
};

// Runs every cell of the plan in `dir` that has no successful cell.json yet (finished cells are
// skipped: a sweep resumes; failed ones run again), `jobs` at once. A failed cell does not stop
// the others. Cells interrupted by `stop` leave no cell.json and run again next time.
// Fails only when `dir` holds no readable plan.
kernel::Result<SweepRunSummary> RunSweepLocally(const std::string& dir,
                                                const SweepRunOptions& options);

struct SweepStatus {
  int total = 0, done = 0, failed = 0, running = 0, pending = 0;
  std::vector<std::pair<std::string, CellRecord>> failures;  // cell name, its record
};
kernel::Result<SweepStatus> ReadSweepStatus(const std::string& dir);

}  // namespace splam::studies

#endif  // SPLAM_STUDIES_SWEEP_H_
