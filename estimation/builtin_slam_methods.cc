// The three published methods behind the SlamMethod interface.
#include <fmt/core.h>

#include "estimation/ekf_bspline_slam.h"
#include "estimation/ekf_line_slam.h"
#include "estimation/graph_slam.h"
#include "estimation/slam_method.h"
#include "estimation/topological_graph_slam.h"
#include "estimation/topological_slam.h"
#include "kernel/angle.h"

namespace splam::estimation {
namespace {

// The EKFs start with a small covariance at the known start pose.
Eigen::Matrix3d StartCovariance() { return Eigen::Vector3d(1e-6, 1e-6, 1e-8).asDiagonal(); }

// What every EKF-SLAM filter answers the same way.
template <class Filter, class Options>
class FilterMethod : public SlamMethod {
 public:
  FilterMethod(const Options& options, const SlamContext& context)
      : slam_(context.start, StartCovariance(), options) {}
  void Predict(const kernel::Pose2& u) override { slam_.Predict(u); }
  kernel::Pose2 pose() const override { return slam_.pose(); }
  std::optional<Eigen::Matrix3d> pose_covariance() const override {
    return slam_.pose_covariance();
  }
  std::size_t MapSize() const override {
    return static_cast<std::size_t>(slam_.state().size() - 3) / 2;
  }
  kernel::Status health() const override { return slam_.health(); }

 protected:
  Filter slam_;
};

class LineSlam : public FilterMethod<EkfLineSlam, EkfLineSlamOptions> {
 public:
  using FilterMethod::FilterMethod;
  void Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) override {
    const UpdateReport r = slam_.Update(scan, robot_T_laser);
    totals_.line_observations += r.line_observations;
    totals_.corner_observations += r.corner_observations;
    totals_.associated += r.associated;
    totals_.new_landmarks += r.new_landmarks;
    totals_.ambiguous += r.ambiguous;
    totals_.too_small += r.too_small;
  }
  std::string MapDescription() const override {
    return fmt::format("{} lines, {} corners", slam_.num_lines(), slam_.num_corners());
  }
  SlamMap Map() const override {
    SlamMap map;
    map.lines = slam_.MapLines();
    map.corners = slam_.MapCorners();
    return map;
  }
  SlamStatistics Statistics() const override {
    SlamStatistics s;
    s.map = {{"lines", static_cast<long>(slam_.num_lines())},
             {"corners", static_cast<long>(slam_.num_corners())}};
    s.associations = {{"line_observations", totals_.line_observations},
                      {"corner_observations", totals_.corner_observations},
                      {"accepted", totals_.associated},
                      {"new_landmarks", totals_.new_landmarks},
                      {"rejected_ambiguous", totals_.ambiguous},
                      {"rejected_too_small", totals_.too_small}};
    return s;
  }

 private:
  UpdateReport totals_;
};

class BSplineSlam : public FilterMethod<EkfBSplineSlam, EkfBSplineSlamOptions> {
 public:
  using FilterMethod::FilterMethod;
  void Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) override {
    const BSplineUpdateReport r = slam_.Update(scan, robot_T_laser);
    observed_ += r.observed_curves;
    matched_ += r.matched_curves;
    beams_used_ += r.beams_used;
    beams_rejected_ += r.beams_rejected;
    created_ += static_cast<long>(r.created.size());
    extended_ += static_cast<long>(r.extended.size());
    ignored_ += r.ignored_curves;
    for (const auto& a : r.associations) with_features_ += a.used_features && !a.beams.empty();
  }
  std::string MapDescription() const override {
    return fmt::format("{} splines, {} control points", slam_.num_splines(),
                       slam_.num_control_points());
  }
  std::size_t MapCurves() const override { return slam_.num_splines(); }
  SlamMap Map() const override {
    SlamMap map;
    map.splines = slam_.MapSplines();
    map.spline_features = slam_.options().extraction;
    return map;
  }
  SlamStatistics Statistics() const override {
    SlamStatistics s;
    s.association = slam_.options().association;
    s.map = {{"splines", static_cast<long>(slam_.num_splines())},
             {"control_points", static_cast<long>(slam_.num_control_points())}};
    s.associations = {{"observed_curves", observed_},
                      {"matched_curves", matched_},
                      {"matches_with_paired_features", with_features_},
                      {"beams_used", beams_used_},
                      {"beams_rejected", beams_rejected_},
                      {"new_splines", created_},
                      {"extensions", extended_},
                      {"ignored_curves", ignored_}};
    return s;
  }

 private:
  long observed_ = 0, matched_ = 0, beams_used_ = 0, beams_rejected_ = 0;
  long created_ = 0, extended_ = 0, ignored_ = 0, with_features_ = 0;
};

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
class TopologicalSlamMethod : public SlamMethod {
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

// The keyframe graph with its loop-closure edges, into *map.
void AddGraph(const GraphSlam& graph, SlamMap* map) {
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

// Graph SLAM on curve maps: no covariance of its own; the map is the curves of its keyframes.
class GraphSlamMethod : public SlamMethod {
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
    AddGraph(slam_, &map);
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

// The topological SLAM with the graph SLAM's back end: the topological map, re-anchored to the
// optimised keyframes; the trajectory from the graph.
class TopologicalGraphSlamMethod : public SlamMethod {
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
    AddGraph(slam_.graph(), &map);
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

void AddBuiltinSlamMethods(kernel::Registry<SlamMethodInfo>* registry) {
  registry->Add(MakeSlamMethodInfo<EkfLineSlamOptions>(
      "ekf-lines", "EKF-SLAM with line and corner landmarks (paper 001, SPEC §2-6)",
      [](const EkfLineSlamOptions& o, const SlamContext& c) {
        return std::make_unique<LineSlam>(o, c);
      },
      [](const SensorNoise& noise, EkfLineSlamOptions* o) {
        o->odometry = OdometryNoiseModel().Scaled(noise.odometry_noise_scale);
        o->extraction.range_sigma_m = noise.range_sigma_m;
        o->extraction.range_sigma_fraction = noise.range_sigma_fraction;
      }));
  registry->Add(MakeSlamMethodInfo<EkfBSplineSlamOptions>(
      "ekf-bspline",
      "EKF-SLAM with B-spline obstacles (Pedraza et al. 2009; paper 000's curvature association)",
      [](const EkfBSplineSlamOptions& o, const SlamContext& c) {
        return std::make_unique<BSplineSlam>(o, c);
      },
      [](const SensorNoise& noise, EkfBSplineSlamOptions* o) {
        o->odometry = OdometryNoiseModel().Scaled(noise.odometry_noise_scale);
        o->range_sigma_floor_m = noise.beam_sigma_floor_m;
        o->range_sigma_fraction = noise.range_sigma_fraction;
      }));
  registry->Add(MakeSlamMethodInfo<TopologicalSlamOptions>(
      "topological",
      "topological B-spline SLAM: local-region association, Ceres corrections (paper 003)",
      [](const TopologicalSlamOptions& o, const SlamContext& c) {
        return std::make_unique<TopologicalSlamMethod>(o, c);
      },
      [](const SensorNoise& noise, TopologicalSlamOptions* o) {
        o->odometry = OdometryNoiseModel().Scaled(noise.odometry_noise_scale);
        o->scan_matching.odometry = o->odometry;
      }));
  registry->Add(MakeSlamMethodInfo<GraphSlamOptions>(
      "graph",
      "graph SLAM on curve maps: scan-to-submap registration, loop closure, Ceres pose graph",
      [](const GraphSlamOptions& o, const SlamContext& c) {
        return std::make_unique<GraphSlamMethod>(o, c);
      },
      [](const SensorNoise& noise, GraphSlamOptions* o) {
        o->odometry = OdometryNoiseModel().Scaled(noise.odometry_noise_scale);
      }));
  registry->Add(MakeSlamMethodInfo<TopologicalGraphSlamOptions>(
      "topological-graph",
      "the topological SLAM with the graph SLAM's loop closures and pose graph behind it",
      [](const TopologicalGraphSlamOptions& o, const SlamContext& c) {
        return std::make_unique<TopologicalGraphSlamMethod>(o, c);
      },
      [](const SensorNoise& noise, TopologicalGraphSlamOptions* o) {
        o->topological.odometry = OdometryNoiseModel().Scaled(noise.odometry_noise_scale);
        o->topological.scan_matching.odometry = o->topological.odometry;
        o->graph.odometry = o->topological.odometry;
      }));
}

}  // namespace splam::estimation
