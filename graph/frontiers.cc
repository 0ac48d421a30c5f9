#include "graph/frontiers.h"

#include <algorithm>

namespace splam::graph {

std::vector<kernel::FrontierArc> Subtract(const kernel::FrontierArc& arc,
                                          const std::vector<kernel::FrontierArc>& covered,
                                          double margin_rad) {
  std::vector<kernel::FrontierArc> cuts = covered;
  std::sort(cuts.begin(), cuts.end(),
            [](const auto& a, const auto& b) { return a.start_angle_rad < b.start_angle_rad; });
  std::vector<kernel::FrontierArc> pieces;
  double from = arc.start_angle_rad;
  for (const kernel::FrontierArc& cut : cuts) {
    const double lo = cut.start_angle_rad - margin_rad;
    const double hi = cut.end_angle_rad + margin_rad;
    if (hi <= from) continue;
    if (lo >= arc.end_angle_rad) break;
    if (lo > from) pieces.push_back({from, lo});
    from = std::max(from, hi);
  }
  if (from < arc.end_angle_rad) pieces.push_back({from, arc.end_angle_rad});
  return pieces;
}

kernel::FrontierArc LeadingPiece(const kernel::FrontierArc& arc, double max_width_rad) {
  if (arc.AngularWidth() <= max_width_rad) return arc;
  return {arc.start_angle_rad, arc.start_angle_rad + max_width_rad};
}

}  // namespace splam::graph
