// A splam program of one's own, built outside splam's tree against the installed package
// (find_package(splam)): two SLAM variants and an explorer variant, one registration line each,
// and splam's command line with them among its choices.
//   my_splam slam --method dead-reckoning LOG --out DIR
//   my_splam slam --method graph-unconfirmed LOG --out DIR
//   my_splam explore --explorer nearest --localization dead-reckoning
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "apps/cli.h"
#include "estimation/pose_graph/graph_method.h"
#include "estimation/pose_graph/loop_closer.h"
#include "estimation/slam_method.h"
#include "exploration/explorer.h"
#include "exploration/reg.h"
#include "exploration/session.h"
#include "exploration/steps.h"
#include "kernel/angle.h"

namespace my_lab {

// The smallest SLAM method: the odometry alone, with an options struct of one field.
struct DeadReckoningOptions {
  double scale = 1.0;  // odometry increments are scaled by this
  void VisitFields(splam::kernel::FieldVisitor& v) { v.Field("scale", &scale, "odometry scale"); }
  splam::kernel::Status Validate() const {
    return scale > 0 ? splam::kernel::Status::Ok()
                     : splam::kernel::Status::Error("scale must be positive");
  }
};

class DeadReckoning : public splam::estimation::SlamMethod {
 public:
  DeadReckoning(const DeadReckoningOptions& o, const splam::estimation::SlamContext& c)
      : scale_(o.scale), pose_(c.start) {}
  void Predict(const splam::kernel::Pose2& u) override {
    pose_ = pose_ * splam::kernel::Pose2(scale_ * u.x(), scale_ * u.y(), u.theta());
  }
  void Update(const splam::kernel::Scan&, const splam::kernel::Pose2&) override { ++scans_; }
  splam::kernel::Pose2 pose() const override { return pose_; }
  std::string MapDescription() const override { return "no map"; }
  splam::estimation::SlamStatistics Statistics() const override {
    splam::estimation::SlamStatistics s;
    s.map = {{"scans", scans_}};
    return s;
  }

 private:
  double scale_;
  splam::kernel::Pose2 pose_;
  long scans_ = 0;
};

// A graph SLAM variant that changes only the loop-closure acceptance: every closure that agrees
// with the graph as it is goes in, no second one needed to confirm it.
class AcceptWhatAgreesWithTheGraph : public splam::estimation::ClosureAcceptance {
 public:
  explicit AcceptWhatAgreesWithTheGraph(double max_chi2) : max_chi2_(max_chi2) {}
  std::vector<splam::estimation::ClosureVerdict> Decide(
      const std::vector<splam::estimation::PendingClosure>& pending,
      const splam::estimation::ClosureContext& context) override {
    std::vector<splam::estimation::ClosureVerdict> verdicts;
    for (const auto& c : pending)
      verdicts.push_back(context.graph.EdgeChi2(c.edge) <= max_chi2_
                             ? splam::estimation::ClosureVerdict::kAccept
                             : splam::estimation::ClosureVerdict::kRefuse);
    return verdicts;
  }

 private:
  double max_chi2_;
};

// An explorer variant: one of REG's steps overridden (which frontier next): the frontier nearest
// the robot's heading first, where REG draws one at random.
class NearestFrontierFirst : public splam::exploration::RegExplorer {
 public:
  using RegExplorer::RegExplorer;
  std::string name() const override { return "nearest"; }
  splam::kernel::FrontierArc NextPiece(splam::exploration::Session& session,
                                       splam::graph::Vertex node,
                                       std::vector<splam::kernel::FrontierArc>* frontiers,
                                       double max_piece_rad) override {
    const double heading = session.graph()[node].configuration.theta();
    std::size_t nearest = 0;
    for (std::size_t k = 1; k < frontiers->size(); ++k)
      if (Turn((*frontiers)[k], heading) < Turn((*frontiers)[nearest], heading)) nearest = k;
    return splam::exploration::TakePiece(session, frontiers, nearest, max_piece_rad);
  }

 private:
  static double Turn(const splam::kernel::FrontierArc& arc, double heading) {
    return std::abs(
        splam::kernel::WrapAngle(0.5 * (arc.start_angle_rad + arc.end_angle_rad) - heading));
  }
};

}  // namespace my_lab

int main(int argc, char** argv) {
  splam::estimation::RegisterSlamMethod<my_lab::DeadReckoningOptions>(
      "dead-reckoning", "the odometry alone (out-of-tree tutorial)",
      [](const my_lab::DeadReckoningOptions& o, const splam::estimation::SlamContext& c) {
        return std::make_unique<my_lab::DeadReckoning>(o, c);
      });
  splam::estimation::RegisterSlamMethod<splam::estimation::GraphSlamOptions>(
      "graph-unconfirmed", "graph SLAM taking every closure that agrees with the graph",
      [](const splam::estimation::GraphSlamOptions& o, const splam::estimation::SlamContext& c) {
        return splam::estimation::MakeGraphSlamMethod(
            o, c, std::make_unique<my_lab::AcceptWhatAgreesWithTheGraph>(o.loop.max_chi2));
      },
      splam::estimation::AdaptGraphSlamToSensors);
  splam::exploration::RegisterExplorer<splam::exploration::RegOptions>(
      "nearest", "REG taking first the frontier nearest the robot's heading (out-of-tree tutorial)",
      [](const splam::exploration::ExplorerOptions& o, const splam::exploration::RegOptions& r) {
        return std::make_unique<my_lab::NearestFrontierFirst>(o, r);
      });
  return splam::apps::Main(argc, argv);
}
