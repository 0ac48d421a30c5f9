// A parameter study from C++: the REG explorer's LSR step alpha against coverage and distance,
// three seeds each, run as a sweep on all cores and merged. What `splam sweep GRID.yaml` does,
// through the library (docs/sweeps.md).
//
// Usage: example_sweep SPLAM_BINARY [OUT_DIR]
#include <fmt/core.h>
#include <fmt/format.h>

#include <string>

#include "io/sweep_grid.h"
#include "studies/sweep.h"
#include "studies/sweep_merge.h"

int main(int argc, char** argv) {
  using namespace splam;
  if (argc < 2) {
    fmt::print(stderr, "usage: {} SPLAM_BINARY [OUT_DIR]\n", argv[0]);
    return 2;
  }
  const std::string splam_binary = argv[1];
  const std::string dir = argc > 2 ? argv[2] : "runs/example-sweep";

  // 1. The grid, as a YAML file would give it: a command, fixed options and the axes. Each cell
  //    is one `splam explore` run; the seed is the replicate axis (merged into mean +- std).
  const io::Result<io::Grid> grid = io::ParseGrid(R"(
command: explore
options: {world: corridor, localization: ground-truth, max-time: 120}
axes:
  set.local_region.alpha: [0.6, 0.8]
  seed: {from: 1, to: 3}
figures: [coverage_fraction, distance_m, nodes]
)",
                                                  "example grid");
  if (!grid.ok()) {
    fmt::print(stderr, "{}\n", grid.error);
    return 2;
  }

  // 2. The plan: grid.yaml and cells.tsv in the sweep directory, one line per cell.
  for (const studies::SweepCell& cell : studies::GridCells(*grid.value))
    fmt::print("cell {}: splam {}\n", cell.name, fmt::join(cell.args, " "));
  if (kernel::Status s = studies::WriteSweepPlan(dir, *grid.value); !s.ok()) {
    fmt::print(stderr, "{}\n", s.message());
    return 2;
  }

  // 3. Run the cells, one per core; cells that finished in an earlier run are skipped.
  studies::SweepRunOptions options;
  options.splam_binary = splam_binary;
  options.progress = studies::PrintSweepProgress();
  const kernel::Result<studies::SweepRunSummary> run = studies::RunSweepLocally(dir, options);
  if (!run.ok()) {
    fmt::print(stderr, "{}\n", run.error);
    return 2;
  }
  fmt::print("{} cells run, {} failed, {} skipped in {:.1f} s\n", run.value->done,
             run.value->failed, run.value->skipped, run.value->wall_s);

  // 4. Merge: a group per alpha, statistics of every figure over the seeds; table.csv,
  //    table.md and report.html in the sweep directory.
  const kernel::Result<studies::MergedSweep> merged = studies::MergeSweep(dir);
  if (!merged.ok() || !studies::WriteMergedSweep(*merged.value).ok()) return 2;
  for (const studies::MergedGroup& g : merged.value->groups) {
    const studies::FigureStats& coverage = g.figures.at("coverage_fraction");
    const studies::FigureStats& distance = g.figures.at("distance_m");
    fmt::print("alpha {}: coverage {:.1f} +- {:.1f} %, distance {:.1f} m (median) over {} seeds\n",
               g.values[0].second, 100 * coverage.mean, 100 * coverage.std, distance.median,
               coverage.n);
  }
  fmt::print("open {}/report.html\n", dir);
  return run.value->failed == 0 ? 0 : 1;
}
