#include "apps/slam_report.h"

namespace splam::apps {

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
