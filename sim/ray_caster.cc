#include "sim/ray_caster.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace splam::sim {
namespace {

using kernel::Box2;
using kernel::kNoHit;

bool InsidePolygon(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  bool inside = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Eigen::Vector2d& a = poly[i];
    const Eigen::Vector2d& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

double MinDistance(const Box2& box, const Eigen::Vector2d& p) {
  const Eigen::Vector2d d = (box.min - p).cwiseMax(p - box.max).cwiseMax(0.0);
  return d.norm();
}

double MaxDistance(const Box2& box, const Eigen::Vector2d& p) {
  return (box.min - p).cwiseAbs().cwiseMax((box.max - p).cwiseAbs()).norm();
}

void SplitUntilSmall(const kernel::CubicBezier& b, double max_extent,
                     std::vector<kernel::CubicBezier>* out, int depth = 0) {
  if (depth >= 12 || b.ControlBounds().Size().maxCoeff() <= max_extent) {
    out->push_back(b);
    return;
  }
  const auto [first, second] = b.Split(0.5);
  SplitUntilSmall(first, max_extent, out, depth + 1);
  SplitUntilSmall(second, max_extent, out, depth + 1);
}

}  // namespace

kernel::Status RayCasterOptions::Validate() const {
  if (!(cell_size_m > 0.0) || !std::isfinite(cell_size_m))
    return kernel::Status::Error("cell_size_m must be positive");
  if (!(max_bezier_extent_cells > 0.0))
    return kernel::Status::Error("max_bezier_extent_cells must be positive");
  return kernel::Status::Ok();
}

RayCaster::RayCaster(const World& world, const RayCasterOptions& options) : options_(options) {
  assert(options.Validate().ok());
  assert(world.Validate().ok());
  glass_.assign(world.obstacles.size(), false);
  for (const std::size_t g : world.glass) glass_[g] = true;
  // At most kMaxCells cells (a building 500 m square has 10^6): a world hundreds of kilometres wide
  // (a coordinate from a fuzzed world file) gets coarser cells, not gigabytes of them.
  constexpr double kMaxCells = 1 << 20;
  if (const Box2 box = world.Bounds(); !box.IsEmpty()) {
    const auto cells = [&](double c) {
      return (box.Size().x() / c + 3.0) * (box.Size().y() / c + 3.0);
    };
    while (cells(options_.cell_size_m) > kMaxCells) options_.cell_size_m *= 2.0;
  }
  const double cs = options_.cell_size_m;
  for (std::size_t i = 0; i < world.obstacles.size(); ++i) {
    Primitives p;
    world.AppendPrimitives(i, &p);
    const int id = static_cast<int>(i);
    auto add = [&](Kind kind, std::size_t index) {
      refs_.push_back({kind, static_cast<std::uint32_t>(index), id});
    };
    for (const auto& s : p.segments)
      add(Kind::kSegment, primitives_.segments.size()), primitives_.segments.push_back(s);
    for (const auto& c : p.circles)
      add(Kind::kCircle, primitives_.circles.size()), primitives_.circles.push_back(c);
    for (const auto& e : p.ellipses)
      add(Kind::kEllipse, primitives_.ellipses.size()), primitives_.ellipses.push_back(e);
    std::vector<kernel::CubicBezier> pieces;
    for (const auto& b : p.beziers)
      SplitUntilSmall(b, options_.max_bezier_extent_cells * cs, &pieces);
    for (const auto& b : pieces)
      add(Kind::kBezier, primitives_.beziers.size()), primitives_.beziers.push_back(b);

    const Shape& shape = world.obstacles[i];
    if (const auto* poly = std::get_if<Polyline>(&shape); poly && poly->closed) {
      closed_polygons_.push_back(poly->vertices);
    } else if (const auto* spline = std::get_if<Spline>(&shape); spline && spline->closed) {
      std::vector<Eigen::Vector2d> dense;
      for (const auto& b : p.beziers) {
        for (int k = 0; k < 32; ++k) dense.push_back(b.Point(k / 32.0));
      }
      closed_polygons_.push_back(std::move(dense));
    }
  }

  Box2 bounds = world.Bounds();
  if (bounds.IsEmpty()) bounds = Box2{Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  origin_ = bounds.min - Eigen::Vector2d::Constant(cs);
  const Eigen::Vector2d extent = bounds.max + Eigen::Vector2d::Constant(cs) - origin_;
  nx_ = std::max(1, static_cast<int>(std::ceil(extent.x() / cs)));
  ny_ = std::max(1, static_cast<int>(std::ceil(extent.y() / cs)));

  std::vector<std::vector<std::uint32_t>> cells(static_cast<std::size_t>(nx_) * ny_);
  for (std::uint32_t r = 0; r < refs_.size(); ++r) {
    const Ref& ref = refs_[r];
    Box2 box;
    switch (ref.kind) {
      case Kind::kSegment:
        box = primitives_.segments[ref.index].Bounds();
        break;
      case Kind::kCircle:
        box = primitives_.circles[ref.index].Bounds();
        break;
      case Kind::kEllipse:
        box = primitives_.ellipses[ref.index].Bounds();
        break;
      case Kind::kBezier:
        box = primitives_.beziers[ref.index].ControlBounds();
        break;
    }
    Register(r, box, &cells);
  }
  cell_start_.assign(cells.size() + 1, 0);
  for (std::size_t c = 0; c < cells.size(); ++c) {
    cell_start_[c + 1] = cell_start_[c] + static_cast<std::uint32_t>(cells[c].size());
    cell_items_.insert(cell_items_.end(), cells[c].begin(), cells[c].end());
  }
}

void RayCaster::Register(std::uint32_t r, const Box2& box,
                         std::vector<std::vector<std::uint32_t>>* cells) const {
  const double cs = options_.cell_size_m;
  const int x0 =
      std::clamp(static_cast<int>(std::floor((box.min.x() - origin_.x()) / cs)), 0, nx_ - 1);
  const int x1 =
      std::clamp(static_cast<int>(std::floor((box.max.x() - origin_.x()) / cs)), 0, nx_ - 1);
  const int y0 =
      std::clamp(static_cast<int>(std::floor((box.min.y() - origin_.y()) / cs)), 0, ny_ - 1);
  const int y1 =
      std::clamp(static_cast<int>(std::floor((box.max.y() - origin_.y()) / cs)), 0, ny_ - 1);
  const Ref& ref = refs_[r];
  constexpr double kPad = 1e-9;  // closed cells, so a primitive on a cell border is in both
  for (int iy = y0; iy <= y1; ++iy) {
    for (int ix = x0; ix <= x1; ++ix) {
      const Box2 cell{origin_ + Eigen::Vector2d(ix * cs - kPad, iy * cs - kPad),
                      origin_ + Eigen::Vector2d((ix + 1) * cs + kPad, (iy + 1) * cs + kPad)};
      bool touches = true;
      switch (ref.kind) {
        case Kind::kSegment:
          touches = kernel::Overlaps(cell, primitives_.segments[ref.index]);
          break;
        case Kind::kCircle: {
          const auto& c = primitives_.circles[ref.index];
          touches =
              MinDistance(cell, c.center) <= c.radius && c.radius <= MaxDistance(cell, c.center);
          break;
        }
        case Kind::kEllipse: {
          // Skip cells entirely inside the (convex) ellipse; keep the rest (conservative).
          const auto& e = primitives_.ellipses[ref.index];
          touches = !(e.Contains(cell.min) && e.Contains(cell.max) &&
                      e.Contains({cell.min.x(), cell.max.y()}) &&
                      e.Contains({cell.max.x(), cell.min.y()}));
          break;
        }
        case Kind::kBezier:
          break;  // the control box is small after splitting
      }
      if (touches) (*cells)[static_cast<std::size_t>(iy) * nx_ + ix].push_back(r);
    }
  }
}

double RayCaster::Intersect(const Ref& ref, const kernel::Ray2& ray, double t_max) const {
  switch (ref.kind) {
    case Kind::kSegment:
      return kernel::Intersect(ray, primitives_.segments[ref.index], 0.0, t_max);
    case Kind::kCircle:
      return kernel::Intersect(ray, primitives_.circles[ref.index], 0.0, t_max);
    case Kind::kEllipse:
      return kernel::Intersect(ray, primitives_.ellipses[ref.index], 0.0, t_max);
    case Kind::kBezier:
      return kernel::Intersect(ray, primitives_.beziers[ref.index], 0.0, t_max);
  }
  return kNoHit;
}

double RayCaster::Distance(const Ref& ref, const Eigen::Vector2d& p) const {
  switch (ref.kind) {
    case Kind::kSegment:
      return primitives_.segments[ref.index].Distance(p);
    case Kind::kCircle:
      return primitives_.circles[ref.index].Distance(p);
    case Kind::kEllipse:
      return primitives_.ellipses[ref.index].Distance(p);
    case Kind::kBezier:
      return primitives_.beziers[ref.index].Distance(p);
  }
  return kNoHit;
}

RayHit RayCaster::Cast(const kernel::Ray2& ray, double max_range_m) const {
  const double cs = options_.cell_size_m;
  const Eigen::Vector2d& o = ray.origin;
  const Eigen::Vector2d& d = ray.direction;
  // Clip the ray to the grid's box (slab method).
  double t_enter = 0.0, t_leave = max_range_m;
  for (int axis = 0; axis < 2; ++axis) {
    const double lo = origin_[axis];
    const double hi = origin_[axis] + (axis == 0 ? nx_ : ny_) * cs;
    if (d[axis] == 0.0) {
      if (o[axis] < lo || o[axis] > hi) return {};
      continue;
    }
    double ta = (lo - o[axis]) / d[axis], tb = (hi - o[axis]) / d[axis];
    if (ta > tb) std::swap(ta, tb);
    t_enter = std::max(t_enter, ta);
    t_leave = std::min(t_leave, tb);
  }
  if (t_enter > t_leave) return {};

  const Eigen::Vector2d start = o + t_enter * d;
  int ix = std::clamp(static_cast<int>(std::floor((start.x() - origin_.x()) / cs)), 0, nx_ - 1);
  int iy = std::clamp(static_cast<int>(std::floor((start.y() - origin_.y()) / cs)), 0, ny_ - 1);
  const int step_x = d.x() > 0.0 ? 1 : -1;
  const int step_y = d.y() > 0.0 ? 1 : -1;
  // Ray parameter at which the ray crosses the next vertical / horizontal cell border.
  double t_next_x =
      d.x() != 0.0 ? (origin_.x() + (ix + (step_x > 0)) * cs - o.x()) / d.x() : kNoHit;
  double t_next_y =
      d.y() != 0.0 ? (origin_.y() + (iy + (step_y > 0)) * cs - o.y()) / d.y() : kNoHit;
  const double dt_x = d.x() != 0.0 ? cs / std::abs(d.x()) : kNoHit;
  const double dt_y = d.y() != 0.0 ? cs / std::abs(d.y()) : kNoHit;

  RayHit hit;
  double best = max_range_m;
  while (true) {
    const std::size_t c = static_cast<std::size_t>(iy) * nx_ + ix;
    for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
      const Ref& ref = refs_[cell_items_[k]];
      const double t = Intersect(ref, ray, best);
      if (t < best) {
        best = t;
        hit.obstacle = ref.obstacle;
      }
    }
    const double t_exit = std::min(t_next_x, t_next_y);
    if (best <= t_exit || t_exit >= t_leave) break;
    if (t_next_x < t_next_y) {
      ix += step_x;
      t_next_x += dt_x;
      if (ix < 0 || ix >= nx_) break;
    } else {
      iy += step_y;
      t_next_y += dt_y;
      if (iy < 0 || iy >= ny_) break;
    }
  }
  if (hit.obstacle >= 0) hit.range_m = best;
  return hit;
}

RayHit RayCaster::CastBruteForce(const kernel::Ray2& ray, double max_range_m) const {
  RayHit hit;
  double best = max_range_m;
  for (const Ref& ref : refs_) {
    const double t = Intersect(ref, ray, best);
    if (t < best) {
      best = t;
      hit.obstacle = ref.obstacle;
    }
  }
  if (hit.obstacle >= 0) hit.range_m = best;
  return hit;
}

template <class Visit>
bool RayCaster::VisitNear(const Eigen::Vector2d& center, double radius_m, Visit visit) const {
  const double cs = options_.cell_size_m;
  auto cell = [&](double v, double origin, int n) {
    return std::clamp(static_cast<int>(std::floor((v - origin) / cs)), 0, n - 1);
  };
  const int x0 = cell(center.x() - radius_m, origin_.x(), nx_);
  const int x1 = cell(center.x() + radius_m, origin_.x(), nx_);
  const int y0 = cell(center.y() - radius_m, origin_.y(), ny_);
  const int y1 = cell(center.y() + radius_m, origin_.y(), ny_);
  for (int iy = y0; iy <= y1; ++iy) {
    for (int ix = x0; ix <= x1; ++ix) {
      const std::size_t c = static_cast<std::size_t>(iy) * nx_ + ix;
      for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
        if (visit(refs_[cell_items_[k]])) return true;
      }
    }
  }
  return false;
}

bool RayCaster::Collides(const Eigen::Vector2d& center, double radius_m) const {
  if (VisitNear(center, radius_m,
                [&](const Ref& ref) { return Distance(ref, center) < radius_m; })) {
    return true;
  }
  return IsInsideObstacle(center);
}

RayHit RayCaster::Nearest(const Eigen::Vector2d& p, double max_distance_m) const {
  RayHit best;
  VisitNear(p, max_distance_m, [&](const Ref& ref) {
    const double d = Distance(ref, p);
    if (d <= max_distance_m && (best.obstacle < 0 || d < best.range_m)) {
      best.range_m = d;
      best.obstacle = ref.obstacle;
    }
    return false;
  });
  return best;
}

bool RayCaster::IsInsideObstacle(const Eigen::Vector2d& p) const {
  for (const auto& poly : closed_polygons_) {
    if (InsidePolygon(poly, p)) return true;
  }
  for (const auto& c : primitives_.circles) {
    if (c.Contains(p)) return true;
  }
  for (const auto& e : primitives_.ellipses) {
    if (e.Contains(p)) return true;
  }
  return false;
}

}  // namespace splam::sim
