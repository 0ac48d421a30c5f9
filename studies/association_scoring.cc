#include "studies/association_scoring.h"

#include <chrono>
#include <set>

#include "estimation/evaluation/metrics.h"
#include "runtime/scoring.h"

namespace splam::studies {

using runtime::MeanDistanceToObstacles;

std::map<int, int> Votes(const std::vector<std::size_t>& beams, const std::vector<int>& obstacles) {
  std::map<int, int> votes;
  for (const std::size_t b : beams) ++votes[obstacles[b]];
  return votes;
}
int MajorityObstacle(const std::vector<std::size_t>& beams, const std::vector<int>& obstacles) {
  int best = -1, count = 0;
  for (const auto& [obstacle, n] : Votes(beams, obstacles)) {
    if (n > count) best = obstacle, count = n;
  }
  return best;
}

AssociationRun RunBSplineFilter(const std::vector<sim::SensorFrame>& frames,
                                const sim::RayCaster& caster,
                                const estimation::EkfBSplineSlamOptions& options) {
  AssociationRun result;
  estimation::EkfBSplineSlam slam(frames.front().odometry_pose,
                                  Eigen::Vector3d(1e-6, 1e-6, 1e-8).asDiagonal(), options);
  // Map spline id -> the obstacles it was made from: those that gave at least 10 % of the beams
  // of its creation or of an extension (a segment may run over two touching obstacles).
  std::map<int, std::set<int>> spline_obstacles;
  auto record = [&](const estimation::SplineChangeRecord& c, const std::vector<int>& obstacles) {
    for (const auto& [obstacle, n] : Votes(c.beams, obstacles)) {
      if (10 * n >= static_cast<int>(c.beams.size()))
        spline_obstacles[c.map_spline].insert(obstacle);
    }
  };
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const sim::SensorFrame& f = frames[i];
    if (i > 0) slam.Predict(frames[i - 1].odometry_pose.Between(f.odometry_pose));
    const estimation::BSplineUpdateReport r = slam.Update(f.scan);
    if (!slam.healthy()) {
      result.healthy = false;
      result.failure = slam.health().message();
      break;
    }
    // Associations are judged against what the spline was made of before this scan.
    // An association (an accepted match, whether or not its beams then passed the
    // correspondence test and the gate) is wrong when most of its stretch's beams hit an
    // obstacle the spline was not made from.
    for (const auto& a : r.associations) {
      if (a.matched_beams.empty()) continue;
      const std::set<int>& truth = spline_obstacles[a.map_spline];
      ++result.associations;
      result.with_features += a.used_features;
      result.wrong_associations +=
          !truth.contains(MajorityObstacle(a.matched_beams, f.beam_obstacles));
      for (const std::size_t b : a.beams) {
        ++result.beams;
        result.wrong_beams += !truth.contains(f.beam_obstacles[b]);
      }
    }
    for (const auto& c : r.created) record(c, f.beam_obstacles);
    for (const auto& c : r.extended) record(c, f.beam_obstacles);
    result.estimate.push_back({f.time_s, slam.pose()});
    result.mean_nees += evaluation::PoseNees(f.true_pose, slam.pose(), slam.pose_covariance()) /
                        static_cast<double>(frames.size());
  }
  result.ms_per_scan =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() /
      static_cast<double>(frames.size());
  result.map = slam.MapSplines();
  result.map_error_m = MeanDistanceToObstacles(caster, result.map);
  return result;
}

}  // namespace splam::studies
