// Tutorial: a graph SLAM built from its three parts (docs/graph_slam_toolkit.md), the way Ceres'
// pose_graph_2d or KISS-ICP's pipeline show their libraries: a keyframe store, a front end that
// registers scans and makes keyframes, a loop closer that finds closures between them, and a
// back end that optimises the pose graph. It is method `graph` step for step: on the simulated
// route it gives the same keyframes to the bit.
// Usage: example_minimal_graph_slam [LOG [RELATIONS]] [PICTURE.png]
//   no LOG: the `complex` route, simulated (seed 1), scored against its truth;
//   a CARMEN LOG with its RELATIONS file: scored by the relations metric.
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "estimation/evaluation/metrics.h"
#include "estimation/pose_graph/graph_back_end.h"
#include "estimation/pose_graph/graph_front_end.h"
#include "estimation/pose_graph/graph_method.h"
#include "estimation/pose_graph/graph_slam.h"
#include "estimation/pose_graph/loop_closer.h"
#include "io/carmen.h"
#include "io/relations.h"
#include "io/run_picture.h"
#include "io/simulation_log.h"
#include "runtime/log_replay.h"
#include "sim/builtin_worlds.h"
#include "sim/simulator.h"

namespace estimation = splam::estimation;
using splam::kernel::Pose2;

// The pipeline. One store of keyframes is shared by the three parts: keyframe k is node k of
// the back end's graph.
class MinimalGraphSlam {
 public:
  MinimalGraphSlam(const Pose2& start, const estimation::GraphSlamOptions& options)
      : options_(options),
        front_end_(start, options.front_end, &keyframes_,
                   estimation::LoopCloser::NeedsHitViews(options.loop)),
        back_end_(options.back_end, &keyframes_, options.loop.enabled),
        loop_closer_(options.loop, estimation::LoopCloser::FrontEndOf(options.front_end),
                     &keyframes_, &back_end_.graph()) {}

  void Predict(const Pose2& odometry) { front_end_.Predict(odometry); }

  // 1. Register the scan against the submap; 2. settle at the registered pose; 3. a keyframe
  // when it has moved far enough; 4. every scan's pose is kept relative to its keyframe, so that
  // it moves with it when the graph is optimised.
  void Update(const splam::kernel::Scan& scan, const Pose2& robot_T_laser) {
    std::optional<estimation::GraphFrontEnd::PreparedScan> registered =
        front_end_.Register(scan, robot_T_laser);
    if (!registered || !front_end_.Settle(front_end_.pose())) return;
    if (front_end_.KeyframeDue()) AddKeyframe(std::move(*registered), robot_T_laser);
    scans_.push_back({static_cast<int>(keyframes_.size()) - 1,
                      keyframes_.back().pose.Between(front_end_.pose())});
  }

  // The data has ended: the last search's closures, a final decision, a last optimisation.
  void Finish() {
    if (const std::optional<double> travelled = loop_closer_.Collect())
      AddClosures(false, *travelled);
    AddClosures(true, front_end_.travelled_m());
    loop_closer_.Record(
        back_end_.Finish(loop_closer_.counts().accepted > 0, front_end_.mutable_pose()), 0,
        front_end_.travelled_m());
  }

  std::vector<Pose2> Trajectory() const {
    std::vector<Pose2> poses;
    for (const auto& [keyframe, offset] : scans_)
      poses.push_back(keyframes_[static_cast<std::size_t>(keyframe)].pose * offset);
    return poses;
  }
  const estimation::Keyframes& keyframes() const { return keyframes_; }
  // The map: the curves of the map keyframes, in the world; the keyframes and loop edges.
  estimation::SlamMap Map() const {
    estimation::SlamMap map;
    for (const estimation::Keyframe& kf : keyframes_) {
      map.keyframes.push_back(kf.pose);
      if (!kf.in_map) continue;
      for (const auto& c : kf.data->curves)
        map.splines.push_back(
            {static_cast<int>(map.splines.size()), c.spline.Transformed(kf.pose), 1});
    }
    for (const estimation::PoseGraphEdge& e : back_end_.graph().edges())
      if (e.loop) map.loop_edges.emplace_back(e.from, e.to);
    return map;
  }
  long closures() const { return loop_closer_.counts().accepted; }

 private:
  void AddKeyframe(estimation::GraphFrontEnd::PreparedScan scan, const Pose2& robot_T_laser) {
    // The previous keyframe's search has run beside the front end: its closures go in first, so
    // that the new keyframe stands where the corrected graph puts it.
    if (const std::optional<double> travelled = loop_closer_.Collect())
      AddClosures(false, *travelled);
    bool robust = false;
    keyframes_.push_back(front_end_.MakeKeyframe(std::move(scan), robot_T_laser,
                                                 static_cast<int>(scans_.size()), &robust));
    const int k = static_cast<int>(keyframes_.size()) - 1;
    back_end_.AddKeyframe(
        k > 0 ? estimation::KeyframeEdgeCovariance(options_.front_end.edge, keyframes_, k)
              : Eigen::Matrix3d::Identity(),
        robust);
    front_end_.KeyframeAdded(k);
    // The keyframe that has left every window reading keyframe data may drop its own.
    back_end_.Trim(estimation::TrimmedKeyframe(options_, k));
    loop_closer_.Start(k, front_end_.travelled_m());
  }

  // The closures the acceptance lets in go to the back end; what it did goes back to the loop
  // closer's record, and an optimisation makes the front end build its submap anew.
  void AddClosures(bool final, double travelled_m) {
    const estimation::LoopCloser::Accepted accepted = loop_closer_.Decide(final);
    if (accepted.closures.empty()) return;
    const estimation::ClosureReport report = back_end_.AddClosures(
        accepted.closures, accepted.tags, loop_closer_.waiting(), front_end_.mutable_pose());
    loop_closer_.Record(report, accepted.closures.size(), travelled_m);
    if (report.moved) front_end_.MapMoved();
  }

  estimation::GraphSlamOptions options_;
  estimation::Keyframes keyframes_;
  estimation::GraphFrontEnd front_end_;
  estimation::GraphBackEnd back_end_;
  estimation::LoopCloser loop_closer_;        // last: destroyed first, waiting for its search
  std::vector<std::pair<int, Pose2>> scans_;  // keyframe, keyframe_T_scan
};

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  std::string picture = "minimal_graph_slam.png";
  if (!args.empty() && args.back().ends_with(".png")) {
    picture = args.back();
    args.pop_back();
  }
  // The data: a log, or the simulated `complex` route.
  std::optional<splam::sim::World> world;
  splam::io::CarmenLog log;
  if (args.empty()) {
    world = *splam::sim::BuiltinWorld("complex");
    const splam::sim::RayCaster caster(*world);
    splam::sim::Simulator simulator(caster, {}, *world->start, /*seed=*/1);
    const auto route = splam::sim::FollowRoute(&simulator, world->route, {});
    log = splam::io::MakeCarmenLog(route.frames, simulator.options());
  } else {
    splam::io::CarmenReadResult read = splam::io::ReadCarmenLog(args[0]);
    if (!read.log.ok()) return std::fprintf(stderr, "%s\n", read.log.error.c_str()), 2;
    log = std::move(*read.log.value);
  }
  const auto lasers = log.Lasers();
  if (lasers.empty()) return std::fprintf(stderr, "the log has no scans\n"), 2;

  // The options as the registry gives them to method `graph` for this log's sensors (the
  // odometry prior's noise model among them: a precondition of the front end).
  estimation::GraphSlamOptions options;
  estimation::AdaptGraphSlamToSensors(splam::runtime::SensorNoiseOf(*lasers[0]), &options);
  MinimalGraphSlam slam(lasers[0]->robot_pose, options);
  estimation::GraphSlam built_in(lasers[0]->robot_pose, options);
  for (std::size_t i = 0; i < lasers.size(); ++i) {
    if (i > 0) {
      const Pose2 u = lasers[i - 1]->robot_pose.Between(lasers[i]->robot_pose);
      slam.Predict(u);
      built_in.Predict(u);
    }
    const Pose2 robot_T_laser = lasers[i]->robot_pose.Between(lasers[i]->laser_pose);
    slam.Update(lasers[i]->scan, robot_T_laser);
    built_in.Update(lasers[i]->scan, robot_T_laser);
  }
  slam.Finish();
  built_in.Finish();

  // The same keyframes as method `graph`, to the bit.
  bool same = slam.keyframes().size() == built_in.keyframes().size();
  for (std::size_t k = 0; same && k < slam.keyframes().size(); ++k)
    same = slam.keyframes()[k].pose.ToVector() == built_in.keyframes()[k].pose.ToVector();
  std::printf("%zu scans, %zu keyframes, %ld loop closures; keyframes %s method graph's\n",
              lasers.size(), slam.keyframes().size(), slam.closures(),
              same ? "identical to" : "DIFFERENT from");

  // Scores: against the truth of a simulated log, by the relations metric of a real one.
  splam::kernel::Trajectory estimate;
  const std::vector<Pose2> poses = slam.Trajectory();
  for (std::size_t i = 0; i < poses.size(); ++i)
    estimate.push_back({lasers[i]->stamp.ipc_timestamp_s, poses[i]});
  const splam::kernel::Trajectory truth = splam::io::TrueTrajectory(log);
  if (!truth.empty())
    std::printf("position RMSE %.4f m\n",
                splam::evaluation::CompareToTruth(truth, estimate).rmse_position_m);
  if (args.size() > 1) {
    const auto relations = splam::io::ReadRelations(args[1]);
    if (!relations.ok()) return std::fprintf(stderr, "%s\n", relations.error.c_str()), 2;
    const auto r = splam::evaluation::EvaluateRelations(*relations.value, estimate);
    std::printf("relations metric %.4f +- %.4f m (%zu relations)\n", r.translation_mean,
                r.translation_std, r.used);
  }
  splam::io::RunPicture figure;
  figure.title = "a graph SLAM from its parts";
  figure.world = world ? &*world : nullptr;
  figure.truth = truth;
  figure.estimates = {{"estimate", estimate}};
  splam::io::DrawMap(slam.Map(), &figure);
  if (const auto s = splam::io::SaveRunPicture(figure, {picture}); !s.ok())
    return std::fprintf(stderr, "%s\n", s.message().c_str()), 4;
  std::printf("wrote %s\n", picture.c_str());
  return same ? 0 : 1;
}
