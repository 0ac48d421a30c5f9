#ifndef SPLAM_ESTIMATION_EXPLORATION_NODES_H_
#define SPLAM_ESTIMATION_EXPLORATION_NODES_H_

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "estimation/slam_method.h"
#include "kernel/local_safe_region.h"
#include "kernel/pose2.h"

namespace splam::estimation {

// What a SLAM method that takes part in exploration (SPLAM, paper 003) implements besides
// SlamMethod: the explorer tells it of every new node and asks where the nodes now are. A method
// opts in by deriving from both; the explorer's localisation finds it with NodesOf, and methods
// without it simply never hear of the nodes. SlamMethod itself stays the same for every method.
class ExplorationNodes {
 public:
  virtual ~ExplorationNodes() = default;
  // A new exploration node with its local safe region (world frame, placed at the estimate).
  // The topological SLAM associates against the curves in the newest node's LSR.
  virtual void AtNode(const kernel::LocalSafeRegion& lsr) = 0;
  // Where the method now puts the nodes of the AtNode calls so far, in order, for methods that
  // revise the past (the graph SLAM moves its nodes with its keyframes); empty: they stay.
  virtual std::vector<kernel::Pose2> NodePoses() const { return {}; }
  // Active loop closing. The covariance of the current pose (x, y, theta, world frame), when the
  // method has one: a pose graph's marginal costs a factorisation of the graph, so the explorer
  // asks at its decisions, not at every scan (SlamMethod::pose_covariance, asked at every scan
  // for the NEES, stays a filter's).
  virtual std::optional<Eigen::Matrix3d> PoseUncertainty() const { return std::nullopt; }
  // The information (nats, the reduction of the pose's entropy) the method
  // expects from driving path_m[i] metres to node nodes[i] and closing a loop there, against
  // its pose now; nullopt where it cannot say (the default: every node).
  virtual std::vector<std::optional<double>> RevisitInformation(
      const std::vector<int>& nodes, const std::vector<double>& /*path_m*/) const {
    return std::vector<std::optional<double>>(nodes.size());
  }
};

// The method's part in exploration, or null when it takes none.
inline ExplorationNodes* NodesOf(SlamMethod& method) {
  return dynamic_cast<ExplorationNodes*>(&method);
}
inline const ExplorationNodes* NodesOf(const SlamMethod& method) {
  return dynamic_cast<const ExplorationNodes*>(&method);
}

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_EXPLORATION_NODES_H_
