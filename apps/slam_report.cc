#include "apps/slam_report.h"

#include "io/map_export.h"
#include "kernel/spline_extraction.h"

namespace splam::apps {

void DrawMap(const estimation::SlamMap& map, RunPicture* picture) {
  for (const estimation::MapLine& l : map.lines) picture->map_segments.push_back({l.start, l.end});
  for (const estimation::MapCorner& c : map.corners) picture->map_corners.push_back(c.position);
  for (const estimation::MapSpline& s : map.splines) {
    const kernel::SplineCurve curve = kernel::DescribeCurve(s.spline, map.spline_features);
    picture->map_curves.push_back(curve.samples);
    for (const Eigen::Vector2d& p : s.spline.control_points())
      picture->map_control_points.push_back(p);
    for (const kernel::CurveFeature& f : curve.features) {
      (f.type == kernel::FeatureType::kCorner ? picture->map_corners : picture->map_inflections)
          .push_back(f.position);
    }
  }
}

std::vector<std::string> WriteMap(const estimation::SlamMap& map, const std::string& dir) {
  if (!map.splines.empty() || (map.lines.empty() && map.corners.empty())) {
    return {io::WriteSplineMapText(dir + "/map.txt", map.splines),
            io::WriteSplineMapDxf(dir + "/map.dxf", map.splines)};
  }
  return {io::WriteLineMapText(dir + "/map.txt", map.lines, map.corners),
          io::WriteLineMapDxf(dir + "/map.dxf", map.lines, map.corners)};
}

nlohmann::ordered_json StatisticsJson(const estimation::SlamStatistics& statistics) {
  nlohmann::ordered_json map = nlohmann::ordered_json::object();
  for (const auto& [key, value] : statistics.map) map[key] = value;
  nlohmann::ordered_json associations = nlohmann::ordered_json::object();
  if (!statistics.association.empty()) associations["method"] = statistics.association;
  for (const auto& [key, value] : statistics.associations) associations[key] = value;
  nlohmann::ordered_json json = {{"map", map}, {"associations", associations}};
  if (statistics.solver_runs > 0) {
    json["least_squares"] = {{"solves", statistics.solver_runs},
                             {"not_converged", statistics.solver_failures}};
  }
  return json;
}

nlohmann::ordered_json ErrorJson(const estimation::TrajectoryError& e) {
  return {{"matched_poses", e.matched},
          {"rmse_position_m", e.rmse_position_m},
          {"max_position_m", e.max_position_m},
          {"rmse_heading_rad", e.rmse_heading_rad},
          {"max_heading_rad", e.max_heading_rad}};
}

nlohmann::ordered_json TimeBinsJson(const std::vector<loop::TimeBin>& bins) {
  nlohmann::ordered_json json = nlohmann::ordered_json::array();
  for (const loop::TimeBin& b : bins) {
    json.push_back({{"map_size_from", b.map_size_from},
                    {"map_size_to", b.map_size_to},
                    {"scans", b.steps},
                    {"median_ms", b.median_ms}});
  }
  return json;
}

}  // namespace splam::apps
