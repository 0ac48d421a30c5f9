#include "studies/corridor_experiment.h"

#include <Eigen/LU>
#include <cmath>

#include <fmt/core.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "estimation/chi_square.h"
#include "estimation/evaluation/metrics.h"
#include "estimation/slam_method.h"
#include "io/plot.h"
#include "io/render.h"
#include "io/run_picture.h"
#include "kernel/angle.h"
#include "runtime/exit_status.h"
#include "runtime/json_text.h"
#include "runtime/log_replay.h"
#include "runtime/run_html.h"
#include "sim/builtin_worlds.h"
#include "sim/simulator.h"
#include "studies/experiment_trials.h"

namespace splam::studies {

using runtime::ReplayResult;

using runtime::JsonText;
using runtime::kExitBadInput;
using runtime::kExitIncomplete;
using runtime::kExitOk;
using runtime::SlamDriver;
using runtime::WriteRunHtml;

double CorridorDistance::TrueValue() const {
  if (!between_lines) return (a - b).norm();
  return std::abs(Eigen::Vector2d(std::cos(a_theta), std::sin(a_theta)).dot(b - a));
}

const std::vector<CorridorDistance>& CorridorDistances() {
  const double up = kernel::kPi / 2;
  static const std::vector<CorridorDistance> d = {
      {"d1: corridor width (walls)", true, {5, -1.2}, {5, 1.2}, -up, up},
      {"d2: south room depth (walls)", true, {8, -1.2}, {8, -3.2}, -up, -up},
      {"d3: north room depth (walls)", true, {9, 1.2}, {9, 3.2}, up, up},
      {"d4: corners (18,-1.2)-(18,1.2)", false, {18, -1.2}, {18, 1.2}},
      {"d5: corners (18,-1.6)-(18,1.5)", false, {18, -1.6}, {18, 1.5}},
      {"d6: corners (12,-1.5)-(14,1.5)", false, {12, -1.5}, {14, 1.5}},
      {"d7: corners (9,-3.2)-(12,-1.5)", false, {9, -3.2}, {12, -1.5}},
      {"d8: corners (11,3.2)-(14,1.5)", false, {11, 3.2}, {14, 1.5}},
      {"d9: corners (14,1.5)-(18,1.5)", false, {14, 1.5}, {18, 1.5}},
  };
  return d;
}

const estimation::MapLine* MappedWall(const Eigen::Vector2d& point, double theta,
                                      const std::vector<estimation::MapLine>& lines) {
  const estimation::MapLine* best = nullptr;
  for (const auto& l : lines) {
    const Eigen::Vector2d n(std::cos(l.line.theta), std::sin(l.line.theta));
    if (std::abs(std::sin(l.line.theta - theta)) > std::sin(kernel::DegToRad(5))) continue;
    if (std::abs(n.dot(point) - l.line.rho) > 0.2) continue;
    if (best == nullptr || l.observations > best->observations) best = &l;
  }
  return best;
}

std::optional<Eigen::Vector2d> MappedCorner(const Eigen::Vector2d& truth,
                                            const std::vector<estimation::MapCorner>& corners,
                                            const std::vector<estimation::MapLine>& lines) {
  std::optional<Eigen::Vector2d> best;
  double best_d = 0.25;
  for (const auto& c : corners) {
    if ((c.position - truth).norm() < best_d)
      best_d = (c.position - truth).norm(), best = c.position;
  }
  if (best) return best;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    for (std::size_t j = i + 1; j < lines.size(); ++j) {
      if (std::abs(std::sin(lines[i].line.theta - lines[j].line.theta)) < 0.5) continue;
      Eigen::Matrix2d n;
      n << std::cos(lines[i].line.theta), std::sin(lines[i].line.theta),
          std::cos(lines[j].line.theta), std::sin(lines[j].line.theta);
      const Eigen::Vector2d x = n.inverse() * Eigen::Vector2d(lines[i].line.rho, lines[j].line.rho);
      if ((x - truth).norm() < best_d) best_d = (x - truth).norm(), best = x;
    }
  }
  return best;
}

std::optional<double> MeasuredDistance(const CorridorDistance& d,
                                       const std::vector<estimation::MapLine>& lines,
                                       const std::vector<estimation::MapCorner>& corners) {
  if (d.between_lines) {
    const estimation::MapLine* a = MappedWall(d.a, d.a_theta, lines);
    const estimation::MapLine* b = MappedWall(d.b, d.b_theta, lines);
    if (a == nullptr || b == nullptr) return std::nullopt;
    // Distance of the middle of b's extent from line a.
    const Eigen::Vector2d n(std::cos(a->line.theta), std::sin(a->line.theta));
    return std::abs(n.dot(0.5 * (b->start + b->end)) - a->line.rho);
  }
  const auto a = MappedCorner(d.a, corners, lines);
  const auto b = MappedCorner(d.b, corners, lines);
  if (!a || !b) return std::nullopt;
  return (*a - *b).norm();
}

CorridorResult RunCorridorExperiment(const CorridorOptions& args) {
  const sim::World world = *sim::BuiltinWorld("corridor");
  const sim::RayCaster caster(world);
  sim::SimulatorOptions sim_options;
  sim_options.laser = sim::LaserOptions::Lms200(0.5);
  // The filter knows the simulator's odometry and laser noise models; the walls of the simulated
  // corridor are exactly straight, so the floors that stand for model error are small.
  estimation::SlamOptionsOf<estimation::EkfLineSlamOptions> wrapped;
  estimation::EkfLineSlamOptions& options = wrapped.options();
  options.extraction.range_sigma_m = sim_options.laser.noise_floor_m;
  options.extraction.range_sigma_fraction = 0.0;
  options.line_rho_floor_m = 0.001 * args.line_floor_scale;
  options.line_theta_floor_rad = 0.0005 * args.line_floor_scale;
  options.corner_sigma_m = args.corner_floor_m;
  options.use_corners = args.corners;
  options.association = args.association;
  options.odometry.translation_floor_m = args.odometry_floor;
  options.odometry.rotation_floor_rad = args.odometry_floor;

  const auto& distances = CorridorDistances();
  CorridorResult result;
  result.measured.resize(distances.size());
  result.average_nees.assign(static_cast<std::size_t>(args.steps) + 1, 0.0);
  for (int run = 0; run < args.runs; ++run) {
    // The straight run, then the filter over its frames.
    sim::Simulator simulator(caster, sim_options, *world.start,
                             args.seed + static_cast<std::uint64_t>(run));
    std::vector<sim::SensorFrame> frames = {simulator.Sense()};
    for (int step = 1; step <= args.steps; ++step) {
      if (!simulator.Step(args.speed_mps, 0.0)) {
        result.error = "the robot hit a wall at step " + std::to_string(step);
        return result;
      }
      frames.push_back(simulator.Sense());
    }
    auto made = estimation::SlamRegistry::Global().Make("ekf-lines", &wrapped, {*world.start, {}});
    if (!made.ok()) {
      result.error = made.error;
      return result;
    }
    SlamDriver driver(std::move(*made.value));
    const ReplayResult replay = ReplayFrames(frames, sim_options.laser.robot_T_laser, &driver);
    if (replay.failed_at) {
      result.error =
          "run " + std::to_string(run) + " failed: " + driver.method().health().message();
      return result;
    }
    for (std::size_t step = 0; step < replay.nees.size(); ++step)
      result.average_nees[step] += replay.nees[step];  // the sum, averaged below
    result.nees.push_back(replay.nees);
    const kernel::Pose2& truth = frames.back().true_pose;
    result.final_error_m.push_back(
        (replay.estimate.back().pose.translation() - truth.translation()).norm());
    result.final_odometry_error_m.push_back(
        (frames.back().odometry_pose.translation() - truth.translation()).norm());
    const estimation::SlamMap map = driver.method().Map();
    result.measured_by_run.emplace_back();
    for (std::size_t k = 0; k < distances.size(); ++k) {
      const auto d = MeasuredDistance(distances[k], map.lines, map.corners);
      if (d) result.measured[k].push_back(*d);
      result.measured_by_run.back().push_back(d);
    }
    if (run == 0) {
      result.truth = replay.truth;
      result.estimate = replay.estimate;
      result.odometry = replay.odometry;
      result.lines = map.lines;
      result.corners = map.corners;
    }
  }
  for (double& nees : result.average_nees) nees /= args.runs;
  return result;
}

namespace {

// The first run's map over the world and its errors over time; empty on success.
kernel::Status SaveCorridorPictures(const CorridorOptions& options, const CorridorResult& result,
                                    const std::string& out) {
  const sim::World world = *sim::BuiltinWorld("corridor");
  io::RunPicture picture;
  picture.title =
      fmt::format("corridor, LMS-200, {} steps from 2.7 deg: {} lines, {} corners (seed {})",
                  options.steps, result.lines.size(), result.corners.size(), options.seed);
  picture.world = &world;
  picture.world_color = io::Rgb{0.75, 0.75, 0.75};
  picture.truth = result.truth;
  picture.odometry = result.odometry;
  picture.estimates = {{"estimate", result.estimate}};
  estimation::SlamMap map;
  map.lines = result.lines;
  map.corners = result.corners;
  io::DrawMap(map, &picture);
  return kernel::FirstError(
      io::SaveRunPicture(picture, {out + "/map.svg", out + "/map.png"}),
      io::SaveErrorPlot("corridor run, seed " + std::to_string(options.seed), result.truth,
                        {{"odometry", io::palette::kOdometry, result.odometry},
                         {"ekf-lines", io::palette::kEstimate, result.estimate}},
                        {out + "/errors.svg", out + "/errors.png"}));
}

// 001 Table 1: the nine distances, true and mapped (mean +- std over the runs mapping them);
// printed, returned as Markdown and added to the report.
std::string Table1(const CorridorOptions& options, const CorridorResult& result,
                   nlohmann::ordered_json* report) {
  const auto& distances = CorridorDistances();
  const std::vector<std::vector<double>>& measured = result.measured;
  (*report)["experiment"] = "corridor-lines (paper 001 section 6)";
  (*report)["runs"] = options.runs;
  (*report)["steps"] = options.steps;
  std::string table =
      "| distance | true (m) | SLAM (m), mean +- std over runs | error (%) | mapped in runs "
      "|\n|---|---|---|---|---|\n";
  fmt::print("{}", table);
  for (std::size_t k = 0; k < distances.size(); ++k) {
    const double truth = distances[k].TrueValue();
    const std::vector<double>& v = measured[k];
    std::string row;
    if (v.empty()) {
      row = fmt::format("| {} | {:.3f} | not mapped | - | 0/{} |\n", distances[k].name, truth,
                        options.runs);
      (*report)["distances"].push_back(
          {{"name", distances[k].name}, {"true_m", truth}, {"mapped_runs", 0}});
    } else {
      const auto [mean, std] = evaluation::MeanStd(v);
      const double error = 100.0 * std::abs(mean - truth) / truth;
      row = fmt::format("| {} | {:.3f} | {:.3f} +- {:.3f} | {:.2f} | {}/{} |\n", distances[k].name,
                        truth, mean, std, error, v.size(), options.runs);
      (*report)["distances"].push_back({{"name", distances[k].name},
                                        {"true_m", truth},
                                        {"slam_mean_m", mean},
                                        {"slam_std_m", std},
                                        {"error_percent", error},
                                        {"mapped_runs", v.size()}});
    }
    table += row;
    fmt::print("{}", row);
  }
  return table;
}

// Every run's raw numbers, for a merge of one-run cells: NEES per step, final errors, and each
// distance as mapped (null when not).
nlohmann::ordered_json PerRunJson(const CorridorResult& result) {
  nlohmann::ordered_json runs = nlohmann::ordered_json::array();
  for (std::size_t r = 0; r < result.nees.size(); ++r) {
    nlohmann::ordered_json measured = nlohmann::ordered_json::array();
    for (const std::optional<double>& d : result.measured_by_run[r])
      measured.push_back(d ? nlohmann::ordered_json(*d) : nlohmann::ordered_json());
    runs.push_back({{"nees", result.nees[r]},
                    {"final_error_m", result.final_error_m[r]},
                    {"final_odometry_error_m", result.final_odometry_error_m[r]},
                    {"measured_m", measured}});
  }
  return runs;
}

// The runs of one-run cells' report.json merged into one result (no trajectories or map: the
// pictures are the first cell's); the error names a cell without them.
CorridorResult MergeRuns(const std::vector<nlohmann::json>& reports, int steps) {
  CorridorResult result;
  result.measured.resize(CorridorDistances().size());
  result.average_nees.assign(static_cast<std::size_t>(steps) + 1, 0.0);
  for (const nlohmann::json& report : reports) {
    for (const nlohmann::json& run : report["per_run"]) {
      const std::vector<double> nees = run["nees"];
      for (std::size_t step = 0; step < nees.size() && step < result.average_nees.size(); ++step)
        result.average_nees[step] += nees[step];
      result.nees.push_back(nees);
      result.final_error_m.push_back(run["final_error_m"]);
      result.final_odometry_error_m.push_back(run["final_odometry_error_m"]);
      result.measured_by_run.emplace_back();
      for (std::size_t k = 0; k < result.measured.size(); ++k) {
        const nlohmann::json& d = run["measured_m"][k];
        if (!d.is_null()) result.measured[k].push_back(d.get<double>());
        result.measured_by_run.back().push_back(
            d.is_null() ? std::nullopt : std::optional<double>(d.get<double>()));
      }
    }
  }
  for (double& nees : result.average_nees) nees /= static_cast<double>(result.nees.size());
  return result;
}

int WriteCorridorResult(const CorridorOptions& options, const CorridorResult& result,
                        const std::string& out) {
  nlohmann::ordered_json report;
  const std::string table = Table1(options, result, &report);
  // Consistency.
  const double n = options.runs;
  const double lo = estimation::ChiSquareQuantile(0.025, 3 * n) / n,
               hi = estimation::ChiSquareQuantile(0.975, 3 * n) / n;
  const std::vector<double>& average = result.average_nees;
  std::vector<double> steps;
  int inside = 0;
  for (int s = 0; s <= options.steps; ++s) {
    steps.push_back(s);
    inside += average[s] >= lo && average[s] <= hi;
  }
  const double fraction = static_cast<double>(inside) / (options.steps + 1);
  double mean_final = 0, mean_odometry = 0;
  for (std::size_t i = 0; i < result.final_error_m.size(); ++i)
    mean_final += result.final_error_m[i], mean_odometry += result.final_odometry_error_m[i];
  mean_final /= n;
  mean_odometry /= n;
  report["nees"] = {
      {"band", {lo, hi}}, {"fraction_of_steps_inside", fraction}, {"passed", fraction >= 0.9}};
  report["final_position_error_m"] = {{"ekf_lines_mean", mean_final},
                                      {"odometry_mean", mean_odometry}};
  io::PlotOptions plot_options;
  plot_options.title =
      fmt::format("average NEES over {} runs; 95 % band [{:.2f}, {:.2f}]: {:.0f} % of steps inside",
                  options.runs, lo, hi, 100 * fraction);
  plot_options.x_label = "step";
  const io::PlotPanel panel{
      "NEES (3 dof)",
      {{"average NEES", io::palette::kEstimate, steps, average},
       {"95 % band", io::palette::kOdometry, {0.0, static_cast<double>(options.steps)}, {lo, lo}},
       {"", io::palette::kOdometry, {0.0, static_cast<double>(options.steps)}, {hi, hi}}}};
  if (kernel::Status e =
          io::SavePlot({panel}, plot_options, {out + "/nees.svg", out + "/nees.png"});
      !e.ok()) {
    fmt::print(stderr, "splam experiment: {}\n", e.message());
    return kExitBadInput;
  }
  report["per_run"] = PerRunJson(result);
  if (const int status = WriteExperimentFiles(
          {{out + "/table1.md", table}, {out + "/report.json", JsonText(report, 2) + "\n"}});
      status != kExitOk)
    return status;
  if (kernel::Status s = WriteRunHtml(out, "splam experiment corridor-lines (paper 001 Table 1)");
      !s.ok()) {
    fmt::print(stderr, "splam experiment: {}\n", s.message());
    return kExitBadInput;
  }
  fmt::print("average NEES inside the 95 % band [{:.2f}, {:.2f}] for {:.1f} % of {} steps ({})\n",
             lo, hi, 100 * fraction, options.steps + 1,
             fraction >= 0.9 ? "consistent" : "NOT consistent");
  fmt::print("final position error: ekf-lines {:.3f} m, odometry {:.3f} m (mean of {} runs)\n",
             mean_final, mean_odometry, options.runs);
  fmt::print(
      "wrote {}/{{table1.md, report.json, report.html, nees.svg, nees.png, map.svg, map.png, "
      "errors.svg, "
      "errors.png}}\n",
      out);
  return kExitOk;
}

}  // namespace

io::Grid CorridorGrid(const CorridorOptions& options) {
  io::Grid grid;
  grid.command = {"experiment", "corridor-lines"};
  grid.options = {{"runs", "1", false},
                  {"steps", std::to_string(options.steps), false},
                  {"speed", fmt::format("{}", options.speed_mps), false},
                  {"corner-floor", fmt::format("{}", options.corner_floor_m), false},
                  {"odometry-floor", fmt::format("{}", options.odometry_floor), false},
                  {"line-floor-scale", fmt::format("{}", options.line_floor_scale), false}};
  if (!options.corners) grid.options.push_back({"no-corners", "true", false});
  if (options.association == estimation::EkfAssociation::kJointCompatibility)
    grid.options.push_back({"association", "jcbb", false});
  grid.axes = {io::SeedAxis(options.seed, options.runs)};
  grid.figures = {"nees.fraction_of_steps_inside", "final_position_error_m.ekf_lines_mean",
                  "final_position_error_m.odometry_mean"};
  return grid;
}

int RunCorridorLinesExperiment(const CorridorOptions& options, const std::string& out) {
  std::filesystem::create_directories(out);
  if (options.runs == 1) {  // here, with the pictures of this run
    const CorridorResult result = RunCorridorExperiment(options);
    if (!result.error.empty()) {
      fmt::print(stderr, "splam experiment: {}\n", result.error);
      return kExitIncomplete;
    }
    if (kernel::Status e = SaveCorridorPictures(options, result, out); !e.ok()) {
      fmt::print(stderr, "splam experiment: {}\n", e.message());
      return kExitBadInput;
    }
    return WriteCorridorResult(options, result, out);
  }
  if (const int status = RunExperimentTrials(out, CorridorGrid(options), options.splam_binary,
                                             options.jobs, options.stop);
      status != kExitOk)
    return status;
  std::vector<nlohmann::json> reports;
  for (int i = 0; i < options.runs; ++i) {
    const std::string dir =
        fmt::format("{}/cells/seed-{}", out, options.seed + static_cast<std::uint64_t>(i));
    std::optional<nlohmann::json> report = TrialReport(dir);
    if (!report) return kExitIncomplete;
    reports.push_back(std::move(*report));
    if (i > 0) continue;
    if (kernel::Status error =  // the first seed's pictures
        CopyTrialFiles(dir, out, {"map.svg", "map.png", "errors.svg", "errors.png"});
        !error.ok()) {
      fmt::print(stderr, "splam experiment: {}\n", error.message());
      return kExitBadInput;
    }
  }
  return WriteCorridorResult(options, MergeRuns(reports, options.steps), out);
}

}  // namespace splam::studies
