#include "runtime/slam_report.h"

#include "kernel/angle.h"

#include <sys/resource.h>

#include <chrono>
#include <cmath>

#include "estimation/chi_square.h"
#include "io/occupancy_grid_file.h"

namespace splam::runtime {

nlohmann::ordered_json StatisticsJson(const estimation::SlamStatistics& statistics) {
  nlohmann::ordered_json map = nlohmann::ordered_json::object();
  for (const auto& [key, value] : statistics.map) map[key] = value;
  nlohmann::ordered_json associations = nlohmann::ordered_json::object();
  if (!statistics.association.empty()) associations["method"] = statistics.association;
  if (const auto& r = statistics.registration) {
    associations["registrations"] = r->registrations;
    associations["registration_recovery_searches"] = r->recovery_searches;
    associations["registration_recovered"] = r->recovered;
    associations["registration_fallbacks"] = r->fallbacks;
  }
  if (const auto& l = statistics.loop_closure) {
    associations["loop_searches"] = l->searches;
    associations["loop_accepted"] = l->accepted;
    associations["loop_rejected_score"] = l->rejected_score;
    associations["loop_rejected_ambiguous"] = l->rejected_ambiguous;
    associations["loop_rejected_registration"] = l->rejected_registration;
    associations["loop_rejected_misfit"] = l->rejected_misfit;
    associations["loop_rejected_disagreement"] = l->rejected_disagreement;
    associations["loop_rejected_unconfirmed"] = l->rejected_unconfirmed;
  }
  for (const auto& [key, value] : statistics.associations) associations[key] = value;
  nlohmann::ordered_json json = {{"map", map}, {"associations", associations}};
  if (statistics.solver_runs > 0) {
    json["least_squares"] = {{"solves", statistics.solver_runs},
                             {"not_converged", statistics.solver_failures}};
  }
  if (!statistics.time_ms.empty()) {
    nlohmann::ordered_json times = nlohmann::ordered_json::object();
    for (const auto& [key, value] : statistics.time_ms) times[key] = value;
    json["time_ms"] = times;
  }
  if (!statistics.optimizations.empty()) {
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const auto& o : statistics.optimizations)
      list.push_back({{"nodes", o.nodes},
                      {"free_nodes", o.free_nodes},
                      {"edges", o.edges},
                      {"loop_edges", o.loop_edges},
                      {"iterations", o.iterations},
                      {"initial_cost", o.initial_cost},
                      {"final_cost", o.final_cost},
                      {"converged", o.converged},
                      {"ms", o.time_ms}});
    json["optimizations"] = list;
  }
  return json;
}

nlohmann::ordered_json RelationsJson(const evaluation::RelationsError& r) {
  return {
      {"relations_used", r.used},
      {"relations_skipped", r.skipped},
      {"translation_m", {{"mean", r.translation_mean}, {"std", r.translation_std}}},
      {"translation_sq_m2", {{"mean", r.translation_sq_mean}, {"std", r.translation_sq_std}}},
      {"rotation_deg",
       {{"mean", kernel::RadToDeg(r.rotation_mean)}, {"std", kernel::RadToDeg(r.rotation_std)}}},
      {"rotation_sq_deg2",
       {{"mean", kernel::RadToDeg(kernel::RadToDeg(r.rotation_sq_mean))},
        {"std", kernel::RadToDeg(kernel::RadToDeg(r.rotation_sq_std))}}}};
}

nlohmann::ordered_json ConsistencyJson(const evaluation::ConsistencyReport& report,
                                       const evaluation::ConsistencyOptions& options) {
  return {{"scans_checked", report.scans_checked},
          {"mean_contradicting", report.mean_contradicting},
          {"inconsistent_scans", report.inconsistent},
          {"inconsistent_share", report.inconsistent_share},
          {"inconsistent_above", options.inconsistent_share},
          {"flagged", report.flagged},
          {"flagged_above", options.flag_share},
          {"scan_spacing_m", options.scan_spacing_m},
          {"reference_radius_m", options.reference_radius_m},
          {"min_path_gap_m", options.min_path_gap_m},
          {"inlier_distance_m", options.inlier_distance_m}};
}

nlohmann::ordered_json ErrorJson(const evaluation::TrajectoryError& e) {
  return {{"matched_poses", e.matched},
          {"rmse_position_m", e.rmse_position_m},
          {"max_position_m", e.max_position_m},
          {"rmse_heading_rad", e.rmse_heading_rad},
          {"max_heading_rad", e.max_heading_rad}};
}

nlohmann::ordered_json TimeBinsJson(const std::vector<TimeBin>& bins) {
  nlohmann::ordered_json json = nlohmann::ordered_json::array();
  for (const TimeBin& b : bins) {
    json.push_back({{"map_size_from", b.map_size_from},
                    {"map_size_to", b.map_size_to},
                    {"scans", b.steps},
                    {"median_ms", b.median_ms}});
  }
  return json;
}

nlohmann::ordered_json ReplaySummaryJson(const estimation::SlamMethod& slam,
                                         const estimation::SlamStatistics& statistics,
                                         const ReplayResult& run, const SlamDriver& driver) {
  const std::vector<double>& step_ms = driver.update_ms();
  nlohmann::ordered_json summary;
  summary["scans"] = run.estimate.size();
  summary["data_duration_s"] = run.data_s();
  summary["backward_time_stamps"] = run.backward_time_stamps();
  summary["wall_time_s"] = run.wall_s;
  summary["real_time_factor"] = run.wall_s > 0 ? run.data_s() / run.wall_s : 0.0;
  summary["time_per_scan_ms"] = {
      {"mean", step_ms.empty() ? 0.0 : run.wall_s * 1000.0 / static_cast<double>(step_ms.size())},
      {"median", Percentile(step_ms, 0.5)},
      {"p95", Percentile(step_ms, 0.95)},
      {"max", Percentile(step_ms, 1.0)}};
  // The process's peak resident memory so far (Linux reports kilobytes): bounded by the map a
  // method builds, not by the log's length or the laser's range.
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  summary["peak_memory_mb"] = static_cast<double>(usage.ru_maxrss) / 1024.0;
  summary["time_per_scan_vs_map_size"] = TimeBinsJson(TimeByMapSize(step_ms, driver.map_size()));
  summary.update(StatisticsJson(statistics));
  summary["health"] = {{"healthy", slam.healthy()},
                       {"message", slam.health().message()},
                       {"scans_processed", run.estimate.size()},
                       {"scans_in_log", run.scans_in_log}};
  if (const auto p = slam.PoseCovarianceEveryScan() ? slam.PoseCovariance() : std::nullopt) {
    summary["health"]["final_pose_sigma"] = {std::sqrt((*p)(0, 0)), std::sqrt((*p)(1, 1)),
                                             std::sqrt((*p)(2, 2))};
  }
  if (!run.truth.empty()) {
    summary["error"] = {
        {"estimate", ErrorJson(evaluation::CompareToTruth(run.truth, run.estimate))},
        {"odometry", ErrorJson(evaluation::CompareToTruth(run.truth, run.odometry))}};
    const double lo = estimation::ChiSquareQuantile(0.025, 3),
                 hi = estimation::ChiSquareQuantile(0.975, 3);
    double sum = 0.0;
    std::size_t inside = 0;
    for (double v : run.nees) {
      sum += v;
      inside += v >= lo && v <= hi;
    }
    if (!run.nees.empty()) {
      const double n = static_cast<double>(run.nees.size());
      summary["nees"] = {{"mean", sum / n},
                         {"fraction_in_95_band", static_cast<double>(inside) / n},
                         {"steps", run.nees.size()}};
    }
  }
  return summary;
}

nlohmann::ordered_json WriteGridFiles(const std::vector<evaluation::PlacedScan>& scans,
                                      const estimation::OccupancyGridOptions& options,
                                      const std::string& yaml_path,
                                      const std::vector<std::string>& pictures,
                                      const std::string& title, const kernel::Trajectory& path,
                                      std::vector<kernel::Status>* errors) {
  const auto start = std::chrono::steady_clock::now();
  const kernel::Result<estimation::OccupancyGrid> grid =
      estimation::BuildOccupancyGrid(scans, options);
  if (!grid.ok()) return {{"error", grid.error}};
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  errors->push_back(io::WriteOccupancyGrid(*grid, yaml_path, options));
  errors->push_back(io::SaveOccupancyGridPicture(*grid, options, title, path, pictures));
  int occupied = 0, free = 0;
  for (int y = 0; y < grid->height(); ++y) {
    for (int x = 0; x < grid->width(); ++x) {
      const estimation::CellState c =
          grid->State(x, y, options.occupied_threshold, options.free_threshold);
      occupied += c == estimation::CellState::kOccupied;
      free += c == estimation::CellState::kFree;
    }
  }
  return {{"resolution_m", grid->resolution_m()},
          {"cells", {grid->width(), grid->height()}},
          {"origin_m", {grid->origin().x(), grid->origin().y()}},
          {"occupied_cells", occupied},
          {"free_cells", free},
          {"build_s", seconds}};
}

}  // namespace splam::runtime
