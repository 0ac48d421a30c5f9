// Tutorial: plug a robot into an explorer, run SRT and REG, and couple REG with a SLAM method.
//
// An explorer only sees a RobotInterface (velocity commands, odometry, laser, sonar) and a
// Localization (where the robot believes it is). Here the robot is the built-in simulator; the
// localisation is first its ground truth (exploration alone), then a SLAM method written as one
// class (the SPLAM loop: the explorer plans with the SLAM estimate).
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "estimation/topological_slam.h"
#include "exploration/explorer.h"
#include "exploration/localization.h"
#include "exploration/robot_interface.h"
#include "sim/builtin_worlds.h"
#include "sim/ray_caster.h"
#include "sim/simulator.h"

namespace {

using splam::exploration::Perception;
using splam::kernel::Pose2;

// Step 1: the robot. Everything an explorer needs from it, in a few lines of glue.
class Robot : public splam::exploration::RobotInterface {
 public:
  explicit Robot(splam::sim::Simulator* sim) : sim_(sim) {
    description_.radius_m = sim->options().robot.radius_m;
    description_.time_step_s = sim->options().time_step_s;
    description_.robot_T_laser = sim->options().laser.robot_T_laser;
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

// Step 2: a SLAM method as the explorer's localisation. This is the one class a researcher
// writes to try a new variant: here the topological B-spline SLAM of paper 003 (SPEC §10), whose
// options (or whose whole estimator) you would change. Every odometry reading predicts, every scan
// corrects, and at every new node the explorer hands over its local safe region, which limits the
// association to the map curves inside it.
class MySlam : public splam::exploration::Localization {
 public:
  std::string name() const override { return "my-slam"; }
  bool needs_scans() const override { return true; }  // Update() also gets the laser scans
  std::string Start(const splam::exploration::RobotDescription& robot, const Pose2& start,
                    const Perception& first) override {
    robot_T_laser_ = robot.robot_T_laser;
    last_odometry_ = first.odometry_pose;
    splam::estimation::TopologicalSlamOptions options;  // the defaults; try your own here
    slam_.emplace(start, options);
    return slam_->health();  // empty: ready
  }
  Pose2 Update(const Perception& perception) override {
    slam_->Predict(last_odometry_.Between(perception.odometry_pose));
    last_odometry_ = perception.odometry_pose;
    if (!perception.scan.ranges_m.empty()) slam_->Update(perception.scan, robot_T_laser_);
    return slam_->pose();
  }
  void AtNode(const splam::kernel::LocalSafeRegion& lsr) override { slam_->SetLocalRegion(lsr); }

  std::size_t map_curves() const { return slam_ ? slam_->num_curves() : 0; }

 private:
  std::optional<splam::estimation::TopologicalSlam> slam_;
  Pose2 robot_T_laser_, last_odometry_;
};

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
  for (const char* name : {"srt", "reg", "reg+my-slam"}) {
    // Step 3: a fresh simulated robot with sonar, seeded so that runs are reproducible.
    splam::sim::SimulatorOptions sim_options;
    sim_options.enable_sonar = true;
    splam::sim::Simulator simulator(caster, sim_options, *world.start, /*seed=*/1);
    Robot robot(&simulator);
    // Step 4: the explorer with its options (LSR radius r = 3 m, step alpha * r = 2.4 m, ...)
    // and the localisation: ground truth, or our SLAM class.
    splam::exploration::ExplorerOptions options;
    options.seed = 1;
    const bool with_slam = std::string(name) == "reg+my-slam";
    splam::exploration::GroundTruthLocalization ground_truth;
    MySlam my_slam;
    splam::exploration::Localization* localization =
        with_slam ? static_cast<splam::exploration::Localization*>(&my_slam) : &ground_truth;
    const splam::exploration::ExplorationRun run =
        splam::exploration::MakeExplorer(with_slam ? "reg" : name, options)
            ->Run(&robot, localization);
    // Step 5: what happened.
    std::printf("%s: %zu nodes, %zu edges, %.1f m in %.0f s simulated; %s (%s)\n", name,
                boost::num_vertices(run.graph), boost::num_edges(run.graph), run.distance_m,
                run.time_s, splam::exploration::TerminationName(run.termination).c_str(),
                run.message.c_str());
    if (with_slam) {
      std::printf("  my-slam: position RMSE %.3f m (odometry alone %.3f m), %zu map curves\n",
                  PositionRmse(run, false), PositionRmse(run, true), my_slam.map_curves());
      if (PositionRmse(run, false) >= PositionRmse(run, true)) return 1;
    }
    if (run.termination != splam::exploration::Termination::kExplored) return 1;
  }
  return 0;
}
