// splam experiment: the published experiments, reproduced on the simulator.
//
// corridor-lines (paper 001 §6): EKF-SLAM with lines and corners on a straight run of 160 steps
// through the `corridor` world, started 2.7 deg off the corridor axis, with a SICK LMS-200.
// Reports, as 001 Table 1, nine distances between mapped corners next to their true values, and
// checks the filter's consistency: the average NEES of the robot pose over the seeded runs must
// stay inside the 95 % chi-square band for at least 90 % of the steps.
#include <fmt/core.h>
#include <Eigen/LU>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "apps/bspline_experiment.h"
#include "apps/commands.h"
#include "apps/exploration_experiment.h"
#include "apps/run_picture.h"
#include "apps/splam_experiment.h"
#include "estimation/chi_square.h"
#include "estimation/ekf_line_slam.h"
#include "estimation/metrics.h"
#include "io/plot.h"
#include "io/render.h"
#include "kernel/angle.h"
#include "sim/builtin_worlds.h"
#include "sim/simulator.h"

namespace splam::apps {
namespace {

struct ExperimentArgs {
  std::string name = "corridor-lines";
  int runs = 0;  // 0: the experiment's default (corridor-lines 20, complex-bspline 10)
  int max_scans = 0;
  double odometry_noise_scale = 1.0;            // complex-bspline
  double max_correspondence_distance_m = 0.15;  // complex-bspline
  int steps = 160;
  double speed_mps = 1.0;
  std::uint64_t seed = 1;
  std::string out;
  bool corners = true;
  double corner_floor_m = 0.01;
  double odometry_floor = 1e-4;
  double line_floor_scale = 1.0;  // scales the line floors of 1 mm and 0.5 mrad
};

// Nine distances between features the straight run maps, like the nine distances of 001 Table 1:
// the corridor's width and the two rooms' depths between parallel mapped walls, and six
// distances between mapped corners (driving along +x, the robot sees the recess walls that face
// it, so the far-side recess corners and the room corners are mapped).
struct Distance {
  std::string name;
  bool between_lines;
  Eigen::Vector2d a, b;                 // corners, or a point on each wall (lines)
  double a_theta = 0.0, b_theta = 0.0;  // wall normals (lines)
};
const std::vector<Distance>& CorridorDistances() {
  const double up = kernel::kPi / 2;
  static const std::vector<Distance> d = {
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

// The mapped line of a true wall through `point` with normal angle `theta`: the most observed
// mapped line within 5 deg and 0.2 m of it.
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

// The mapped position of a true corner: the nearest corner landmark within 0.25 m, else the
// nearest crossing of two mapped lines at least 30 deg apart within 0.25 m.
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

int RunCorridorLines(const ExperimentArgs& args) {
  const sim::World world = *sim::BuiltinWorld("corridor");
  const sim::RayCaster caster(world);
  sim::SimulatorOptions sim_options;
  sim_options.laser = sim::LaserOptions::Lms200(0.5);
  // The filter knows the simulator's odometry and laser noise models; the walls of the simulated
  // corridor are exactly straight, so the floors that stand for model error are small.
  estimation::EkfLineSlamOptions options;
  options.extraction.range_sigma_m = sim_options.laser.noise_floor_m;
  options.extraction.range_sigma_fraction = 0.0;
  options.line_rho_floor_m = 0.001 * args.line_floor_scale;
  options.line_theta_floor_rad = 0.0005 * args.line_floor_scale;
  options.corner_sigma_m = args.corner_floor_m;
  options.use_corners = args.corners;
  options.odometry.translation_floor_m = args.odometry_floor;
  options.odometry.rotation_floor_rad = args.odometry_floor;
  std::filesystem::create_directories(args.out);

  const auto& distances = CorridorDistances();
  std::vector<std::vector<double>> measured(distances.size());
  std::vector<double> nees_sum(args.steps + 1, 0.0);
  std::vector<double> final_error, odometry_error;
  for (int run = 0; run < args.runs; ++run) {
    sim::Simulator simulator(caster, sim_options, *world.start,
                             args.seed + static_cast<std::uint64_t>(run));
    estimation::EkfLineSlam slam(*world.start, Eigen::Vector3d(1e-6, 1e-6, 1e-8).asDiagonal(),
                                 options);
    sim::SensorFrame frame = simulator.Sense();
    slam.Update(frame.scan);
    kernel::Trajectory truth, estimate, odometry;
    kernel::Pose2 last_odometry = frame.odometry_pose;
    for (int step = 0; step <= args.steps; ++step) {
      if (step > 0) {
        if (!simulator.Step(args.speed_mps, 0.0)) {
          fmt::print(stderr, "splam experiment: the robot hit a wall at step {}\n", step);
          return kExitIncomplete;
        }
        frame = simulator.Sense();
        slam.Predict(last_odometry.Between(frame.odometry_pose));
        last_odometry = frame.odometry_pose;
        slam.Update(frame.scan);
      }
      if (!slam.healthy()) {
        fmt::print(stderr, "splam experiment: run {} failed: {}\n", run, slam.health());
        return kExitIncomplete;
      }
      nees_sum[step] += estimation::PoseNees(frame.true_pose, slam.pose(), slam.pose_covariance());
      truth.push_back({frame.time_s, frame.true_pose});
      estimate.push_back({frame.time_s, slam.pose()});
      odometry.push_back({frame.time_s, frame.odometry_pose});
    }
    final_error.push_back((slam.pose().translation() - frame.true_pose.translation()).norm());
    odometry_error.push_back(
        (frame.odometry_pose.translation() - frame.true_pose.translation()).norm());
    const auto lines = slam.MapLines();
    const auto corners = slam.MapCorners();
    for (std::size_t k = 0; k < distances.size(); ++k) {
      const Distance& d = distances[k];
      if (d.between_lines) {
        const estimation::MapLine* a = MappedWall(d.a, d.a_theta, lines);
        const estimation::MapLine* b = MappedWall(d.b, d.b_theta, lines);
        if (a == nullptr || b == nullptr) continue;
        // Distance of the middle of b's extent from line a.
        const Eigen::Vector2d n(std::cos(a->line.theta), std::sin(a->line.theta));
        measured[k].push_back(std::abs(n.dot(0.5 * (b->start + b->end)) - a->line.rho));
      } else {
        const auto a = MappedCorner(d.a, corners, lines);
        const auto b = MappedCorner(d.b, corners, lines);
        if (a && b) measured[k].push_back((*a - *b).norm());
      }
    }
    if (run == 0) {  // pictures of the first run
      RunPicture picture;
      picture.title =
          fmt::format("corridor, LMS-200, {} steps from 2.7 deg: {} lines, {} corners (seed {})",
                      args.steps, lines.size(), corners.size(), args.seed);
      picture.world = &world;
      picture.world_color = io::Rgb{0.75, 0.75, 0.75};
      picture.truth = truth;
      picture.odometry = odometry;
      picture.estimates = {{"estimate", estimate}};
      for (const auto& l : lines) picture.map_segments.push_back({l.start, l.end});
      for (const auto& c : corners) picture.map_corners.push_back(c.position);
      for (const std::string& e :
           {SaveRunPicture(picture, {args.out + "/map.svg", args.out + "/map.png"}),
            SaveErrorPlot("corridor run, seed " + std::to_string(args.seed), truth,
                          {{"odometry", io::palette::kOdometry, odometry},
                           {"ekf-lines", io::palette::kEstimate, estimate}},
                          {args.out + "/errors.svg", args.out + "/errors.png"})}) {
        if (!e.empty()) {
          fmt::print(stderr, "splam experiment: {}\n", e);
          return kExitBadInput;
        }
      }
    }
  }

  // Table 1.
  nlohmann::ordered_json report;
  report["experiment"] = "corridor-lines (paper 001 section 6)";
  report["runs"] = args.runs;
  report["steps"] = args.steps;
  std::string table =
      "| distance | true (m) | SLAM (m), mean +- std over runs | error (%) | mapped in runs "
      "|\n|---|---|---|---|---|\n";
  fmt::print("{}", table);
  for (std::size_t k = 0; k < distances.size(); ++k) {
    const double truth = distances[k].between_lines
                             ? std::abs(Eigen::Vector2d(std::cos(distances[k].a_theta),
                                                        std::sin(distances[k].a_theta))
                                            .dot(distances[k].b - distances[k].a))
                             : (distances[k].a - distances[k].b).norm();
    const std::vector<double>& v = measured[k];
    std::string row;
    if (v.empty()) {
      row = fmt::format("| {} | {:.3f} | not mapped | - | 0/{} |\n", distances[k].name, truth,
                        args.runs);
      report["distances"].push_back(
          {{"name", distances[k].name}, {"true_m", truth}, {"mapped_runs", 0}});
    } else {
      const auto [mean, std] = estimation::MeanStd(v);
      const double error = 100.0 * std::abs(mean - truth) / truth;
      row = fmt::format("| {} | {:.3f} | {:.3f} +- {:.3f} | {:.2f} | {}/{} |\n", distances[k].name,
                        truth, mean, std, error, v.size(), args.runs);
      report["distances"].push_back({{"name", distances[k].name},
                                     {"true_m", truth},
                                     {"slam_mean_m", mean},
                                     {"slam_std_m", std},
                                     {"error_percent", error},
                                     {"mapped_runs", v.size()}});
    }
    table += row;
    fmt::print("{}", row);
  }
  // Consistency.
  const double n = args.runs;
  const double lo = estimation::ChiSquareQuantile(0.025, 3 * n) / n,
               hi = estimation::ChiSquareQuantile(0.975, 3 * n) / n;
  std::vector<double> steps, average;
  int inside = 0;
  for (int s = 0; s <= args.steps; ++s) {
    steps.push_back(s);
    average.push_back(nees_sum[s] / n);
    inside += average.back() >= lo && average.back() <= hi;
  }
  const double fraction = static_cast<double>(inside) / (args.steps + 1);
  double mean_final = 0, mean_odometry = 0;
  for (std::size_t i = 0; i < final_error.size(); ++i)
    mean_final += final_error[i], mean_odometry += odometry_error[i];
  mean_final /= n;
  mean_odometry /= n;
  report["nees"] = {
      {"band", {lo, hi}}, {"fraction_of_steps_inside", fraction}, {"passed", fraction >= 0.9}};
  report["final_position_error_m"] = {{"ekf_lines_mean", mean_final},
                                      {"odometry_mean", mean_odometry}};
  io::PlotOptions plot_options;
  plot_options.title =
      fmt::format("average NEES over {} runs; 95 % band [{:.2f}, {:.2f}]: {:.0f} % of steps inside",
                  args.runs, lo, hi, 100 * fraction);
  plot_options.x_label = "step";
  const io::PlotPanel panel{
      "NEES (3 dof)",
      {{"average NEES", io::palette::kEstimate, steps, average},
       {"95 % band", io::palette::kOdometry, {0.0, static_cast<double>(args.steps)}, {lo, lo}},
       {"", io::palette::kOdometry, {0.0, static_cast<double>(args.steps)}, {hi, hi}}}};
  if (std::string e =
          io::SavePlot({panel}, plot_options, {args.out + "/nees.svg", args.out + "/nees.png"});
      !e.empty()) {
    fmt::print(stderr, "splam experiment: {}\n", e);
    return kExitBadInput;
  }
  std::ofstream(args.out + "/table1.md") << table;
  std::ofstream(args.out + "/report.json") << report.dump(2) << "\n";
  fmt::print("average NEES inside the 95 % band [{:.2f}, {:.2f}] for {:.1f} % of {} steps ({})\n",
             lo, hi, 100 * fraction, args.steps + 1,
             fraction >= 0.9 ? "consistent" : "NOT consistent");
  fmt::print("final position error: ekf-lines {:.3f} m, odometry {:.3f} m (mean of {} runs)\n",
             mean_final, mean_odometry, args.runs);
  fmt::print(
      "wrote {}/{{table1.md, report.json, nees.svg, nees.png, map.svg, map.png, errors.svg, "
      "errors.png}}\n",
      args.out);
  return kExitOk;
}

// An experiment's arguments with the shared ones (runs, seed, out) taken from the command line
// when given, else the experiment's defaults.
template <typename Args>
Args WithCommonArgs(const ExperimentArgs& given) {
  Args args;
  args.runs = given.runs > 0 ? given.runs : args.runs;
  args.seed = given.seed;
  args.out = given.out.empty() ? args.out : given.out;
  return args;
}

}  // namespace

void AddExperimentCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<ExperimentArgs>();
  CLI::App* cmd =
      app->add_subcommand("experiment", "Reproduce a published experiment on the simulator.");
  cmd->add_option("name", args->name,
                  "Experiment: corridor-lines (paper 001 section 6), complex-bspline (paper 000 "
                  "Figs. 15-17), exploration (paper 003 Fig. 18) or splam (paper 003 Figs. "
                  "19-22: SRT + ekf-lines, SRT + ekf-bspline, REG + topological)")
      ->check(CLI::IsMember({"corridor-lines", "complex-bspline", "exploration", "splam"}))
      ->capture_default_str();
  cmd->add_option("--runs", args->runs, "Seeded runs (default: 20 corridor-lines, 10 the others)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--max-scans", args->max_scans,
                  "complex-bspline: stop each route after this many scans (0 = the whole route)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--steps", args->steps, "Steps (scans) of the straight run")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--speed", args->speed_mps, "Forward speed, m/s (0.1 s per step)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "Seed of the first run; run i uses seed + i")
      ->capture_default_str();
  cmd->add_option("--out", args->out, "Output directory (default runs/experiment-<name>)");
  cmd->add_option("--odometry-noise", args->odometry_noise_scale,
                  "complex-bspline: scale of the odometry noise (simulated and modelled)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--max-correspondence", args->max_correspondence_distance_m,
                  "complex-bspline: largest distance (m) between a beam's predicted hit and the "
                  "map point its association paired it with; large values switch the test off")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("!--no-corners", args->corners, "Use lines only, no corner landmarks");
  cmd->add_option("--line-floor-scale", args->line_floor_scale,
                  "Scale of the line noise floors (1 mm, 0.5 mrad)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--corner-floor", args->corner_floor_m, "Corner measurement noise floor, m")
      ->capture_default_str();
  cmd->add_option("--odometry-floor", args->odometry_floor,
                  "Odometry noise floors per step (m and rad)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->callback([args, exit_code] {
    if (args->name == "splam") {
      *exit_code = RunSplamExperiment(WithCommonArgs<SplamExperimentArgs>(*args));
      return;
    }
    if (args->name == "exploration") {
      *exit_code = RunExplorationExperiment(WithCommonArgs<ExplorationExperimentArgs>(*args));
      return;
    }
    if (args->name == "complex-bspline") {
      BSplineExperimentArgs b = WithCommonArgs<BSplineExperimentArgs>(*args);
      b.max_scans = args->max_scans;
      b.odometry_noise_scale = args->odometry_noise_scale;
      b.max_correspondence_distance_m = args->max_correspondence_distance_m;
      *exit_code = RunComplexBSpline(b);
      return;
    }
    ExperimentArgs a = *args;
    a.runs = a.runs > 0 ? a.runs : 20;
    a.out = a.out.empty() ? "runs/experiment-corridor-lines" : a.out;
    *exit_code = RunCorridorLines(a);
  });
}

}  // namespace splam::apps
