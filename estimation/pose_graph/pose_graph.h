#ifndef SPLAM_ESTIMATION_POSE_GRAPH_POSE_GRAPH_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_POSE_GRAPH_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "estimation/slam_map.h"
#include "kernel/options.h"
#include "kernel/pose2.h"
#include "kernel/status.h"

namespace splam::estimation {

// One relative-pose constraint: the motion from node `from` to node `to` in from's frame
// (from_T_to), with its information matrix (inverse covariance of (dx, dy, dtheta)).
struct PoseGraphEdge {
  int from = 0, to = 0;
  kernel::Pose2 measurement;
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();
  bool loop = false;  // a loop closure (robust loss) rather than a front-end edge
  // A front-end edge that also gets the closures' robust loss (see
  // FrontEndOptions::Advanced::robust_recovery_edges).
  bool robust = false;
};

struct PoseGraphOptions {
  // Loop-closure edges get a Cauchy loss of this scale on their whitened residual: a wrong
  // closure that survived the tests pulls with bounded force.
  double loop_loss_scale = 2.0;
  int max_iterations = 50;

  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// The whitened residual of an edge between the poses (x, y, theta) of its two nodes,
//   w = sqrt(I) (R_m^T (R_from^T (t_to - t_from) - t_m), wrap(th_to - th_from - th_m)),
// the translation error taken in the measurement's frame (where the information is given),
// with its analytic Jacobians dw/d from and dw/d to when not null.
class EdgeResidual {
 public:
  explicit EdgeResidual(const PoseGraphEdge& edge);
  Eigen::Vector3d operator()(const double* from, const double* to,
                             Eigen::Matrix3d* d_from = nullptr,
                             Eigen::Matrix3d* d_to = nullptr) const;

 private:
  Eigen::Vector3d measurement_;
  Eigen::Matrix3d sqrt_information_;  // upper Cholesky factor of the information
};

// The same constraint as an edge from `to` to `from`: the inverse measurement, its information
// carried to the reversed residual (which is -Ad(z) e to first order, z the measurement).
PoseGraphEdge ReversedEdge(const PoseGraphEdge& edge);
// Two edges between the same two nodes (in either direction) as one edge from a.from to a.to,
// whose whitened squared residual is the sum of theirs up to a constant, to first order in the
// residuals: information I_a + B^T I_b B and a measurement moved by the weighted mean of their
// difference (B rotates b's residual into a's frame). Keeps a's flags.
PoseGraphEdge FusedEdge(const PoseGraphEdge& a, const PoseGraphEdge& b);

// A 2-D pose graph (Ceres, after its examples/slam/pose_graph_2d): minimises
//   sum_e rho_e(r_e^T I_e r_e),  r_e = (R_from^T (t_to - t_from) - t_m, wrap(th_to - th_from -
//   th_m))
// over every node but the first, which anchors the gauge.
class PoseGraph {
 public:
  int AddNode(const kernel::Pose2& pose);
  void AddEdge(const PoseGraphEdge& edge);
  // Removes the edges with these indices (ascending).
  void RemoveEdges(const std::vector<int>& indices);
  // Every node ever added, merged ones included (node indices are never reused).
  int num_nodes() const { return static_cast<int>(poses_.size()); }
  // The nodes not merged into another.
  int num_live_nodes() const { return live_nodes_; }
  // Merges node j into node `into` (both live, distinct), for a graph whose size follows the
  // map rather than the path (a reduced pose graph, Johannsson et al. 2013): j is held at its
  // present pose relative to `into` (node(j) = node(into) * into_T_j from now on, SetNode
  // ignores it) and leaves the optimisation. Its other edges go to `into`, each the same
  // residual to first order, and the edges between j and `into` are dropped. When j has one
  // other edge (a node of a chain merged into its neighbour) the dropped edges' covariance is
  // carried into it as the offset's error: the two edges are composed, and the marginal of the
  // nodes left is unchanged. Otherwise the offset is taken as exact, as a reduced pose graph
  // does for a revisit tied to the place: a node of several edges has no marginal in separate
  // edges, and counting the offset's error once per edge weakened the closures and a revisit's
  // odometry (docs/graph_slam.md, "Memory"). An edge parallel to an edge of the same
  // kind (loop, robust) is fused into it (FusedEdge), so that the edges follow the pairs of
  // places joined. The edges that did not reach j keep their order.
  void MergeNode(int j, int into);
  bool merged(int i) const;
  const std::vector<PoseGraphEdge>& edges() const { return edges_; }
  // A merged node's pose follows the node it was merged into.
  kernel::Pose2 node(int i) const;
  void SetNode(int i, const kernel::Pose2& pose);
  // Whitened squared residual r^T I r of edge `e` at the current node poses.
  double EdgeChi2(const PoseGraphEdge& e) const;
  // Optimises the nodes from first_free on, holding the earlier ones (0: every node but the
  // first, which anchors the gauge); edges between held nodes are left out.
  PoseGraphSummary Optimize(const PoseGraphOptions& options, int first_free = 0);
  // The joint marginal covariance of the poses (x, y, theta; world frame) of `nodes`, 3x3 block
  // (i, j) for nodes[i] and nodes[j], at the current estimate with the first node held (the
  // gauge: its rows are zero): the inverse of the Gauss-Newton Hessian J^T J of the whitened
  // residuals (ceres::Covariance, sparse QR), loop and robust edges weighed by their Cauchy loss
  // at their present residual, as the optimisation weighs them. A merged node's rows are its
  // parent's moved through the held offset (x_j = x_p (+) offset: d x_j / d x_p =
  // [I, (-(y_j - y_p), x_j - x_p)^T; 0, 1]). Exact for a linear-Gaussian graph, the usual
  // Laplace approximation otherwise. nullopt when a node is out of range or the Hessian is
  // rank-deficient (a node no edge reaches). Costs a sparse factorisation of the graph.
  std::optional<Eigen::MatrixXd> JointCovariance(const std::vector<int>& nodes,
                                                 const PoseGraphOptions& options) const;
  // The same for the pairs (anchor, others[i]) alone, each a 6x6 joint covariance (anchor
  // first): one factorisation for many candidates, without the blocks between them.
  std::optional<std::vector<Eigen::Matrix<double, 6, 6>>> JointCovariancesWith(
      int anchor, const std::vector<int>& others, const PoseGraphOptions& options) const;

 private:
  // The covariance blocks (nodes[i], nodes[j]) of JointCovariance for these index pairs.
  std::optional<std::vector<Eigen::Matrix3d>> CovarianceBlocks(
      const std::vector<int>& nodes, const std::vector<std::pair<int, int>>& pairs,
      const PoseGraphOptions& options) const;

  // (x, y, theta): in the world, or for a merged node relative to its parent.
  std::vector<Eigen::Vector3d> poses_;
  std::vector<int> parent_;  // the node it was merged into, -1 while live
  int live_nodes_ = 0;
  std::vector<PoseGraphEdge> edges_;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_POSE_GRAPH_H_
