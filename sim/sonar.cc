#include "sim/sonar.h"

#include <algorithm>
#include <cmath>

#include "kernel/angle.h"
#include "kernel/scan.h"

namespace splam::sim {

std::vector<kernel::Pose2> SonarOptions::PioneerRing() {
  // Angles in degrees; the sensors sit on the body outline, about 0.2 m from the centre.
  const double front[] = {90, 50, 30, 10, -10, -30, -50, -90};
  const double back[] = {-90, -130, -150, -170, 170, 150, 130, 90};
  std::vector<kernel::Pose2> ring;
  for (double deg : front) {
    const double a = kernel::DegToRad(deg);
    ring.emplace_back(0.12 + 0.07 * std::cos(a), 0.17 * std::sin(a), a);
  }
  for (double deg : back) {
    const double a = kernel::DegToRad(deg);
    ring.emplace_back(-0.12 + 0.07 * std::cos(a), 0.17 * std::sin(a), a);
  }
  return ring;
}

kernel::Status SonarOptions::Validate() const {
  if (robot_T_sonar.empty()) return kernel::Status::Error("sonar ring has no sensors");
  if (!(cone_half_angle_rad >= 0.0 && cone_half_angle_rad < kernel::kPi / 2)) {
    return kernel::Status::Error("sonar cone_half_angle_rad must be in [0, pi/2)");
  }
  if (rays_per_cone < 1) return kernel::Status::Error("sonar rays_per_cone must be at least 1");
  if (!(min_range_m >= 0.0) || !(max_range_m > min_range_m))
    return kernel::Status::Error("sonar needs 0 <= min < max range");
  if (!(noise_fraction >= 0.0) || !(noise_floor_m >= 0.0))
    return kernel::Status::Error("sonar noise must be >= 0");
  return kernel::Status::Ok();
}

std::vector<double> SimulateSonar(const RayCaster& caster, const SonarOptions& options,
                                  const kernel::Pose2& world_T_robot, kernel::Random* random) {
  std::vector<double> ranges;
  ranges.reserve(options.robot_T_sonar.size());
  for (const kernel::Pose2& robot_T_sonar : options.robot_T_sonar) {
    const kernel::Pose2 world_T_sonar = world_T_robot * robot_T_sonar;
    kernel::Ray2 ray;
    ray.origin = world_T_sonar.translation();
    double nearest = kernel::kNoHit;
    for (int k = 0; k < options.rays_per_cone; ++k) {
      const double offset =
          options.rays_per_cone == 1
              ? 0.0
              : options.cone_half_angle_rad * (2.0 * k / (options.rays_per_cone - 1) - 1.0);
      const double angle = world_T_sonar.theta() + offset;
      ray.direction = {std::cos(angle), std::sin(angle)};
      nearest = std::min(nearest, caster.Cast(ray, options.max_range_m).range_m);
    }
    double range = kernel::Scan::kNoReturn;
    if (nearest < options.max_range_m) {
      range = nearest + random->Gaussian(options.noise_floor_m + options.noise_fraction * nearest);
      range = std::max(range, options.min_range_m);
      if (range >= options.max_range_m) range = kernel::Scan::kNoReturn;
    }
    ranges.push_back(range);
  }
  return ranges;
}

void SonarOptions::VisitFields(kernel::FieldVisitor& v) {
  // The mounting poses stay the Pioneer ring (robot_T_sonar is set in code).
  v.Field("cone_half_angle_rad", &cone_half_angle_rad, "each sonar sees +- this, rad");
  v.Field("rays_per_cone", &rays_per_cone, "rays that model one cone");
  v.Field("min_range_m", &min_range_m, "shortest reading, m");
  v.Field("max_range_m", &max_range_m, "no echo beyond, m");
  v.Field("noise_fraction", &noise_fraction, "range sigma per m of range");
  v.Field("noise_floor_m", &noise_floor_m, "range sigma independent of range, m");
}

}  // namespace splam::sim
