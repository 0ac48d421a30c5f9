#include "kernel/scan.h"

#include <cmath>

namespace splam::kernel {

Eigen::Vector2d PolarToCartesian(const Polar& polar) {
  return {polar.range_m * std::cos(polar.angle_rad), polar.range_m * std::sin(polar.angle_rad)};
}

Polar CartesianToPolar(const Eigen::Vector2d& point) {
  return {point.norm(), std::atan2(point.y(), point.x())};
}

double Scan::BeamAngle(std::size_t i) const {
  return start_angle_rad + static_cast<double>(i) * angular_step_rad;
}

bool Scan::IsHit(std::size_t i) const {
  const double r = ranges_m[i];
  return std::isfinite(r) && r >= min_range_m && r < max_range_m;
}

bool Scan::IsNoReturn(std::size_t i) const { return ranges_m[i] == kNoReturn; }

double Scan::FieldOfView() const {
  return ranges_m.empty() ? 0.0 : static_cast<double>(ranges_m.size() - 1) * angular_step_rad;
}

std::vector<Eigen::Vector2d> Scan::HitPoints() const {
  std::vector<Eigen::Vector2d> points;
  points.reserve(ranges_m.size());
  for (std::size_t i = 0; i < ranges_m.size(); ++i) {
    if (IsHit(i)) points.push_back(PolarToCartesian({ranges_m[i], BeamAngle(i)}));
  }
  return points;
}

std::vector<std::size_t> Scan::HitIndices() const {
  std::vector<std::size_t> indices;
  for (std::size_t i = 0; i < ranges_m.size(); ++i) {
    if (IsHit(i)) indices.push_back(i);
  }
  return indices;
}

Scan Scan::Clipped(double range_m) const {
  Scan clipped = *this;
  for (double& r : clipped.ranges_m) {
    if (r > range_m && !std::isnan(r)) r = kNoReturn;
  }
  return clipped;
}

}  // namespace splam::kernel
