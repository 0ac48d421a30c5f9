#ifndef SPLAM_ESTIMATION_SLAM_MAP_H_
#define SPLAM_ESTIMATION_SLAM_MAP_H_

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "estimation/map_line.h"
#include "estimation/map_spline.h"
#include "kernel/pose2.h"
#include "kernel/spline_extraction.h"

// What every SLAM method reports, whatever its family: its map as layers and its counters
// (SlamMethod::Map, SlamMethod::Statistics). A method fills the layers it has and leaves the
// others empty; drawing, export and the reports read the layers, never a method.
namespace splam::estimation {

// One loop-closure search and what became of it (GraphSlam::loop_searches, SlamMap::loop_searches).
struct LoopSearch {
  enum class Outcome {
    kPending,       // passed the search's tests, waiting for confirmation
    kAccepted,      // in the graph
    kScore,         // refused: no pose scored, too little overlap or too low a likelihood
    kAmbiguous,     // refused: a distinct pose scored nearly as well
    kRegistration,  // refused: the fine registration failed its test
    kMisfit,        // refused: too much of the query where the target saw free space
    kUnconfirmed,   // dropped: no other closure agreed with it in time
    kUndone,        // added, then removed: it disagreed with the optimised graph
  };
  int query = 0;                            // the new keyframe
  int target = 0;                           // the candidate keyframe
  int query_scan = -1, target_scan = -1;    // the scans that made them (0-based, in input order)
  kernel::Pose2 searched;                   // the query keyframe's pose when it was searched
  double window_m = 0.0, window_rad = 0.0;  // the search's half-widths
  double time_ms = 0.0;                     // the search's wall time (target, search, tests)
  bool matched = false;  // the correlative search found a pose (`match` is then the query's)
  kernel::Pose2 match;   // world pose of the query keyframe the search proposed
  kernel::Pose2 target_searched;  // the target keyframe's pose when it was searched
  Outcome outcome = Outcome::kPending;
};
const char* OutcomeName(LoopSearch::Outcome outcome);

// What one optimisation did (kept per optimisation in summary.json).
struct PoseGraphSummary {
  int nodes = 0, edges = 0, loop_edges = 0;
  int free_nodes = 0;  // the nodes optimised (PoseGraph::Optimize's first_free on)
  int iterations = 0;
  double initial_cost = 0.0, final_cost = 0.0;
  bool converged = false;
  double time_ms = 0.0;
};

// The map of a method, in the world frame, as layers: what drawing, export and the reports read.
// A method fills those it has: lines and corners (ekf-lines), spline curves with the options
// that find their features (ekf-bspline, topological, graph), a keyframe graph with its
// loop-closure edges and searches (graph, topological-graph); a new method whose map is one of
// these needs no change here.
struct SlamMap {
  // Landmarks.
  std::vector<MapLine> lines;
  std::vector<MapCorner> corners;
  // Curves.
  std::vector<MapSpline> splines;
  kernel::SplineExtractionOptions spline_features;  // how features of `splines` are found
  // A keyframe graph: its nodes in order and its loop-closure edges (node indices).
  std::vector<kernel::Pose2> keyframes;
  std::vector<std::pair<int, int>> loop_edges;
  // Every loop-closure search (query and target index `keyframes`) and its outcome.
  std::vector<LoopSearch> loop_searches;
};

// Counters of scan-to-map registrations (a graph SLAM's front end, localisation in a saved map).
struct RegistrationCounts {
  long registrations = 0;
  long recovery_searches = 0;  // a correlative search around the prediction ran
  long recovered = 0;          // and its pose was taken
  long fallbacks = 0;          // scans left at the odometric prediction
};

// Loop-closure counters: every candidate searched, and what became of it.
struct LoopClosureCounts {
  long searches = 0;
  long accepted = 0;
  long rejected_score = 0, rejected_ambiguous = 0, rejected_registration = 0, rejected_misfit = 0,
       rejected_disagreement = 0, rejected_unconfirmed = 0;
};

// Method-independent counters of what a method did, in the order they are reported: the typed
// ones of the kinds a method has, then its own named counters.
struct SlamStatistics {
  std::string association;  // the association's name ("" when the method has none to report)
  std::vector<std::pair<std::string, long>> map;  // e.g. {"lines", 12}, {"corners", 3}
  std::optional<RegistrationCounts> registration;
  std::optional<LoopClosureCounts> loop_closure;
  std::vector<std::pair<std::string, long>> associations;  // e.g. {"accepted", 4120}
  // Nonlinear least-squares solves (Ceres) and those that did not converge.
  long solver_runs = 0;
  long solver_failures = 0;
  // Wall time by part of the method, ms (e.g. {"registration", 812.0}); may be empty.
  std::vector<std::pair<std::string, double>> time_ms;
  // Every pose-graph optimisation (graph SLAM), in order.
  std::vector<PoseGraphSummary> optimizations;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_SLAM_MAP_H_
