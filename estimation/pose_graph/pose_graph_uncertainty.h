#ifndef SPLAM_ESTIMATION_POSE_GRAPH_POSE_GRAPH_UNCERTAINTY_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_POSE_GRAPH_UNCERTAINTY_H_

#include <Eigen/Core>
#include <optional>
#include <utility>
#include <vector>

#include "estimation/pose_graph/pose_graph.h"
#include "kernel/pose2.h"

// How uncertain the pose graph's relative poses are, for choosing loop-closure candidates and
// sizing their search windows by the graph's own uncertainty rather than by the distance
// travelled.
namespace splam::estimation {

// A covariance of pose b's error (right perturbation, b * exp(xi)) moved to c = b * b_T_c:
// Ad(c_T_b) cov Ad(c_T_b)^T, with Ad(R, t) = [R, (t_y, -t_x)^T; 0, 1].
Eigen::Matrix3d PropagatedCovariance(const Eigen::Matrix3d& covariance, const kernel::Pose2& b_T_c);

// Dijkstra projection (Bosse et al. 2003, the ATLAS framework): for every node i, the covariance
// of the source's pose relative to node i (right perturbation at the source, in its frame),
// summed over the edges of the path from the source to i that minimises the trace of its
// translation block. An edge's covariance (its information's inverse) is moved to the source
// through the adjoint of `to`_T_source at the current node poses. Along one chain of front-end
// edges this is the chain's covariance; a loop closure on the way gives a shorter, more certain
// path. The marginal covariance of the relative pose is smaller still where several paths join
// (this bound ignores that), and it costs one Dijkstra search, O(E log N), instead of a sparse
// inverse of the whole problem. Nodes the source does not reach get infinite covariances.
std::vector<Eigen::Matrix3d> RelativeCovariances(const PoseGraph& graph, int source);

// Each node's (neighbour, edge index) pairs, each edge seen from both ends.
using PoseGraphAdjacency = std::vector<std::vector<std::pair<int, int>>>;
PoseGraphAdjacency Adjacency(const PoseGraph& graph);

// RelativeCovariances' covariance for `target` alone, the search bounded to the nodes whose
// covariance's translation trace is at most max_trace_m2 (a few nodes around the source when the
// bound is small): nullopt when the target lies beyond. `adjacent` is Adjacency(graph).
std::optional<Eigen::Matrix3d> RelativeCovarianceWithin(const PoseGraph& graph,
                                                        const PoseGraphAdjacency& adjacent,
                                                        int source, int target,
                                                        double max_trace_m2);

// d(c (+) u)/dc for poses (x, y, theta) in the world frame, the composition moving c by
// `displacement` (world frame): [I, (-dy, dx)^T; 0, 1].
Eigen::Matrix3d CompositionJacobian(const Eigen::Vector2d& displacement);

// Expected effect of a revisit (active loop closing; linear-Gaussian, poses (x, y, theta) in the
// world frame). The robot, now at c, drives to keyframe k (`displacement` = t_k - t_c), its pose
// gaining `travel` on the way, and registers against k there with covariance `closure`. `joint`
// is the 6x6 covariance of (x_c, x_k). At the goal g = c (+) u:
//   S_gg = J S_cc J^T + travel, S_gk = J S_ck, J = d(c (+) u)/dc = [I, (-dy, dx)^T; 0, 1];
// the closure measures d = x_g - x_k (at the goal the rotation into k's frame is a constant),
// and the update of a Gaussian conditioned on it leaves
//   S_gg' = S_gg - (S_gg - S_gk) (S_gg + S_kk - S_gk - S_kg + closure)^-1 (S_gg - S_gk)^T.
Eigen::Matrix3d CovarianceAfterRevisit(const Eigen::Matrix<double, 6, 6>& joint,
                                       const Eigen::Vector2d& displacement,
                                       const Eigen::Matrix3d& travel,
                                       const Eigen::Matrix3d& closure);

// The information a Gaussian's change from `before` to `after` gains, 0.5 ln(det before /
// det after), nats (the entropy reduction; independent of the units of x, y and theta).
double InformationGain(const Eigen::Matrix3d& before, const Eigen::Matrix3d& after);

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_POSE_GRAPH_UNCERTAINTY_H_
