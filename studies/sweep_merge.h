#ifndef SPLAM_STUDIES_SWEEP_MERGE_H_
#define SPLAM_STUDIES_SWEEP_MERGE_H_

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "kernel/status.h"
#include "studies/sweep.h"

// `splam sweep merge`: the cells' figures gathered into one table per group of the varied axes
// (the replicate axis, seeds by default, is what a group repeats), and a self-contained HTML
// report.
namespace splam::studies {

struct FigureStats {
  int n = 0;
  double mean = 0, std = 0, median = 0, min = 0, max = 0;  // std: the population's
};
FigureStats StatsOf(std::vector<double> values);

struct MergedCell {
  SweepCell cell;
  std::optional<CellRecord> record;  // none: it has not run (or is running)
  std::map<std::string, double> figures;
};

struct MergedGroup {
  std::vector<std::pair<std::string, std::string>> values;  // the axes but the replicate
  int cells = 0, failed = 0, missing = 0;
  std::map<std::string, FigureStats> figures;  // over the group's successful cells
};

struct MergedSweep {
  std::string dir;
  SweepPlan plan;
  std::vector<std::string> group_axes;  // every axis but the replicate
  std::vector<std::string> figures;     // the grid's `figures`, else every one some cell has
  std::vector<MergedCell> cells;
  std::vector<MergedGroup> groups;  // in grid order
};

kernel::Result<MergedSweep> MergeSweep(const std::string& dir);

// table.csv (one row per group and figure: the group's axis values, figure, n, mean, std,
// median, min, max), table.md (the same as a Markdown table, mean +- std) and report.html (the
// table, one strip plot of the figures against each axis, a row per cell linking to its run
// directory and pictures, the grid, the version). Returns the files written or the first error.
kernel::Result<std::vector<std::string>> WriteMergedSweep(const MergedSweep& merged);

}  // namespace splam::studies

#endif  // SPLAM_STUDIES_SWEEP_MERGE_H_
