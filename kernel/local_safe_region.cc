#include "kernel/local_safe_region.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>

#include <algorithm>
#include <cmath>

#include "kernel/angle.h"

namespace splam::kernel {
namespace {

using CgalKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalPoint = CgalKernel::Point_2;

constexpr double kMinReach = 0.01;  // fraction of the radius

}  // namespace

LocalSafeRegion LocalSafeRegion::FromScan(const Scan& scan, const Pose2& world_T_laser,
                                          double radius_m) {
  LocalSafeRegion lsr;
  lsr.center_ = world_T_laser.translation();
  lsr.radius_ = radius_m;
  const bool full_circle = scan.FieldOfView() + scan.angular_step_rad >= 2.0 * kPi - 1e-9;
  if (!full_circle) lsr.boundary_.push_back(lsr.center_);
  bool in_arc = false;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double r = scan.ranges_m[i];
    const bool free = !std::isnan(r) && r >= radius_m;  // no return within the radius
    // Invalid (NaN) or very short readings end at 1 % of the radius, so that no boundary vertex
    // falls on the sensor and the polygon stays simple.
    const double reach =
        std::isnan(r) ? kMinReach * radius_m : std::clamp(r, kMinReach * radius_m, radius_m);
    const double angle = world_T_laser.theta() + scan.BeamAngle(i);
    lsr.boundary_.push_back(lsr.center_ +
                            reach * Eigen::Vector2d(std::cos(angle), std::sin(angle)));
    if (free && !in_arc) lsr.frontiers_.push_back({angle, angle});
    if (free) lsr.frontiers_.back().end_angle_rad = angle;
    in_arc = free;
  }
  // A full-circle scan whose first and last beams are both free has one arc across the seam.
  auto& arcs = lsr.frontiers_;
  if (full_circle && arcs.size() >= 2 && scan.size() > 0 && in_arc &&
      arcs.front().start_angle_rad == world_T_laser.theta() + scan.BeamAngle(0)) {
    arcs.front().start_angle_rad = arcs.back().start_angle_rad - 2.0 * kPi;
    arcs.pop_back();
  }
  return lsr;
}

bool LocalSafeRegion::Contains(const Eigen::Vector2d& p) const {
  if (boundary_.size() < 3) return false;
  std::vector<CgalPoint> polygon;
  polygon.reserve(boundary_.size());
  for (const Eigen::Vector2d& v : boundary_) polygon.emplace_back(v.x(), v.y());
  return CGAL::bounded_side_2(polygon.begin(), polygon.end(), CgalPoint(p.x(), p.y()),
                              CgalKernel()) != CGAL::ON_UNBOUNDED_SIDE;
}

}  // namespace splam::kernel
