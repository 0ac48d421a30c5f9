#ifndef SPLAM_EXPLORATION_FRONTIER_RULES_H_
#define SPLAM_EXPLORATION_FRONTIER_RULES_H_

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <vector>

#include "exploration/explorer.h"
#include "kernel/local_safe_region.h"

namespace splam::exploration {

// When a free arc or an occlusion edge of an LSR is a frontier, and when other LSRs cover it:
// ExplorerOptions' frontier rules (min_frontier_m, doorway_goals, min_doorway_arc_m,
// frontier_view_depth_m, shadow_edge_m, frontiers_carry_on, arc_sampling_rad) for a robot that
// keeps needed_m (its radius plus the clearance margin) from obstacles. Pure geometry of LSRs
// given by the caller: the explorer's map is in frontier_map.h.
class FrontierRules {
 public:
  FrontierRules(const ExplorerOptions& options, double needed_m)
      : options_(options), needed_m_(needed_m) {}

  const ExplorerOptions& options() const { return options_; }
  // The robot's radius plus the clearance margin, m.
  double needed_m() const { return needed_m_; }

  // When another LSR covers a frontier (the view_depth and shadow_edge options).
  kernel::CoverOptions Cover() const;
  // The free arcs of an LSR that are frontiers: those at least min_frontier_m long, and with
  // doorway_goals the shorter ones seen through a gap at least 2 needed_m wide (GapOf): a door at
  // a slant near the LSR's rim leaves an arc shorter than the door (office-doors: a room whose
  // door a node saw 2.9 m away at 50 deg left a 0.36 m arc, dropped, and the run said
  // `explored`). Only within the laser's field of view `laser_view` (world frame; nullopt: all
  // around): the sonars' cones are 30 deg wide, and a short arc between two of them is an
  // artefact of the cone model, which may lie inside an obstacle a cone's edge did not echo
  // (`complex`, SRT seed 1: a 0.11 m arc in a pillar, open at the end of a run that explored
  // everything).
  std::vector<kernel::FrontierArc> FrontiersOf(
      const kernel::LocalSafeRegion& lsr,
      const std::optional<kernel::FrontierArc>& laser_view = std::nullopt) const;
  // The gap through which the sensor saw free arc `arc` of `lsr`: its jambs, the boundary
  // vertices on either side of the arc's middle where the region narrows to the occluders: the
  // near end of the first shadow edge (kernel::IsShadowEdge) past the arc, or the first vertex
  // off the arc when the edge to it is shorter than shadow_edge_m (a door at the rim); within 45
  // deg of the arc's middle. nullopt when a side has none.
  struct Gap {
    Eigen::Vector2d left, right;
    double Width() const { return (left - right).norm(); }
  };
  std::optional<Gap> GapOf(const kernel::LocalSafeRegion& lsr,
                           const kernel::FrontierArc& arc) const;
  // The free arcs of `arcs` at least min_frontier_m long.
  std::vector<kernel::FrontierArc> LongEnough(const std::vector<kernel::FrontierArc>& arcs) const;
  // The parts of `arc` (a frontier of `owner`) that the union of `others` does not cover (the
  // view_depth and shadow_edge options), long enough to stay frontiers; with doorway_goals, the
  // whole arc when they cover none of it (it passed FrontiersOf).
  std::vector<kernel::FrontierArc> UncoveredParts(
      const kernel::LocalSafeRegion& owner, const kernel::FrontierArc& arc,
      const std::vector<const kernel::LocalSafeRegion*>& others) const;
  // Whether the space behind occlusion edge `edge` of `owner` is seen by the union of `others`:
  // the ray out of `owner` from the edge's middle, or from a quarter of it either side
  // (kernel::UnionSeesBeyond, the view_depth and shadow_edge options).
  bool ShadowCovered(const kernel::LocalSafeRegion& owner, std::size_t edge,
                     const std::vector<const kernel::LocalSafeRegion*>& others) const;

  // A point 0.5 m into the space hidden behind occlusion edge `edge` of `lsr`: what the robot
  // approaches (SafePaths::Approach) to see it.
  static Eigen::Vector2d ShadowTarget(const kernel::LocalSafeRegion& lsr, std::size_t edge);
  // The point of a frontier that an approach must see (Retries) and turns to (Session::Drive):
  // 0.1 m inside the LSR on the middle of free arc `arc`, or of occlusion edge `edge`.
  static Eigen::Vector2d ArcSight(const kernel::LocalSafeRegion& lsr,
                                  const kernel::FrontierArc& arc);
  static Eigen::Vector2d ShadowSight(const kernel::LocalSafeRegion& lsr, std::size_t edge);
  // The same for a point of an unseen stretch (frontier_map.h) of `lsr`.
  static Eigen::Vector2d UnseenSight(const kernel::LocalSafeRegion& lsr,
                                     const Eigen::Vector2d& point);

 private:
  ExplorerOptions options_;
  double needed_m_;
};

}  // namespace splam::exploration

#endif  // SPLAM_EXPLORATION_FRONTIER_RULES_H_
