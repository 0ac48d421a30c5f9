#include "estimation/pose_graph/graph_method.h"

#include <fmt/core.h>

#include "estimation/exploration_nodes.h"
#include "estimation/pose_graph/graph_slam.h"

namespace splam::estimation {

// The keyframe graph with its loop-closure edges, into *map.
void AddGraphLayers(const GraphSlam& graph, SlamMap* map) {
  for (const auto& kf : graph.keyframes()) map->keyframes.push_back(kf.pose);
  for (const auto& e : graph.graph().edges())
    if (e.loop) map->loop_edges.emplace_back(e.from, e.to);
  map->loop_searches = graph.loop_searches();
}

// The loop-closure counters, times and optimisations of a graph, appended to *s.
void AddGraphStatistics(const GraphSlam& graph, SlamStatistics* s) {
  const LoopClosureCounts& l = graph.loops();
  s->associations.insert(s->associations.end(),
                         {{"loop_searches", l.searches},
                          {"loop_accepted", l.accepted},
                          {"loop_rejected_score", l.rejected_score},
                          {"loop_rejected_ambiguous", l.rejected_ambiguous},
                          {"loop_rejected_registration", l.rejected_registration},
                          {"loop_rejected_misfit", l.rejected_misfit},
                          {"loop_rejected_disagreement", l.rejected_disagreement},
                          {"loop_rejected_unconfirmed", l.rejected_unconfirmed},
                          {"loop_flushes_deferred", graph.deferred_optimizations()},
                          {"moving_object_beams", graph.moving_beams()}});
  const GraphSlam::Times& t = graph.times();
  s->time_ms = {{"registration", t.registration_ms}, {"keyframes", t.keyframe_ms},
                {"moving_objects", t.moving_ms},     {"submaps", t.submap_ms},
                {"loop_search", t.loop_search_ms},   {"loop_search_wait", t.loop_wait_ms},
                {"optimization", t.optimization_ms}};
  s->optimizations = graph.optimizations();
  s->solver_runs += static_cast<long>(s->optimizations.size());
  for (const auto& o : s->optimizations) s->solver_failures += !o.converged;
}

namespace {

// Graph SLAM on curve maps: no covariance of its own; the map is the curves of its keyframes.
class GraphSlamMethod : public SlamMethod, public ExplorationNodes {
 public:
  GraphSlamMethod(const GraphSlamOptions& options, const SlamContext& context)
      : slam_(context.start, options) {}
  void Predict(const kernel::Pose2& u) override { slam_.Predict(u); }
  void Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) override {
    slam_.Update(scan, robot_T_laser);
  }
  kernel::Pose2 pose() const override { return slam_.pose(); }
  void Finish() override { slam_.Finish(); }
  std::vector<kernel::Pose2> Trajectory() const override { return slam_.Trajectory(); }
  kernel::Status health() const override { return slam_.health(); }
  std::size_t MapSize() const override { return slam_.num_map_control_points(); }
  std::size_t MapCurves() const override { return slam_.num_map_curves(); }
  // An exploration node becomes a keyframe and moves with it.
  void AtNode(const kernel::LocalSafeRegion& /*lsr*/) override { slam_.MarkNode(); }
  std::vector<kernel::Pose2> NodePoses() const override { return slam_.NodePoses(); }
  std::string MapDescription() const override {
    return fmt::format("{} keyframes, {} loop closures, {} curves", slam_.keyframes().size(),
                       slam_.loops().accepted, slam_.num_map_curves());
  }
  SlamMap Map() const override {
    SlamMap map;
    map.splines = slam_.MapSplines();
    map.spline_features = slam_.options().extraction;
    AddGraphLayers(slam_, &map);
    return map;
  }
  SlamStatistics Statistics() const override {
    SlamStatistics s;
    s.association = "scan-to-submap registration, correlative loop closure";
    s.map = {{"keyframes", static_cast<long>(slam_.keyframes().size())},
             {"keyframes_trimmed", slam_.trimmed_keyframes()},
             {"keyframes_merged", slam_.merged_keyframes()},
             {"graph_nodes", slam_.graph().num_live_nodes()},
             {"graph_edges", static_cast<long>(slam_.graph().edges().size())},
             {"submap_builds", slam_.submap_builds()},
             {"submap_inserts", slam_.submap_inserts()},
             {"curves", static_cast<long>(slam_.num_map_curves())},
             {"control_points", static_cast<long>(slam_.num_map_control_points())}};
    s.associations = {{"registrations", slam_.registrations()},
                      {"registration_recovery_searches", slam_.recovery_searches()},
                      {"registration_recovered", slam_.recovered()},
                      {"registration_fallbacks", slam_.registration_fallbacks()}};
    AddGraphStatistics(slam_, &s);
    return s;
  }

 private:
  GraphSlam slam_;
};

}  // namespace

void AddGraphSlamMethod(kernel::Registry<SlamMethodInfo>* registry) {
  registry->Add(MakeSlamMethodInfo<GraphSlamOptions>(
      "graph",
      "graph SLAM on curve maps: scan-to-submap registration, loop closure, Ceres pose graph",
      [](const GraphSlamOptions& o, const SlamContext& c) {
        return std::make_unique<GraphSlamMethod>(o, c);
      },
      [](const SensorNoise& noise, GraphSlamOptions* o) {
        o->odometry = OdometryNoiseModel().Scaled(noise.odometry_noise_scale);
      }));
}

}  // namespace splam::estimation
