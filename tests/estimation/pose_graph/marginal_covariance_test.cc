// The pose graph's marginal covariances and the expected effect of a revisit (active loop
// closing), against Monte Carlo: the graph's measurements drawn from their covariances around
// the truth, optimised, and the spread of the optimised poses measured.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <random>
#include <vector>

#include "estimation/pose_graph/pose_graph.h"
#include "estimation/pose_graph/pose_graph_uncertainty.h"

namespace splam::estimation {
namespace {

using kernel::Pose2;

Eigen::Matrix3d Diagonal(double sigma_m, double sigma_rad) {
  return Eigen::Vector3d(sigma_m * sigma_m, sigma_m * sigma_m, sigma_rad * sigma_rad).asDiagonal();
}

// A measured edge: the true relative pose perturbed on its right by a draw of `covariance`
// (the residual's frame to first order), with that covariance's information; exact when gen is
// null.
PoseGraphEdge DrawnEdge(int from, int to, const std::vector<Pose2>& truth,
                        const Eigen::Matrix3d& covariance, std::mt19937* gen) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Vector3d xi = Eigen::Vector3d::Zero();
  if (gen != nullptr) xi = covariance.llt().matrixL() * Eigen::Vector3d(n(*gen), n(*gen), n(*gen));
  PoseGraphEdge e;
  e.from = from;
  e.to = to;
  e.measurement =
      truth[static_cast<std::size_t>(from)].Between(truth[static_cast<std::size_t>(to)]) *
      Pose2(xi.x(), xi.y(), xi.z());
  e.information = covariance.inverse();
  return e;
}

struct EdgeSpec {
  int from, to;
  Eigen::Matrix3d covariance;
};

// The graph of `edges` measured once (gen) or exactly (gen null), its nodes started at the
// chain of the first edges' measurements (edge i - 1 leads to node i), node 0 at the truth.
PoseGraph Measured(const std::vector<Pose2>& truth, const std::vector<EdgeSpec>& edges,
                   std::mt19937* gen) {
  PoseGraph graph;
  std::vector<PoseGraphEdge> measured;
  for (const EdgeSpec& spec : edges) {
    measured.push_back(DrawnEdge(spec.from, spec.to, truth, spec.covariance, gen));
  }
  graph.AddNode(truth[0]);
  Pose2 pose = truth[0];
  for (std::size_t i = 1; i < truth.size(); ++i) {
    pose = pose * measured[i - 1].measurement;
    graph.AddNode(pose);
  }
  for (const PoseGraphEdge& e : measured) graph.AddEdge(e);
  return graph;
}

// A square loop of `n` nodes, 1 m apart, turning 90 deg at every corner.
std::vector<Pose2> SquareLoop(int n) {
  std::vector<Pose2> truth{Pose2()};
  for (int i = 1; i < n; ++i)
    truth.push_back(truth.back() * Pose2(1.0, 0.0, i % 3 == 0 ? M_PI / 2 : 0.0));
  return truth;
}

// The sample covariance of the stacked vectors.
Eigen::MatrixXd SampleCovariance(const std::vector<Eigen::VectorXd>& samples) {
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(samples[0].size());
  for (const auto& s : samples) mean += s / static_cast<double>(samples.size());
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(mean.size(), mean.size());
  for (const auto& s : samples)
    c += (s - mean) * (s - mean).transpose() / static_cast<double>(samples.size() - 1);
  return c;
}

// Within the sampling error of `samples` draws: every entry within 4 standard errors of a
// Wishart entry, sqrt((S_ij^2 + S_ii S_jj) / samples).
void ExpectCovarianceNear(const Eigen::MatrixXd& predicted, const Eigen::MatrixXd& sampled,
                          int samples) {
  for (Eigen::Index i = 0; i < predicted.rows(); ++i)
    for (Eigen::Index j = 0; j < predicted.cols(); ++j) {
      const double se = std::sqrt(
          (predicted(i, j) * predicted(i, j) + predicted(i, i) * predicted(j, j)) / samples);
      EXPECT_NEAR(sampled(i, j), predicted(i, j), 4.0 * se) << "entry " << i << ", " << j;
    }
}

// The joint marginal covariance of two nodes of a loop with a closure, from the graph measured
// exactly, equals the spread of the optimised poses over 2,000 graphs measured with noise.
TEST(PoseGraphCovariance, PropertyTheMarginalsMatchMonteCarloOnALoop) {
  const std::vector<Pose2> truth = SquareLoop(12);
  std::vector<EdgeSpec> edges;
  for (int i = 1; i < 12; ++i) edges.push_back({i - 1, i, Diagonal(0.03, 0.01)});
  edges.push_back({0, 11, Diagonal(0.02, 0.005)});  // the closure (not robust: Gaussian)
  edges.push_back({2, 8, Diagonal(0.05, 0.02)});
  const std::vector<int> nodes{5, 11};
  const auto predicted = Measured(truth, edges, nullptr).JointCovariance(nodes, {});
  ASSERT_TRUE(predicted.has_value());
  std::mt19937 gen(11);
  constexpr int kSamples = 2000;
  std::vector<Eigen::VectorXd> samples;
  for (int t = 0; t < kSamples; ++t) {
    PoseGraph graph = Measured(truth, edges, &gen);
    graph.Optimize({});
    Eigen::VectorXd s(6);
    for (int i = 0; i < 2; ++i) {
      const Pose2 p = graph.node(nodes[static_cast<std::size_t>(i)]);
      const Pose2& q = truth[static_cast<std::size_t>(nodes[static_cast<std::size_t>(i)])];
      s.segment<3>(3 * i) << p.x() - q.x(), p.y() - q.y(),
          std::remainder(p.theta() - q.theta(), 2 * M_PI);
    }
    samples.push_back(s);
  }
  ExpectCovarianceNear(*predicted, SampleCovariance(samples), kSamples);
  // The gauge's rows are zero; a node out of range has no covariance.
  const auto with_gauge = Measured(truth, edges, nullptr).JointCovariance({0, 5}, {});
  ASSERT_TRUE(with_gauge.has_value());
  EXPECT_TRUE(with_gauge->topRows<3>().isZero());
  EXPECT_FALSE(Measured(truth, edges, nullptr).JointCovariance({12}, {}).has_value());
  // The pairwise form gives the same blocks.
  const auto pairs = Measured(truth, edges, nullptr).JointCovariancesWith(11, {5}, {});
  ASSERT_TRUE(pairs.has_value());
  EXPECT_LT(((*pairs)[0].topLeftCorner<3, 3>() - predicted->bottomRightCorner<3, 3>()).norm(),
            1e-12);
  EXPECT_LT(((*pairs)[0].topRightCorner<3, 3>() - predicted->bottomLeftCorner<3, 3>()).norm(),
            1e-12);
}

// A node merged into another is held at its offset: its covariance is its parent's moved
// through the offset, whatever the merge did to the edges.
TEST(PoseGraphCovariance, AMergedNodeFollowsItsParent) {
  const std::vector<Pose2> truth = SquareLoop(8);
  std::vector<EdgeSpec> edges;
  for (int i = 1; i < 8; ++i) edges.push_back({i - 1, i, Diagonal(0.03, 0.01)});
  PoseGraph graph = Measured(truth, edges, nullptr);
  graph.MergeNode(7, 6);
  const auto joint = graph.JointCovariance({6, 7}, {});
  ASSERT_TRUE(joint.has_value());
  const Eigen::Vector2d lever = graph.node(7).translation() - graph.node(6).translation();
  Eigen::Matrix3d j = Eigen::Matrix3d::Identity();
  j(0, 2) = -lever.y();
  j(1, 2) = lever.x();
  const Eigen::Matrix3d parent = joint->topLeftCorner<3, 3>();
  EXPECT_LT((joint->bottomRightCorner<3, 3>() - j * parent * j.transpose()).norm(), 1e-12);
  EXPECT_LT((joint->bottomLeftCorner<3, 3>() - j * parent).norm(), 1e-12);
}

// The revisit: a robot at the end of a chain (node 9) drives back to node 2 and closes a loop
// there. The predicted covariance at the goal (CovarianceAfterRevisit from the chain's joint
// covariance of nodes 9 and 2) equals the exact marginal of the graph with the drive and the
// closure added, and the spread over 2,000 noisy graphs; the information it gains is positive and
// shrinks as the drive gets longer.
TEST(PoseGraphCovariance, PropertyTheRevisitPredictionMatchesMonteCarlo) {
  std::vector<Pose2> truth = SquareLoop(10);
  const Eigen::Matrix3d travel = Diagonal(0.08, 0.02), closure = Diagonal(0.02, 0.005);
  std::vector<EdgeSpec> chain;
  for (int i = 1; i < 10; ++i) chain.push_back({i - 1, i, Diagonal(0.03, 0.01)});
  const auto joint = Measured(truth, chain, nullptr).JointCovariance({9, 2}, {});
  ASSERT_TRUE(joint.has_value());
  const Eigen::Matrix<double, 6, 6> joint6 = *joint;
  const Eigen::Matrix3d predicted = CovarianceAfterRevisit(
      joint6, truth[2].translation() - truth[9].translation(), travel, closure);
  // The graph with the drive (node 10 at node 2's place) and the closure 2 -> 10.
  truth.push_back(Pose2(truth[2].x(), truth[2].y(), truth[9].theta()));
  std::vector<EdgeSpec> revisit = chain;
  revisit.push_back({9, 10, travel});  // isotropic in position: the same in any frame
  revisit.push_back({2, 10, closure});
  const auto exact = Measured(truth, revisit, nullptr).JointCovariance({10}, {});
  ASSERT_TRUE(exact.has_value());
  EXPECT_LT((predicted - *exact).norm(), 1e-3 * exact->norm());
  std::mt19937 gen(5);
  constexpr int kSamples = 2000;
  std::vector<Eigen::VectorXd> samples;
  for (int t = 0; t < kSamples; ++t) {
    PoseGraph graph = Measured(truth, revisit, &gen);
    graph.Optimize({});
    const Pose2 p = graph.node(10);
    Eigen::VectorXd s(3);
    s << p.x() - truth[10].x(), p.y() - truth[10].y(),
        std::remainder(p.theta() - truth[10].theta(), 2 * M_PI);
    samples.push_back(s);
  }
  ExpectCovarianceNear(predicted, SampleCovariance(samples), kSamples);
  // Before the revisit the robot's covariance is node 9's; the closure must gain information.
  const Eigen::Matrix3d now = joint6.topLeftCorner<3, 3>();
  const double gain = InformationGain(now, predicted);
  EXPECT_GT(gain, 1.0);
  const Eigen::Matrix3d far = CovarianceAfterRevisit(
      joint6, truth[2].translation() - truth[9].translation(), 25.0 * travel, closure);
  EXPECT_LT(InformationGain(now, far), gain);
  // Revisiting the node the robot stands at gains nothing but the closure's noise.
  const auto here = Measured(truth, chain, nullptr).JointCovariance({9, 9}, {});
  const Eigen::Matrix<double, 6, 6> here6 = *here;
  EXPECT_LT(InformationGain(now, CovarianceAfterRevisit(here6, Eigen::Vector2d::Zero(),
                                                        Eigen::Matrix3d::Zero(), closure)),
            0.01);
}

}  // namespace
}  // namespace splam::estimation
