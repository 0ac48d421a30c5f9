#ifndef SPLAM_SIM_LASER_H_
#define SPLAM_SIM_LASER_H_

#include <span>
#include <string>
#include <vector>

#include "kernel/options.h"
#include "kernel/pose2.h"
#include "kernel/random.h"
#include "kernel/scan.h"
#include "kernel/status.h"
#include "sim/ray_caster.h"

namespace splam::sim {

// A planar laser range finder (SPEC §1). Reading model: the exact range t to the nearest
// obstacle plus Gaussian noise with sigma = noise_floor_m + noise_fraction * t. A beam whose true
// or noisy range is at or beyond max_range_m, or that drops out, reads Scan::kNoReturn; a noisy
// range below min_range_m is an invalid reading (NaN), as a real sensor reports an error code.
struct LaserOptions {
  std::string model = "URG-04LX";       // name written to logs
  int num_beams = 667;                  // beams per sweep
  double start_angle_rad = -2.0923;     // first beam, sensor frame (-119.88 deg)
  double angular_step_rad = 0.0062832;  // between beams (0.36 deg)
  double min_range_m = 0.02;
  double max_range_m = 4.0;
  double noise_fraction = 0.01;      // range noise sigma per metre of range (1 %)
  double noise_floor_m = 0.0;        // range noise sigma independent of range
  double dropout_probability = 0.0;  // chance that a beam with a hit reads no return
  kernel::Pose2 robot_T_laser;       // mounting pose of the laser on the robot
  // Sweeps cycle through this many start angles, angular_step_rad / interlace_phases apart, as a
  // SICK LMS in its interlaced modes (4 phases of 0.25 deg at 1 deg). A shifted sweep drops its
  // last beam to stay within the field of view (181 beams, then 180, 180, 180). 1: no interlace.
  int interlace_phases = 1;

  // This sweep's geometry: the start angle shifted by (sweep mod phases) / phases of a step and,
  // when shifted, one beam fewer.
  LaserOptions Sweep(long long sweep) const;

  // Hokuyo URG-04LX: 240 deg field of view at 0.36 deg (667 beams), 0.02-4 m, sigma 1 % of range.
  static LaserOptions Urg04lx();
  // SICK LMS-200: 180 deg at `resolution_deg` (0.5 -> 361 beams, 1 -> 181), 8 m, sigma 1 cm.
  static LaserOptions Lms200(double resolution_deg = 0.5);
  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  // Ok when valid, else the first problem.
  kernel::Status Validate() const;
};

// Simulates one sweep from the robot at world_T_robot. When `beam_obstacles` is given it
// receives, per beam, the World obstacle index the beam truly hit (-1 for none, a person or
// glass, from which the beam reads no return).
// `people` are discs the beams hit in front of the world's obstacles (people walking).
kernel::Scan SimulateLaser(const RayCaster& caster, const LaserOptions& options,
                           const kernel::Pose2& world_T_robot, double timestamp_s,
                           kernel::Random* random, std::vector<int>* beam_obstacles = nullptr,
                           std::span<const kernel::Circle2> people = {});

}  // namespace splam::sim

#endif  // SPLAM_SIM_LASER_H_
