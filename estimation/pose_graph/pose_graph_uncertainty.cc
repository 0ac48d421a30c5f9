#include "estimation/pose_graph/pose_graph_uncertainty.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <queue>
#include <utility>

namespace splam::estimation {

Eigen::Matrix3d PropagatedCovariance(const Eigen::Matrix3d& covariance,
                                     const kernel::Pose2& b_T_c) {
  const kernel::Pose2 c_T_b = b_T_c.Inverse();
  Eigen::Matrix3d adjoint = Eigen::Matrix3d::Identity();
  adjoint.topLeftCorner<2, 2>() = c_T_b.Rotation();
  adjoint(0, 2) = c_T_b.y();
  adjoint(1, 2) = -c_T_b.x();
  return adjoint * covariance * adjoint.transpose();
}

PoseGraphAdjacency Adjacency(const PoseGraph& graph) {
  PoseGraphAdjacency adjacent(static_cast<std::size_t>(graph.num_nodes()));
  const std::vector<PoseGraphEdge>& edges = graph.edges();
  for (int e = 0; e < static_cast<int>(edges.size()); ++e) {
    const PoseGraphEdge& edge = edges[static_cast<std::size_t>(e)];
    adjacent[static_cast<std::size_t>(edge.from)].emplace_back(edge.to, e);
    adjacent[static_cast<std::size_t>(edge.to)].emplace_back(edge.from, e);
  }
  return adjacent;
}

namespace {

// Dijkstra projection from `source` over the nodes whose covariance's translation trace is at
// most max_trace_m2, stopping once `target` (when >= 0) is settled.
std::vector<Eigen::Matrix3d> Project(const PoseGraph& graph, const PoseGraphAdjacency& adjacent,
                                     int source, int target, double max_trace_m2) {
  const int n = graph.num_nodes();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<Eigen::Matrix3d> covariance(static_cast<std::size_t>(n),
                                          Eigen::Matrix3d::Constant(kInf));
  if (source < 0 || source >= n) return covariance;
  const std::vector<PoseGraphEdge>& edges = graph.edges();
  const kernel::Pose2 source_pose = graph.node(source);
  std::vector<bool> done(static_cast<std::size_t>(n), false);
  using Entry = std::pair<double, int>;  // (trace of the translation block, node)
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  covariance[static_cast<std::size_t>(source)].setZero();
  queue.emplace(0.0, source);
  while (!queue.empty()) {
    const int j = queue.top().second;
    queue.pop();
    if (done[static_cast<std::size_t>(j)]) continue;
    done[static_cast<std::size_t>(j)] = true;
    if (j == target) break;
    for (const auto& [l, e] : adjacent[static_cast<std::size_t>(j)]) {
      if (done[static_cast<std::size_t>(l)]) continue;
      const PoseGraphEdge& edge = edges[static_cast<std::size_t>(e)];
      const Eigen::Matrix3d step = PropagatedCovariance(edge.information.inverse(),
                                                        graph.node(edge.to).Between(source_pose));
      const Eigen::Matrix3d candidate = covariance[static_cast<std::size_t>(j)] + step;
      const double cost = candidate(0, 0) + candidate(1, 1);
      Eigen::Matrix3d& best = covariance[static_cast<std::size_t>(l)];
      if (cost <= max_trace_m2 && cost < best(0, 0) + best(1, 1)) {
        best = candidate;
        queue.emplace(cost, l);
      }
    }
  }
  return covariance;
}

}  // namespace

std::vector<Eigen::Matrix3d> RelativeCovariances(const PoseGraph& graph, int source) {
  return Project(graph, Adjacency(graph), source, -1, std::numeric_limits<double>::infinity());
}

std::optional<Eigen::Matrix3d> RelativeCovarianceWithin(const PoseGraph& graph,
                                                        const PoseGraphAdjacency& adjacent,
                                                        int source, int target,
                                                        double max_trace_m2) {
  const Eigen::Matrix3d c =
      Project(graph, adjacent, source, target, max_trace_m2)[static_cast<std::size_t>(target)];
  if (!(c(0, 0) + c(1, 1) <= max_trace_m2)) return std::nullopt;
  return c;
}

Eigen::Matrix3d CompositionJacobian(const Eigen::Vector2d& displacement) {
  Eigen::Matrix3d j = Eigen::Matrix3d::Identity();
  j(0, 2) = -displacement.y();
  j(1, 2) = displacement.x();
  return j;
}

Eigen::Matrix3d CovarianceAfterRevisit(const Eigen::Matrix<double, 6, 6>& joint,
                                       const Eigen::Vector2d& displacement,
                                       const Eigen::Matrix3d& travel,
                                       const Eigen::Matrix3d& closure) {
  const Eigen::Matrix3d j = CompositionJacobian(displacement);
  const Eigen::Matrix3d gg = j * joint.topLeftCorner<3, 3>() * j.transpose() + travel;
  const Eigen::Matrix3d gk = j * joint.topRightCorner<3, 3>();
  const Eigen::Matrix3d kk = joint.bottomRightCorner<3, 3>();
  const Eigen::Matrix3d gd = gg - gk;  // cov(x_g, d)
  const Eigen::Matrix3d dd = gg + kk - gk - gk.transpose() + closure;
  const Eigen::Matrix3d after = gg - gd * dd.ldlt().solve(gd.transpose());
  return 0.5 * (after + after.transpose());
}

double InformationGain(const Eigen::Matrix3d& before, const Eigen::Matrix3d& after) {
  return 0.5 * (std::log(before.determinant()) - std::log(after.determinant()));
}

}  // namespace splam::estimation
