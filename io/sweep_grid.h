#ifndef SPLAM_IO_SWEEP_GRID_H_
#define SPLAM_IO_SWEEP_GRID_H_

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "io/result.h"

// Grid files of `splam sweep` (docs/sweeps.md): a splam command, its fixed options and the axes
// whose cross product is the set of runs (cells).
//
//   command: explore                  # any splam command line before its options
//   options: {world: office}          # fixed: --world office
//   set: {exploration.alpha: -20}     # fixed: --set exploration.alpha=-20
//   axes:                             # varied, in this order; every combination is a cell
//     explorer: [reg, srt]            # --explorer reg, then --explorer srt
//     seed: {from: 1, to: 10}         # a range (step 1 unless `step`)
//     set.exploration.min_frontier_m: [0.3, 0.5]   # an axis on a --set key
//     strategy:                       # values that set several options; `name` labels them
//       - {name: fig19, explorer: srt, localization: ekf-lines}
//   replicate: seed                   # the axis of repeats, merged into mean +- std (default seed)
//   figures: [coverage_fraction]      # what the merged report plots (default: every figure)
//
// An option value `true` is a flag (`--no-sonar`), `false` leaves it out.
namespace splam::io {

// One option of a cell's command line: `--name value` (`--name` alone when the value is true,
// nothing when it is false), or `--set name=value` when `set`.
struct GridOption {
  std::string name, value;
  bool set = false;
  bool operator==(const GridOption&) const = default;
};

// One value of an axis: its label (the value, or a bundle's name) and the options it sets.
struct GridValue {
  std::string label;
  std::vector<GridOption> options;
  bool operator==(const GridValue&) const = default;
};

struct GridAxis {
  std::string name;  // as written in the grid ("seed", "set.exploration.alpha", "strategy")
  std::vector<GridValue> values;
  bool operator==(const GridAxis&) const = default;
};

struct Grid {
  std::vector<std::string> command;  // e.g. {"explore"} or {"experiment", "corridor-lines"}
  std::vector<GridOption> options;   // fixed, in the file's order (options, then set)
  std::vector<GridAxis> axes;
  std::string replicate = "seed";    // an axis name, or "" when there is none
  std::vector<std::string> figures;  // empty: every figure
  bool operator==(const Grid&) const = default;
};

// Reads a grid file. Errors start with "path:line: " and name the key: an unknown top-level key,
// a missing or empty command, an axis without values, a range that is not finite or has more
// than 100000 values, a bundle without a name, two axes of one name, an option value that is a
// list or a map, a replicate that is no axis, a key that is a list or a map, a command other than
// slam, explore, simulate or experiment, axes that make more than 10^6 cells.
Result<Grid> ReadGrid(const std::string& path);
Result<Grid> ParseGrid(const std::string& text, const std::string& path);

// The axis "seed" with the values first, first + 1, ... (count of them), each setting --seed.
GridAxis SeedAxis(std::uint64_t first, int count);

// The grid as YAML that ParseGrid reads back to the same Grid.
std::string GridToYaml(const Grid& grid);

}  // namespace splam::io

#endif  // SPLAM_IO_SWEEP_GRID_H_
