#include "sim/laser.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernel/angle.h"

namespace splam::sim {

LaserOptions LaserOptions::Urg04lx() {
  LaserOptions o;
  o.model = "URG-04LX";
  o.num_beams = 667;
  o.angular_step_rad = kernel::DegToRad(0.36);
  o.start_angle_rad = -0.5 * (o.num_beams - 1) * o.angular_step_rad;
  o.min_range_m = 0.02;
  o.max_range_m = 4.0;
  o.noise_fraction = 0.01;
  o.noise_floor_m = 0.0;
  return o;
}

LaserOptions LaserOptions::Lms200(double resolution_deg) {
  LaserOptions o;
  o.model = "LMS-200";
  o.angular_step_rad = kernel::DegToRad(resolution_deg);
  o.num_beams = static_cast<int>(std::lround(180.0 / resolution_deg)) + 1;
  o.start_angle_rad = -kernel::kPi / 2.0;
  o.min_range_m = 0.01;
  o.max_range_m = 8.0;
  o.noise_fraction = 0.0;
  o.noise_floor_m = 0.01;
  return o;
}

kernel::Status LaserOptions::Validate() const {
  if (num_beams < 1) return kernel::Status::Error("laser num_beams must be at least 1");
  if (!std::isfinite(start_angle_rad) || !std::isfinite(angular_step_rad)) {
    return kernel::Status::Error("laser angles must be finite");
  }
  if (!(min_range_m >= 0.0) || !(max_range_m > min_range_m) || !std::isfinite(max_range_m)) {
    return kernel::Status::Error("laser ranges need 0 <= min_range_m < max_range_m < infinity");
  }
  if (!(noise_fraction >= 0.0) || !(noise_floor_m >= 0.0))
    return kernel::Status::Error("laser noise must be >= 0");
  if (interlace_phases < 1 || interlace_phases > 100)
    return kernel::Status::Error("laser interlace_phases must be in [1, 100]");
  if (!(dropout_probability >= 0.0 && dropout_probability <= 1.0)) {
    return kernel::Status::Error("laser dropout_probability must be in [0, 1]");
  }
  return kernel::Status::Ok();
}

LaserOptions LaserOptions::Sweep(long long sweep) const {
  LaserOptions o = *this;
  const long long phase = sweep % interlace_phases;
  if (phase > 0) {
    o.start_angle_rad += angular_step_rad * static_cast<double>(phase) / interlace_phases;
    o.num_beams = std::max(1, num_beams - 1);
  }
  return o;
}

kernel::Scan SimulateLaser(const RayCaster& caster, const LaserOptions& options,
                           const kernel::Pose2& world_T_robot, double timestamp_s,
                           kernel::Random* random, std::vector<int>* beam_obstacles,
                           std::span<const kernel::Circle2> people) {
  kernel::Scan scan;
  scan.timestamp_s = timestamp_s;
  scan.start_angle_rad = options.start_angle_rad;
  scan.angular_step_rad = options.angular_step_rad;
  scan.min_range_m = options.min_range_m;
  scan.max_range_m = options.max_range_m;
  scan.ranges_m.resize(options.num_beams);
  if (beam_obstacles != nullptr) beam_obstacles->assign(options.num_beams, -1);

  const kernel::Pose2 world_T_laser = world_T_robot * options.robot_T_laser;
  kernel::Ray2 ray;
  ray.origin = world_T_laser.translation();
  // Beam directions by repeated rotation through the angular step: one 2x2 product per beam
  // instead of a cosine and a sine (the drift after 1000 beams is about 1e-13 rad).
  const Eigen::Matrix2d step = kernel::Pose2(0.0, 0.0, options.angular_step_rad).Rotation();
  const double first = world_T_laser.theta() + options.start_angle_rad;
  Eigen::Vector2d direction(std::cos(first), std::sin(first));
  for (int i = 0; i < options.num_beams; ++i, direction = step * direction) {
    ray.direction = direction;
    RayHit hit = caster.Cast(ray, options.max_range_m);
    // A person in front of the nearest obstacle hides it.
    bool person = false;
    for (const kernel::Circle2& p : people) {
      const double t = kernel::Intersect(ray, p, 0.0, std::min(hit.range_m, options.max_range_m));
      if (t == kernel::kNoHit) continue;
      hit = {t, -1};
      person = true;
    }
    double range = kernel::Scan::kNoReturn;
    if ((hit.obstacle >= 0 && !caster.IsGlass(hit.obstacle)) || person) {
      range = hit.range_m +
              random->Gaussian(options.noise_floor_m + options.noise_fraction * hit.range_m);
      if (options.dropout_probability > 0.0 && random->Uniform() < options.dropout_probability) {
        range = kernel::Scan::kNoReturn;
      } else if (range >= options.max_range_m) {
        range = kernel::Scan::kNoReturn;
      } else if (range < options.min_range_m) {
        range = std::numeric_limits<double>::quiet_NaN();
      }
      if (beam_obstacles != nullptr) (*beam_obstacles)[i] = hit.obstacle;
    }
    scan.ranges_m[i] = range;
  }
  return scan;
}

void LaserOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("model", &model, "name written to logs");
  v.Field("num_beams", &num_beams, "beams per sweep");
  v.Field("start_angle_rad", &start_angle_rad, "first beam, sensor frame, rad");
  v.Field("angular_step_rad", &angular_step_rad, "between beams, rad");
  v.Field("min_range_m", &min_range_m, "shorter readings are invalid, m");
  v.Field("max_range_m", &max_range_m, "no return at or beyond, m");
  v.Field("noise_fraction", &noise_fraction, "range sigma per m of range");
  v.Field("noise_floor_m", &noise_floor_m, "range sigma independent of range, m");
  v.Field("dropout_probability", &dropout_probability, "chance that a hit reads no return");
  v.Field("robot_T_laser", &robot_T_laser, "mounting pose [x m, y m, theta rad]");
  v.Field("interlace_phases", &interlace_phases,
          "sweeps cycle through this many start angles a step / phases apart (1: none)");
}

}  // namespace splam::sim
