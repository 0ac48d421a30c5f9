#ifndef SPLAM_SIM_SONAR_H_
#define SPLAM_SIM_SONAR_H_

#include <string>
#include <vector>

#include "kernel/options.h"
#include "kernel/pose2.h"
#include "kernel/random.h"
#include "kernel/status.h"
#include "sim/ray_caster.h"

namespace splam::sim {

// A ring of ultrasonic range sensors (SPEC §1). Each sonar reports the nearest echo inside its
// cone, modelled by `rays_per_cone` rays spread evenly over the cone, plus Gaussian noise
// (sigma = noise_floor_m + noise_fraction * range); nothing within max_range_m reads
// kernel::Scan::kNoReturn.
struct SonarOptions {
  std::vector<kernel::Pose2> robot_T_sonar = PioneerRing();  // mounting poses
  double cone_half_angle_rad = 0.2618;                       // 15 deg: a 30 deg beam
  int rays_per_cone = 5;
  double min_range_m = 0.1;
  double max_range_m = 5.0;
  double noise_fraction = 0.01;
  double noise_floor_m = 0.02;

  // The 16 sonars of a Pioneer P3-DX: 8 in front at 90, 50, 30, 10, -10, -30, -50, -90 deg and
  // 8 at the back at -90, -130, -150, -170, 170, 150, 130, 90 deg; the 6 rear ones between
  // -130 and 130 cover the 120 deg behind the robot that the laser cannot see.
  static std::vector<kernel::Pose2> PioneerRing();
  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// One reading per sonar, in the order of robot_T_sonar.
std::vector<double> SimulateSonar(const RayCaster& caster, const SonarOptions& options,
                                  const kernel::Pose2& world_T_robot, kernel::Random* random);

}  // namespace splam::sim

#endif  // SPLAM_SIM_SONAR_H_
