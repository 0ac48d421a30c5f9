#include "exploration/frontier_map.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <unordered_set>
#include <utility>

#include "kernel/shapes.h"

namespace splam::exploration {
namespace {

// Laser hit points on a grid of kCell squares: an obstacle a laser saw bounds the space behind
// a sonar boundary in front of it (UnseenStretches).
class LaserHits {
 public:
  void Add(const Eigen::Vector2d& p) { cells_.insert(Key(p)); }
  // Whether a hit lies in a cell next to the ray p + t u, 0 <= t <= length (u unit).
  bool AlongRay(const Eigen::Vector2d& p, const Eigen::Vector2d& u, double length) const {
    for (double t = 0.0; t <= length; t += 0.5 * kCell) {
      for (const double dx : {-kCell, 0.0, kCell})
        for (const double dy : {-kCell, 0.0, kCell})
          if (cells_.contains(Key(p + t * u + Eigen::Vector2d(dx, dy)))) return true;
    }
    return false;
  }

 private:
  static constexpr double kCell = 0.1;  // m
  static std::int64_t Key(const Eigen::Vector2d& p) {
    return (static_cast<std::int64_t>(std::floor(p.x() / kCell)) << 32) ^
           (static_cast<std::int64_t>(std::floor(p.y() / kCell)) & 0xffffffff);
  }
  std::unordered_set<std::int64_t> cells_;
};

// Every node's laser hits, where the nodes are now.
LaserHits NodeLaserHits(const ExplorationRun& run, const kernel::Pose2& robot_T_laser) {
  LaserHits hits;
  for (graph::Vertex v = 0; v < run.nodes.size(); ++v) {
    kernel::Scan laser = run.nodes[v].safe_region_scan;
    laser.ranges_m.resize(run.nodes[v].laser_beams);
    const kernel::Pose2 world_T_laser = run.graph[v].configuration * robot_T_laser;
    for (const Eigen::Vector2d& hit : laser.HitPoints()) hits.Add(world_T_laser * hit);
  }
  return hits;
}

// GivenUpFrontiers' unseen stretches; `hits`: every node's laser hits (NodeLaserHits).
std::vector<GivenUpFrontier> UnseenStretches(const FrontierRules& rules, const ExplorationRun& run,
                                             const kernel::Pose2& robot_T_laser,
                                             const LaserHits& hits) {
  const ExplorerOptions& options = rules.options();
  constexpr double kInside = 0.05;  // m: a boundary point is tested this far inside it
  const graph::ExplorationGraph& g = run.graph;
  // What each node's laser alone saw, where the node is now.
  std::vector<kernel::LocalSafeRegion> laser_lsrs;
  for (graph::Vertex v = 0; v < run.nodes.size(); ++v) {
    kernel::Scan laser = run.nodes[v].safe_region_scan;
    laser.ranges_m.resize(run.nodes[v].laser_beams);
    laser_lsrs.push_back(kernel::LocalSafeRegion::FromScan(
        laser, g[v].configuration * robot_T_laser, options.lsr_radius_m));
  }
  std::vector<GivenUpFrontier> list;
  for (graph::Vertex v = 0; v < run.nodes.size(); ++v) {
    const NodeRecord& record = run.nodes[v];
    const kernel::LocalSafeRegion& lsr = g[v].lsr;
    const std::vector<Eigen::Vector2d>& boundary = lsr.boundary();
    if (!lsr.full_circle() || boundary.size() != record.safe_region_scan.size()) continue;
    std::vector<const kernel::LocalSafeRegion*> near;
    for (const kernel::LocalSafeRegion& other : laser_lsrs) {
      if ((other.center() - lsr.center()).norm() <=
          2.0 * options.lsr_radius_m + options.frontier_view_depth_m)
        near.push_back(&other);
    }
    std::vector<Eigen::Vector2d> stretch;
    const auto close = [&] {
      // Not empty: with min_frontier_m 0 an empty stretch is as long as it.
      if (!stretch.empty() && kernel::PolylineLength(stretch) >= options.min_frontier_m) {
        GivenUpFrontier f;
        f.node = static_cast<int>(v);
        f.midpoint = stretch[stretch.size() / 2];
        f.reason = "bounded by the sonars only; no laser saw beyond";
        f.unseen = stretch;
        list.push_back(std::move(f));
      }
      stretch.clear();
    };
    for (std::size_t i = record.laser_beams; i < boundary.size(); ++i) {
      const double range = record.safe_region_scan.ranges_m[i];
      const Eigen::Vector2d offset = boundary[i] - lsr.center();
      bool seen = !std::isnan(range) && range >= options.lsr_radius_m;  // a free arc
      if (!seen && offset.norm() > 1e-9) {
        const Eigen::Vector2d u = offset.normalized();
        const Eigen::Vector2d inside = boundary[i] - std::min(kInside, 0.5 * offset.norm()) * u;
        seen = hits.AlongRay(boundary[i], u, options.frontier_view_depth_m) ||
               kernel::UnionSeesBeyond(near, inside, u, rules.Cover());
      }
      if (seen) {
        close();
      } else {
        stretch.push_back(boundary[i]);
      }
    }
    close();
  }
  return list;
}

}  // namespace

std::vector<const kernel::LocalSafeRegion*> OthersNear(const FrontierRules& rules,
                                                       const graph::ExplorationGraph& g,
                                                       graph::Vertex v) {
  const ExplorerOptions& options = rules.options();
  const kernel::LocalSafeRegion& owner = g[v].lsr;
  std::vector<const kernel::LocalSafeRegion*> others;
  for (graph::Vertex w = 0; w < g.num_nodes(); ++w) {
    const kernel::LocalSafeRegion& other = g[w].lsr;
    const double reach = other.radius() + owner.radius() + options.frontier_view_depth_m;
    if (w != v && (other.center() - owner.center()).norm() <= reach) others.push_back(&other);
  }
  return others;
}

std::vector<kernel::FrontierArc> OpenParts(const FrontierRules& rules,
                                           const graph::ExplorationGraph& g, graph::Vertex v,
                                           const kernel::FrontierArc& arc) {
  return rules.UncoveredParts(g[v].lsr, arc, OthersNear(rules, g, v));
}

bool ShadowOpen(const FrontierRules& rules, const graph::ExplorationGraph& g, graph::Vertex v,
                std::size_t edge) {
  return !rules.ShadowCovered(g[v].lsr, edge, OthersNear(rules, g, v));
}

bool InSight(const FrontierRules& rules, const graph::ExplorationGraph& g,
             const Eigen::Vector2d& from, const Eigen::Vector2d& point) {
  std::vector<const kernel::LocalSafeRegion*> regions;
  for (graph::Vertex v = 0; v < g.num_nodes(); ++v)
    if ((g[v].lsr.center() - point).norm() <= g[v].lsr.radius() + (point - from).norm())
      regions.push_back(&g[v].lsr);
  return kernel::UnionLineOfSight(regions, from, point, rules.options().shadow_edge_m);
}

std::vector<Eigen::Vector2d> NodePositions(const graph::ExplorationGraph& g) {
  std::vector<Eigen::Vector2d> nodes;
  for (graph::Vertex v = 0; v < g.num_nodes(); ++v)
    nodes.push_back(g[v].configuration.translation());
  return nodes;
}

std::vector<GivenUpFrontier> GivenUpFrontiers(const FrontierRules& rules, const ExplorationRun& run,
                                              const kernel::Pose2& robot_T_laser) {
  const ExplorerOptions& options = rules.options();
  const graph::ExplorationGraph& g = run.graph;
  const LaserHits hits = NodeLaserHits(run, robot_T_laser);
  std::vector<GivenUpFrontier> list;
  for (graph::Vertex v = 0; v < g.num_nodes(); ++v) {
    const kernel::LocalSafeRegion& owner = g[v].lsr;
    for (const graph::GivenUpArc& given_up : g[v].given_up) {
      if (given_up.shadow_edge >= 0) {
        const auto edge = static_cast<std::size_t>(given_up.shadow_edge);
        list.push_back({static_cast<int>(v),
                        {},
                        given_up.shadow_edge,
                        {},
                        kernel::EdgeMiddleAndNormal(owner, edge).middle,
                        given_up.reason,
                        ShadowOpen(rules, g, v, edge)});
        continue;
      }
      std::vector<kernel::FrontierArc> left = OpenParts(rules, g, v, given_up.arc);
      if (!left.empty()) {
        // A part behind which a laser hit an obstacle within frontier_view_depth_m at every
        // point is closed, as where an LSR's ray leaves across an obstacle (kernel::CoverOptions):
        // with a SLAM localisation the LSR that saw the obstacle may lie too far off to hold it
        // (`complex`, the paper formulation's seed 1: an arc 0.3 m inside a pillar).
        std::erase_if(left, [&](const kernel::FrontierArc& arc) {
          const int steps = std::max(
              1, static_cast<int>(std::ceil(arc.AngularWidth() / options.arc_sampling_rad)));
          for (int k = 0; k <= steps; ++k) {
            const double angle = arc.start_angle_rad + arc.AngularWidth() * k / steps;
            if (!hits.AlongRay(owner.ArcPoint(angle),
                               Eigen::Vector2d(std::cos(angle), std::sin(angle)),
                               options.frontier_view_depth_m))
              return false;
          }
          return true;
        });
      }
      const double mid = 0.5 * (given_up.arc.start_angle_rad + given_up.arc.end_angle_rad);
      if (left.empty())
        list.push_back({static_cast<int>(v),
                        given_up.arc,
                        -1,
                        {},
                        owner.ArcPoint(mid),
                        given_up.reason,
                        false});
      for (const kernel::FrontierArc& arc : left) {
        const double m = 0.5 * (arc.start_angle_rad + arc.end_angle_rad);
        list.push_back(
            {static_cast<int>(v), arc, -1, {}, owner.ArcPoint(m), given_up.reason, true});
      }
    }
  }
  std::vector<GivenUpFrontier> unseen = options.unseen_frontiers
                                            ? UnseenStretches(rules, run, robot_T_laser, hits)
                                            : std::vector<GivenUpFrontier>();
  list.insert(list.end(), std::make_move_iterator(unseen.begin()),
              std::make_move_iterator(unseen.end()));
  return list;
}

}  // namespace splam::exploration
