#ifndef SPLAM_ESTIMATION_POSE_GRAPH_KEYFRAMES_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_KEYFRAMES_H_

#include <Eigen/Core>
#include <array>
#include <chrono>
#include <memory>
#include <vector>

#include "estimation/pose_graph/distance_grid.h"
#include "estimation/pose_graph/moving_objects.h"
#include "kernel/pose2.h"
#include "kernel/scan.h"
#include "kernel/spline_extraction.h"

// The keyframes the three parts of the graph SLAM share (graph_slam.h): the front end makes
// them and edits the recent ones, the loop closer reads the older ones, the back end moves their
// poses and drops the data of redundant ones. Keyframe k is node k of the back end's pose graph.
namespace splam::estimation {

struct Keyframe {
  kernel::Pose2 pose;        // world_T_robot, optimised
  int trajectory = 0;        // the trajectory (log, session, robot) it belongs to
  double travelled_m = 0.0;  // path length at this keyframe
  int scan = 0;              // the scan that made it (0-based, input order)
  bool in_map = false;
  bool trimmed = false;  // its data dropped (trim_spacing_m)
  // The views rasterised on the lattice at `pose` (RasteriseView; by_hits from seen_by_hits),
  // for the submap ([0], the front end's thread) and the loop targets ([1], the loop search's):
  // made again only when the keyframe has moved or its view changed (ViewsOf).
  struct ViewRaster {
    bool valid = false;
    kernel::Pose2 pose;
    ViewCells seen;
    bool by_hits_valid = false;
    ViewCells by_hits;
  };
  // What a keyframe holds until it is trimmed: on its own allocation, so that a trimmed
  // keyframe (most of them on a long revisiting run) keeps only the fields above.
  struct Data {
    std::vector<OrientedPoint> points;          // the scan's hits, robot frame, with normals
    std::vector<OrientedPoint> raster;          // curve samples (+ points), robot frame
    std::vector<kernel::SplineCurve> curves;    // robot frame; map keyframes only
    std::vector<Eigen::Vector2d> seen;          // the scan's view: sensor, then beam ends
    std::vector<Eigen::Vector2d> seen_by_hits;  // the view of its beams that returned
    // That scan, clipped, its moving objects read as NaN, and its mounting; kept while the
    // keyframe is among the front end's last moving_keyframes (empty after).
    kernel::Scan reading;
    BeamRanges candidates;  // the reading's (ForegroundObjects)
    kernel::Pose2 robot_T_laser;
    mutable std::array<ViewRaster, 2> rasters;
  };
  std::unique_ptr<Data> data;  // null once trimmed
};

using Keyframes = std::vector<Keyframe>;

// The raster of these keyframes in the world frame (trimmed ones add nothing).
std::vector<OrientedPoint> WorldRaster(const Keyframes& keyframes, const std::vector<int>& ids);
// Their views (or those of their beams that returned) rasterised at resolution_m with
// seen_margin_m, from their Keyframe::Data::rasters[slot] (0: the submap's, 1: the loop
// targets'), made again where stale. Trimmed keyframes add nothing.
std::vector<const ViewCells*> ViewsOf(const Keyframes& keyframes, const std::vector<int>& ids,
                                      int slot, double resolution_m, double seen_margin_m,
                                      bool by_hits = false);
// The keyframes' poses (x, y, theta).
std::vector<Eigen::Vector3d> PosesOf(const Keyframes& keyframes, const std::vector<int>& ids);
// Every keyframe up to `newest` holding data within radius_m of `center`.
std::vector<int> AreaKeyframes(const Keyframes& keyframes, const Eigen::Vector2d& center,
                               double radius_m, int newest);

// One element per cell of a `spacing` grid: the mean of the cell's points (and the normalised
// sum of their normals), in the order the cells were first met.
std::vector<OrientedPoint> Thinned(const std::vector<OrientedPoint>& elements, double spacing);
std::vector<Eigen::Vector2d> Positions(const std::vector<OrientedPoint>& oriented);
// True when b lies closer than distance_m to a and is turned less than angle_rad from it.
bool Within(const kernel::Pose2& a, const kernel::Pose2& b, double distance_m, double angle_rad);
// diag(sigma_m^2, sigma_m^2, sigma_rad^2).
Eigen::Matrix3d Diagonal(double sigma_m, double sigma_rad);

// Adds the wall time of its scope to a counter, ms.
class ScopedTimer {
 public:
  explicit ScopedTimer(double* total_ms)
      : total_ms_(total_ms), start_(std::chrono::steady_clock::now()) {}
  ~ScopedTimer() {
    *total_ms_ +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_)
            .count();
  }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  double* total_ms_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_KEYFRAMES_H_
