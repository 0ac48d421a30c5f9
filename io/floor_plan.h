#ifndef SPLAM_IO_FLOOR_PLAN_H_
#define SPLAM_IO_FLOOR_PLAN_H_

#include <Eigen/Core>
#include <string>

#include "io/result.h"
#include "kernel/status.h"
#include "sim/world.h"

namespace splam::io {

struct FloorPlanOptions {
  // The size of one pixel, m, within [kMinResolutionM, kMaxResolutionM]: 0.1 mm to 10 m per pixel
  // spans every floor plan; 1e-9 made walls thinner than the ray caster's tolerance, 1e300
  // overflowed the world's arithmetic.
  static constexpr double kMinResolutionM = 1e-4;
  static constexpr double kMaxResolutionM = 10.0;
  double resolution_m_per_px = 0.05;
  int dark_threshold = 128;  // grey level (0-255) below which a pixel is an obstacle
  // World coordinates of the bottom-left corner of the image (x to the right, y up).
  Eigen::Vector2d origin_m = Eigen::Vector2d::Zero();
  // Douglas-Peucker tolerance when turning outlines into polygons, pixels.
  double simplify_tolerance_px = 0.7;

  kernel::Status Validate() const;
};

// A world from a floor-plan image (any format OpenCV reads, PNG in practice): the outline of every
// region of dark pixels, and of every hole in one, becomes a closed loop of walls, so walls are
// as thick as drawn. The loops are walls, not solids: a room inside a ring of dark pixels is free
// space. Fails on unreadable images and images without dark pixels.
Result<sim::World> ReadFloorPlan(const std::string& path, const FloorPlanOptions& options);
// Whether `point` (world frame) falls on a dark pixel of the floor plan at `path`: inside a wall
// or a solid region, where the outlines alone cannot tell it from a room. False outside the
// image. Fails like ReadFloorPlan.
Result<bool> FloorPlanIsDarkAt(const std::string& path, const FloorPlanOptions& options,
                               const Eigen::Vector2d& point);

}  // namespace splam::io

#endif  // SPLAM_IO_FLOOR_PLAN_H_
