#ifndef SPLAM_ESTIMATION_POSE_GRAPH_GLOBAL_LOCALIZER_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_GLOBAL_LOCALIZER_H_

#include <memory>
#include <string>
#include <vector>

#include "estimation/pose_graph/distance_grid.h"
#include "estimation/pose_graph/graph_slam_options.h"
#include "estimation/slam_state.h"
#include "kernel/pose2.h"
#include "kernel/status.h"

// Global localisation: where a scan, or a short stretch of scans, lies anywhere in a saved map,
// at any heading, with no initial pose (the kidnapped robot; a session that shares no frame with
// the map). After Cartographer's global search (Hess et al. 2016): a correlative branch and bound
// over the whole map's likelihood pyramid and every heading, then a fine registration.
namespace splam::estimation {

// The outcome of one query.
struct GlobalFix {
  bool found = false;
  kernel::Pose2 pose;         // world_T_robot (refused: the search's best, unchecked)
  double score = 0.0;         // the correlative search's best mean likelihood
  double second_score = 0.0;  // the best distinct pose's (0: none above the floor)
  kernel::Pose2 second_pose;  // that pose, when second_score > 0
  long evaluated = 0;         // score evaluations of the search (its cost)
  std::string refused;        // why not found: "points", "score", "ambiguous", "registration"
};

// A stretch of scans as one query: each scan's points (MapScanPoints) placed in the last scan's
// frame by the scans' poses (where a front end put them: only their relative poses matter).
std::vector<OrientedPoint> StretchPoints(const std::vector<MapScan>& scans,
                                         const FrontEndOptions& front_end);

class GlobalLocalizer {
 public:
  // The map's field from its scans (each at its pose, with its view); `front_end` says how scans
  // become points (range, normals) and how the fix is registered. `map` must not be empty.
  GlobalLocalizer(const std::vector<MapScan>& map, const FrontEndOptions& front_end,
                  const GlobalLocalizationOptions& options);
  ~GlobalLocalizer();
  GlobalLocalizer(const GlobalLocalizer&) = delete;
  GlobalLocalizer& operator=(const GlobalLocalizer&) = delete;

  // Where `points` (robot frame, with normals: a scan's, or a stretch of scans placed in the
  // last one's frame) lie in the map.
  GlobalFix Locate(const std::vector<OrientedPoint>& points) const;
  // The same for one scan.
  GlobalFix Locate(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) const;

  const DistanceGrid& field() const { return grid_; }

 private:
  FrontEndOptions front_end_;
  GlobalLocalizationOptions options_;
  DistanceGrid grid_;
  std::unique_ptr<LikelihoodPyramid> pyramid_;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_GLOBAL_LOCALIZER_H_
