#ifndef SPLAM_KERNEL_EXPLORATION_NODES_H_
#define SPLAM_KERNEL_EXPLORATION_NODES_H_

#include <optional>
#include <vector>

#include "kernel/local_safe_region.h"
#include "kernel/pose2.h"

namespace splam::kernel {

// What an explorer tells and asks whatever localises it (SPLAM, paper 003): every new node, where
// the nodes now are, and what a revisit would give. Declared once, for the explorer's
// localisation (exploration::Localization) and for the SLAM methods that take part in
// exploration (estimation::SlamMethod and this, found by estimation::NodesOf); the defaults are
// those of a localisation that does not revise the past.
class ExplorationNodes {
 public:
  virtual ~ExplorationNodes() = default;
  // A new exploration node with its local safe region (world frame, placed at the estimate).
  // The topological SLAM associates against the curves in the newest node's LSR.
  virtual void AtNode(const LocalSafeRegion& /*lsr*/) {}
  // Where the nodes of the AtNode calls so far now are, in order, for those that revise the past
  // (a pose graph moves its nodes with its keyframes): the explorer then moves its nodes, their
  // LSRs and frontiers and the paths between them. Empty: they stay.
  virtual std::vector<Pose2> NodePoses() const { return {}; }
  // Active loop closing: the information (nats, the reduction of the pose's entropy against now)
  // expected from driving path_m[i] metres to node nodes[i] (AtNode order) and closing a loop
  // there; nullopt where it cannot say (the default: every node).
  virtual std::vector<std::optional<double>> RevisitInformation(
      const std::vector<int>& nodes, const std::vector<double>& /*path_m*/) const {
    return std::vector<std::optional<double>>(nodes.size());
  }
};

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_EXPLORATION_NODES_H_
