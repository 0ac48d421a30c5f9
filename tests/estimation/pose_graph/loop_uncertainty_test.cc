// The pose graph's relative uncertainty (loop-closure candidates and windows).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include "estimation/pose_graph/pose_graph.h"
#include "estimation/pose_graph/pose_graph_uncertainty.h"
#include "kernel/angle.h"

namespace splam::estimation {
namespace {

using kernel::Pose2;

PoseGraphEdge Edge(int from, int to, const Pose2& measurement, const Eigen::Matrix3d& covariance) {
  PoseGraphEdge e;
  e.from = from;
  e.to = to;
  e.measurement = measurement;
  e.information = covariance.inverse();
  return e;
}

// Along a chain, the covariance of the source relative to an earlier node is that of composing
// the chain's noisy edges: checked against Monte Carlo (20,000 samples of every edge's error,
// right perturbations with the edges' covariances, composed, the source's error taken in its own
// frame), for random chains (fixed seed) that turn and shorten.
TEST(RelativeCovariances, PropertyAChainMatchesMonteCarlo) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    PoseGraph graph;
    std::vector<Pose2> steps;
    std::vector<Eigen::Matrix3d> covariances;
    Pose2 pose;
    graph.AddNode(pose);
    for (int i = 1; i <= 12; ++i) {
      const Pose2 step(0.5 + 0.3 * u(gen), 0.1 * u(gen), 0.4 * u(gen));
      Eigen::Matrix3d c =
          Eigen::Vector3d(std::pow(0.02 + 0.01 * u(gen), 2), std::pow(0.02 + 0.01 * u(gen), 2),
                          std::pow(0.01 + 0.005 * u(gen), 2))
              .asDiagonal();
      pose = pose * step;
      graph.AddNode(pose);
      graph.AddEdge(Edge(i - 1, i, step, c));
      steps.push_back(step);
      covariances.push_back(c);
    }
    const int source = graph.num_nodes() - 1;
    const std::vector<Eigen::Matrix3d> relative = RelativeCovariances(graph, source);
    EXPECT_TRUE(relative[static_cast<std::size_t>(source)].isZero());
    // Monte Carlo of 0_T_source: every edge perturbed on its right.
    std::normal_distribution<double> n(0.0, 1.0);
    Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
    const int samples = 20000;
    for (int s = 0; s < samples; ++s) {
      Pose2 noisy;
      for (std::size_t e = 0; e < steps.size(); ++e) {
        const Eigen::Vector3d xi =
            covariances[e].llt().matrixL() * Eigen::Vector3d(n(gen), n(gen), n(gen));
        noisy = noisy * steps[e] * Pose2(xi.x(), xi.y(), xi.z());
      }
      const Eigen::Vector3d error = pose.Between(noisy).ToVector();
      sum += error * error.transpose();
    }
    const Eigen::Matrix3d empirical = sum / samples;
    const Eigen::Matrix3d& computed = relative[0];
    for (int r = 0; r < 3; ++r)
      EXPECT_NEAR(computed(r, r), empirical(r, r), 0.08 * empirical(r, r)) << "trial " << trial;
    EXPECT_NEAR(computed(0, 1), empirical(0, 1),
                0.08 * std::sqrt(empirical(0, 0) * empirical(1, 1)));
  }
}

// A loop closure is a shortcut: after a closure from the source back to the first node, the
// first node is as certain as the closure, and the nodes between are reached from either end.
// A square loop of 40 steps of 0.5 m, a quarter turn every 10 steps, each step's covariance
// 1e-4 on every axis; not closed.
PoseGraph SquareLoop() {
  PoseGraph graph;
  const Eigen::Matrix3d step_covariance = Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal();
  Pose2 pose;
  graph.AddNode(pose);
  for (int i = 1; i <= 40; ++i) {
    const Pose2 step(0.5, 0.0, i % 10 == 0 ? kernel::kPi / 2 : 0.0);
    pose = pose * step;
    graph.AddNode(pose);
    graph.AddEdge(Edge(i - 1, i, step, step_covariance));
  }
  return graph;
}

TEST(RelativeCovariances, AClosureShortensTheUncertainPath) {
  PoseGraph graph = SquareLoop();
  const auto trace = [](const Eigen::Matrix3d& c) { return c(0, 0) + c(1, 1); };
  const std::vector<Eigen::Matrix3d> open = RelativeCovariances(graph, 40);
  const Eigen::Matrix3d closure_covariance = Eigen::Vector3d(4e-4, 4e-4, 1e-4).asDiagonal();
  graph.AddEdge(Edge(0, 40, graph.node(0).Between(graph.node(40)), closure_covariance));
  const std::vector<Eigen::Matrix3d> closed = RelativeCovariances(graph, 40);
  EXPECT_GT(trace(open[0]), 10 * trace(closed[0]));
  EXPECT_NEAR(trace(closed[0]), trace(closure_covariance), 1e-12);
  for (int i = 0; i < 40; ++i)
    EXPECT_LE(trace(closed[static_cast<std::size_t>(i)]),
              trace(open[static_cast<std::size_t>(i)]) + 1e-12);
  // Node 5 lies 5 steps from node 0: nearer the source through the closure than the long way.
  EXPECT_LT(trace(closed[5]), 0.5 * trace(open[5]));
  // A node the source does not reach has an infinite covariance.
  graph.AddNode(Pose2(100, 0, 0));
  EXPECT_FALSE(std::isfinite(RelativeCovariances(graph, 40)[41](0, 0)));
}

// RelativeCovarianceWithin gives RelativeCovariances' covariance of one node, searching only as
// far as the bound: the same matrix for every node within it, nothing beyond it, and a node
// reached only the long way round is beyond a bound that the closure's path meets.
TEST(RelativeCovariances, TheBoundedSearchAgreesWithTheWholeOneWithinItsBound) {
  PoseGraph graph = SquareLoop();
  const Eigen::Matrix3d closure_covariance = Eigen::Vector3d(4e-4, 4e-4, 1e-4).asDiagonal();
  graph.AddEdge(Edge(0, 40, graph.node(0).Between(graph.node(40)), closure_covariance));
  const PoseGraphAdjacency adjacent = Adjacency(graph);
  const std::vector<Eigen::Matrix3d> whole = RelativeCovariances(graph, 40);
  const auto trace = [](const Eigen::Matrix3d& c) { return c(0, 0) + c(1, 1); };
  const double bound = trace(whole[2]) + 1e-12;  // node 2: through the closure, two steps on
  int within = 0;
  for (int i = 0; i <= 40; ++i) {
    const std::optional<Eigen::Matrix3d> c =
        RelativeCovarianceWithin(graph, adjacent, 40, i, bound);
    const double t = trace(whole[static_cast<std::size_t>(i)]);
    if (t <= bound) {
      ASSERT_TRUE(c.has_value()) << i;
      EXPECT_LT((*c - whole[static_cast<std::size_t>(i)]).norm(), 1e-15) << i;
      ++within;
    } else {
      EXPECT_FALSE(c.has_value()) << i;
    }
  }
  EXPECT_GE(within, 5);   // 40, 39, 38, ... and 0, 1, 2 through the closure
  EXPECT_LE(within, 20);  // not the far side of the square
  EXPECT_FALSE(RelativeCovarianceWithin(graph, adjacent, 40, 20, bound).has_value());
}

}  // namespace
}  // namespace splam::estimation
