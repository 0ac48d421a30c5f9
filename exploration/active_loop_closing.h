#ifndef SPLAM_EXPLORATION_ACTIVE_LOOP_CLOSING_H_
#define SPLAM_EXPLORATION_ACTIVE_LOOP_CLOSING_H_

#include <Eigen/Core>
#include <optional>
#include <set>
#include <vector>

#include "graph/exploration_graph.h"
#include "kernel/options.h"
#include "kernel/status.h"

// Active loop closing (Stachniss et al. 2005; Makarenko et al. 2002): an explorer whose
// localisation grows uncertain drives back to a place it knows, where the SLAM closes a loop,
// before it explores on. The localisation says how uncertain it is (Localization::
// PoseCovariance) and what a revisit to each node is expected to give (Localization::
// RevisitInformation: the reduction of the pose's entropy after the drive and the closure, in
// nats); the explorer weighs that against the drive's length.
namespace splam::exploration {

class Localization;
class Session;

struct ActiveLoopClosingOptions {
  bool enabled = false;
  // A revisit is weighed once the pose's position standard deviation (the square root of the
  // largest eigenvalue of its position covariance) reaches this, m: 3 sigma is then the graph
  // SLAM's near loop-search window (LoopClosureOptions::near_window_m, 3 m), beyond which only
  // its wide search, slower and readier to take a look-alike place, still finds the robot. The
  // graph SLAM's covariance follows its front-end edge model (FrontEndOptions::edge), wider
  // than what its registration achieves: exploring `complex` it reaches 1 m after
  // 20-40 m of path without closures.
  double min_position_sigma_m = 1.0;
  // A revisit is taken when its expected information minus cost_nats_per_m times its detour
  // (twice its path: there and back to where exploring goes on) is positive, the best such node
  // first. A closure that takes the position's standard deviation from 1 m to 0.1 m in both axes
  // gains 2 ln 10 = 4.6 nats (with the heading's, 6-8 nats exploring `complex`): at 0.25 nats/m it
  // is worth a node up to 9-16 m away, a few LSR steps (alpha r = 2.4 m at the defaults).
  double cost_nats_per_m = 0.25;
  // ... and gains at least this, nats (ln 2: the covariance's volume halved).
  double min_information_nats = 0.69;
  // After a revisit, none again before the robot has driven this far (its estimate's path), m:
  // the closures a revisit finds are confirmed and optimised over the next few keyframes
  // (LoopClosureOptions::optimize_every_keyframes, LoopClosureOptions::confirm_keyframes: 20
  // keyframes, 6 m), and until then the covariance does not show them.
  double min_travel_between_m = 10.0;

  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// A revisit the explorer may make from node `from`.
struct RevisitChoice {
  graph::Vertex to = 0;
  std::vector<graph::Vertex> path;  // from `from` to `to` over the graph
  double path_m = 0.0;
  double information_nats = 0.0;  // expected (Localization::RevisitInformation)
  double utility = 0.0;           // information - cost_nats_per_m * 2 path_m
};

// The revisit with the highest utility from `from` among the nodes it reaches over `graph` (the
// nodes in `excluded` and `from` itself left out), or nullopt when none gains
// min_information_nats with a positive utility, or the localisation cannot say.
std::optional<RevisitChoice> ChooseRevisit(const graph::ExplorationGraph& graph, graph::Vertex from,
                                           const Localization& localization,
                                           const ActiveLoopClosingOptions& options,
                                           const std::set<graph::Vertex>& excluded = {});

// The position standard deviation of a pose covariance (x, y, theta): the square root of the
// largest eigenvalue of its position block, m.
double PositionSigma(const Eigen::Matrix3d& covariance);

// A revisit made (ExplorationRun::revisits).
struct RevisitRecord {
  int from = -1, to = -1;  // the node the robot left and the node it revisited
  double time_s = 0.0;     // when it was chosen (simulated)
  double path_m = 0.0;     // the graph path's length
  double information_nats = 0.0;
  double position_sigma_m = 0.0;  // of the pose when it was chosen
  // At the next decision after it (the closures it found in the graph by then); NaN when there
  // was none.
  double position_sigma_after_m = 0.0;
  bool reached = false;
  std::size_t trace_begin = 0, trace_end = 0;  // the drive, as indices into the run's trace
};

// The explorer's part: called at each node where it decides, it revisits when the pose's
// uncertainty calls for it (min_position_sigma_m, min_travel_between_m) and ChooseRevisit finds a
// node worth it, each node at most once, and records it in the run.
class ActiveLoopClosing {
 public:
  explicit ActiveLoopClosing(const ActiveLoopClosingOptions& options) : options_(options) {}
  // At node `current`: the node where the robot is after a revisit (`current` again with
  // come_back: SRT's tree goes on from where it was), or nullopt when it did not revisit.
  std::optional<graph::Vertex> Step(Session* session, graph::Vertex current, bool come_back);

 private:
  ActiveLoopClosingOptions options_;
  std::set<graph::Vertex> revisited_;
  std::size_t traced_ = 0;       // trace samples counted into travelled_m_
  double travelled_m_ = 0.0;     // the estimate's path so far
  double last_revisit_m_ = 0.0;  // travelled_m_ at the last revisit
  bool any_ = false;             // a revisit was made
};

}  // namespace splam::exploration

#endif  // SPLAM_EXPLORATION_ACTIVE_LOOP_CLOSING_H_
