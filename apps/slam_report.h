#ifndef SPLAM_APPS_SLAM_REPORT_H_
#define SPLAM_APPS_SLAM_REPORT_H_

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "estimation/metrics.h"
#include "estimation/slam_method.h"
#include "io/map_export.h"
#include "io/run_picture.h"
#include "loop/scoring.h"

// A SLAM method's statistics and errors as JSON (drawing and export: io/run_picture.h,
// io/map_export.h). The methods themselves know nothing of files.
namespace splam::apps {

using io::DrawMap;
using io::RunPicture;
using io::SaveErrorPlot;
using io::SaveRunPicture;
using io::WriteMap;

// {"map": {...}, "associations": {"method": ..., ...}, "least_squares": {...}}
nlohmann::ordered_json StatisticsJson(const estimation::SlamStatistics& statistics);
// A trajectory error as summary.json and report.json write it.
nlohmann::ordered_json ErrorJson(const estimation::TrajectoryError& e);
// Median time per step by map size.
nlohmann::ordered_json TimeBinsJson(const std::vector<loop::TimeBin>& bins);

}  // namespace splam::apps

#endif  // SPLAM_APPS_SLAM_REPORT_H_
