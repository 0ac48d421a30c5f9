#include "estimation/pose_graph_uncertainty.h"

#include <Eigen/LU>
#include <functional>
#include <limits>
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

std::vector<Eigen::Matrix3d> RelativeCovariances(const PoseGraph& graph, int source) {
  const int n = graph.num_nodes();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<Eigen::Matrix3d> covariance(static_cast<std::size_t>(n),
                                          Eigen::Matrix3d::Constant(kInf));
  if (source < 0 || source >= n) return covariance;
  // Each edge once, seen from both ends: (neighbour, edge index).
  std::vector<std::vector<std::pair<int, int>>> adjacent(static_cast<std::size_t>(n));
  const std::vector<PoseGraphEdge>& edges = graph.edges();
  for (int e = 0; e < static_cast<int>(edges.size()); ++e) {
    const PoseGraphEdge& edge = edges[static_cast<std::size_t>(e)];
    adjacent[static_cast<std::size_t>(edge.from)].emplace_back(edge.to, e);
    adjacent[static_cast<std::size_t>(edge.to)].emplace_back(edge.from, e);
  }
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
    for (const auto& [l, e] : adjacent[static_cast<std::size_t>(j)]) {
      if (done[static_cast<std::size_t>(l)]) continue;
      const PoseGraphEdge& edge = edges[static_cast<std::size_t>(e)];
      const Eigen::Matrix3d step = PropagatedCovariance(edge.information.inverse(),
                                                        graph.node(edge.to).Between(source_pose));
      const Eigen::Matrix3d candidate = covariance[static_cast<std::size_t>(j)] + step;
      const double cost = candidate(0, 0) + candidate(1, 1);
      Eigen::Matrix3d& best = covariance[static_cast<std::size_t>(l)];
      if (cost < best(0, 0) + best(1, 1)) {
        best = candidate;
        queue.emplace(cost, l);
      }
    }
  }
  return covariance;
}

}  // namespace splam::estimation
