#include "exploration/frontier_rules.h"

#include <cmath>
#include <limits>

#include "graph/frontiers.h"
#include "kernel/angle.h"
#include "kernel/shapes.h"

namespace splam::exploration {
namespace {

// The point of a frontier that an approach must see lies this far inside its owner's LSR, m.
constexpr double kSightInside = 0.1;

}  // namespace

kernel::CoverOptions FrontierRules::Cover() const {
  kernel::CoverOptions cover;
  cover.view_depth_m = options_.frontier_view_depth_m;
  cover.shadow_edge_m = options_.shadow_edge_m;
  if (options_.frontiers_carry_on) cover.min_free_arc_m = options_.min_frontier_m;
  return cover;
}

bool FrontierRules::ShadowCovered(const kernel::LocalSafeRegion& owner, std::size_t edge,
                                  const std::vector<const kernel::LocalSafeRegion*>& others) const {
  // Seen behind at a quarter, the middle or three quarters of the edge: the hidden space is not
  // a slit then (near the occluder the ray from the middle often runs into the occluder's own
  // flank, seen at grazing incidence).
  const kernel::EdgeSide side = kernel::EdgeMiddleAndNormal(owner, edge);
  const Eigen::Vector2d& a = owner.boundary()[edge];
  const Eigen::Vector2d& b = owner.boundary()[(edge + 1) % owner.boundary().size()];
  for (const double f : {0.5, 0.25, 0.75})
    if (kernel::UnionSeesBeyond(others, a + f * (b - a), side.outward, Cover())) return true;
  return false;
}

Eigen::Vector2d FrontierRules::ShadowTarget(const kernel::LocalSafeRegion& lsr, std::size_t edge) {
  constexpr double kInto = 0.5;  // m
  const kernel::EdgeSide side = kernel::EdgeMiddleAndNormal(lsr, edge);
  return side.middle + kInto * side.outward;
}

Eigen::Vector2d FrontierRules::ArcSight(const kernel::LocalSafeRegion& lsr,
                                        const kernel::FrontierArc& arc) {
  const double mid = 0.5 * (arc.start_angle_rad + arc.end_angle_rad);
  return lsr.center() +
         (lsr.radius() - kSightInside) * Eigen::Vector2d(std::cos(mid), std::sin(mid));
}

Eigen::Vector2d FrontierRules::ShadowSight(const kernel::LocalSafeRegion& lsr, std::size_t edge) {
  const kernel::EdgeSide side = kernel::EdgeMiddleAndNormal(lsr, edge);
  return side.middle - kSightInside * side.outward;
}

Eigen::Vector2d FrontierRules::UnseenSight(const kernel::LocalSafeRegion& lsr,
                                           const Eigen::Vector2d& point) {
  const Eigen::Vector2d offset = point - lsr.center();
  const double norm = offset.norm();
  return norm > 2.0 * kSightInside ? Eigen::Vector2d(point - kSightInside / norm * offset) : point;
}

std::optional<FrontierRules::Gap> FrontierRules::GapOf(const kernel::LocalSafeRegion& lsr,
                                                       const kernel::FrontierArc& arc) const {
  constexpr double kSearch = kernel::kPi / 4;
  const std::vector<Eigen::Vector2d>& pts = lsr.boundary();
  const std::size_t n = pts.size();
  const Eigen::Vector2d& c = lsr.center();
  const double free_reach = lsr.radius() * (1.0 - 1e-9);
  auto range = [&](std::size_t i) { return (pts[i] - c).norm(); };
  auto bearing = [&](std::size_t i) { return std::atan2(pts[i].y() - c.y(), pts[i].x() - c.x()); };
  // The arc's vertex nearest its middle direction.
  const double mid = 0.5 * (arc.start_angle_rad + arc.end_angle_rad);
  std::optional<std::size_t> middle;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    if (range(i) < free_reach) continue;
    const double off = std::abs(kernel::WrapAngle(bearing(i) - mid));
    if (off < best) {
      best = off;
      middle = i;
    }
  }
  if (!middle) return std::nullopt;
  // Walking from the middle in `step` (+1 or -1) direction past the arc: the first edge off it
  // joins the arc to the jamb when it is short (a door at the rim), else the jamb is the near end
  // of the first shadow edge (a depth jump at the occluder), within kSearch of the middle.
  auto jamb = [&](int step) -> std::optional<Eigen::Vector2d> {
    std::size_t i = *middle;
    bool left_arc = false;
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t edge = step > 0 ? i : (i + n - 1) % n;  // from vertex edge to edge + 1
      const std::size_t next = step > 0 ? (i + 1) % n : (i + n - 1) % n;
      if (!lsr.full_circle() && (edge == 0 || edge == n - 1)) return std::nullopt;  // the sensor
      if (std::abs(kernel::WrapAngle(bearing(next) - mid)) > kSearch) return std::nullopt;
      if (range(next) < free_reach && !left_arc) {
        left_arc = true;
        if ((pts[next] - pts[i]).norm() <= options_.shadow_edge_m) return pts[next];
      }
      if (left_arc && kernel::IsShadowEdge(lsr, edge, options_.shadow_edge_m))
        return range(i) < range(next) ? pts[i] : pts[next];
      i = next;
    }
    return std::nullopt;
  };
  const std::optional<Eigen::Vector2d> left = jamb(+1), right = jamb(-1);
  if (!left || !right) return std::nullopt;
  return Gap{*left, *right};
}

std::vector<kernel::FrontierArc> FrontierRules::FrontiersOf(
    const kernel::LocalSafeRegion& lsr,
    const std::optional<kernel::FrontierArc>& laser_view) const {
  const auto in_laser_view = [&](const kernel::FrontierArc& arc) {
    if (!laser_view) return true;
    const double mid = 0.5 * (arc.start_angle_rad + arc.end_angle_rad);
    const double from_start = kernel::WrapAngle(mid - laser_view->start_angle_rad);
    return (from_start >= 0.0 ? from_start : from_start + 2.0 * kernel::kPi) <=
           laser_view->AngularWidth();
  };
  std::vector<kernel::FrontierArc> kept;
  for (const kernel::FrontierArc& arc : lsr.frontiers()) {
    if (graph::ArcLength(arc, options_.lsr_radius_m) >= options_.min_frontier_m) {
      kept.push_back(arc);
    } else if (options_.doorway_goals && in_laser_view(arc) &&
               graph::ArcLength(arc, options_.lsr_radius_m) >= options_.min_doorway_arc_m) {
      const std::optional<Gap> gap = GapOf(lsr, arc);
      if (gap && gap->Width() >= 2.0 * needed_m_) kept.push_back(arc);
    }
  }
  return kept;
}

std::vector<kernel::FrontierArc> FrontierRules::UncoveredParts(
    const kernel::LocalSafeRegion& owner, const kernel::FrontierArc& arc,
    const std::vector<const kernel::LocalSafeRegion*>& others) const {
  const auto covered =
      kernel::ArcPartsInside(owner, arc, others, options_.arc_sampling_rad, Cover());
  // A frontier nothing covers stays as its node made it: FrontiersOf keeps an arc shorter than
  // min_frontier_m seen through a door (doorway_goals), and re-filtering dropped it at the
  // node's first overlap with any LSR, so that REG never went for such doors.
  if (covered.empty() && options_.doorway_goals) return {arc};
  return LongEnough(graph::Subtract(arc, covered, options_.arc_sampling_rad));
}

std::vector<kernel::FrontierArc> FrontierRules::LongEnough(
    const std::vector<kernel::FrontierArc>& arcs) const {
  std::vector<kernel::FrontierArc> kept;
  for (const kernel::FrontierArc& arc : arcs) {
    if (graph::ArcLength(arc, options_.lsr_radius_m) >= options_.min_frontier_m)
      kept.push_back(arc);
  }
  return kept;
}

}  // namespace splam::exploration
