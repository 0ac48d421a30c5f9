#include "estimation/pose_graph/pose_graph.h"

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "estimation/pose_graph/ceres_solve.h"
#include "estimation/pose_graph/pose_graph_uncertainty.h"
#include "kernel/angle.h"

namespace splam::estimation {

int PoseGraph::AddNode(const kernel::Pose2& pose) {
  poses_.push_back(pose.ToVector());
  parent_.push_back(-1);
  ++live_nodes_;
  return num_nodes() - 1;
}

void PoseGraph::AddEdge(const PoseGraphEdge& edge) { edges_.push_back(edge); }

void PoseGraph::RemoveEdges(const std::vector<int>& indices) {
  for (auto it = indices.rbegin(); it != indices.rend(); ++it) edges_.erase(edges_.begin() + *it);
}

kernel::Pose2 PoseGraph::node(int i) const {
  const auto at = [&](int n) {
    const Eigen::Vector3d& p = poses_[static_cast<std::size_t>(n)];
    return kernel::Pose2(p.x(), p.y(), p.z());
  };
  // A merged node's pose is relative to its parent, which may have been merged since.
  const int parent = parent_[static_cast<std::size_t>(i)];
  return parent < 0 ? at(i) : node(parent) * at(i);
}

void PoseGraph::SetNode(int i, const kernel::Pose2& pose) {
  if (!merged(i)) poses_[static_cast<std::size_t>(i)] = pose.ToVector();
}

double PoseGraph::EdgeChi2(const PoseGraphEdge& e) const {
  return EdgeResidual(e)(poses_[static_cast<std::size_t>(e.from)].data(),
                         poses_[static_cast<std::size_t>(e.to)].data())
      .squaredNorm();
}

EdgeResidual::EdgeResidual(const PoseGraphEdge& edge)
    : measurement_(edge.measurement.ToVector()),
      sqrt_information_(Eigen::LLT<Eigen::Matrix3d>(edge.information).matrixU()) {}

Eigen::Vector3d EdgeResidual::operator()(const double* from, const double* to,
                                         Eigen::Matrix3d* d_from, Eigen::Matrix3d* d_to) const {
  const double c = std::cos(from[2]), s = std::sin(from[2]);
  const double dx = to[0] - from[0], dy = to[1] - from[1];
  // M rotates the error into the measurement's frame.
  const double cm = std::cos(measurement_.z()), sm = std::sin(measurement_.z());
  Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
  m.topLeftCorner<2, 2>() << cm, sm, -sm, cm;
  const Eigen::Vector3d r(c * dx + s * dy - measurement_.x(), -s * dx + c * dy - measurement_.y(),
                          kernel::WrapAngle(to[2] - from[2] - measurement_.z()));
  const Eigen::Matrix3d whitened = sqrt_information_ * m;
  if (d_from != nullptr) {
    Eigen::Matrix3d dr;
    dr << -c, -s, -s * dx + c * dy, s, -c, -c * dx - s * dy, 0, 0, -1;
    *d_from = whitened * dr;
  }
  if (d_to != nullptr) {
    Eigen::Matrix3d dr;
    dr << c, s, 0, -s, c, 0, 0, 0, 1;
    *d_to = whitened * dr;
  }
  return whitened * r;
}

PoseGraphEdge ReversedEdge(const PoseGraphEdge& edge) {
  PoseGraphEdge reversed = edge;
  std::swap(reversed.from, reversed.to);
  reversed.measurement = edge.measurement.Inverse();
  // The reversed residual is -Ad(z) e to first order (z the measurement, e the residual).
  reversed.information =
      PropagatedCovariance(edge.information.inverse(), reversed.measurement).inverse();
  return reversed;
}

PoseGraphEdge FusedEdge(const PoseGraphEdge& a, const PoseGraphEdge& b_any) {
  const PoseGraphEdge b = b_any.from == a.from ? b_any : ReversedEdge(b_any);
  // The residuals are the coordinates of E_a = z_a^-1 D and E_b = z_b^-1 D = delta E_a, with
  // delta = z_b^-1 z_a: e_b = d + B e_a to first order in e_a, d the coordinates of delta and
  // B = diag(R_delta, 1). e_a^T I_a e_a + e_b^T I_b e_b = (e_a - mu)^T I (e_a - mu) + const with
  // I = I_a + B^T I_b B and mu = -I^-1 B^T I_b d; the fused edge's residual, the coordinates of
  // exp(mu)^-1 E_a, is e_a - mu to first order.
  const kernel::Pose2 delta = b.measurement.Between(a.measurement);
  Eigen::Matrix3d rotate = Eigen::Matrix3d::Identity();
  rotate.topLeftCorner<2, 2>() = delta.Rotation();
  PoseGraphEdge fused = a;
  fused.information = a.information + rotate.transpose() * b.information * rotate;
  const Eigen::Vector3d mu =
      -fused.information.inverse() * rotate.transpose() * b.information * delta.ToVector();
  fused.measurement = a.measurement * kernel::Pose2(mu.x(), mu.y(), mu.z());
  return fused;
}

bool PoseGraph::merged(int i) const { return parent_[static_cast<std::size_t>(i)] >= 0; }

void PoseGraph::MergeNode(int j, int into) {
  const kernel::Pose2 offset = node(into).Between(node(j));  // into_T_j
  // The edges between j and `into`, fused into one from `into` to j: its residual is the
  // offset's error eps (j = into o eps), its covariance `held`; zero without such an edge.
  std::optional<PoseGraphEdge> between;
  int others = 0;  // j's edges to other nodes
  for (const PoseGraphEdge& edge : edges_) {
    if (edge.from != j && edge.to != j) continue;
    if (edge.from != into && edge.to != into) {
      ++others;
      continue;
    }
    const PoseGraphEdge forward = edge.from == into ? edge : ReversedEdge(edge);
    between = between ? FusedEdge(*between, forward) : forward;
  }
  const Eigen::Matrix3d held = between && others == 1
                                   ? Eigen::Matrix3d(between->information.inverse())
                                   : Eigen::Matrix3d::Zero();
  std::vector<PoseGraphEdge> kept, moved;
  kept.reserve(edges_.size());
  for (PoseGraphEdge edge : edges_) {
    if (edge.from != j && edge.to != j) {
      kept.push_back(edge);
      continue;
    }
    // From side, z' = o z gives the residual E = z^-1 j^-1 x = (z^-1 eps^-1 z) E', so
    // e = e' - Ad(z^-1) eps; to side, z' = z o^-1 gives E' = o E eps^-1 o^-1, so
    // e' = Ad(o) (e - eps), to first order.
    if (edge.from == j) {
      edge.from = into;
      edge.information =
          (edge.information.inverse() + PropagatedCovariance(held, edge.measurement)).inverse();
      edge.measurement = offset * edge.measurement;
    }
    if (edge.to == j) {
      edge.to = into;
      edge.measurement = edge.measurement * offset.Inverse();
      edge.information =
          PropagatedCovariance(edge.information.inverse() + held, offset.Inverse()).inverse();
    }
    if (edge.from != edge.to) moved.push_back(edge);
  }
  for (const PoseGraphEdge& edge : moved) {
    const auto parallel = std::find_if(kept.begin(), kept.end(), [&](const PoseGraphEdge& o) {
      return o.loop == edge.loop && o.robust == edge.robust &&
             ((o.from == edge.from && o.to == edge.to) || (o.from == edge.to && o.to == edge.from));
    });
    if (parallel != kept.end())
      *parallel = FusedEdge(*parallel, edge);
    else
      kept.push_back(edge);
  }
  edges_ = std::move(kept);
  poses_[static_cast<std::size_t>(j)] = offset.ToVector();
  parent_[static_cast<std::size_t>(j)] = into;
  --live_nodes_;
}

// The pose graph's optimisation (Ceres).
namespace {

// a wrapped to (-pi, pi], for doubles and Jets.
template <typename T>
T WrapAngle(const T& a) {
  const T two_pi = T(2.0 * M_PI);
  return a - two_pi * ceres::floor((a + T(M_PI)) / two_pi);
}

// An edge's residual for Ceres, with its analytic Jacobians (EdgeResidual): as fast as automatic
// differentiation of it (BM_PoseGraph within the machine's noise), one residual for the
// optimisation, the closures' chi-square and the registration's prior.
class EdgeCost : public ceres::SizedCostFunction<3, 3, 3> {
 public:
  explicit EdgeCost(const PoseGraphEdge& edge) : residual_(edge) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    Eigen::Matrix3d d_from, d_to;
    const bool want = jacobians != nullptr;
    const Eigen::Vector3d w =
        residual_(parameters[0], parameters[1], want && jacobians[0] ? &d_from : nullptr,
                  want && jacobians[1] ? &d_to : nullptr);
    Eigen::Map<Eigen::Vector3d> out(residuals);
    out = w;
    using RowMajor = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
    if (want && jacobians[0] != nullptr) Eigen::Map<RowMajor>{jacobians[0]} = d_from;
    if (want && jacobians[1] != nullptr) Eigen::Map<RowMajor>{jacobians[1]} = d_to;
    return true;
  }

 private:
  EdgeResidual residual_;
};

// Adds to `problem` the residuals of the edges that reach a node from first_free on (loop
// closures with `loop_loss`) and holds the nodes before it, or the first node (the gauge) when
// first_free is 0.
void AddPoseGraph(const std::vector<PoseGraphEdge>& edges, std::vector<Eigen::Vector3d>* poses,
                  int first_free, ceres::LossFunction* loop_loss, ceres::Problem* problem) {
  const auto pose = [&](int i) { return (*poses)[static_cast<std::size_t>(i)].data(); };
  for (const PoseGraphEdge& e : edges)
    if (std::max(e.from, e.to) >= first_free)
      problem->AddResidualBlock(new EdgeCost(e), e.loop || e.robust ? loop_loss : nullptr,
                                pose(e.from), pose(e.to));
  for (int i = 0; i < std::max(first_free, 1); ++i)
    if (problem->HasParameterBlock(pose(i))) problem->SetParameterBlockConstant(pose(i));
}

}  // namespace

PoseGraphSummary PoseGraph::Optimize(const PoseGraphOptions& options, int first_free) {
  const auto start = std::chrono::steady_clock::now();
  first_free = std::clamp(first_free, 0, num_nodes());
  PoseGraphSummary s;
  s.nodes = num_live_nodes();
  for (int i = std::max(first_free, 1); i < num_nodes(); ++i) s.free_nodes += !merged(i);
  s.edges = static_cast<int>(edges_.size());
  if (s.free_nodes < 1) return s;
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::CauchyLoss loop_loss(options.loop_loss_scale);
  for (const PoseGraphEdge& e : edges_) s.loop_edges += e.loop;
  AddPoseGraph(edges_, &poses_, first_free, &loop_loss, &problem);
  const ceres::Solver::Summary summary =
      SolveSilently(&problem, ceres::SPARSE_NORMAL_CHOLESKY, options.max_iterations);
  for (std::size_t i = static_cast<std::size_t>(first_free); i < poses_.size(); ++i)
    poses_[i].z() = WrapAngle(poses_[i].z());
  s.iterations = static_cast<int>(summary.iterations.size());
  s.initial_cost = summary.initial_cost;
  s.final_cost = summary.final_cost;
  s.converged = summary.termination_type == ceres::CONVERGENCE;
  s.time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return s;
}

std::optional<std::vector<Eigen::Matrix3d>> PoseGraph::CovarianceBlocks(
    const std::vector<int>& nodes, const std::vector<std::pair<int, int>>& pairs,
    const PoseGraphOptions& options) const {
  // Each node's live root and the Jacobian of its pose by the root's.
  std::vector<int> root(nodes.size());
  std::vector<Eigen::Matrix3d> by_root(nodes.size(), Eigen::Matrix3d::Identity());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const int n = nodes[i];
    if (n < 0 || n >= num_nodes()) return std::nullopt;
    int r = n;
    while (parent_[static_cast<std::size_t>(r)] >= 0) r = parent_[static_cast<std::size_t>(r)];
    root[i] = r;
    by_root[i] = CompositionJacobian(node(n).translation() - node(r).translation());
  }
  std::vector<Eigen::Vector3d> poses = poses_;
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::CauchyLoss loop_loss(options.loop_loss_scale);
  AddPoseGraph(edges_, &poses, 0, &loop_loss, &problem);
  const auto block = [&](int r) { return poses[static_cast<std::size_t>(r)].data(); };
  for (const int r : root)
    if (r != 0 && !problem.HasParameterBlock(block(r))) return std::nullopt;
  // The gauge (node 0) is held: its rows are zero.
  const auto free = [&](int r) { return r != 0; };
  std::vector<std::pair<const double*, const double*>> requested;
  for (const auto& [i, j] : pairs) {
    const int a = root[static_cast<std::size_t>(i)], b = root[static_cast<std::size_t>(j)];
    if (!free(a) || !free(b)) continue;
    const std::pair<const double*, const double*> pair(block(std::min(a, b)),
                                                       block(std::max(a, b)));
    if (std::find(requested.begin(), requested.end(), pair) == requested.end())
      requested.push_back(pair);
  }
  ceres::Covariance::Options covariance_options;
  covariance_options.num_threads = 1;
  ceres::Covariance covariance(covariance_options);
  if (!requested.empty() && !covariance.Compute(requested, &problem)) return std::nullopt;
  std::vector<Eigen::Matrix3d> blocks;
  blocks.reserve(pairs.size());
  for (const auto& [i, j] : pairs) {
    const int a = root[static_cast<std::size_t>(i)], b = root[static_cast<std::size_t>(j)];
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> c = Eigen::Matrix3d::Zero();
    if (free(a) && free(b)) covariance.GetCovarianceBlock(block(a), block(b), c.data());
    blocks.push_back(by_root[static_cast<std::size_t>(i)] * c *
                     by_root[static_cast<std::size_t>(j)].transpose());
  }
  return blocks;
}

std::optional<Eigen::MatrixXd> PoseGraph::JointCovariance(const std::vector<int>& nodes,
                                                          const PoseGraphOptions& options) const {
  const int k = static_cast<int>(nodes.size());
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < k; ++i)
    for (int j = i; j < k; ++j) pairs.emplace_back(i, j);
  const auto blocks = CovarianceBlocks(nodes, pairs, options);
  if (!blocks) return std::nullopt;
  Eigen::MatrixXd joint(3 * k, 3 * k);
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const auto [i, j] = pairs[p];
    joint.block<3, 3>(3 * i, 3 * j) = (*blocks)[p];
    joint.block<3, 3>(3 * j, 3 * i) = (*blocks)[p].transpose();
  }
  return joint;
}

std::optional<std::vector<Eigen::Matrix<double, 6, 6>>> PoseGraph::JointCovariancesWith(
    int anchor, const std::vector<int>& others, const PoseGraphOptions& options) const {
  std::vector<int> nodes{anchor};
  nodes.insert(nodes.end(), others.begin(), others.end());
  std::vector<std::pair<int, int>> pairs{{0, 0}};
  for (int i = 1; i < static_cast<int>(nodes.size()); ++i) {
    pairs.emplace_back(0, i);
    pairs.emplace_back(i, i);
  }
  const auto blocks = CovarianceBlocks(nodes, pairs, options);
  if (!blocks) return std::nullopt;
  std::vector<Eigen::Matrix<double, 6, 6>> joints(others.size());
  for (std::size_t o = 0; o < others.size(); ++o) {
    joints[o].topLeftCorner<3, 3>() = (*blocks)[0];
    joints[o].topRightCorner<3, 3>() = (*blocks)[1 + 2 * o];
    joints[o].bottomLeftCorner<3, 3>() = (*blocks)[1 + 2 * o].transpose();
    joints[o].bottomRightCorner<3, 3>() = (*blocks)[2 + 2 * o];
  }
  return joints;
}

void PoseGraphOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("loop_loss_scale", &loop_loss_scale,
          "Cauchy loss on loop-closure edges, whitened residual units");
  v.Field("max_iterations", &max_iterations, "Ceres iterations per optimisation");
}

kernel::Status PoseGraphOptions::Validate() const {
  if (!(loop_loss_scale > 0) || max_iterations < 1 || max_iterations > 1000)
    return kernel::Status::Error("pose graph: loop_loss_scale > 0 and max_iterations in [1, 1000]");
  return kernel::Status::Ok();
}

}  // namespace splam::estimation
