#ifndef SPLAM_KERNEL_LOCAL_SAFE_REGION_H_
#define SPLAM_KERNEL_LOCAL_SAFE_REGION_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "kernel/options.h"
#include "kernel/pose2.h"
#include "kernel/scan.h"
#include "kernel/status.h"

namespace splam::kernel {

// The size of the local safe regions (SPEC §9) and of a step between exploration nodes. Two
// components share it, so it is set in one place: the explorers (LSR radius r, a new node alpha r
// away) and the topological SLAM, whose local region is the newest node's LSR, or a virtual one
// of radius r once the robot is more than alpha r from it.
struct LocalRegionOptions {
  double radius_m = 3.0;  // r: LSRs are clipped here (below the URG-04LX's 4 m range), m
  double alpha = 0.8;     // a new node lies alpha r from the current one, 0 < alpha < 1
  void VisitFields(FieldVisitor& v);
  // Ok when valid, else the first problem.
  Status Validate() const;
};

// A free arc of the LSR boundary: directions in which nothing was hit within the LSR radius
// (free, unexplored), from start_angle_rad counter-clockwise to end_angle_rad, world frame.
struct FrontierArc {
  double start_angle_rad = 0.0;
  double end_angle_rad = 0.0;  // >= start_angle_rad
  double AngularWidth() const { return end_angle_rad - start_angle_rad; }
  // The arc turned by angle_rad about its region's centre.
  FrontierArc Turned(double angle_rad) const {
    return {start_angle_rad + angle_rad, end_angle_rad + angle_rad};
  }
};

// Local safe region (SPEC §9, Oriolo et al. 2004): the star-shaped region around the sensor
// bounded by the range reading in every direction, clipped at the LSR radius r. Outside the
// sensor's field of view nothing is known, so there the region has radius 0. Invalid readings
// (NaN) count as obstacles next to the sensor (at 1 % of r, as do shorter readings): the region
// is never larger than what was seen free, and its boundary is a simple polygon.
class LocalSafeRegion {
 public:
  // From a scan taken by a sensor at world_T_laser; radius_m > 0.
  static LocalSafeRegion FromScan(const Scan& scan, const Pose2& world_T_laser, double radius_m);

  const Eigen::Vector2d& center() const { return center_; }
  double radius() const { return radius_; }
  // The boundary as a simple polygon, counter-clockwise: the sensor position (unless the scan
  // covers the full circle), then the clipped reading of every beam.
  const std::vector<Eigen::Vector2d>& boundary() const { return boundary_; }
  const std::vector<FrontierArc>& frontiers() const { return frontiers_; }
  // True when p lies inside or on the boundary; exact (CGAL's filtered predicates).
  bool Contains(const Eigen::Vector2d& p) const;
  // The region moved by the rigid transform `moved_T_world` (world frame to world frame): its
  // centre and boundary mapped, its arcs' angles turned by its heading.
  LocalSafeRegion Transformed(const Pose2& moved_T_world) const;
  // The point of a frontier arc at `angle_rad` (on the circle of radius r).
  Eigen::Vector2d ArcPoint(double angle_rad) const;
  // True when the scan covered the full circle (the boundary has no vertex at the sensor).
  bool full_circle() const { return full_circle_; }

 private:
  Eigen::Vector2d center_ = Eigen::Vector2d::Zero();
  double radius_ = 0.0;
  std::vector<Eigen::Vector2d> boundary_;
  std::vector<FrontierArc> frontiers_;
  bool full_circle_ = false;
};

// True when the two regions share a point: a boundary vertex of one lies in the other, or two
// boundary edges meet (exact segment-intersection predicates; edges far apart are culled by
// their boxes first). Overlapping regions are joined by a safe path through the overlap (REG's
// CURR_INTERSECTION adds an edge then).
bool Overlaps(const LocalSafeRegion& a, const LocalSafeRegion& b);

// When another region covers a point of a frontier arc (ArcPartsInside).
struct CoverOptions {
  // 0: the point lies inside the other region (Oriolo et al. 2004, paper 003). Above 0, the other
  // region must also have seen beyond it: the ray from the point away from the owner's centre
  // stays inside the other region for view_depth_m, or leaves it before across an obstacle or
  // across the other's own free arc (whose frontier then carries on), not across a shadow edge,
  // m. A region that looked in through a door at a slant holds the frontier point in a narrow
  // wedge between two shadow edges, and the room beyond is as unknown as before.
  double view_depth_m = 0.0;
  // A boundary edge longer than this between two beams whose range jumps (IsShadowEdge) is a
  // shadow edge: the sensor saw an occluder at one end and past it at the other, not the space
  // between (a door jamb's shadow). So are the two edges at the sensor of a partial-circle region.
  // m.
  double shadow_edge_m = 0.2;
  // A ray that leaves the other region across its free arc counts as seen only where that arc,
  // outside the owner's circle (owner_center, owner_radius_m; radius 0: no owner), is at least
  // this long: shorter free arcs are not frontiers (the explorers' minimum), so nothing carries
  // on there. Two nodes that each looked at a door near their rims covered each other's arc
  // through it, each leaving a piece too short to keep, and the room was never entered
  // (docs/experiments.md, Fig. 18). 0: any free arc carries on. m.
  double min_free_arc_m = 0.0;
  Eigen::Vector2d owner_center = Eigen::Vector2d::Zero();
  double owner_radius_m = 0.0;
};

// Whether boundary edge i (from vertex i to i + 1) of `region` is a shadow: an edge at the sensor
// of a partial-circle region, or longer than shadow_edge_m, not on the free arc, with a range step
// over 3 times the steps of the edges on either side (a depth jump at an occluder; a wall at
// grazing incidence has long edges too, but its range grows smoothly from beam to beam).
bool IsShadowEdge(const LocalSafeRegion& region, std::size_t i, double shadow_edge_m);

// The shadow edges between beams (not those at the sensor) at least min_length_m long, by their
// boundary index: the space behind each, within the radius, is hidden from the region's sensor
// (behind a table, a door jamb seen at a slant).
std::vector<std::size_t> OcclusionEdges(const LocalSafeRegion& region, double shadow_edge_m,
                                        double min_length_m);
// The middle of boundary edge i and the unit normal there pointing out of the region (to the
// side an occlusion edge hides).
struct EdgeSide {
  Eigen::Vector2d middle;
  Eigen::Vector2d outward;
};
EdgeSide EdgeMiddleAndNormal(const LocalSafeRegion& region, std::size_t i);

// Where the ray p + t u (u unit, t > t_from) first leaves `region` within t <= t_to, and across
// what. p + t_from u is assumed inside the region.
struct RayExit {
  enum class Kind {
    kNone,      // no crossing up to t_to: inside all the way
    kObstacle,  // across an edge between two beams that is neither free arc nor shadow
    kFreeArc,   // across the region's own free arc (both ends at the LSR radius)
    kShadow,    // across a shadow edge or an edge at the sensor: nothing was seen beyond
  };
  Kind kind = Kind::kNone;
  double t = 0.0;  // the crossing, when kind != kNone
};
RayExit FirstExit(const LocalSafeRegion& region, const Eigen::Vector2d& p, const Eigen::Vector2d& u,
                  double t_from, double t_to, const CoverOptions& cover);

// Whether the union of `regions` saw beyond `p` in direction `u` (unit): p inside one, and the
// ray p + t u, 0 < t <= cover.view_depth_m, followed from region to region (each taking it on
// where another left it across a shadow edge: a room seen partly from each of two nodes) stays
// inside or leaves across an obstacle or a free arc (CoverOptions).
bool UnionSeesBeyond(const std::vector<const LocalSafeRegion*>& regions, const Eigen::Vector2d& p,
                     const Eigen::Vector2d& u, const CoverOptions& cover);

// Whether the segment p-q runs inside the union of `regions`: p lies inside one, and the walk
// along the segment (as UnionSeesBeyond's) leaves each region across a shadow edge or a free arc
// where another takes it on, up to q; false where it runs into an obstacle. What a robot at p
// would see of q, as far as the regions know.
bool UnionLineOfSight(const std::vector<const LocalSafeRegion*>& regions, const Eigen::Vector2d& p,
                      const Eigen::Vector2d& q, double shadow_edge_m);

// The parts of `arc` (a frontier arc of `owner`) that the union of `others` covers (CoverOptions,
// UnionSeesBeyond), as angular intervals of the arc, found by classifying points spacing_rad
// apart with the exact containment test (exact at those points; a covered piece narrower than
// the spacing can be missed).
std::vector<FrontierArc> ArcPartsInside(const LocalSafeRegion& owner, const FrontierArc& arc,
                                        const std::vector<const LocalSafeRegion*>& others,
                                        double spacing_rad, const CoverOptions& cover = {});
inline std::vector<FrontierArc> ArcPartsInside(const LocalSafeRegion& owner, const FrontierArc& arc,
                                               const LocalSafeRegion& other, double spacing_rad,
                                               const CoverOptions& cover = {}) {
  return ArcPartsInside(owner, arc, {&other}, spacing_rad, cover);
}

// How far the segment a-b stays from the boundary of `region`: the smallest distance between the
// segment and a boundary edge (0 when it crosses the boundary). The two edges that meet at the
// sensor of a partial-circle region are left out: they only bound what the sensor did not see,
// and a robot standing at the sensor is inside them. A disc of radius rho swept along a-b stays
// inside the region when `a` is inside and the clearance exceeds rho (up to the obstacle parts
// that poke between two beams, less than the beam spacing times the range).
double SegmentClearance(const LocalSafeRegion& region, const Eigen::Vector2d& a,
                        const Eigen::Vector2d& b);

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_LOCAL_SAFE_REGION_H_
