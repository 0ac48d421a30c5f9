#ifndef SPLAM_KERNEL_SCAN_H_
#define SPLAM_KERNEL_SCAN_H_

#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <vector>

namespace splam::kernel {

// Range and bearing of a point in a sensor frame.
struct Polar {
  double range_m = 0.0;
  double angle_rad = 0.0;
};

Eigen::Vector2d PolarToCartesian(const Polar& polar);
// The angle of the origin is 0 by convention.
Polar CartesianToPolar(const Eigen::Vector2d& point);

// One sweep of a planar range finder, in the sensor frame; beam i points at
// start_angle_rad + i * angular_step_rad.
//
// Reading conventions, shared by the simulator and the log readers:
//   - a hit is a finite range in [min_range_m, max_range_m);
//   - kNoReturn (+infinity) means nothing was hit within max_range_m (free space up to there);
//   - NaN, negative and below-minimum values are invalid readings that carry no information.
// Nothing downstream uses a reading that is not a hit as a point.
struct Scan {
  static constexpr double kNoReturn = std::numeric_limits<double>::infinity();

  double timestamp_s = 0.0;
  double start_angle_rad = 0.0;
  double angular_step_rad = 0.0;
  double min_range_m = 0.0;
  double max_range_m = 0.0;
  std::vector<double> ranges_m;

  std::size_t size() const { return ranges_m.size(); }
  double BeamAngle(std::size_t i) const;
  bool IsHit(std::size_t i) const;
  bool IsNoReturn(std::size_t i) const;
  // Angular extent from the first to the last beam.
  double FieldOfView() const;
  // A copy whose hits beyond range_m read as no-returns.
  Scan Clipped(double range_m) const;
  // The hits as points in the sensor frame, in beam order.
  std::vector<Eigen::Vector2d> HitPoints() const;
  // Beam indices of HitPoints().
  std::vector<std::size_t> HitIndices() const;
};

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_SCAN_H_
