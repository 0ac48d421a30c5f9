#ifndef SPLAM_APPS_SLAM_REPORT_H_
#define SPLAM_APPS_SLAM_REPORT_H_

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "apps/run_picture.h"
#include "estimation/metrics.h"
#include "estimation/slam_method.h"
#include "loop/scoring.h"

// A SLAM method's results as files: its map drawn and exported, its statistics and errors as
// JSON. The methods themselves know nothing of files.
namespace splam::apps {

// Lines and corners, or spline curves with control points (small dots), inflection points
// (circles) and corners (diamonds) as paper 000 Figs. 13 and 16 draw them.
void DrawMap(const estimation::SlamMap& map, RunPicture* picture);
// map.txt and map.dxf into dir; the errors, if any (empty strings for success).
std::vector<std::string> WriteMap(const estimation::SlamMap& map, const std::string& dir);
// {"map": {...}, "associations": {"method": ..., ...}, "least_squares": {...}}
nlohmann::ordered_json StatisticsJson(const estimation::SlamStatistics& statistics);
// A trajectory error as summary.json and report.json write it.
nlohmann::ordered_json ErrorJson(const estimation::TrajectoryError& e);
// Median time per step by map size.
nlohmann::ordered_json TimeBinsJson(const std::vector<loop::TimeBin>& bins);

}  // namespace splam::apps

#endif  // SPLAM_APPS_SLAM_REPORT_H_
