#include "kernel/local_safe_region.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernel/angle.h"

namespace splam::kernel {
namespace {

using CgalKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalPoint = CgalKernel::Point_2;

constexpr double kMinReach = 0.01;  // fraction of the radius
// A range step between two beams is a depth jump (an occlusion) when it is this many times the
// steps on either side of it. Along a wall the steps grow smoothly, by a few per cent a beam even
// at grazing incidence (r tan(theta) dtheta); at an occluder's edge they jump tenfold or more.
constexpr double kJumpRatio = 3.0;

// Range of boundary vertex k from the centre.
double Range(const LocalSafeRegion& region, std::size_t k) {
  return (region.boundary()[k] - region.center()).norm();
}

// Whether boundary edge i joins two beams that reached the radius: a piece of the free arc.
bool OnFreeArc(const LocalSafeRegion& region, std::size_t i) {
  const double free_reach = region.radius() * (1.0 - 1e-9);
  return Range(region, i) >= free_reach &&
         Range(region, (i + 1) % region.boundary().size()) >= free_reach;
}

}  // namespace

LocalSafeRegion LocalSafeRegion::FromScan(const Scan& scan, const Pose2& world_T_laser,
                                          double radius_m) {
  LocalSafeRegion lsr;
  lsr.center_ = world_T_laser.translation();
  lsr.radius_ = radius_m;
  const bool full_circle = scan.FieldOfView() + scan.angular_step_rad >= 2.0 * kPi - 1e-9;
  lsr.full_circle_ = full_circle;
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

Eigen::Vector2d LocalSafeRegion::ArcPoint(double angle_rad) const {
  return center_ + radius_ * Eigen::Vector2d(std::cos(angle_rad), std::sin(angle_rad));
}

bool Overlaps(const LocalSafeRegion& a, const LocalSafeRegion& b) {
  const std::vector<Eigen::Vector2d>& pa = a.boundary();
  const std::vector<Eigen::Vector2d>& pb = b.boundary();
  if (pa.size() < 3 || pb.size() < 3) return false;
  if ((a.center() - b.center()).norm() > a.radius() + b.radius()) return false;
  if (a.Contains(pb.front()) || b.Contains(pa.front())) return true;
  // Otherwise they share a point only if their boundaries cross.
  std::vector<CgalKernel::Segment_2> sb;
  std::vector<Eigen::AlignedBox2d> boxes_b;
  for (std::size_t j = 0; j < pb.size(); ++j) {
    const Eigen::Vector2d& p = pb[j];
    const Eigen::Vector2d& q = pb[(j + 1) % pb.size()];
    sb.emplace_back(CgalPoint(p.x(), p.y()), CgalPoint(q.x(), q.y()));
    boxes_b.emplace_back(p.cwiseMin(q), p.cwiseMax(q));
  }
  for (std::size_t i = 0; i < pa.size(); ++i) {
    const Eigen::Vector2d& p = pa[i];
    const Eigen::Vector2d& q = pa[(i + 1) % pa.size()];
    const Eigen::AlignedBox2d box(p.cwiseMin(q), p.cwiseMax(q));
    const CgalKernel::Segment_2 s(CgalPoint(p.x(), p.y()), CgalPoint(q.x(), q.y()));
    for (std::size_t j = 0; j < sb.size(); ++j) {
      if (box.intersects(boxes_b[j]) && CGAL::do_intersect(s, sb[j])) return true;
    }
  }
  return false;
}

bool IsShadowEdge(const LocalSafeRegion& region, std::size_t i, double shadow_edge_m) {
  const std::vector<Eigen::Vector2d>& pts = region.boundary();
  const std::size_t n = pts.size();
  const bool partial = !region.full_circle();
  if (partial && (i == 0 || i == n - 1)) return true;  // the edges at the sensor
  const std::size_t j = (i + 1) % n;
  if ((pts[j] - pts[i]).norm() <= shadow_edge_m || OnFreeArc(region, i)) return false;
  const double ri = Range(region, i), rj = Range(region, j);
  // The steps before and after, between beams (not across the sensor vertex).
  const auto step = [&](std::size_t a, std::size_t b) {
    if (partial && (a == 0 || b == 0)) return 0.0;
    return std::abs(Range(region, b) - Range(region, a));
  };
  const double before = step((i + n - 1) % n, i), after = step(j, (j + 1) % n);
  return std::abs(rj - ri) > kJumpRatio * std::max(before, after);
}

std::vector<std::size_t> OcclusionEdges(const LocalSafeRegion& region, double shadow_edge_m,
                                        double min_length_m) {
  std::vector<std::size_t> edges;
  const std::vector<Eigen::Vector2d>& pts = region.boundary();
  const std::size_t n = pts.size();
  const std::size_t first = region.full_circle() ? 0 : 1;
  const std::size_t last = region.full_circle() ? n : n - 1;  // the sensor edges excluded
  for (std::size_t i = first; i < last; ++i) {
    if ((pts[(i + 1) % n] - pts[i]).norm() >= min_length_m &&
        IsShadowEdge(region, i, shadow_edge_m))
      edges.push_back(i);
  }
  return edges;
}

EdgeSide EdgeMiddleAndNormal(const LocalSafeRegion& region, std::size_t i) {
  const std::vector<Eigen::Vector2d>& pts = region.boundary();
  const Eigen::Vector2d& a = pts[i];
  const Eigen::Vector2d& b = pts[(i + 1) % pts.size()];
  const Eigen::Vector2d e = (b - a).normalized();
  return {0.5 * (a + b), Eigen::Vector2d(e.y(), -e.x())};  // counter-clockwise: outside is right
}

namespace {

// Whether the free arc of `region` through boundary edge `edge` is at least
// cover.min_free_arc_m long outside the owner's circle: the length of the free-arc edges next to
// it (both ways) whose far vertex lies outside that circle.
bool CarriesOn(const LocalSafeRegion& region, std::size_t edge, const CoverOptions& cover) {
  if (cover.min_free_arc_m <= 0.0) return true;
  const std::vector<Eigen::Vector2d>& pts = region.boundary();
  const std::size_t n = pts.size();
  const auto outside = [&](std::size_t i) {
    return cover.owner_radius_m <= 0.0 ||
           (pts[i] - cover.owner_center).norm() > cover.owner_radius_m;
  };
  const auto length = [&](std::size_t i) { return (pts[(i + 1) % n] - pts[i]).norm(); };
  double total = length(edge);
  for (std::size_t k = 1, i = (edge + 1) % n; k < n && total < cover.min_free_arc_m; ++k) {
    if (!OnFreeArc(region, i) || !outside((i + 1) % n)) break;
    total += length(i);
    i = (i + 1) % n;
  }
  for (std::size_t k = 1, i = (edge + n - 1) % n; k < n && total < cover.min_free_arc_m; ++k) {
    if (!OnFreeArc(region, i) || !outside(i)) break;
    total += length(i);
    i = (i + n - 1) % n;
  }
  return total >= cover.min_free_arc_m;
}

}  // namespace

RayExit FirstExit(const LocalSafeRegion& region, const Eigen::Vector2d& p, const Eigen::Vector2d& u,
                  double t_from, double t_to, const CoverOptions& cover) {
  const std::vector<Eigen::Vector2d>& pts = region.boundary();
  const std::size_t n = pts.size();
  // The first boundary edge crossed: p + t u = a + s (b - a), t_from < t <= t_to, 0 <= s <= 1.
  double first_t = std::numeric_limits<double>::infinity();
  std::size_t first_edge = n;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = pts[i];
    const Eigen::Vector2d e = pts[(i + 1) % n] - a;
    const double denom = u.x() * e.y() - u.y() * e.x();  // cross(u, e)
    if (std::abs(denom) < 1e-15) continue;               // parallel
    const Eigen::Vector2d w = a - p;
    const double t = (w.x() * e.y() - w.y() * e.x()) / denom;
    const double s = (w.x() * u.y() - w.y() * u.x()) / denom;
    if (t > t_from && t <= t_to && s >= 0.0 && s <= 1.0 && t < first_t) {
      first_t = t;
      first_edge = i;
    }
  }
  if (first_edge == n) return {};
  if (OnFreeArc(region, first_edge)) {
    return {CarriesOn(region, first_edge, cover) ? RayExit::Kind::kFreeArc : RayExit::Kind::kShadow,
            first_t};
  }
  return {IsShadowEdge(region, first_edge, cover.shadow_edge_m) ? RayExit::Kind::kShadow
                                                                : RayExit::Kind::kObstacle,
          first_t};
}

namespace {

// Walks the ray p + t u, 0 < t <= t_to, through the union of `regions`: at each point every
// region containing it tells where the ray leaves it (FirstExit). True as soon as one exit is
// `done`; else the walk carries on from the farthest exit when `passes` lets it across, and is
// false outside every region or where no region takes the ray on measurably (1e-9 m, so that the
// walk ends).
template <typename Done, typename Passes>
bool WalkUnion(const std::vector<const LocalSafeRegion*>& regions, const Eigen::Vector2d& p,
               const Eigen::Vector2d& u, double t_to, const CoverOptions& cover, Done done,
               Passes passes) {
  // After the start, containment is tested just past t: the point where the ray left a region
  // lies on that region's boundary, which Contains() counts as inside, and the walk then took the
  // region on again past its own shadow edge (a frontier seen through a door from two nodes was
  // covered by the space behind the jamb that neither saw).
  constexpr double kPast = 1e-6;  // m
  double t = 0.0;
  while (true) {
    const Eigen::Vector2d at = p + (t > 0.0 ? t + kPast : 0.0) * u;
    bool inside = false;
    RayExit farthest{RayExit::Kind::kShadow, t};
    for (const LocalSafeRegion* region : regions) {
      if (!region->Contains(at)) continue;
      inside = true;
      const RayExit exit = FirstExit(*region, p, u, t, t_to, cover);
      if (done(exit.kind)) return true;
      if (exit.t > farthest.t) farthest = exit;
    }
    if (!inside || !passes(farthest.kind) || farthest.t <= t + 1e-9) return false;
    t = farthest.t;
  }
}

}  // namespace

bool UnionSeesBeyond(const std::vector<const LocalSafeRegion*>& regions, const Eigen::Vector2d& p,
                     const Eigen::Vector2d& u, const CoverOptions& cover) {
  // Seen: the ray stays inside a region up to view_depth (with 0, lying inside one is enough),
  // or leaves it across an obstacle or a free arc; across a shadow edge another region must
  // take it on.
  return WalkUnion(
      regions, p, u, std::max(cover.view_depth_m, 0.0), cover,
      [](RayExit::Kind kind) { return kind != RayExit::Kind::kShadow; },
      [](RayExit::Kind) { return true; });
}

bool UnionLineOfSight(const std::vector<const LocalSafeRegion*>& regions, const Eigen::Vector2d& p,
                      const Eigen::Vector2d& q, double shadow_edge_m) {
  const double length = (q - p).norm();
  const Eigen::Vector2d u =
      length > 0.0 ? Eigen::Vector2d((q - p) / length) : Eigen::Vector2d(1, 0);
  CoverOptions cover;
  cover.shadow_edge_m = shadow_edge_m;
  // In sight: some region holds the rest of the segment; the walk ends at an obstacle.
  return WalkUnion(
      regions, p, u, length, cover, [](RayExit::Kind kind) { return kind == RayExit::Kind::kNone; },
      [](RayExit::Kind kind) { return kind != RayExit::Kind::kObstacle; });
}

std::vector<FrontierArc> ArcPartsInside(const LocalSafeRegion& owner, const FrontierArc& arc,
                                        const std::vector<const LocalSafeRegion*>& others,
                                        double spacing_rad, const CoverOptions& cover) {
  CoverOptions from_owner = cover;
  from_owner.owner_center = owner.center();
  from_owner.owner_radius_m = owner.radius();
  std::vector<FrontierArc> parts;
  const int steps = std::max(1, static_cast<int>(std::ceil(arc.AngularWidth() / spacing_rad)));
  bool inside = false;
  for (int k = 0; k <= steps; ++k) {
    const double angle = arc.start_angle_rad + arc.AngularWidth() * k / steps;
    const bool in = UnionSeesBeyond(others, owner.ArcPoint(angle),
                                    Eigen::Vector2d(std::cos(angle), std::sin(angle)), from_owner);
    if (in && !inside) parts.push_back({angle, angle});
    if (in) parts.back().end_angle_rad = angle;
    inside = in;
  }
  return parts;
}

double SegmentClearance(const LocalSafeRegion& region, const Eigen::Vector2d& a,
                        const Eigen::Vector2d& b) {
  const std::vector<Eigen::Vector2d>& pts = region.boundary();
  const std::size_t n = pts.size();
  if (n < 3) return 0.0;
  const CgalKernel::Segment_2 s(CgalPoint(a.x(), a.y()), CgalPoint(b.x(), b.y()));
  const Eigen::AlignedBox2d box(a.cwiseMin(b), a.cwiseMax(b));
  double best_sq = std::numeric_limits<double>::infinity();
  // Edge i joins vertex i to vertex i + 1; vertex 0 is the sensor of a partial-circle region.
  const std::size_t first = region.full_circle() ? 0 : 1;
  const std::size_t last = region.full_circle() ? n : n - 1;
  for (std::size_t i = first; i < last; ++i) {
    const Eigen::Vector2d& p = pts[i];
    const Eigen::Vector2d& q = pts[(i + 1) % n];
    // The gap between the boxes is a lower bound of the distance; skip edges that cannot win.
    const Eigen::AlignedBox2d edge_box(p.cwiseMin(q), p.cwiseMax(q));
    const double gap =
        std::max({0.0, edge_box.min().x() - box.max().x(), box.min().x() - edge_box.max().x()});
    const double gap_y =
        std::max({0.0, edge_box.min().y() - box.max().y(), box.min().y() - edge_box.max().y()});
    if (gap * gap + gap_y * gap_y >= best_sq) continue;
    const CgalKernel::Segment_2 e(CgalPoint(p.x(), p.y()), CgalPoint(q.x(), q.y()));
    best_sq = std::min(best_sq, CGAL::to_double(CGAL::squared_distance(s, e)));
  }
  return std::sqrt(best_sq);
}

LocalSafeRegion LocalSafeRegion::Transformed(const Pose2& moved_T_world) const {
  LocalSafeRegion moved = *this;
  moved.center_ = moved_T_world * center_;
  for (auto& p : moved.boundary_) p = moved_T_world * p;
  for (auto& arc : moved.frontiers_) arc = arc.Turned(moved_T_world.theta());
  return moved;
}

bool LocalSafeRegion::Contains(const Eigen::Vector2d& p) const {
  if (boundary_.size() < 3) return false;
  std::vector<CgalPoint> polygon;
  polygon.reserve(boundary_.size());
  for (const Eigen::Vector2d& v : boundary_) polygon.emplace_back(v.x(), v.y());
  return CGAL::bounded_side_2(polygon.begin(), polygon.end(), CgalPoint(p.x(), p.y()),
                              CgalKernel()) != CGAL::ON_UNBOUNDED_SIDE;
}

void LocalRegionOptions::VisitFields(FieldVisitor& v) {
  v.Field("radius_m", &radius_m, "LSR radius r (explorers and the topological SLAM's region), m");
  v.Field("alpha", &alpha, "a new node lies alpha r from the current one, 0 < alpha < 1");
}

Status LocalRegionOptions::Validate() const {
  // The explorers plan inside the LSR on 5 cm cells: 1000 m asked for 6.4e9 of them, 100 m for
  // 1.6e7 at every planning step (over 10 s a node); an LSR is a robot's near surroundings.
  if (!(radius_m > 0.0 && radius_m <= 30.0)) return Status::Error("radius_m must be in (0, 30] m");
  if (!(alpha > 0.0 && alpha < 1.0)) return Status::Error("alpha must lie in (0, 1)");
  return Status::Ok();
}

}  // namespace splam::kernel
