// Tutorial: plug a robot into an explorer, run SRT and REG, and compare them.
//
// An explorer only sees a RobotInterface (velocity commands, odometry, laser, sonar) and a
// Localization (where the robot believes it is). Here the robot is the built-in simulator and
// the localisation is its ground truth; a real robot or a SLAM method plugs in the same way.
#include <cstdio>

#include "exploration/explorer.h"
#include "exploration/localization.h"
#include "exploration/robot_interface.h"
#include "sim/builtin_worlds.h"
#include "sim/ray_caster.h"
#include "sim/simulator.h"

namespace {

using splam::exploration::Perception;

// Step 1: the robot. Everything an explorer needs from it, in a few lines of glue.
class Robot : public splam::exploration::RobotInterface {
 public:
  explicit Robot(splam::sim::Simulator* sim) : sim_(sim) {
    description_.radius_m = sim->options().robot.radius_m;
    description_.time_step_s = sim->options().time_step_s;
    description_.robot_T_sonar = sim->options().sonar.robot_T_sonar;  // fills the LSR behind
  }
  const splam::exploration::RobotDescription& description() const override { return description_; }
  bool Step(double v, double w) override { return sim_->Step(v, w); }  // false: would collide
  Perception ReadOdometry() override {
    return {sim_->time_s(), sim_->odometry_pose(), sim_->true_pose(), {}, {}};
  }
  Perception Sense() override {
    splam::sim::SensorFrame f = sim_->Sense();
    return {f.time_s, f.odometry_pose, f.true_pose, f.scan, f.sonar_ranges_m};
  }

 private:
  splam::sim::Simulator* sim_;
  splam::exploration::RobotDescription description_;
};

}  // namespace

int main() {
  const splam::sim::World world = *splam::sim::BuiltinWorld("complex");
  const splam::sim::RayCaster caster(world);
  for (const char* name : {"srt", "reg"}) {
    // Step 2: a fresh simulated robot with sonar, seeded so that runs are reproducible.
    splam::sim::SimulatorOptions sim_options;
    sim_options.enable_sonar = true;
    splam::sim::Simulator simulator(caster, sim_options, *world.start, /*seed=*/1);
    Robot robot(&simulator);
    // Step 3: the explorer with its options (LSR radius r = 3 m, step alpha * r = 2.4 m, ...).
    splam::exploration::ExplorerOptions options;
    options.seed = 1;
    splam::exploration::GroundTruthLocalization localization;
    const splam::exploration::ExplorationRun run =
        splam::exploration::MakeExplorer(name, options)->Run(&robot, &localization);
    // Step 4: what happened.
    std::printf("%s: %zu nodes, %zu edges, %.1f m in %.0f s simulated; %s (%s)\n", name,
                boost::num_vertices(run.graph), boost::num_edges(run.graph), run.distance_m,
                run.time_s, splam::exploration::TerminationName(run.termination).c_str(),
                run.message.c_str());
    if (run.termination != splam::exploration::Termination::kExplored) return 1;
  }
  return 0;
}
