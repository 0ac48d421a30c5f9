#include "estimation/pose_graph/graph_back_end.h"

#include <Eigen/LU>

#include <algorithm>
#include <cassert>
#include <limits>

#include "estimation/chi_square.h"
#include "estimation/pose_graph/pose_graph_uncertainty.h"

namespace splam::estimation {

GraphBackEnd::GraphBackEnd(const BackEndOptions& options, Keyframes* keyframes, bool closures)
    : options_(options), keyframes_(keyframes), closures_(closures) {}

void GraphBackEnd::AddKeyframe(const Eigen::Matrix3d& edge_covariance, bool robust) {
  // One node per keyframe, in order: the store has just grown by one.
  assert(static_cast<int>(keyframes_->size()) == graph_.num_nodes() + 1);
  const int k = graph_.AddNode(keyframes_->back().pose);
  if (k == 0) return;
  PoseGraphEdge edge;
  edge.from = k - 1;
  edge.to = k;
  edge.measurement =
      (*keyframes_)[static_cast<std::size_t>(k - 1)].pose.Between(keyframes_->back().pose);
  edge.information = edge_covariance.inverse();
  edge.robust = robust;
  graph_.AddEdge(edge);
}

void GraphBackEnd::Trim(int j) {
  if (j < 1 || !(options_.trim_spacing_m > 0)) return;
  Keyframe& kf = (*keyframes_)[static_cast<std::size_t>(j)];
  if (kf.in_map || kf.trimmed) return;
  // The nearest earlier keyframe that holds its data within the spacing.
  int cover = -1;
  double nearest_m = std::numeric_limits<double>::infinity();
  for (int i = 0; i < j; ++i) {
    const Keyframe& o = (*keyframes_)[static_cast<std::size_t>(i)];
    const double d = (o.pose.translation() - kf.pose.translation()).norm();
    if (!o.trimmed && d < nearest_m &&
        Within(o.pose, kf.pose, options_.trim_spacing_m, options_.trim_spacing_rad)) {
      cover = i;
      nearest_m = d;
    }
  }
  // Without loop closure no search reads a keyframe that has left the submap.
  if (closures_ && cover < 0) return;
  if (closures_ && options_.merge_trimmed_keyframes) merge_queue_.push_back({j, cover});
  kf.data.reset();
  kf.trimmed = true;
  ++trimmed_;
}

ClosureReport GraphBackEnd::AddClosures(const std::vector<PoseGraphEdge>& closures,
                                        const std::vector<int>& tags,
                                        const std::vector<PoseGraphEdge>& waiting,
                                        kernel::Pose2* pose) {
  if (closures.empty()) return {};
  bool agree_with_graph = true;
  double chi2 = 0.0;
  for (const PoseGraphEdge& e : closures) {
    const double c = graph_.EdgeChi2(e);
    agree_with_graph &= c <= options_.max_chi2;
    chi2 += c;
  }
  // Closures that agree with the graph as it is wait in it, unoptimised (DeferOptimization).
  if (!agree_with_graph || !DeferOptimization(chi2, static_cast<int>(closures.size())))
    return AddAndOptimize(closures, tags, waiting, pose);
  deferred_chi2_ += chi2;
  for (std::size_t i = 0; i < closures.size(); ++i) {
    deferred_edges_.push_back(static_cast<int>(graph_.edges().size()));
    deferred_tags_.push_back(tags[i]);
    graph_.AddEdge(closures[i]);
  }
  ++deferred_optimizations_;
  // Node 0 is held in any case: a window over the whole graph frees nodes 1 on.
  ClosureReport report;
  if (options_.advanced.local_optimization_keyframes > 0) {
    Optimize(std::max(1, LocalWindow(closures)), pose);
    report.moved = true;
  }
  report.deferred = true;
  report.stand = tags;
  return report;
}

ClosureReport GraphBackEnd::AddAndOptimize(const std::vector<PoseGraphEdge>& closures,
                                           const std::vector<int>& tags,
                                           const std::vector<PoseGraphEdge>& waiting,
                                           kernel::Pose2* pose) {
  // The closures checked after the optimisation: those that waited in the graph, then the new.
  std::vector<int> checked = deferred_edges_, checked_tags = deferred_tags_;
  std::vector<kernel::Pose2> before;
  for (int i = 0; i < graph_.num_nodes(); ++i) before.push_back(graph_.node(i));
  const kernel::Pose2 pose_before = *pose;
  for (std::size_t i = 0; i < closures.size(); ++i) {
    checked.push_back(static_cast<int>(graph_.edges().size()));
    checked_tags.push_back(tags[i]);
    graph_.AddEdge(closures[i]);
  }
  Optimize(0, pose);
  // Agreement with the other edges: optimised together, a closure's residual stays small;
  // those that do not are removed and the graph optimised again from where it was.
  ClosureReport report;
  report.moved = true;
  std::vector<int> disagree;
  for (std::size_t i = 0; i < checked.size(); ++i) {
    const bool undone =
        graph_.EdgeChi2(graph_.edges()[static_cast<std::size_t>(checked[i])]) > options_.max_chi2;
    if (undone) disagree.push_back(checked[i]);
    (undone ? report.undone : report.stand).push_back(checked_tags[i]);
  }
  if (!disagree.empty()) {
    graph_.RemoveEdges(disagree);
    for (int i = 0; i < graph_.num_nodes(); ++i) {
      graph_.SetNode(i, before[static_cast<std::size_t>(i)]);
      (*keyframes_)[static_cast<std::size_t>(i)].pose = graph_.node(i);
    }
    *pose = pose_before;
    if (disagree.size() < checked.size()) Optimize(0, pose);
  }
  MergeTrimmed(waiting);
  return report;
}

ClosureReport GraphBackEnd::Finish(bool optimize, kernel::Pose2* pose) {
  if (!deferred_edges_.empty()) return AddAndOptimize({}, {}, {}, pose);
  ClosureReport report;
  if (optimize) {
    Optimize(0, pose);
    report.moved = true;
  }
  return report;
}

void GraphBackEnd::MergeTrimmed(const std::vector<PoseGraphEdge>& waiting) {
  if (merge_queue_.empty()) return;
  // The graph must know where the keyframe lies beside the one it is merged into: within a third
  // of the trim spacing (one sigma of the translation, RelativeCovarianceWithin), as when a
  // closure ties the revisit to the place. Without one, the two are near only as far as the
  // drift lets the estimate tell, and a merge would close the loop there with certainty.
  const double sigma_m = options_.trim_spacing_m / 3;
  const PoseGraphAdjacency adjacent = Adjacency(graph_);
  std::vector<QueuedMerge> held;
  std::vector<QueuedMerge> merge;
  for (QueuedMerge m : merge_queue_) {
    const bool pending = std::any_of(waiting.begin(), waiting.end(), [&](const PoseGraphEdge& e) {
      return e.from == m.keyframe || e.to == m.keyframe;
    });
    if (!pending &&
        RelativeCovarianceWithin(graph_, adjacent, m.keyframe, m.into, 2 * sigma_m * sigma_m))
      merge.push_back(m);
    else if (++m.checks < 2)  // one more whole optimisation to be tied to the place
      held.push_back(m);
  }
  for (const QueuedMerge& m : merge) graph_.MergeNode(m.keyframe, m.into);
  merge_queue_ = std::move(held);
}

int GraphBackEnd::LocalWindow(const std::vector<PoseGraphEdge>& closures) const {
  int first_free = std::max(0, graph_.num_nodes() - options_.advanced.local_optimization_keyframes);
  for (const PoseGraphEdge& e : closures) first_free = std::min(first_free, std::max(e.from, e.to));
  return first_free;
}

bool GraphBackEnd::DeferOptimization(double chi2, int closures) const {
  const double fraction = options_.advanced.deferred_optimization_fraction;
  if (!(fraction > 0) ||
      graph_.num_nodes() - optimized_nodes_ >= fraction * static_cast<double>(optimized_nodes_))
    return false;
  // Right closures on right poses: the sum of their whitened squared residuals is chi^2 with
  // three degrees of freedom per closure; tested at max_chi2's significance.
  constexpr double kSignificance = 0.999;
  const int n = static_cast<int>(deferred_edges_.size()) + closures;
  return deferred_chi2_ + chi2 <= ChiSquareQuantile(kSignificance, 3.0 * n);
}

void GraphBackEnd::Optimize(int first_free, kernel::Pose2* pose) {
  const ScopedTimer timer(&optimization_ms_);
  const int last = graph_.num_nodes() - 1;
  if (first_free == 0) {
    optimized_nodes_ = graph_.num_nodes();
    deferred_chi2_ = 0.0;
    deferred_edges_.clear();
    deferred_tags_.clear();
  }
  const kernel::Pose2 offset = keyframes_->back().pose.Between(*pose);
  optimizations_.push_back(graph_.Optimize(options_.pose_graph, first_free));
  for (int i = first_free; i <= last; ++i)
    (*keyframes_)[static_cast<std::size_t>(i)].pose = graph_.node(i);
  *pose = keyframes_->back().pose * offset;
}

}  // namespace splam::estimation
