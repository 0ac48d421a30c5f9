// Tutorial: build a world in code, drive the simulated robot through it, and look at what its
// laser saw. Usage: example_sim [picture.png]
#include <cstdio>
#include <string>

#include "io/render.h"
#include "sim/ray_caster.h"
#include "sim/simulator.h"

int main(int argc, char** argv) {
  namespace sim = splam::sim;
  using splam::kernel::Pose2;
  const std::string picture = argc > 1 ? argv[1] : "example_sim.png";

  // 1. A world: a room of straight walls, a round pillar, an elliptical table and a curved wall
  //    given as a cubic B-spline (clamped: it starts and ends at its end control points).
  sim::World world;
  world.name = "tutorial";
  world.obstacles.push_back(sim::Polyline{{{0, 0}, {8, 0}, {8, 6}, {0, 6}, {0, 0}}, false});
  world.obstacles.push_back(splam::kernel::Circle2{{3.0, 2.0}, 0.3});
  world.obstacles.push_back(splam::kernel::Ellipse2{{6.0, 4.5}, 0.8, 0.4, 0.3});
  world.obstacles.push_back(sim::Spline{{{1.0, 4.0}, {2.0, 5.2}, {3.5, 3.6}, {4.5, 4.8}}, false});
  //    A person walking back and forth across the room at 1 m/s: the laser sees a disc of
  //    0.25 m, but it is no obstacle (no map holds it, and the robot drives through it).
  world.people.push_back(sim::Walker{{{5.0, 0.5}, {5.0, 3.5}}, 1.0, 0.25, 0.0});
  //    A glass partition (obstacle 4): a wall for the robot, but the laser reads no return where
  //    it meets glass, as real lasers do at windows and glass doors.
  world.obstacles.push_back(sim::Polyline{{{7.0, 5.9}, {7.0, 5.0}}, false});
  world.glass.push_back(4);
  if (const splam::kernel::Status problem = world.Validate(); !problem.ok()) {
    std::fprintf(stderr, "invalid world: %s\n", problem.message().c_str());
    return 1;
  }

  // 2. The ray caster indexes the obstacles once; every sensor uses it.
  const sim::RayCaster caster(world);

  // 3. The simulator: a Pioneer-sized robot with a URG-04LX laser and noisy odometry. The seed
  //    fixes every random draw: the same seed gives the same run.
  sim::SimulatorOptions options;  // defaults: URG-04LX, odometry noise of a few per cent
  sim::Simulator simulator(caster, options, Pose2(1.0, 1.0, 0.0), /*seed=*/42);
  simulator.SetPeople(world.people);

  // 4. Drive a loop of waypoints; a sensor frame is recorded after every 0.1 s step.
  const sim::RouteRun run =
      sim::FollowRoute(&simulator, {{6.5, 1.0}, {6.5, 3.0}, {1.5, 2.8}}, sim::RouteOptions());
  std::printf("%s after %zu frames, %.2f m driven\n",
              run.completed ? "route completed" : run.message.c_str(), run.frames.size(),
              run.distance_m);

  // 5. Compare ground truth and odometry at the end, and count what the last scan saw.
  const sim::SensorFrame& last = run.frames.back();
  const Pose2 error = last.true_pose.Between(last.odometry_pose);
  std::printf("odometry error at the end: %.3f m, %.4f rad\n", error.translation().norm(),
              error.theta());
  std::printf("last scan: %zu of %zu beams hit something\n", last.scan.HitIndices().size(),
              last.scan.size());

  // 6. A picture: the world, both trajectories and the last scan in the world frame.
  std::vector<Pose2> truth, odometry;
  for (const sim::SensorFrame& f : run.frames) {
    truth.push_back(f.true_pose);
    odometry.push_back(f.odometry_pose);
  }
  splam::io::FigureOptions figure_options;
  figure_options.title = "tutorial world";
  splam::io::Figure figure(world.Bounds(), figure_options);
  figure.DrawPoints(last.true_pose * last.scan.HitPoints(), splam::io::palette::kScan, 1.5,
                    "last scan");
  figure.DrawWorld(world);
  figure.DrawPolyline(world.people[0].path, splam::io::palette::kPeople, 1.0, "a person's walk",
                      /*dashed=*/true);
  figure.DrawPath(odometry, splam::io::palette::kOdometry, 1.5, "odometry");
  figure.DrawPath(truth, splam::io::palette::kTrue, 1.5, "ground truth");
  figure.DrawRobot(last.true_pose, options.robot.radius_m, splam::io::palette::kTrue);
  if (const splam::kernel::Status error_message = figure.Save(picture); !error_message.ok()) {
    std::fprintf(stderr, "%s\n", error_message.message().c_str());
    return 1;
  }
  std::printf("wrote %s\n", picture.c_str());
  return run.completed ? 0 : 1;
}
