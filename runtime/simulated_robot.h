#ifndef SPLAM_RUNTIME_SIMULATED_ROBOT_H_
#define SPLAM_RUNTIME_SIMULATED_ROBOT_H_

#include "exploration/robot_interface.h"
#include "sim/simulator.h"

namespace splam::runtime {

// The simulator as the robot an explorer drives.
class SimulatedRobot : public exploration::RobotInterface {
 public:
  // `simulator` must outlive this object.
  explicit SimulatedRobot(sim::Simulator* simulator) : simulator_(simulator) {
    const sim::SimulatorOptions& options = simulator->options();
    description_.radius_m = options.robot.radius_m;
    description_.time_step_s = options.time_step_s;
    description_.robot_T_laser = options.laser.robot_T_laser;
    if (options.enable_sonar) {
      description_.robot_T_sonar = options.sonar.robot_T_sonar;
      description_.sonar_cone_half_angle_rad = options.sonar.cone_half_angle_rad;
      description_.sonar_max_range_m = options.sonar.max_range_m;
    }
  }

  const exploration::RobotDescription& description() const override { return description_; }
  bool Step(double v_mps, double w_radps) override { return simulator_->Step(v_mps, w_radps); }
  exploration::Perception ReadOdometry() override {
    exploration::Perception p;
    p.time_s = simulator_->time_s();
    p.odometry_pose = simulator_->odometry_pose();
    p.true_pose = simulator_->true_pose();
    return p;
  }
  exploration::Perception Sense() override {
    sim::SensorFrame frame = simulator_->Sense();
    exploration::Perception p;
    p.time_s = frame.time_s;
    p.odometry_pose = frame.odometry_pose;
    p.true_pose = frame.true_pose;
    p.scan = std::move(frame.scan);
    p.sonar_ranges_m = std::move(frame.sonar_ranges_m);
    return p;
  }

 private:
  sim::Simulator* simulator_;
  exploration::RobotDescription description_;
};

}  // namespace splam::runtime

#endif  // SPLAM_RUNTIME_SIMULATED_ROBOT_H_
