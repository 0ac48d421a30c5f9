#include "io/no_return_pile.h"

#include <algorithm>
#include <variant>
#include <vector>

namespace splam::io {

std::optional<NoReturnPile> FindNoReturnPile(const CarmenLog& log,
                                             const NoReturnPileOptions& options) {
  std::vector<double> hits;
  for (const LaserMessage* m : log.Lasers())
    for (std::size_t i = 0; i < m->scan.size(); ++i)
      if (m->scan.IsHit(i)) hits.push_back(m->scan.ranges_m[i]);
  if (hits.empty()) return std::nullopt;
  const double top = *std::max_element(hits.begin(), hits.end());
  const double band_from = top - options.band_m;
  const double below_from = band_from - options.below_m;
  long in_band = 0, below = 0;
  double smallest_in_band = top;
  for (double r : hits) {
    if (r >= band_from) {
      ++in_band;
      smallest_in_band = std::min(smallest_in_band, r);
    } else if (r >= below_from) {
      ++below;
    }
  }
  const double share = static_cast<double>(in_band) / static_cast<double>(hits.size());
  const double band_density = static_cast<double>(in_band) / options.band_m;
  const double below_density = static_cast<double>(below) / options.below_m;
  std::nth_element(hits.begin(), hits.begin() + static_cast<long>(hits.size() / 2), hits.end());
  const double median = hits[hits.size() / 2];
  if (share < options.min_share || band_density < options.min_density_ratio * below_density ||
      smallest_in_band < options.min_times_median * median)
    return std::nullopt;
  return NoReturnPile{smallest_in_band, top, in_band, share};
}

void MarkNoReturns(double from_m, CarmenLog* log) {
  for (LogMessage& message : log->messages) {
    LaserMessage* m = std::get_if<LaserMessage>(&message);
    if (m == nullptr) continue;
    for (double& r : m->scan.ranges_m)
      if (r >= from_m) r = kernel::Scan::kNoReturn;
    m->scan.max_range_m = std::min(m->scan.max_range_m, from_m);
  }
}

}  // namespace splam::io
