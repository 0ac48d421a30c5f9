// Tutorial: plug a robot into an explorer, run SRT and REG, and couple REG with a SLAM method.
//
// An explorer only sees a RobotInterface (velocity commands, odometry, laser, sonar) and a
// Localization (where the robot believes it is). Here the robot is the built-in simulator behind
// loop::SimulatedRobot; the localisation is first its ground truth (exploration alone), then a
// registered SLAM method behind loop::SlamLocalization (the SPLAM loop: the explorer plans with
// the SLAM estimate). `splam explore` runs exactly these classes.
#include <cmath>
#include <cstdio>
#include <string>

#include "exploration/explorer.h"
#include "exploration/localization.h"
#include "loop/simulated_robot.h"
#include "loop/slam_localization.h"
#include "sim/builtin_worlds.h"
#include "sim/ray_caster.h"
#include "sim/simulator.h"

namespace {

using splam::kernel::Pose2;

// Root mean square of the distance between the estimated and the true positions over a run.
double PositionRmse(const splam::exploration::ExplorationRun& run, bool odometry) {
  double sum = 0.0;
  for (const splam::exploration::TraceSample& s : run.trace) {
    const Pose2& p = odometry ? s.odometry : s.estimate;
    sum += (p.translation() - s.truth.translation()).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(run.trace.size()));
}

}  // namespace

int main() {
  const splam::sim::World world = *splam::sim::BuiltinWorld("complex");
  const splam::sim::RayCaster caster(world);
  for (const char* name : {"srt", "reg", "reg+topological"}) {
    // A fresh simulated robot with sonar, seeded so that runs are reproducible.
    splam::sim::SimulatorOptions sim_options;
    sim_options.enable_sonar = true;
    splam::sim::Simulator simulator(caster, sim_options, *world.start, /*seed=*/1);
    // Step 1: the robot. A real robot implements exploration::RobotInterface the same way:
    // Step(v, w), ReadOdometry(), Sense() and a RobotDescription (radius, laser mounting, ...).
    splam::loop::SimulatedRobot robot(&simulator);
    // Step 2: the explorer with its options (LSR radius r = 3 m, step alpha * r = 2.4 m, ...)
    // and the localisation: ground truth, or a SLAM method by its registry name. The SLAM
    // method's local region uses the explorer's r and alpha, so both are given once.
    splam::exploration::ExplorerOptions options;
    options.seed = 1;
    const bool with_slam = std::string(name) == "reg+topological";
    splam::exploration::GroundTruthLocalization ground_truth;
    splam::loop::SlamLocalization my_slam("topological", /*options=*/nullptr,
                                          {options.lsr_radius_m, options.alpha});
    splam::exploration::Localization* localization =
        with_slam ? static_cast<splam::exploration::Localization*>(&my_slam) : &ground_truth;
    const splam::exploration::ExplorationRun run =
        (*splam::exploration::ExplorerRegistry::Global().Make(with_slam ? "reg" : name, options)
              .value)
            ->Run(&robot, localization);
    // Step 3: what happened.
    std::printf("%s: %zu nodes, %zu edges, %.1f m in %.0f s simulated; %s (%s)\n", name,
                boost::num_vertices(run.graph), boost::num_edges(run.graph), run.distance_m,
                run.time_s, splam::exploration::TerminationName(run.termination).c_str(),
                run.message.c_str());
    if (with_slam) {
      std::printf("  topological: position RMSE %.3f m (odometry alone %.3f m), %zu map curves\n",
                  PositionRmse(run, false), PositionRmse(run, true),
                  my_slam.driver()->method().MapCurves());
      if (PositionRmse(run, false) >= PositionRmse(run, true)) return 1;
    }
    if (run.termination != splam::exploration::Termination::kExplored) return 1;
  }
  return 0;
}
