#ifndef SPLAM_IO_RUN_PICTURE_H_
#define SPLAM_IO_RUN_PICTURE_H_

#include <Eigen/Core>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "estimation/slam_method.h"
#include "io/carmen.h"
#include "io/render.h"
#include "io/trajectory.h"
#include "kernel/status.h"
#include "sim/world.h"

namespace splam::io {

// Everything one picture of a run can show; empty parts are left out.
struct RunPicture {
  std::string title;
  const sim::World* world = nullptr;
  io::Trajectory truth;
  io::Trajectory odometry;
  std::vector<std::pair<std::string, io::Trajectory>> estimates;  // legend label, trajectory
  std::vector<Eigen::Vector2d> scan_points;                       // world frame
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> map_segments;  // estimated map lines
  std::vector<Eigen::Vector2d> map_corners;                               // estimated map corners
  std::vector<std::vector<Eigen::Vector2d>> map_curves;  // estimated map curves as polylines
  std::vector<Eigen::Vector2d> map_control_points;       // ... their control points
  std::vector<Eigen::Vector2d> map_inflections;          // ... and inflection points
  // A keyframe graph: its nodes and its loop-closure edges (world frame).
  std::vector<Eigen::Vector2d> graph_nodes;
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> graph_loops;
  // Closures that passed the search's tests and were then dropped (unconfirmed, or undone by the
  // optimised graph), between their two keyframes.
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> dropped_loops;
  // Scans checked for the map's self-consistency (CheckMapConsistency): where those that agree
  // with the other passes and those that contradict them were taken.
  std::vector<Eigen::Vector2d> consistent_scans, inconsistent_scans;
  // The estimate as the method gave it while running, before later optimisations moved it.
  io::Trajectory before_optimization;
  io::Rgb world_color = io::palette::kWorld;
  double robot_radius_m = 0.0;  // > 0 draws the robot at the last true (else odometric) pose
  double pixels_per_meter = 40.0;
};

// Hit points of every `every`-th scan of the log, placed with the true pose of the same time
// when the log has ground truth (TRUEPOS), else with the scan's own odometric laser pose.
std::vector<Eigen::Vector2d> ScanPointsInWorld(const io::CarmenLog& log, int every);

// Adds a SLAM map to the picture: lines and corners, or spline curves with control points
// (small dots), inflection points (circles) and corners (diamonds) as paper 000 Figs. 13 and 16
// draw them; and a keyframe graph (nodes, loop closures) when the map has one.
void DrawMap(const estimation::SlamMap& map, RunPicture* picture);

// Draws the picture into each path (.svg or .png); ok, else the first error. The
// frame holds the world, the truth, the estimates and the map; the odometry, which drifts far
// off on real logs, widens it only when there is nothing else to frame, and is clipped.
kernel::Status SaveRunPicture(const RunPicture& picture, const std::vector<std::string>& paths);

// Plots the x, y and theta errors over time of each (label, colour, trajectory) against the
// truth, to each path; ok, else the first error.
kernel::Status SaveErrorPlot(
    const std::string& title, const kernel::Trajectory& truth,
    const std::vector<std::tuple<std::string, io::Rgb, kernel::Trajectory>>& runs,
    const std::vector<std::string>& paths);

}  // namespace splam::io

#endif  // SPLAM_IO_RUN_PICTURE_H_
