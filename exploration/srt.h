#ifndef SPLAM_EXPLORATION_SRT_H_
#define SPLAM_EXPLORATION_SRT_H_

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "exploration/explorer.h"
#include "graph/exploration_graph.h"
#include "kernel/local_safe_region.h"

namespace splam::exploration {

class Session;

// SRT's own options (the shared ones are ExplorerOptions).
struct SrtOptions {
  // RANDOM_DIR + VALID_CONF attempts before backtracking to the parent.
  int max_attempts = 30;
  // When the draws run out while the node's free arcs still hold parts no other LSR saw beyond
  // (frontier_view_depth_m), VALID_CONF is relaxed for them: the candidate may lie inside other
  // LSRs and closer than alpha r, else the robot approaches the part (grid_paths). false: the
  // published SRT (Oriolo et al. 2004), which in `office` left rooms seen only through their
  // doors (docs/experiments.md, Fig. 18).
  bool relaxed_valid_conf = true;

  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// Sensor-based Random Tree (Oriolo et al. 2004; paper 003 §2.1, Figs 1-2; SPEC §9). At the
// current node: RANDOM_DIR draws directions uniformly over the node's free arcs; the candidate
// lies alpha * r along it (the LSR radius in a free direction is r); VALID_CONF accepts it when
// it lies outside the LSRs of all other nodes and the straight leg to it is clear for the
// robot's disc. After max_attempts rejected draws, or with no free arc, the robot backtracks
// to the parent along the tree edge. The run ends back at the root with nothing left.
//
// The run loop is fixed; its choices are steps a variant overrides: which direction next
// (NextDirection), where to step along it (StepTowards), and where to go back when the node has
// nothing left (BacktrackTo).
class SrtExplorer : public Explorer {
 public:
  explicit SrtExplorer(const ExplorerOptions& options, const SrtOptions& srt = {})
      : options_(options), srt_(srt) {}
  std::string name() const override { return "srt"; }
  ExplorationRun Run(RobotInterface* robot, Localization* localization) override;

  // Which direction next (rad, world frame), among node `node`'s free arcs (not empty). SRT:
  // RANDOM_DIR, uniform over the arcs (RandomDirection).
  virtual double NextDirection(Session& session, graph::Vertex node,
                               const std::vector<kernel::FrontierArc>& frontiers);
  // Where to step along it: the path to the candidate configuration, nullopt when the
  // candidate is refused (another draw follows, up to max_attempts). SRT: VALID_CONF, alpha r
  // along the direction, outside every other node's LSR and reached by a clear leg inside this
  // one.
  virtual std::optional<std::vector<Eigen::Vector2d>> StepTowards(Session& session,
                                                                  graph::Vertex node,
                                                                  double direction_rad);
  // Where to go when the node has nothing left (its frontiers given up): the node to drive back
  // to, -1 at the root (the given-up frontiers are then retried, or the run ends). SRT: the
  // parent along the tree edge.
  virtual int BacktrackTo(Session& session, graph::Vertex node);

  const ExplorerOptions& options() const { return options_; }
  const SrtOptions& srt_options() const { return srt_; }

 private:
  ExplorerOptions options_;
  SrtOptions srt_;
};

}  // namespace splam::exploration

#endif  // SPLAM_EXPLORATION_SRT_H_
