#ifndef SPLAM_RUNTIME_SLAM_RUN_H_
#define SPLAM_RUNTIME_SLAM_RUN_H_

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "estimation/evaluation/metrics.h"
#include "estimation/occupancy_grid.h"
#include "estimation/slam_method.h"
#include "io/carmen.h"
#include "kernel/status.h"
#include "runtime/log_replay.h"
#include "runtime/slam_driver.h"
#include "sim/world.h"

// A SLAM run's evaluation and files, as `splam slam` writes them, for any program: the
// trajectories (splam's format and TUM), odometry and truth, the map (text, DXF, pictures), the
// map's self-consistency (consistency.csv), the occupancy grid (map.yaml + map.pgm, grid.png),
// the relations metric when given, the saved state when asked, steps.csv when traced,
// summary.json and report.html. `splam slam` parses its options, replays the log and calls
// WriteSlamRun; RunSlam is both in one call.
namespace splam::runtime {

// Where a run is written and what it is scored against.
struct SlamRunFiles {
  std::string method;  // the method's registry name ("graph"), for the labels and summary.json
  std::string out;     // the run's directory (made when missing)
  std::string log;     // the log's path: the files' headers, the pictures' titles, summary.json
  const sim::World* world = nullptr;  // drawn under the map when given
  // The relations metric (Kümmerle et al. 2009) of the log, when given: summary.json's
  // "relations" and the headline.
  std::optional<std::vector<evaluation::Relation>> relations;
  std::string relations_file;  // its path, for summary.json
  estimation::OccupancyGridOptions grid;
  std::string save_state;  // the method's state is written here (a PersistentSlam); "": not
  bool trace = false;      // steps.csv (the driver recorded the steps)
  // The sensors' noise the method was configured for, and what reading the log found
  // (summary.json).
  estimation::SensorNoise noise;
  io::CarmenReadStats read_stats;
  std::string stopped_early;  // why the log was read only in part; "": whole
};

// What WriteSlamRun wrote and found.
struct SlamRunReport {
  std::string label;                  // the method, with its association when it names one
  std::vector<std::string> headline;  // the run's figures in a few lines (report.html)
  nlohmann::ordered_json summary;     // summary.json
  std::optional<evaluation::RelationsError> relations;
  // False when relations were given and none matched a time of the estimate, or the metric is
  // not finite.
  bool scored = true;
  // The occupancy grid could not be built (a diverged estimate spanning kilometres): why; the
  // run's other files are written.
  std::optional<std::string> grid_error;
  kernel::Status written;  // the first file that could not be written
};

// Scores the replay `run` of `log` by `driver` and writes its files into files.out.
SlamRunReport WriteSlamRun(const io::CarmenLog& log, const SlamDriver& driver,
                           const ReplayResult& run, const SlamRunFiles& files);

// Replays `log` through `method` (ReplayLog) and writes the run (WriteSlamRun). *result, when
// given, receives the replay.
SlamRunReport RunSlam(const io::CarmenLog& log, std::unique_ptr<estimation::SlamMethod> method,
                      const ReplayOptions& replay, const SlamRunFiles& files,
                      ReplayResult* result = nullptr);

}  // namespace splam::runtime

#endif  // SPLAM_RUNTIME_SLAM_RUN_H_
