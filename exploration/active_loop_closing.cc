#include "exploration/active_loop_closing.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "exploration/localization.h"
#include "exploration/session.h"

namespace splam::exploration {

double PositionSigma(const Eigen::Matrix3d& covariance) {
  const Eigen::Matrix2d position = covariance.topLeftCorner<2, 2>();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(position, Eigen::EigenvaluesOnly);
  return std::sqrt(std::max(solver.eigenvalues().maxCoeff(), 0.0));
}

std::optional<RevisitChoice> ChooseRevisit(const graph::ExplorationGraph& graph, graph::Vertex from,
                                           const Localization& localization,
                                           const ActiveLoopClosingOptions& options,
                                           const std::set<graph::Vertex>& excluded) {
  std::vector<graph::Vertex> previous;
  const std::vector<double> distance = graph.DistancesFrom(from, &previous);
  std::vector<int> nodes;
  std::vector<double> path_m;
  for (graph::Vertex v = 0; v < graph.num_nodes(); ++v) {
    if (v == from || excluded.contains(v) || !std::isfinite(distance[v])) continue;
    nodes.push_back(static_cast<int>(v));
    path_m.push_back(distance[v]);
  }
  const std::vector<std::optional<double>> information =
      localization.RevisitInformation(nodes, path_m);
  std::optional<RevisitChoice> best;
  for (std::size_t i = 0; i < nodes.size() && i < information.size(); ++i) {
    if (!information[i] || *information[i] < options.min_information_nats) continue;
    const double utility = *information[i] - options.cost_nats_per_m * 2.0 * path_m[i];
    if (utility <= 0.0 || (best && utility <= best->utility)) continue;
    best = RevisitChoice{
        static_cast<graph::Vertex>(nodes[i]), {}, path_m[i], *information[i], utility};
  }
  if (!best) return std::nullopt;
  for (graph::Vertex v = best->to; v != from; v = previous[v]) best->path.push_back(v);
  best->path.push_back(from);
  std::reverse(best->path.begin(), best->path.end());
  return best;
}

std::optional<graph::Vertex> ActiveLoopClosing::Step(Session* session, graph::Vertex current,
                                                     bool come_back) {
  if (!options_.enabled) return std::nullopt;
  ExplorationRun& run = session->run();
  for (; traced_ + 1 < run.trace.size(); ++traced_)
    travelled_m_ +=
        (run.trace[traced_ + 1].estimate.translation() - run.trace[traced_].estimate.translation())
            .norm();
  std::optional<double> sigma;
  {
    Session::PlanningTimer timer(session);
    if (const auto covariance = session->localization().PoseCovariance())
      sigma = PositionSigma(*covariance);
  }
  if (sigma && !run.trace.empty()) run.position_sigma.emplace_back(run.trace.back().time_s, *sigma);
  if (sigma && !run.revisits.empty() && std::isnan(run.revisits.back().position_sigma_after_m))
    run.revisits.back().position_sigma_after_m = *sigma;
  if (!sigma || *sigma < options_.min_position_sigma_m) return std::nullopt;
  if (any_ && travelled_m_ - last_revisit_m_ < options_.min_travel_between_m) return std::nullopt;
  std::optional<RevisitChoice> choice;
  {
    Session::PlanningTimer timer(session);
    choice =
        ChooseRevisit(session->graph(), current, session->localization(), options_, revisited_);
  }
  if (!choice) return std::nullopt;
  revisited_.insert(choice->to);
  any_ = true;
  last_revisit_m_ = travelled_m_;
  RevisitRecord record;
  record.from = static_cast<int>(current);
  record.to = static_cast<int>(choice->to);
  record.time_s = run.trace.empty() ? 0.0 : run.trace.back().time_s;
  record.path_m = choice->path_m;
  record.information_nats = choice->information_nats;
  record.position_sigma_m = *sigma;
  record.position_sigma_after_m = std::numeric_limits<double>::quiet_NaN();
  record.trace_begin = run.trace.size();
  std::vector<graph::Vertex> path = choice->path;
  if (come_back) path.insert(path.end(), std::next(choice->path.rbegin()), choice->path.rend());
  const MoveResult move = session->Drive(session->graph().Waypoints(path));
  record.reached = move.reached;
  record.trace_end = session->run().trace.size();
  session->run().revisits.push_back(record);
  if (!move.reached) return session->NodeAfterFailedMove(current);
  return come_back ? current : choice->to;
}

void ActiveLoopClosingOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("enabled", &enabled,
          "revisit known places when the pose grows uncertain (needs a localisation that says "
          "how uncertain it is: graph)");
  v.Field("min_position_sigma_m", &min_position_sigma_m,
          "revisits are weighed from this position standard deviation on, m");
  v.Field("cost_nats_per_m", &cost_nats_per_m,
          "each metre of a revisit's detour (twice its path) costs this much expected "
          "information, nats/m");
  v.Field("min_information_nats", &min_information_nats,
          "a revisit must be expected to gain at least this, nats");
  v.Field("min_travel_between_m", &min_travel_between_m,
          "after a revisit, none again before the robot has driven this far, m");
}

kernel::Status ActiveLoopClosingOptions::Validate() const {
  if (!(min_position_sigma_m >= 0.0 && min_position_sigma_m <= 1e3))
    return kernel::Status::Error("min_position_sigma_m must be in [0, 1000] m");
  if (!(cost_nats_per_m >= 0.0 && cost_nats_per_m <= 1e3))
    return kernel::Status::Error("cost_nats_per_m must be in [0, 1000]");
  if (!(min_information_nats >= 0.0 && min_information_nats <= 1e3))
    return kernel::Status::Error("min_information_nats must be in [0, 1000]");
  if (!(min_travel_between_m >= 0.0 && min_travel_between_m <= 1e6))
    return kernel::Status::Error("min_travel_between_m must be in [0, 1e6] m");
  return kernel::Status::Ok();
}

}  // namespace splam::exploration
