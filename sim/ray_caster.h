#ifndef SPLAM_SIM_RAY_CASTER_H_
#define SPLAM_SIM_RAY_CASTER_H_

#include <cstdint>
#include <string>
#include <vector>

#include "kernel/shapes.h"
#include "kernel/status.h"
#include "sim/world.h"

namespace splam::sim {

struct RayCasterOptions {
  // Side of the square cells of the uniform grid that indexes the primitives, metres. Smaller
  // cells test fewer primitives per cell but visit more cells per ray.
  double cell_size_m = 0.5;
  // Bezier pieces are split until their control-point box is at most this many cells wide, so
  // that a curve is registered only in cells near it.
  double max_bezier_extent_cells = 1.0;

  kernel::Status Validate() const;
};

struct RayHit {
  double range_m = kernel::kNoHit;  // kNoHit when nothing is hit within the maximum range
  int obstacle = -1;                // index into World::obstacles, -1 for no hit
};

// Exact ray casting against a World through a uniform grid: the ray walks the cells it crosses
// (Amanatides & Woo 1987) and tests only the primitives registered in them, stopping at the
// first cell that contains the nearest hit. Thread-safe after construction.
class RayCaster {
 public:
  explicit RayCaster(const World& world, const RayCasterOptions& options = {});

  // Nearest hit with 0 < range < max_range_m.
  RayHit Cast(const kernel::Ray2& ray, double max_range_m) const;
  // The same answer by testing every primitive: the reference for tests.
  RayHit CastBruteForce(const kernel::Ray2& ray, double max_range_m) const;
  // True when a disc of `radius_m` around `center` touches an obstacle boundary or the center
  // lies inside a closed obstacle.
  bool Collides(const Eigen::Vector2d& center, double radius_m) const;
  // The nearest obstacle boundary within max_distance_m of p: range_m is the distance, obstacle
  // its index (kNoHit and -1 when nothing is that close).
  RayHit Nearest(const Eigen::Vector2d& p, double max_distance_m) const;
  // True when p lies inside a solid obstacle: a polygon, circle, ellipse or closed spline (the
  // closed splines sampled at 32 points per piece; open polylines have no inside).
  bool IsInsideObstacle(const Eigen::Vector2d& p) const;
  // True when obstacle `obstacle` is of glass (World::glass): the laser reads no return from it.
  bool IsGlass(int obstacle) const {
    return obstacle >= 0 && static_cast<std::size_t>(obstacle) < glass_.size() &&
           glass_[static_cast<std::size_t>(obstacle)];
  }

 private:
  enum class Kind : std::uint8_t { kSegment, kCircle, kEllipse, kBezier };
  struct Ref {
    Kind kind;
    std::uint32_t index;  // into the primitive array of its kind
    int obstacle;
  };

  double Intersect(const Ref& ref, const kernel::Ray2& ray, double t_max) const;
  double Distance(const Ref& ref, const Eigen::Vector2d& p) const;
  // Calls visit(ref) for the primitives registered in the cells within radius_m of center (a
  // primitive may come more than once) until it returns true; true if it did.
  template <class Visit>
  bool VisitNear(const Eigen::Vector2d& center, double radius_m, Visit visit) const;
  void Register(std::uint32_t ref, const kernel::Box2& box,
                std::vector<std::vector<std::uint32_t>>* cells) const;

  RayCasterOptions options_;
  Primitives primitives_;
  std::vector<Ref> refs_;
  // Grid: cell (ix, iy) covers origin_ + [ix, ix+1) x [iy, iy+1) * cell_size; its primitives are
  // cell_items_[cell_start_[c] .. cell_start_[c+1]) with c = iy * nx_ + ix.
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> cell_start_;
  std::vector<std::uint32_t> cell_items_;
  // Closed obstacles as polygons (closed splines sampled densely) for IsInsideObstacle.
  std::vector<std::vector<Eigen::Vector2d>> closed_polygons_;
  std::vector<bool> glass_;  // per obstacle
};

}  // namespace splam::sim

#endif  // SPLAM_SIM_RAY_CASTER_H_
