#ifndef SPLAM_ESTIMATION_EVALUATION_MAP_CONSISTENCY_H_
#define SPLAM_ESTIMATION_EVALUATION_MAP_CONSISTENCY_H_

#include <Eigen/Core>
#include <vector>

#include "kernel/pose2.h"
#include "kernel/scan.h"
#include "kernel/status.h"

// How self-consistent a map is, without ground truth: where a trajectory passes a place twice,
// the scans of one pass must not put walls where the other pass saw free space. A map whose
// loops did not close shows every corridor twice, and the walls of one copy then stand in the
// other's free corridor; a right map leaves a few per cent of a scan there (noise, people, doors
// that moved). Works with the trajectory of any method.
namespace splam::evaluation {

struct ConsistencyOptions {
  // One scan is checked per scan_spacing_m of travel, m.
  double scan_spacing_m = 1.0;
  // Its references: checked scans within reference_radius_m of it whose travel differs from
  // its own by at least min_path_gap_m (another pass, not the same stretch seen again a moment
  // later); the nearest max_references of them, m.
  double reference_radius_m = 5.0;
  double min_path_gap_m = 30.0;
  int max_references = 20;
  // Beams longer than this are not used (the far returns' angular error alone grows past the
  // inlier distance), m.
  double max_range_m = 15.0;
  // The references' field: cells of resolution_m, their views seen seen_margin_m behind hits.
  double resolution_m = 0.1;
  double seen_margin_m = 0.2;
  // A point contradicts the references when it lies where they saw free space, at least
  // inlier_distance_m from their outline (SeenFreeMisfitFraction), m.
  double inlier_distance_m = 0.1;
  // A checked scan with more than this share of its points contradicting is inconsistent: a
  // wall drawn twice 1 m apart puts 30-60 % of a scan in the other copy's corridor, while
  // people, doors and clutter seldom reach a fifth.
  double inconsistent_share = 0.2;
  // The map is flagged when more than this share of the scans checked are inconsistent: right
  // maps of real buildings stay near 1 %, a corridor drawn twice reaches a fifth
  // (docs/graph_slam.md).
  double flag_share = 0.05;

  kernel::Status Validate() const;
};

// A scan placed in the world by a trajectory: the robot's pose and the laser's mounting.
struct PlacedScan {
  kernel::Pose2 pose;
  kernel::Pose2 robot_T_laser;
  const kernel::Scan* scan = nullptr;
};

struct CheckedScan {
  int index = 0;               // into the scans given
  Eigen::Vector2d position;    // the robot's
  int references = 0;          // scans of other passes it was checked against
  double contradicting = 0.0;  // share of its points in their free space
};

struct ConsistencyReport {
  int scans_checked = 0;          // scans that had references (other passes nearby)
  double mean_contradicting = 0;  // share of points, mean over those scans
  int inconsistent = 0;           // those above inconsistent_share
  double inconsistent_share = 0;  // inconsistent / scans_checked (0 when none)
  bool flagged = false;           // inconsistent_share above ConsistencyOptions::flag_share
  std::vector<CheckedScan> checked;
};

// Checks one scan per scan_spacing_m against the scans of other passes near it.
ConsistencyReport CheckMapConsistency(const std::vector<PlacedScan>& scans,
                                      const ConsistencyOptions& options = {});

}  // namespace splam::evaluation

#endif  // SPLAM_ESTIMATION_EVALUATION_MAP_CONSISTENCY_H_
