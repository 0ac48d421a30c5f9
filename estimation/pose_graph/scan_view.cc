#include "estimation/pose_graph/scan_view.h"

#include <algorithm>
#include <utility>

namespace splam::estimation {

std::vector<Eigen::Vector2d> ScanView(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser,
                                      double range, double seen_margin_m, bool no_returns) {
  std::vector<std::pair<double, double>> ends;  // (range, angle) of each usable beam's end
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (scan.IsHit(i))
      ends.emplace_back(std::min(scan.ranges_m[i] + seen_margin_m, range), scan.BeamAngle(i));
    else if (scan.IsNoReturn(i))
      ends.emplace_back(no_returns ? std::min(range, scan.max_range_m) - seen_margin_m : 0.0,
                        scan.BeamAngle(i));
  }
  std::vector<Eigen::Vector2d> view{robot_T_laser.translation()};
  const auto add = [&](double r, double angle) {
    view.push_back(robot_T_laser * kernel::PolarToCartesian({r, angle}));
  };
  for (std::size_t k = 0; k < ends.size(); ++k) {
    const auto [r, angle] = ends[k];
    add(r, angle);
    if (k + 1 == ends.size()) break;
    const auto [next_r, next_angle] = ends[k + 1];
    if (next_r < r)
      add(next_r, angle);
    else if (r < next_r)
      add(r, next_angle);
  }
  return view;
}

}  // namespace splam::estimation
