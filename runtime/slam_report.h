#ifndef SPLAM_RUNTIME_SLAM_REPORT_H_
#define SPLAM_RUNTIME_SLAM_REPORT_H_

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "estimation/evaluation/map_consistency.h"
#include "estimation/evaluation/metrics.h"
#include "estimation/occupancy_grid.h"
#include "estimation/slam_method.h"
#include "io/map_export.h"
#include "io/run_picture.h"
#include "runtime/log_replay.h"
#include "runtime/scoring.h"

// A SLAM method's statistics and errors as JSON (drawing and export: io/run_picture.h,
// io/map_export.h). The methods themselves know nothing of files.
namespace splam::runtime {

// {"map": {...}, "associations": {"method": ..., ...}, "least_squares": {...}}
nlohmann::ordered_json StatisticsJson(const estimation::SlamStatistics& statistics);
// A trajectory error as summary.json and report.json write it.
nlohmann::ordered_json ErrorJson(const evaluation::TrajectoryError& e);
// The relations metric as summary.json (`slam --relations`) and eval.json write it: translation
// in m and m^2, rotation in deg and deg^2.
nlohmann::ordered_json RelationsJson(const evaluation::RelationsError& r);
// The map's self-consistency (CheckMapConsistency) for summary.json: totals and the options.
nlohmann::ordered_json ConsistencyJson(const evaluation::ConsistencyReport& report,
                                       const evaluation::ConsistencyOptions& options);
// Median time per step by map size.
nlohmann::ordered_json TimeBinsJson(const std::vector<TimeBin>& bins);

// Timing, statistics, health, errors against the truth and NEES of a log replay, as the
// summary.json of `splam slam` keeps them.
nlohmann::ordered_json ReplaySummaryJson(const estimation::SlamMethod& slam,
                                         const estimation::SlamStatistics& statistics,
                                         const ReplayResult& run, const SlamDriver& driver);

// The occupancy grid of `scans`: `yaml_path` with its .pgm (map_server's format) and the
// pictures; returns what was built for summary.json (resolution, cells, origin, occupied and free
// cells, build time), or {"error": why} when the grid cannot be built (a diverged estimate
// spanning kilometres): not a failure of the run. Write errors go to *errors.
nlohmann::ordered_json WriteGridFiles(const std::vector<evaluation::PlacedScan>& scans,
                                      const estimation::OccupancyGridOptions& options,
                                      const std::string& yaml_path,
                                      const std::vector<std::string>& pictures,
                                      const std::string& title, const kernel::Trajectory& path,
                                      std::vector<kernel::Status>* errors);

}  // namespace splam::runtime

#endif  // SPLAM_RUNTIME_SLAM_REPORT_H_
