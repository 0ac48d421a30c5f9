// Tutorial: EKF-SLAM with line and corner landmarks, step by step, on a simulated run.
// Usage: example_estimation [picture.png]
#include <cstdio>
#include <string>

#include "estimation/ekf/ekf_line_slam.h"
#include "estimation/evaluation/metrics.h"
#include "estimation/slam_method.h"
#include "io/render.h"
#include "runtime/log_replay.h"
#include "sim/builtin_worlds.h"
#include "sim/simulator.h"

int main(int argc, char** argv) {
  namespace estimation = splam::estimation;
  namespace evaluation = splam::evaluation;
  namespace sim = splam::sim;
  using splam::kernel::Pose2;
  const std::string picture = argc > 1 ? argv[1] : "example_estimation.png";

  // 1. A simulated run: the office world, an LMS-200 laser, odometry with a few per cent of noise.
  const sim::World world = *sim::BuiltinWorld("office");
  const sim::RayCaster caster(world);
  sim::SimulatorOptions sim_options;
  sim_options.laser = sim::LaserOptions::Lms200();
  sim::Simulator simulator(caster, sim_options, *world.start, /*seed=*/7);
  const sim::RouteRun run = sim::FollowRoute(&simulator, world.route, sim::RouteOptions());

  // 2. The filter, by its registry name, with its options. Its odometry noise model has the
  //    same form and defaults as the simulator's; the line extractor is told the laser's range
  //    noise (1 cm for the LMS-200).
  estimation::SlamOptionsOf<estimation::EkfLineSlamOptions> options;
  options.options().extraction.range_sigma_m = 0.01;
  options.options().extraction.range_sigma_fraction = 0.0;
  auto made = estimation::SlamRegistry::Global().Make("ekf-lines", &options,
                                                      {run.frames[0].odometry_pose, {}});
  if (!made.ok()) {
    std::fprintf(stderr, "%s\n", made.error.c_str());
    return 1;
  }

  // 3. Every scan: the driver predicts with the odometry increment, then updates with the scan's
  //    lines and corners (extraction, Mahalanobis association with a chi-square gate, EKF
  //    correction, new landmarks). `splam slam` replays logs through the same driver.
  splam::runtime::SlamDriver driver(std::move(*made.value));
  const splam::runtime::ReplayResult replay =
      splam::runtime::ReplayFrames(run.frames, sim_options.laser.robot_T_laser, &driver);
  const estimation::SlamMethod& slam = driver.method();
  const splam::kernel::Trajectory& truth = replay.truth;
  const splam::kernel::Trajectory& estimate = replay.estimate;
  const splam::kernel::Trajectory& odometry = replay.odometry;

  // 4. How good is it? Position and heading error against the simulator's ground truth.
  const evaluation::TrajectoryError e = evaluation::CompareToTruth(truth, estimate);
  const evaluation::TrajectoryError o = evaluation::CompareToTruth(truth, odometry);
  std::printf("%zu scans; map: %s; filter %s\n", run.frames.size(), slam.MapDescription().c_str(),
              slam.healthy() ? "healthy" : slam.health().message().c_str());
  std::printf(
      "position RMSE: EKF %.3f m, odometry %.3f m; heading RMSE: EKF %.4f rad, odometry %.4f rad\n",
      e.rmse_position_m, o.rmse_position_m, e.rmse_heading_rad, o.rmse_heading_rad);

  // 5. The map over the world, with the three trajectories.
  splam::io::FigureOptions figure_options;
  figure_options.title = "EKF-SLAM with lines in the office";
  splam::io::Figure figure(world.Bounds(), figure_options);
  figure.DrawWorld(world, splam::io::Rgb{0.8, 0.8, 0.8});
  const estimation::SlamMap map = slam.Map();
  for (const estimation::MapLine& l : map.lines) {
    figure.DrawPolyline({l.start, l.end}, splam::io::palette::kMap, 2.5, "map lines");
  }
  std::vector<Eigen::Vector2d> corners;
  for (const estimation::MapCorner& c : map.corners) corners.push_back(c.position);
  figure.DrawMarkers(corners, splam::io::Figure::Marker::kDiamond, splam::io::palette::kMap, 5.0,
                     "map corners");
  figure.DrawPath(splam::kernel::Poses(odometry), splam::io::palette::kOdometry, 1.5, "odometry");
  figure.DrawPath(splam::kernel::Poses(estimate), splam::io::palette::kEstimate, 1.5, "estimate");
  figure.DrawPath(splam::kernel::Poses(truth), splam::io::palette::kTrue, 1.0, "ground truth");
  if (const splam::kernel::Status error = figure.Save(picture); !error.ok()) {
    std::fprintf(stderr, "%s\n", error.message().c_str());
    return 1;
  }
  std::printf("wrote %s\n", picture.c_str());
  return slam.healthy() && e.rmse_position_m < o.rmse_position_m ? 0 : 1;
}
