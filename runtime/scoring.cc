#include "runtime/scoring.h"

#include <algorithm>
#include <map>
#include <set>

namespace splam::runtime {

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const std::size_t k =
      std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

std::vector<TimeBin> TimeByMapSize(const std::vector<double>& ms,
                                   const std::vector<std::size_t>& map_size) {
  std::vector<TimeBin> bins;
  if (ms.empty()) return bins;
  const std::size_t top = *std::max_element(map_size.begin(), map_size.end()) + 1;
  const std::size_t width = (top + 7) / 8;
  for (std::size_t lo = 0; lo < top; lo += width) {
    std::vector<double> in;
    for (std::size_t i = 0; i < ms.size(); ++i) {
      if (map_size[i] >= lo && map_size[i] < lo + width) in.push_back(ms[i]);
    }
    if (!in.empty()) bins.push_back({lo, lo + width - 1, in.size(), Percentile(in, 0.5)});
  }
  return bins;
}

double MeanDistanceToObstacles(const sim::RayCaster& caster,
                               const std::vector<estimation::MapSpline>& splines) {
  constexpr double kCap = 2.0;  // m
  double sum = 0.0;
  std::size_t n = 0;
  for (const estimation::MapSpline& s : splines) {
    for (const Eigen::Vector2d& p : s.spline.ResampleByArcLength(0.05)) {
      const sim::RayHit near = caster.Nearest(p, kCap);
      sum += near.obstacle >= 0 ? near.range_m : kCap;
      ++n;
    }
  }
  return n > 0 ? sum / static_cast<double>(n) : 0.0;
}

double CurvesPerObstacle(const sim::RayCaster& caster,
                         const std::vector<estimation::MapSpline>& splines) {
  constexpr double kNear = 0.5;  // m
  std::set<int> obstacles;
  for (const estimation::MapSpline& s : splines) {
    std::map<int, int> votes;
    for (const Eigen::Vector2d& p : s.spline.ResampleByArcLength(0.05))
      ++votes[caster.Nearest(p, kNear).obstacle];
    const auto best =
        std::max_element(votes.begin(), votes.end(),
                         [](const auto& a, const auto& b) { return a.second < b.second; });
    if (best != votes.end() && best->first >= 0) obstacles.insert(best->first);
  }
  return obstacles.empty()
             ? 0.0
             : static_cast<double>(splines.size()) / static_cast<double>(obstacles.size());
}

}  // namespace splam::runtime
