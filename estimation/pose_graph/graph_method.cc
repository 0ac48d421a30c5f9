#include "estimation/pose_graph/graph_method.h"

#include <fmt/core.h>

#include "estimation/exploration_nodes.h"
#include "estimation/pose_graph/graph_slam.h"
#include "estimation/pose_graph/map_localizer.h"
#include "estimation/slam_state.h"

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
  s->loop_closure = graph.loops();
  s->associations.insert(s->associations.end(),
                         {{"loop_flushes_deferred", graph.deferred_optimizations()},
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
// Saved, its state is the map and every kept keyframe's reading at its final pose; loaded, it
// localises new scans in that map (MapLocalizer) or goes on mapping from it.
class GraphSlamMethod : public SlamMethod, public ExplorationNodes, public PersistentSlam {
 public:
  GraphSlamMethod(const GraphSlamOptions& options, const SlamContext& context,
                  std::unique_ptr<ClosureAcceptance> acceptance)
      : slam_(context.start, options, std::move(acceptance)), start_(context.start) {}
  void Predict(const kernel::Pose2& u) override {
    if (localizer_) return localizer_->Predict(u);
    slam_.Predict(u);
  }
  void Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) override {
    if (localizer_) return localizer_->Update(scan, robot_T_laser);
    const std::size_t before = slam_.keyframes().size();
    if (continuing_) {
      // The first scan after a loaded map: localised in it, then joined to the map's last
      // keyframe by the jump there, so that registration and loop closure go on from it.
      continuing_ = false;
      slam_.Predict(slam_.pose().Between(StartInMap(scan, robot_T_laser)));
      Place(scan, robot_T_laser, slam_.pose());
    } else {
      slam_.Update(scan, robot_T_laser);
    }
    if (keep_readings_ && slam_.keyframes().size() > before)
      readings_.push_back({slam_.keyframes().size() - 1, robot_T_laser, scan});
  }
  kernel::Pose2 pose() const override { return localizer_ ? localizer_->pose() : slam_.pose(); }
  void Finish() override {
    if (!localizer_) slam_.Finish();
  }
  std::vector<kernel::Pose2> Trajectory() const override {
    if (localizer_) return localizer_->poses();  // the pose after each update, relocalised
    std::vector<kernel::Pose2> all = slam_.Trajectory();
    return {all.begin() + static_cast<std::ptrdiff_t>(std::min(loaded_scans_, all.size())),
            all.end()};
  }
  kernel::Status health() const override { return slam_.health(); }
  std::size_t MapSize() const override {
    return localizer_ ? loaded_control_points_ : slam_.num_map_control_points();
  }
  std::size_t MapCurves() const override {
    return localizer_ ? loaded_.map.splines.size() : slam_.num_map_curves();
  }
  // An exploration node becomes a keyframe and moves with it.
  void AtNode(const kernel::LocalSafeRegion& /*lsr*/) override { slam_.MarkNode(); }
  std::vector<kernel::Pose2> NodePoses() const override { return slam_.NodePoses(); }
  std::vector<std::optional<double>> RevisitInformation(
      const std::vector<int>& nodes, const std::vector<double>& path_m) const override {
    if (localizer_) return ExplorationNodes::RevisitInformation(nodes, path_m);
    return slam_.RevisitInformation(nodes, path_m);
  }
  // The pose graph's marginal (a factorisation): asked at decisions, not at every scan.
  bool PoseCovarianceEveryScan() const override { return false; }
  std::optional<Eigen::Matrix3d> PoseCovariance() const override {
    if (localizer_) return std::nullopt;
    return slam_.PoseCovariance();
  }
  std::string MapDescription() const override {
    if (localizer_)
      return fmt::format("localising in a saved map of {} keyframes, {} curves",
                         loaded_.map.keyframes.size(), loaded_.map.splines.size());
    return fmt::format("{} keyframes, {} loop closures, {} curves", slam_.keyframes().size(),
                       slam_.loops().accepted, slam_.num_map_curves());
  }
  SlamMap Map() const override {
    if (localizer_) return loaded_.map;
    SlamMap map;
    map.splines = slam_.MapSplines();
    map.spline_features = slam_.options().front_end.extraction;
    AddGraphLayers(slam_, &map);
    return map;
  }
  SlamStatistics Statistics() const override {
    SlamStatistics s;
    if (localizer_) {
      s.association = "scan-to-map registration in a saved map";
      s.map = {{"keyframes", static_cast<long>(loaded_.map.keyframes.size())},
               {"map_scans", static_cast<long>(loaded_.scans.size())},
               {"curves", static_cast<long>(loaded_.map.splines.size())},
               {"local_fields_built", localizer_->grid_builds()}};
      s.registration = localizer_->registration_counts();
      s.associations = {{"start_found", localizer_->found_start() ? 1 : 0},
                        {"start_confirmed", localizer_->start_confirmed() ? 1 : 0},
                        {"relocalized", localizer_->relocalized() ? 1 : 0}};
      return s;
    }
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
    s.registration = slam_.front_end().registration_counts();
    AddGraphStatistics(slam_, &s);
    return s;
  }

  void KeepStateForSaving() override { keep_readings_ = true; }
  kernel::Result<SlamState> SaveState() const override {
    using R = kernel::Result<SlamState>;
    if (localizer_) return R::Ok(loaded_);  // localisation leaves the map as it was
    if (!keep_readings_) return R::Fail("graph: the readings were not kept (KeepStateForSaving)");
    SlamState state;
    state.method = "graph";
    state.map = Map();
    state.map.loop_searches.clear();  // a record of the run, not part of the map
    for (const Reading& r : readings_) {
      const GraphSlam::Keyframe& kf = slam_.keyframes()[r.keyframe];
      // Trimmed keyframes were redundant with their neighbours for registration; so they are here.
      if (!kf.trimmed) state.scans.push_back({kf.pose, r.robot_T_laser, r.scan});
    }
    return R::Ok(std::move(state));
  }
  kernel::Status LoadState(const SlamState& state, bool localize_only) override {
    if (state.method != "graph")
      return kernel::Status::Error("the state is of method '" + state.method +
                                   "', this run's is 'graph'");
    if (state.scans.empty()) return kernel::Status::Error("the state holds no map scans");
    loaded_ = state;
    loaded_.map.spline_features = slam_.options().front_end.extraction;
    if (localize_only) {
      // Asked after every scan (the time per scan by map size): counted once.
      for (const MapSpline& s : loaded_.map.splines)
        loaded_control_points_ += s.spline.control_points().size();
      localizer_ = std::make_unique<MapLocalizer>(state.scans, start_, slam_.options().front_end,
                                                  slam_.options().localization);
      return kernel::Status::Ok();
    }
    // The map's scans again, at their poses: the same keyframes, curves and closures.
    for (std::size_t i = 0; i < state.scans.size(); ++i) {
      const MapScan& m = state.scans[i];
      if (i > 0) slam_.Predict(state.scans[i - 1].pose.Between(m.pose));
      const std::size_t before = slam_.keyframes().size();
      Place(m.scan, m.robot_T_laser, m.pose);
      if (keep_readings_ && slam_.keyframes().size() > before)
        readings_.push_back({slam_.keyframes().size() - 1, m.robot_T_laser, m.scan});
    }
    loaded_scans_ = state.scans.size();
    continuing_ = true;
    return slam_.health();
  }

 private:
  // A scan at a known pose (the saved map's, the first one localised in it): no registration.
  void Place(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser,
             const kernel::Pose2& pose) {
    GraphFrontEnd& front_end = slam_.front_end();
    std::optional<GraphFrontEnd::PreparedScan> placed = front_end.Place(scan, robot_T_laser, pose);
    if (placed && front_end.Settle(pose)) slam_.AddScan(std::move(*placed), robot_T_laser);
  }
  // The first new scan's pose in the loaded map: found by the localiser from the start pose, and
  // moved by the search of the whole map when that scan's fix there is unambiguous and elsewhere
  // (MapLocalizer::ConfirmStart).
  kernel::Pose2 StartInMap(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) const {
    MapLocalizer localizer(loaded_.scans, start_, slam_.options().front_end,
                           slam_.options().localization);
    localizer.Update(scan, robot_T_laser);
    return localizer.pose();
  }

  struct Reading {
    std::size_t keyframe;
    kernel::Pose2 robot_T_laser;
    kernel::Scan scan;
  };
  GraphSlam slam_;
  kernel::Pose2 start_;
  bool keep_readings_ = false;
  std::vector<Reading> readings_;  // of the keyframes, when kept
  SlamState loaded_;
  std::unique_ptr<MapLocalizer> localizer_;  // localising only
  std::size_t loaded_scans_ = 0;             // trajectory entries of the loaded map's scans
  std::size_t loaded_control_points_ = 0;    // of the loaded map, when localising
  bool continuing_ = false;                  // the next Update is the first after a loaded map
};

}  // namespace

std::unique_ptr<SlamMethod> MakeGraphSlamMethod(const GraphSlamOptions& options,
                                                const SlamContext& context,
                                                std::unique_ptr<ClosureAcceptance> acceptance) {
  return std::make_unique<GraphSlamMethod>(options, context, std::move(acceptance));
}

void AdaptGraphSlamToSensors(const SensorNoise& noise, GraphSlamOptions* options) {
  options->front_end.odometry = OdometryNoiseModel().Scaled(noise.odometry_noise_scale);
}

void AddGraphSlamMethod(kernel::Registry<SlamMethodInfo>* registry) {
  registry->Add(MakeSlamMethodInfo<GraphSlamOptions>(
      "graph",
      "graph SLAM on curve maps: scan-to-submap registration, loop closure, Ceres pose graph",
      [](const GraphSlamOptions& o, const SlamContext& c) {
        return MakeGraphSlamMethod(o, c, nullptr);
      },
      AdaptGraphSlamToSensors));
}

}  // namespace splam::estimation
