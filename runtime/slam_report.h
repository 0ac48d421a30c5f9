#ifndef SPLAM_RUNTIME_SLAM_REPORT_H_
#define SPLAM_RUNTIME_SLAM_REPORT_H_

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "estimation/evaluation/map_consistency.h"
#include "estimation/evaluation/metrics.h"
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

}  // namespace splam::runtime

#endif  // SPLAM_RUNTIME_SLAM_REPORT_H_
