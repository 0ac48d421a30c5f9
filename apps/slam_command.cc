// splam slam: run a SLAM method over a CARMEN log (simulated or real).
#include <fmt/core.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "apps/run_picture.h"
#include "apps/slam_methods.h"
#include "estimation/chi_square.h"
#include "estimation/metrics.h"
#include "io/carmen.h"
#include "io/plot.h"
#include "io/simulation_log.h"
#include "io/world_file.h"
#include "kernel/angle.h"

namespace splam::apps {
namespace {

constexpr double kRealOdometryScale = 3.0;

struct SlamArgs {
  std::string method = "ekf-lines";
  std::string association = "curvature";  // ekf-bspline
  double max_curve_range_m = 0.0;         // ekf-bspline
  std::string log;
  std::string out;
  std::string world;
  int max_scans = 0;
  double flaser_step_deg = 0.0;
  double flaser_max_range_m = 81.8;
  // Range noise (line extraction, beam measurements); negative: chosen from the log's laser
  // type (Hokuyo URG: 1 % of the range; SICK LMS, FLASER logs: 1 cm).
  double range_sigma_m = -1.0;
  double range_sigma_fraction = -1.0;
  // Scale of the default odometry noise model; negative: 1 for simulated logs (ROBOTLASER1),
  // kRealOdometryScale for real FLASER logs, whose odometry is much worse than the simulator's.
  double odometry_noise_scale = -1.0;
};

int RunSlam(const SlamArgs& args) {
  io::CarmenReadOptions read_options;
  read_options.flaser_angular_step_rad = kernel::DegToRad(args.flaser_step_deg);
  read_options.flaser_max_range_m = args.flaser_max_range_m;
  const io::CarmenReadResult read = io::ReadCarmenLog(args.log, read_options);
  if (!read.log.ok()) {
    fmt::print(stderr, "splam slam: {}\n", read.log.error);
    return kExitBadInput;
  }
  const io::CarmenLog& log = *read.log.value;
  const auto lasers = log.Lasers();
  if (lasers.empty()) {
    fmt::print(stderr, "splam slam: {}: the log has no laser scans\n", args.log);
    return kExitBadInput;
  }
  // The world, for pictures: --world, or world.yaml beside a simulated log.
  std::optional<sim::World> world;
  std::string world_source = args.world;
  const std::filesystem::path beside = std::filesystem::path(args.log).parent_path() / "world.yaml";
  if (world_source.empty() && std::filesystem::exists(beside)) world_source = beside.string();
  if (!world_source.empty()) {
    io::Result<sim::World> w = io::LoadWorld(world_source);
    if (!w.ok()) {
      fmt::print(stderr, "splam slam: {}\n", w.error);
      return kExitBadInput;
    }
    world = std::move(w.value);
  }

  const bool urg = lasers[0]->format == io::LaserMessage::Format::kRobotLaser1 &&
                   lasers[0]->laser_type == io::kCarmenHokuyoUrg;
  const double sigma = args.range_sigma_m >= 0 ? args.range_sigma_m : (urg ? 0.003 : 0.01);
  const double sigma_fraction =
      args.range_sigma_fraction >= 0 ? args.range_sigma_fraction : (urg ? 0.01 : 0.0);
  const bool real = lasers[0]->format == io::LaserMessage::Format::kFlaser;
  const double scale = args.odometry_noise_scale >= 0 ? args.odometry_noise_scale
                                                      : (real ? kRealOdometryScale : 1.0);
  // The estimate starts at the first odometric pose with a small covariance: the map frame is
  // the odometry frame (for simulated runs, the true frame).
  SlamSettings settings;
  settings.method = args.method;
  settings.association = args.association;
  settings.max_curve_range_m = args.max_curve_range_m;
  settings.odometry_noise_scale = scale;
  settings.range_sigma_m = sigma;
  settings.range_sigma_fraction = sigma_fraction;
  // The simulator's URG noise has no constant part; a --range-sigma given is used as it is.
  settings.beam_sigma_floor_m = args.range_sigma_m >= 0 ? args.range_sigma_m : (urg ? 0.0 : sigma);
  std::string problem;
  std::unique_ptr<SlamMethod> slam = MakeSlamMethod(settings, lasers[0]->robot_pose, &problem);
  if (!problem.empty()) {
    fmt::print(stderr, "splam slam: {}\n", problem);
    return kExitBadInput;
  }
  const std::string label =
      args.method == "ekf-bspline" ? args.method + " (" + args.association + ")" : args.method;
  const std::string out =
      args.out.empty() ? "runs/slam-" + std::filesystem::path(args.log).stem().string() : args.out;
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) {
    fmt::print(stderr, "splam slam: cannot create {}: {}\n", out, ec.message());
    return kExitBadInput;
  }

  const io::Trajectory truth = io::TrueTrajectory(log);
  const std::size_t n =
      args.max_scans > 0 ? std::min<std::size_t>(args.max_scans, lasers.size()) : lasers.size();
  io::Trajectory estimate, odometry;
  std::vector<double> step_ms, nees;
  std::vector<std::size_t> map_size;  // after each step
  const auto wall_start = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < n; ++i) {
    const io::LaserMessage& m = *lasers[i];
    const auto t0 = std::chrono::steady_clock::now();
    if (i > 0) slam->Predict(lasers[i - 1]->robot_pose.Between(m.robot_pose));
    slam->Update(m.scan, m.robot_pose.Between(m.laser_pose));
    step_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    map_size.push_back(slam->MapSize());
    if (!slam->healthy()) {
      fmt::print(stderr, "splam slam: the filter failed at scan {} (t = {} s): {}\n", i,
                 m.stamp.ipc_timestamp_s, slam->health());
      break;
    }
    estimate.push_back({m.stamp.ipc_timestamp_s, slam->pose()});
    odometry.push_back({m.stamp.ipc_timestamp_s, m.robot_pose});
    const auto t = kernel::PoseAt(truth, m.stamp.ipc_timestamp_s, 0.0, 1e-3);
    if (const auto covariance = slam->pose_covariance(); t && covariance) {
      nees.push_back(estimation::PoseNees(*t, slam->pose(), *covariance));
    }
    if ((i + 1) % 1000 == 0) {
      fmt::print("  {}/{} scans, {} in the map\n", i + 1, n, slam->MapDescription());
      std::fflush(stdout);
    }
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  const double data_s = estimate.empty() ? 0.0 : estimate.back().time_s - estimate.front().time_s;

  // Files.
  std::vector<std::string> errors = slam->WriteMap(out);
  errors.push_back(
      io::WriteTrajectory(out + "/trajectory.txt", estimate, label + " estimate of " + args.log));
  errors.push_back(io::WriteTrajectory(out + "/odometry.txt", odometry, "odometry of " + args.log));
  if (!truth.empty())
    errors.push_back(io::WriteTrajectory(out + "/truth.txt", truth, "ground truth of " + args.log));

  RunPicture picture;
  picture.title =
      fmt::format("{} on {}: {}", label, std::filesystem::path(args.log).filename().string(),
                  slam->MapDescription());
  picture.world = world ? &*world : nullptr;
  picture.world_color = io::Rgb{0.75, 0.75, 0.75};
  picture.truth = truth;
  picture.odometry = odometry;
  picture.estimates = {{"estimate", estimate}};
  slam->DrawMap(&picture);
  picture.pixels_per_meter = 40.0;
  errors.push_back(SaveRunPicture(picture, {out + "/map.svg", out + "/map.png"}));

  nlohmann::ordered_json summary;
  summary["method"] = args.method;
  if (args.method == "ekf-bspline") summary["association"] = args.association;
  summary["odometry_noise_scale"] = scale;
  summary["range_noise_model"] = {{"range_sigma_m", sigma},
                                  {"range_sigma_fraction", sigma_fraction}};
  summary["log"] = args.log;
  summary["scans"] = estimate.size();
  summary["data_duration_s"] = data_s;
  summary["wall_time_s"] = wall_s;
  summary["real_time_factor"] = wall_s > 0 ? data_s / wall_s : 0.0;
  summary["time_per_scan_ms"] = {
      {"mean", step_ms.empty() ? 0.0 : wall_s * 1000.0 / static_cast<double>(step_ms.size())},
      {"median", Percentile(step_ms, 0.5)},
      {"p95", Percentile(step_ms, 0.95)},
      {"max", Percentile(step_ms, 1.0)}};
  summary["time_per_scan_vs_map_size"] = TimeByMapSize(step_ms, map_size);
  summary.update(slam->Statistics());
  summary["health"] = {{"healthy", slam->healthy()},
                       {"message", slam->health()},
                       {"scans_processed", estimate.size()},
                       {"scans_in_log", lasers.size()}};
  if (const auto p = slam->pose_covariance()) {
    summary["health"]["final_pose_sigma"] = {std::sqrt((*p)(0, 0)), std::sqrt((*p)(1, 1)),
                                             std::sqrt((*p)(2, 2))};
  }
  if (!truth.empty()) {
    summary["error"] = {{"estimate", ErrorJson(estimation::CompareToTruth(truth, estimate))},
                        {"odometry", ErrorJson(estimation::CompareToTruth(truth, odometry))}};
    const double lo = estimation::ChiSquareQuantile(0.025, 3),
                 hi = estimation::ChiSquareQuantile(0.975, 3);
    double sum = 0.0;
    std::size_t inside = 0;
    for (double v : nees) {
      sum += v;
      inside += v >= lo && v <= hi;
    }
    if (!nees.empty()) {
      summary["nees"] = {
          {"mean", sum / static_cast<double>(nees.size())},
          {"fraction_in_95_band", static_cast<double>(inside) / static_cast<double>(nees.size())},
          {"steps", nees.size()}};
    }
    errors.push_back(SaveErrorPlot(
        label + ": error against ground truth", truth,
        {{"odometry", io::palette::kOdometry, odometry}, {label, io::palette::kEstimate, estimate}},
        {out + "/errors.svg", out + "/errors.png"}));
  }
  std::ofstream(out + "/summary.json") << summary.dump(2) << "\n";
  for (const std::string& e : errors) {
    if (!e.empty()) {
      fmt::print(stderr, "splam slam: {}\n", e);
      return kExitBadInput;
    }
  }
  fmt::print(
      "{} scans ({:.0f} s of data) in {:.1f} s: {:.1f}x real time, {:.2f} ms per scan (median "
      "{:.2f})\n",
      estimate.size(), data_s, wall_s, wall_s > 0 ? data_s / wall_s : 0.0,
      summary["time_per_scan_ms"]["mean"].get<double>(), Percentile(step_ms, 0.5));
  fmt::print("map: {}; associations: {}\n", slam->MapDescription(), summary["associations"].dump());
  if (!truth.empty()) {
    const auto e = estimation::CompareToTruth(truth, estimate);
    const auto o = estimation::CompareToTruth(truth, odometry);
    fmt::print(
        "position RMSE: {} {:.3f} m, odometry {:.3f} m; heading RMSE: {:.2f} deg, {:.2f} "
        "deg\n",
        label, e.rmse_position_m, o.rmse_position_m, kernel::RadToDeg(e.rmse_heading_rad),
        kernel::RadToDeg(o.rmse_heading_rad));
  }
  fmt::print(
      "wrote {}/{{trajectory.txt, odometry.txt, map.txt, map.dxf, map.svg, map.png, "
      "summary.json{}}}\n",
      out, truth.empty() ? "" : ", truth.txt, errors.svg, errors.png");
  if (!slam->healthy()) return kExitIncomplete;
  return kExitOk;
}

}  // namespace

void AddSlamCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<SlamArgs>();
  CLI::App* cmd = app->add_subcommand("slam",
                                      "Run a SLAM method over a CARMEN log; write the trajectory, "
                                      "the map, pictures and a summary.");
  cmd->add_option("--method", args->method, "SLAM method")
      ->check(CLI::IsMember({"ekf-lines", "ekf-bspline", "topological"}))
      ->capture_default_str();
  cmd->add_option("--association", args->association,
                  "ekf-bspline data association: pedraza (end points) or curvature (paper 000)")
      ->check(CLI::IsMember({"pedraza", "curvature"}))
      ->capture_default_str();
  cmd->add_option("log", args->log, "CARMEN log (simulated or real)")->required();
  cmd->add_option("--max-curve-range", args->max_curve_range_m,
                  "ekf-bspline: beams longer than this (metres) are not used for curves; 0 = the "
                  "laser's maximum range")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--out", args->out, "Output directory (default runs/slam-<log>)");
  cmd->add_option("--world", args->world,
                  "World to draw under the map (default: world.yaml beside the log, if any)");
  cmd->add_option("--max-scans", args->max_scans, "Process only the first N scans (0 = all)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--flaser-step-deg", args->flaser_step_deg,
                  "FLASER beam spacing in degrees (0: 180/n or 180/(n-1))")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--flaser-max-range", args->flaser_max_range_m,
                  "FLASER readings at or above this are no-returns")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--range-sigma", args->range_sigma_m,
                  "Laser range noise, metres (constant part); default from the log's laser type: "
                  "3 mm for a Hokuyo URG, 1 cm for SICK and FLASER logs")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option(
         "--range-sigma-fraction", args->range_sigma_fraction,
         "Laser range noise, fraction of the range; default 0.01 for a Hokuyo URG, 0 otherwise")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--odometry-noise", args->odometry_noise_scale,
                  "Scale of the default odometry noise model (3 % of distance and rotation); "
                  "default 1 for simulated "
                  "logs and 3 for real FLASER logs")
      ->check(CLI::NonNegativeNumber);
  cmd->callback([args, exit_code] { *exit_code = RunSlam(*args); });
}

}  // namespace splam::apps
