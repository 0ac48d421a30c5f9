#include "estimation/topological/topological_methods.h"

#include <fmt/core.h>

#include "estimation/exploration_nodes.h"
#include "estimation/pose_graph/graph_method.h"
#include "estimation/topological/topological_graph_slam.h"
#include "estimation/topological/topological_slam.h"
#include "kernel/angle.h"

namespace splam::estimation {
namespace {

TopologicalSlamOptions WithRegion(TopologicalSlamOptions options,
                                  const kernel::LocalRegionOptions& region) {
  options.region = region;
  return options;
}

// What the topological SLAM's updates did (methods topological and topological-graph): totals,
// and the last update for the per-step trace.
class TopologicalTally {
 public:
  void Add(const TopologicalUpdateReport& r) {
    last_ = r;
    observed_ += r.observed_curves;
    associated_ += r.associated_curves;
    verified_ += r.verified_curves;
    localized_ += r.localized;
    fallbacks_ += r.used_fallback;
    dense_ += r.dense;
    scan_matched_ += r.scan_matched;
    refused_ += r.refused_no_better;
    failed_ += r.associated_curves > 0 && !r.localized;
    created_ += r.added_curves;
    extended_ += r.extended_curves;
    solver_ += r.solver;
  }
  std::vector<std::pair<std::string, double>> LastUpdate(const TopologicalSlam& slam) const {
    const TopologicalUpdateReport& r = last_;
    return {{"observed_curves", r.observed_curves},
            {"local_map_curves", r.local_map_curves},
            {"associated_curves", r.associated_curves},
            {"localized", r.localized},
            {"fallback", r.used_fallback},
            {"dense", r.dense},
            {"dense_points", r.dense_points},
            {"refused_no_better", r.refused_no_better},
            {"verified_curves", r.verified_curves},
            {"heading_correction_deg", kernel::RadToDeg(r.heading_correction_rad)},
            {"translation_correction_x_m", r.translation_correction.x()},
            {"translation_correction_y_m", r.translation_correction.y()},
            {"map_updated", r.map_updated},
            {"added_curves", r.added_curves},
            {"extended_curves", r.extended_curves},
            {"map_curves", static_cast<double>(slam.num_curves())},
            {"scan_matched", r.scan_matched}};
  }
  // The map and association counters, and the solves, into *s.
  void Fill(const TopologicalSlam& slam, SlamStatistics* s) const {
    s->association = "curvature";
    s->map = {{"curves", static_cast<long>(slam.num_curves())},
              {"control_points", static_cast<long>(slam.num_control_points())}};
    s->associations = {
        {"observed_curves", observed_},    {"associated_curves", associated_},
        {"verified_curves", verified_},    {"scan_matched_predictions", scan_matched_},
        {"localized_scans", localized_},   {"fallback_to_single_curves", fallbacks_},
        {"dense_refinements", dense_},     {"refused_no_better", refused_},
        {"failed_localizations", failed_}, {"new_curves", created_},
        {"extensions", extended_}};
    s->solver_runs += solver_.runs;
    s->solver_failures += solver_.failures;
  }

 private:
  TopologicalUpdateReport last_;
  long observed_ = 0, associated_ = 0, verified_ = 0;
  long localized_ = 0, fallbacks_ = 0, dense_ = 0, scan_matched_ = 0, refused_ = 0, failed_ = 0,
       created_ = 0, extended_ = 0;
  SolverCounts solver_;
};

// Topological B-spline SLAM: no covariance; the map is curves with their control points.
class TopologicalSlamMethod : public SlamMethod, public ExplorationNodes {
 public:
  TopologicalSlamMethod(const TopologicalSlamOptions& options, const SlamContext& context)
      : slam_(context.start, WithRegion(options, context.region)) {}
  void Predict(const kernel::Pose2& u) override { slam_.Predict(u); }
  void Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) override {
    tally_.Add(slam_.Update(scan, robot_T_laser));
  }
  kernel::Pose2 pose() const override { return slam_.pose(); }
  kernel::Status health() const override { return slam_.health(); }
  std::size_t MapSize() const override { return slam_.num_control_points(); }
  std::size_t MapCurves() const override { return slam_.num_curves(); }
  void AtNode(const kernel::LocalSafeRegion& lsr) override { slam_.SetLocalRegion(lsr); }
  std::string MapDescription() const override {
    return fmt::format("{} curves, {} control points", slam_.num_curves(),
                       slam_.num_control_points());
  }
  SlamMap Map() const override {
    SlamMap map;
    map.splines = slam_.MapSplines();
    map.spline_features = slam_.options().extraction;
    return map;
  }
  std::vector<std::pair<std::string, double>> LastUpdate() const override {
    return tally_.LastUpdate(slam_);
  }
  SlamStatistics Statistics() const override {
    SlamStatistics s;
    tally_.Fill(slam_, &s);
    return s;
  }

 private:
  TopologicalSlam slam_;
  TopologicalTally tally_;
};

// The topological SLAM with the graph SLAM's back end: the topological map, re-anchored to the
// optimised keyframes; the trajectory from the graph.
class TopologicalGraphSlamMethod : public SlamMethod, public ExplorationNodes {
 public:
  TopologicalGraphSlamMethod(TopologicalGraphSlamOptions options, const SlamContext& context)
      : slam_(context.start,
              {WithRegion(std::move(options.topological), context.region), options.graph}) {}
  void Predict(const kernel::Pose2& u) override { slam_.Predict(u); }
  void Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) override {
    tally_.Add(slam_.Update(scan, robot_T_laser));
  }
  kernel::Pose2 pose() const override { return slam_.pose(); }
  void Finish() override { slam_.Finish(); }
  std::vector<kernel::Pose2> Trajectory() const override { return slam_.graph().Trajectory(); }
  kernel::Status health() const override { return slam_.health(); }
  std::size_t MapSize() const override { return slam_.topological().num_control_points(); }
  std::size_t MapCurves() const override { return slam_.topological().num_curves(); }
  void AtNode(const kernel::LocalSafeRegion& lsr) override { slam_.SetLocalRegion(lsr); }
  std::vector<kernel::Pose2> NodePoses() const override { return slam_.graph().NodePoses(); }
  std::string MapDescription() const override {
    return fmt::format("{} curves, {} control points, {} keyframes, {} loop closures",
                       slam_.topological().num_curves(), slam_.topological().num_control_points(),
                       slam_.graph().keyframes().size(), slam_.graph().loops().accepted);
  }
  SlamMap Map() const override {
    SlamMap map;
    map.splines = slam_.topological().MapSplines();
    map.spline_features = slam_.topological().options().extraction;
    AddGraphLayers(slam_.graph(), &map);
    return map;
  }
  std::vector<std::pair<std::string, double>> LastUpdate() const override {
    return tally_.LastUpdate(slam_.topological());
  }
  SlamStatistics Statistics() const override {
    SlamStatistics s;
    tally_.Fill(slam_.topological(), &s);
    s.association = "curvature; correlative loop closure";
    s.map.emplace_back("keyframes", static_cast<long>(slam_.graph().keyframes().size()));
    s.map.emplace_back("keyframes_trimmed", slam_.graph().trimmed_keyframes());
    s.map.emplace_back("keyframes_merged", slam_.graph().merged_keyframes());
    AddGraphStatistics(slam_.graph(), &s);
    return s;
  }

 private:
  TopologicalGraphSlam slam_;
  TopologicalTally tally_;
};

}  // namespace

void AddTopologicalMethod(kernel::Registry<SlamMethodInfo>* registry) {
  registry->Add(MakeSlamMethodInfo<TopologicalSlamOptions>(
      "topological",
      "topological B-spline SLAM: local-region association, Ceres corrections (paper 003)",
      [](const TopologicalSlamOptions& o, const SlamContext& c) {
        return std::make_unique<TopologicalSlamMethod>(o, c);
      },
      [](const SensorNoise& noise, TopologicalSlamOptions* o) {
        o->odometry = OdometryNoiseModel().Scaled(noise.odometry_noise_scale);
        o->scan_matching.front_end.odometry = o->odometry;
      }));
}

void AddTopologicalGraphMethod(kernel::Registry<SlamMethodInfo>* registry) {
  registry->Add(MakeSlamMethodInfo<TopologicalGraphSlamOptions>(
      "topological-graph",
      "the topological SLAM with the graph SLAM's loop closures and pose graph behind it",
      [](const TopologicalGraphSlamOptions& o, const SlamContext& c) {
        return std::make_unique<TopologicalGraphSlamMethod>(o, c);
      },
      [](const SensorNoise& noise, TopologicalGraphSlamOptions* o) {
        o->topological.odometry = OdometryNoiseModel().Scaled(noise.odometry_noise_scale);
        o->topological.scan_matching.front_end.odometry = o->topological.odometry;
        o->graph.front_end.odometry = o->topological.odometry;
      }));
}

}  // namespace splam::estimation
