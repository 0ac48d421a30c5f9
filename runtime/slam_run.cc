#include "runtime/slam_run.h"

#include <fmt/core.h>

#include <cmath>
#include <filesystem>
#include <system_error>
#include <utility>

#include "estimation/evaluation/map_consistency.h"
#include "estimation/slam_state.h"
#include "io/map_export.h"
#include "io/plot.h"
#include "io/run_picture.h"
#include "io/simulation_log.h"
#include "io/slam_state_file.h"
#include "io/text.h"
#include "kernel/angle.h"
#include "runtime/json_text.h"
#include "runtime/run_html.h"
#include "runtime/slam_report.h"
#include "runtime/step_trace.h"

namespace splam::runtime {
namespace {

// consistency.csv: every scan checked for the map's self-consistency.
kernel::Status WriteConsistency(const std::string& path,
                                const evaluation::ConsistencyReport& consistency,
                                const kernel::Trajectory& estimate) {
  std::string text = "scan,time_s,x_m,y_m,references,contradicting\n";
  for (const evaluation::CheckedScan& c : consistency.checked)
    text += fmt::format("{},{:.3f},{:.3f},{:.3f},{},{:.4f}\n", c.index,
                        estimate[static_cast<std::size_t>(c.index)].time_s, c.position.x(),
                        c.position.y(), c.references, c.contradicting);
  return io::WriteTextFile(path, text);
}

// The run's figures in a few lines, for report.html and (the first ones) map.png's title: the
// error against the truth or the relations metric when known, the map, the map's
// self-consistency, the time, and why the run stopped early when it did.
std::vector<std::string> SlamHeadline(const estimation::SlamMethod& slam,
                                      const runtime::ReplayResult& run,
                                      const evaluation::ConsistencyReport& consistency,
                                      const std::optional<evaluation::RelationsError>& relations) {
  std::vector<std::string> lines;
  if (!run.truth.empty()) {
    const auto e = evaluation::CompareToTruth(run.truth, run.estimate);
    const auto o = evaluation::CompareToTruth(run.truth, run.odometry);
    lines.push_back(fmt::format("position RMSE {:.3f} m (odometry {:.3f} m)", e.rmse_position_m,
                                o.rmse_position_m));
  }
  if (relations && relations->used > 0)
    lines.push_back(fmt::format("relations metric {:.4f} m, {:.2f} deg",
                                relations->translation_mean,
                                kernel::RadToDeg(relations->rotation_mean)));
  lines.push_back(slam.MapDescription());
  lines.push_back(fmt::format("{:.1f} % of the points in other passes' free space",
                              100 * consistency.mean_contradicting));
  lines.push_back(fmt::format("{} scans in {:.1f} s", run.estimate.size(), run.wall_s));
  if (run.failed_at) lines.push_back("the method failed: " + slam.health().message());
  if (run.stopped_at)
    lines.push_back(fmt::format("interrupted before scan {}", *run.stopped_at + 1));
  return lines;
}

// The headline's first two lines, for a picture's title.
std::string HeadlineTitle(const std::vector<std::string>& headline) {
  std::string title;
  for (std::size_t i = 0; i < headline.size() && i < 2; ++i)
    title += (i > 0 ? "; " : "") + headline[i];
  return title;
}

// trajectory, odometry, truth, map files and pictures; errors appended to *errors.
void WriteSlamFiles(const std::string& log, const std::string& out, const std::string& label,
                    const std::string& headline, const sim::World* world,
                    const estimation::SlamMethod& slam, const runtime::ReplayResult& run,
                    const evaluation::ConsistencyReport& consistency,
                    const evaluation::ConsistencyOptions& consistency_options,
                    std::vector<kernel::Status>* errors) {
  const estimation::SlamMap map = slam.Map();
  errors->push_back(io::WriteMap(map, out));
  // trajectory.txt in splam's format, trajectory.tum (and truth.tum) for evo and the like.
  for (const char* name : {"/trajectory.txt", "/trajectory.tum"})
    errors->push_back(io::WriteTrajectory(out + name, run.estimate, label + " estimate of " + log));
  errors->push_back(io::WriteTrajectory(out + "/odometry.txt", run.odometry, "odometry of " + log));
  for (const char* name : {"/truth.txt", "/truth.tum"})
    if (!run.truth.empty())
      errors->push_back(io::WriteTrajectory(out + name, run.truth, "ground truth of " + log));
  io::RunPicture picture;
  picture.title =
      fmt::format("{} on {}: {}", label, std::filesystem::path(log).filename().string(), headline);
  picture.world = world;
  picture.world_color = io::Rgb{0.75, 0.75, 0.75};
  picture.truth = run.truth;
  picture.odometry = run.odometry;
  picture.estimates = {{"estimate", run.estimate}};
  picture.before_optimization = run.online;
  io::DrawMap(map, &picture);
  for (const evaluation::CheckedScan& c : consistency.checked)
    (c.contradicting > consistency_options.inconsistent_share ? picture.inconsistent_scans
                                                              : picture.consistent_scans)
        .push_back(c.position);
  picture.pixels_per_meter = 40.0;
  errors->push_back(io::SaveRunPicture(picture, {out + "/map.svg", out + "/map.png"}));
  if (!run.truth.empty()) {
    errors->push_back(io::SaveErrorPlot(label + ": error against ground truth", run.truth,
                                        {{"odometry", io::palette::kOdometry, run.odometry},
                                         {label, io::palette::kEstimate, run.estimate}},
                                        {out + "/errors.svg", out + "/errors.png"}));
  }
}

}  // namespace

SlamRunReport WriteSlamRun(const io::CarmenLog& log, const SlamDriver& driver,
                           const ReplayResult& run, const SlamRunFiles& files) {
  SlamRunReport report;
  const std::string& out = files.out;
  std::vector<kernel::Status> errors;
  if (std::error_code e; !std::filesystem::create_directories(out, e) && e)
    errors.push_back(kernel::Status::Error(out + ": cannot create the directory: " + e.message()));
  const estimation::SlamMethod& slam = driver.method();
  const estimation::SlamStatistics statistics = slam.Statistics();
  const evaluation::ConsistencyOptions consistency_options;
  const evaluation::ConsistencyReport consistency =
      evaluation::CheckMapConsistency(PlacedScans(log, run.estimate), consistency_options);
  errors.push_back(WriteConsistency(out + "/consistency.csv", consistency, run.estimate));
  const std::string& method = files.method;
  report.label =
      statistics.association.empty() ? method : method + " (" + statistics.association + ")";
  const std::string& label = report.label;
  if (files.relations)
    report.relations = evaluation::EvaluateRelations(*files.relations, run.estimate);
  if (!files.save_state.empty()) {
    const estimation::PersistentSlam* persistent = estimation::PersistenceOf(&slam);
    const kernel::Result<estimation::SlamState> state =
        persistent != nullptr ? persistent->SaveState()
                              : kernel::Result<estimation::SlamState>::Fail(
                                    method + ": the method cannot save its state");
    errors.push_back(state ? io::WriteSlamState(files.save_state, *state)
                           : kernel::Status::Error(state.error));
  }
  report.headline = SlamHeadline(slam, run, consistency, report.relations);
  if (!files.stopped_early.empty())
    report.headline.push_back("the log stopped early: " + files.stopped_early);
  WriteSlamFiles(files.log, out, label, HeadlineTitle(report.headline), files.world, slam, run,
                 consistency, consistency_options, &errors);
  const nlohmann::ordered_json grid = WriteGridFiles(
      PlacedScans(log, run.estimate), files.grid, out + "/map.yaml", {out + "/grid.png"},
      fmt::format("{} on {}: occupancy grid", label,
                  std::filesystem::path(files.log).filename().string()),
      run.estimate, &errors);
  if (grid.contains("error")) report.grid_error = grid["error"].get<std::string>();
  if (files.trace) {
    std::vector<double> times;
    for (const kernel::StampedPose& p : run.online.empty() ? run.estimate : run.online)
      times.push_back(p.time_s);
    errors.push_back(WriteStepTrace(out + "/steps.csv", driver.steps(), times, run.truth));
  }

  nlohmann::ordered_json& summary = report.summary;
  summary["method"] = method;
  if (!statistics.association.empty()) summary["association"] = statistics.association;
  summary["odometry_noise_scale"] = files.noise.odometry_noise_scale;
  summary["range_noise_model"] = {{"range_sigma_m", files.noise.range_sigma_m},
                                  {"range_sigma_fraction", files.noise.range_sigma_fraction}};
  summary["log"] = files.log;
  const io::CarmenReadStats& read = files.read_stats;
  if (read.piled_no_return_from_m > 0)
    summary["no_returns_found"] = {{"from_m", read.piled_no_return_from_m},
                                   {"readings", read.piled_no_return_readings},
                                   {"share_of_hits", read.piled_no_return_share}};
  // Why the run covers less than the log, when it does.
  if (!files.stopped_early.empty()) summary["stopped_early"] = files.stopped_early;
  if (run.stopped_at)
    summary["stopped_early"] = "interrupted before scan " + std::to_string(*run.stopped_at + 1);
  summary.update(ReplaySummaryJson(slam, statistics, run, driver));
  summary["consistency"] = ConsistencyJson(consistency, consistency_options);
  summary["occupancy_grid"] = grid;
  if (report.relations) {
    const evaluation::RelationsError& r = *report.relations;
    report.scored =
        r.used > 0 && std::isfinite(r.translation_mean) && std::isfinite(r.rotation_mean);
    summary["relations"] = RelationsJson(r);
    summary["relations"]["file"] = files.relations_file;
  }
  errors.push_back(io::WriteTextFile(out + "/summary.json", JsonText(summary, 2) + "\n"));
  errors.push_back(WriteRunHtml(out, "splam slam: " + label + " on " + files.log, report.headline));
  report.written = kernel::FirstError(errors);
  return report;
}

SlamRunReport RunSlam(const io::CarmenLog& log, std::unique_ptr<estimation::SlamMethod> method,
                      const ReplayOptions& replay, const SlamRunFiles& files,
                      ReplayResult* result) {
  SlamDriver driver(std::move(method));
  driver.RecordSteps(files.trace);
  const ReplayResult run = ReplayLog(log, &driver, replay);
  SlamRunReport report = WriteSlamRun(log, driver, run, files);
  if (result != nullptr) *result = run;
  return report;
}

}  // namespace splam::runtime
