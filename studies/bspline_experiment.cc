#include "studies/bspline_experiment.h"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "estimation/ekf/ekf_bspline_slam.h"
#include "estimation/evaluation/metrics.h"
#include "io/plot.h"
#include "io/render.h"
#include "io/run_picture.h"
#include "kernel/angle.h"
#include "runtime/exit_status.h"
#include "runtime/json_text.h"
#include "runtime/run_html.h"
#include "runtime/slam_report.h"
#include "sim/builtin_worlds.h"
#include "sim/simulator.h"
#include "studies/association_scoring.h"
#include "studies/experiment_trials.h"

namespace splam::studies {

using runtime::JsonText;
using runtime::kExitBadInput;
using runtime::kExitIncomplete;
using runtime::kExitOk;
using runtime::WriteRunHtml;
namespace {

// Every seed's numbers of one method (or of odometry, which fills the first three).
struct Summary {
  std::vector<double> rmse, max, heading_rmse, map_error, wrong_fraction, wrong_beam_fraction, ms,
      feature_fraction, nees;
  void Add(const evaluation::TrajectoryError& e) {
    rmse.push_back(e.rmse_position_m);
    max.push_back(e.max_position_m);
    heading_rmse.push_back(e.rmse_heading_rad);
  }
  void Add(const evaluation::TrajectoryError& e, const AssociationRun& r) {
    Add(e);
    map_error.push_back(r.map_error_m);
    wrong_fraction.push_back(
        r.associations > 0 ? static_cast<double>(r.wrong_associations) / r.associations : 0.0);
    wrong_beam_fraction.push_back(
        r.beams > 0 ? static_cast<double>(r.wrong_beams) / static_cast<double>(r.beams) : 0.0);
    ms.push_back(r.ms_per_scan);
    feature_fraction.push_back(
        r.associations > 0 ? static_cast<double>(r.with_features) / r.associations : 0.0);
    nees.push_back(r.mean_nees);
  }
};
double Mean(const std::vector<double>& v) { return evaluation::MeanStd(v).first; }
double Std(const std::vector<double>& v) { return evaluation::MeanStd(v).second; }

// The first seed's map of one association over the world, with the three trajectories.
kernel::Status SaveMethodMap(const sim::World& world, const std::string& method, std::uint64_t seed,
                             const kernel::Trajectory& truth, const kernel::Trajectory& odometry,
                             const AssociationRun& r,
                             const kernel::SplineExtractionOptions& extraction,
                             const std::string& base) {
  io::RunPicture picture;
  picture.title = fmt::format("{}, URG-04LX, {} association (seed {}): {} splines", world.name,
                              method, seed, r.map.size());
  picture.world = &world;
  picture.world_color = io::Rgb{0.75, 0.75, 0.75};
  picture.truth = truth;
  picture.odometry = odometry;
  picture.estimates = {{method, r.estimate}};
  estimation::SlamMap map;
  map.splines = r.map;
  map.spline_features = extraction;
  io::DrawMap(map, &picture);
  return io::SaveRunPicture(picture, {base + ".svg", base + ".png"});
}

// table.md and report.json: mean +- std per method over the seeds, and the seeds in which the
// curvature association had the lower position RMSE. Returns the exit status.
int WriteBSplineReport(const BSplineExperimentArgs& args, const std::vector<std::string>& methods,
                       std::map<std::string, Summary>& summaries, const Summary& odometry_summary) {
  const double scale = args.odometry_noise_scale;
  nlohmann::ordered_json report;
  report["experiment"] = "complex-bspline (paper 000 Figs. 15-17)";
  report["runs"] = args.runs;
  report["odometry_noise_scale"] = scale;
  report["max_correspondence_distance_m"] = args.max_correspondence_distance_m;
  report["match_selection"] = args.match_selection;
  report["world"] = args.world;
  std::string table = fmt::format(
      "| method ({} seeds, odometry noise x{}) | position RMSE (m) | max position error (m) | "
      "heading RMSE (deg) | map "
      "error (m) | wrong associations | wrong beams | associations with paired features | mean "
      "NEES (3 dof) | time per scan (ms) |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n",
      args.runs, scale);
  auto row = [&](const std::string& name, const Summary& s, bool filter) {
    std::string r =
        fmt::format("| {} | {:.3f} +- {:.3f} | {:.3f} +- {:.3f} | {:.2f} +- {:.2f} |", name,
                    Mean(s.rmse), Std(s.rmse), Mean(s.max), Std(s.max),
                    kernel::RadToDeg(Mean(s.heading_rmse)), kernel::RadToDeg(Std(s.heading_rmse)));
    if (!filter) return r + " - | - | - | - | - | - |\n";
    return r +
           fmt::format(" {:.4f} +- {:.4f} | {:.2f} % | {:.2f} % | {:.1f} % | {:.1f} | {:.2f} |\n",
                       Mean(s.map_error), Std(s.map_error), 100 * Mean(s.wrong_fraction),
                       100 * Mean(s.wrong_beam_fraction), 100 * Mean(s.feature_fraction),
                       Mean(s.nees), Mean(s.ms));
  };
  table += row("odometry", odometry_summary, false);
  report["odometry"] = {{"rmse_position_m", Mean(odometry_summary.rmse)},
                        {"max_position_m", Mean(odometry_summary.max)},
                        {"rmse_heading_rad", Mean(odometry_summary.heading_rmse)}};
  for (const std::string& method : methods) {
    const Summary& s = summaries[method];
    table += row(method, s, true);
    report[method] = {{"rmse_position_m", Mean(s.rmse)},
                      {"rmse_position_std_m", Std(s.rmse)},
                      {"max_position_m", Mean(s.max)},
                      {"rmse_heading_rad", Mean(s.heading_rmse)},
                      {"map_error_m", Mean(s.map_error)},
                      {"wrong_association_fraction", Mean(s.wrong_fraction)},
                      {"wrong_beam_fraction", Mean(s.wrong_beam_fraction)},
                      {"ms_per_scan", Mean(s.ms)},
                      {"paired_feature_fraction", Mean(s.feature_fraction)},
                      {"mean_nees", Mean(s.nees)},
                      {"per_seed_rmse_position_m", s.rmse}};
  }
  int curvature_wins = 0;
  for (int i = 0; i < args.runs; ++i)
    curvature_wins += summaries["curvature"].rmse[i] < summaries["pedraza"].rmse[i];
  report["curvature_lower_rmse_in_seeds"] = curvature_wins;
  table +=
      fmt::format("\nThe curvature association has the lower position RMSE in {} of {} seeds.\n",
                  curvature_wins, args.runs);
  fmt::print("\n{}", table);
  if (const int status =
          WriteExperimentFiles({{args.out + "/table.md", table},
                                {args.out + "/report.json", JsonText(report, 2) + "\n"}});
      status != kExitOk)
    return status;
  if (kernel::Status s = WriteRunHtml(args.out, "splam experiment complex-bspline (paper 000)");
      !s.ok())
    fmt::print(stderr, "splam experiment: {}\n", s.message());
  fmt::print(
      "wrote {}/{{table.md, report.json, report.html, errors.svg, errors.png, map_pedraza.svg/png, "
      "map_curvature.svg/png}}\n",
      args.out);
  return kExitOk;
}

// Runs the seeds in this process, one after the other, and writes the report.
int RunSeedsHere(const BSplineExperimentArgs& args) {
  const std::optional<sim::World> built_in = sim::BuiltinWorld(args.world);
  if (!built_in || built_in->route.empty() || !built_in->start) {
    fmt::print(
        stderr,
        "splam experiment: complex-bspline needs a built-in world with a route ({}), not '{}'\n",
        fmt::join(sim::BuiltinWorldNames(), ", "), args.world);
    return kExitBadInput;
  }
  const sim::World& world = *built_in;
  const sim::RayCaster caster(world);
  sim::SimulatorOptions sim_options;
  sim_options.laser = sim::LaserOptions::Urg04lx();
  // The same scale on the simulator's odometry noise and on the filter's model of it.
  const double scale = args.odometry_noise_scale;
  sim_options.odometry = sim_options.odometry.Scaled(scale);
  std::filesystem::create_directories(args.out);
  const std::vector<std::string> methods = {"pedraza", "curvature"};
  std::map<std::string, Summary> summaries;
  Summary odometry_summary;
  for (int run = 0; run < args.runs; ++run) {
    const std::uint64_t seed = args.seed + static_cast<std::uint64_t>(run);
    sim::Simulator simulator(caster, sim_options, *world.start, seed);
    sim::RouteOptions route_options;
    if (args.max_scans > 0) route_options.max_steps = args.max_scans - 1;
    sim::RouteRun route = sim::FollowRoute(&simulator, world.route, route_options);
    if (!route.completed && args.max_scans == 0) {
      fmt::print(stderr, "splam experiment: seed {}: the route failed: {}\n", seed, route.message);
      return kExitIncomplete;
    }
    kernel::Trajectory truth, odometry;
    for (const sim::SensorFrame& f : route.frames) {
      truth.push_back({f.time_s, f.true_pose});
      odometry.push_back({f.time_s, f.odometry_pose});
    }
    const evaluation::TrajectoryError o = evaluation::CompareToTruth(truth, odometry);
    odometry_summary.Add(o);
    std::vector<std::tuple<std::string, io::Rgb, kernel::Trajectory>> plotted = {
        {"odometry", io::palette::kOdometry, odometry}};
    for (const std::string& method : methods) {
      estimation::EkfBSplineSlamOptions options;
      options.association = method;
      options.max_correspondence_distance_m = args.max_correspondence_distance_m;
      options.match_selection = args.match_selection;
      options.odometry = options.odometry.Scaled(scale);
      const AssociationRun r = RunBSplineFilter(route.frames, caster, options);
      if (!r.healthy) {
        fmt::print(stderr, "splam experiment: seed {}, {}: the filter failed: {}\n", seed, method,
                   r.failure);
        return kExitIncomplete;
      }
      const evaluation::TrajectoryError e = evaluation::CompareToTruth(truth, r.estimate);
      summaries[method].Add(e, r);
      fmt::print(
          "seed {} {:9}: position RMSE {:.3f} m (odometry {:.3f}), max {:.3f} m, map error {:.3f} "
          "m, wrong associations {}/{}, {:.2f} ms/scan\n",
          seed, method, e.rmse_position_m, o.rmse_position_m, e.max_position_m, r.map_error_m,
          r.wrong_associations, r.associations, r.ms_per_scan);
      plotted.emplace_back(method,
                           method == "pedraza" ? io::Rgb{0.95, 0.55, 0.0} : io::palette::kEstimate,
                           r.estimate);
      if (run == 0) {
        if (kernel::Status err = SaveMethodMap(world, method, seed, truth, odometry, r,
                                               options.extraction, args.out + "/map_" + method);
            !err.ok()) {
          fmt::print(stderr, "splam experiment: {}\n", err.message());
          return kExitBadInput;
        }
      }
    }
    if (run == 0) {
      if (kernel::Status err = io::SaveErrorPlot(
              fmt::format("{}, URG-04LX: errors against ground truth (seed {})", world.name, seed),
              truth, plotted, {args.out + "/errors.svg", args.out + "/errors.png"});
          !err.ok()) {
        fmt::print(stderr, "splam experiment: {}\n", err.message());
        return kExitBadInput;
      }
    }
  }

  return WriteBSplineReport(args, methods, summaries, odometry_summary);
}

// A summary of one method (or odometry) read back from a one-seed run's report.json.
void AddFromReport(const nlohmann::json& r, bool filter, Summary* s) {
  s->rmse.push_back(r["rmse_position_m"]);
  s->max.push_back(r["max_position_m"]);
  s->heading_rmse.push_back(r["rmse_heading_rad"]);
  if (!filter) return;
  s->map_error.push_back(r["map_error_m"]);
  s->wrong_fraction.push_back(r["wrong_association_fraction"]);
  s->wrong_beam_fraction.push_back(r["wrong_beam_fraction"]);
  s->ms.push_back(r["ms_per_scan"]);
  s->feature_fraction.push_back(r["paired_feature_fraction"]);
  s->nees.push_back(r["mean_nees"]);
}

}  // namespace

io::Grid ComplexBSplineGrid(const BSplineExperimentArgs& args) {
  io::Grid grid;
  grid.command = {"experiment", "complex-bspline"};
  grid.options = {
      {"runs", "1", false},
      {"odometry-noise", fmt::format("{}", args.odometry_noise_scale), false},
      {"max-correspondence", fmt::format("{}", args.max_correspondence_distance_m), false},
      {"world", args.world, false}};
  if (args.max_scans > 0)
    grid.options.push_back({"max-scans", std::to_string(args.max_scans), false});
  if (args.match_selection != "longest")
    grid.options.push_back({"match-selection", args.match_selection, false});
  grid.axes = {io::SeedAxis(args.seed, args.runs)};
  grid.figures = {"pedraza.rmse_position_m", "curvature.rmse_position_m", "pedraza.map_error_m",
                  "curvature.map_error_m",   "pedraza.ms_per_scan",       "curvature.ms_per_scan",
                  "odometry.rmse_position_m"};
  return grid;
}

int RunComplexBSpline(const BSplineExperimentArgs& args) {
  if (args.runs == 1) return RunSeedsHere(args);
  if (const int status = RunExperimentTrials(args.out, ComplexBSplineGrid(args), args.splam_binary,
                                             args.jobs, args.stop);
      status != kExitOk)
    return status;
  const std::vector<std::string> methods = {"pedraza", "curvature"};
  std::map<std::string, Summary> summaries;
  Summary odometry_summary;
  for (int i = 0; i < args.runs; ++i) {
    const std::string dir =
        fmt::format("{}/cells/seed-{}", args.out, args.seed + static_cast<std::uint64_t>(i));
    const std::optional<nlohmann::json> report = TrialReport(dir);
    if (!report) return kExitIncomplete;
    AddFromReport((*report)["odometry"], false, &odometry_summary);
    for (const std::string& method : methods)
      AddFromReport((*report)[method], true, &summaries[method]);
    if (i > 0) continue;
    if (kernel::Status error = CopyTrialFiles(  // the first seed's pictures
            dir, args.out,
            {"errors.svg", "errors.png", "map_pedraza.svg", "map_pedraza.png", "map_curvature.svg",
             "map_curvature.png"});
        !error.ok()) {
      fmt::print(stderr, "splam experiment: {}\n", error.message());
      return kExitBadInput;
    }
  }
  return WriteBSplineReport(args, methods, summaries, odometry_summary);
}

}  // namespace splam::studies
