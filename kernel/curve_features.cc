#include "kernel/curve_features.h"

#include <algorithm>
#include <cmath>

#include "kernel/angle.h"

namespace splam::kernel {
namespace {

// A run of samples of one curvature sign, with hysteresis: the sign changes only where |k|
// rises above the dead band on the other side, so noise around zero inside a lobe does not
// split it. [begin, end) spans the lobe's first to last sample above the dead band.
struct Lobe {
  std::size_t begin, end;
  int sign;
  double peak;  // max |k|
  double turn;  // sign * sum k epsilon over [begin, end): how far the tangent turns
};

std::vector<Lobe> FindLobes(const CurvatureProfile& profile, double dead_band) {
  const std::vector<double>& k = profile.curvature;
  std::vector<Lobe> lobes;
  for (std::size_t i = 0; i < k.size(); ++i) {
    if (std::abs(k[i]) < dead_band || k[i] == 0.0) continue;
    const int sign = k[i] > 0.0 ? 1 : -1;
    if (lobes.empty() || lobes.back().sign != sign) lobes.push_back({i, i + 1, sign, 0.0, 0.0});
    lobes.back().end = i + 1;
  }
  for (Lobe& lobe : lobes) {
    for (std::size_t i = lobe.begin; i < lobe.end; ++i) {
      lobe.peak = std::max(lobe.peak, lobe.sign * k[i]);
      lobe.turn += lobe.sign * k[i] * profile.epsilon_m;
    }
  }
  return lobes;
}

}  // namespace

Status FeatureOptions::Validate() const {
  if (!(inflection_min_curvature >= 0.0) || !(inflection_min_turn_rad >= 0.0) ||
      !(inflection_dead_band >= 0.0)) {
    return Status::Error("inflection thresholds must be >= 0");
  }
  if (!(corner_min_curvature > 0.0)) return Status::Error("corner_min_curvature must be positive");
  if (!(corner_ratio >= 1.0)) return Status::Error("corner_ratio must be >= 1");
  if (!(corner_max_angle_rad > 0.0 && corner_max_angle_rad <= kPi)) {
    return Status::Error("corner_max_angle_rad must be in (0, pi]");
  }
  // In samples (lengths / epsilon) they become counts: 1e308 m overflowed them (UBSan).
  if (!(corner_arm_length_m > 0.0 && corner_arm_length_m <= 100.0) ||
      !(corner_end_margin_m >= 0.0 && corner_end_margin_m <= 100.0)) {
    return Status::Error(
        "corner_arm_length_m must be in (0, 100] m and corner_end_margin_m in "
        "[0, 100] m");
  }
  return Status::Ok();
}

std::vector<CurveFeature> FindFeatures(const CurvatureProfile& profile,
                                       const FeatureOptions& options) {
  const std::vector<double>& k = profile.curvature;
  const std::size_t n = k.size();
  const double eps = profile.epsilon_m;
  std::vector<CurveFeature> features;
  if (n < 3 || !(eps > 0.0)) return features;

  // Inflections: between consecutive significant lobes of opposite sign, at the sign change
  // closest to the middle of the gap between them.
  std::vector<Lobe> lobes = FindLobes(profile, options.inflection_dead_band);
  std::erase_if(lobes, [&](const Lobe& l) {
    return l.peak < options.inflection_min_curvature || l.turn < options.inflection_min_turn_rad;
  });
  for (std::size_t l = 0; l + 1 < lobes.size(); ++l) {
    const Lobe& a = lobes[l];
    const Lobe& b = lobes[l + 1];
    if (a.sign == b.sign) continue;
    const double middle = 0.5 * (static_cast<double>(a.end) + static_cast<double>(b.begin) - 1.0);
    std::size_t best = a.end;
    for (std::size_t i = a.end - 1; i + 1 < b.begin + 1; ++i) {
      if ((k[i] > 0.0) != (k[i + 1] > 0.0) &&
          std::abs(static_cast<double>(i) + 0.5 - middle) <
              std::abs(static_cast<double>(best) - 0.5 - middle)) {
        best = i + 1;
      }
    }
    CurveFeature f;
    f.type = FeatureType::kInflection;
    f.index = best;
    f.arc_length_m = static_cast<double>(best) * eps;
    f.position = profile.smoothed[best];
    f.curvature = b.sign * std::min(a.peak, b.peak);
    features.push_back(f);
  }

  // Corners (He & Yung 2008).
  const std::size_t margin = static_cast<std::size_t>(std::ceil(options.corner_end_margin_m / eps));
  const std::size_t arm = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::lround(options.corner_arm_length_m / eps)));
  for (std::size_t i = std::max<std::size_t>(1, margin); i + 1 < n && i + margin < n; ++i) {
    const double a = std::abs(k[i]);
    if (a < options.corner_min_curvature || a < std::abs(k[i - 1]) || a <= std::abs(k[i + 1]))
      continue;
    // Region of support: to the neighbouring local minima of |k|.
    std::size_t left = i, right = i;
    while (left > 0 && std::abs(k[left - 1]) <= std::abs(k[left])) --left;
    while (right + 1 < n && std::abs(k[right + 1]) <= std::abs(k[right])) ++right;
    double mean = 0.0;
    for (std::size_t j = left; j <= right; ++j) mean += std::abs(k[j]);
    mean /= static_cast<double>(right - left + 1);
    if (a < options.corner_ratio * mean) continue;  // round corner
    const std::size_t l_end = i - std::min(arm, i - left);
    const std::size_t r_end = i + std::min(arm, right - i);
    if (l_end == i || r_end == i) continue;
    const Eigen::Vector2d u = profile.smoothed[l_end] - profile.smoothed[i];
    const Eigen::Vector2d v = profile.smoothed[r_end] - profile.smoothed[i];
    const double angle = std::acos(std::clamp(u.dot(v) / (u.norm() * v.norm()), -1.0, 1.0));
    if (angle > options.corner_max_angle_rad) continue;  // false corner
    if (options.corners_need_inflection_bounds) {
      bool before = false, after = false;
      for (const CurveFeature& f : features) {
        if (f.type != FeatureType::kInflection) continue;
        before |= f.index < i;
        after |= f.index > i;
      }
      if (!before || !after) continue;
    }
    CurveFeature f;
    f.type = FeatureType::kCorner;
    f.index = i;
    f.arc_length_m = static_cast<double>(i) * eps;
    f.position = profile.smoothed[i];
    f.curvature = k[i];
    f.angle_rad = angle;
    features.push_back(f);
  }
  std::sort(features.begin(), features.end(),
            [](const CurveFeature& x, const CurveFeature& y) { return x.index < y.index; });
  return features;
}

void FeatureOptions::VisitFields(FieldVisitor& v) {
  v.Field("inflection_dead_band", &inflection_dead_band,
          "a curvature lobe ends only beyond this |k| of the other sign, 1/m");
  v.Field("inflection_min_curvature", &inflection_min_curvature,
          "each lobe of an inflection reaches this |k|, 1/m");
  v.Field("inflection_min_turn_rad", &inflection_min_turn_rad,
          "... and turns the tangent by this much, rad");
  v.Field("corner_min_curvature", &corner_min_curvature, "corner candidates exceed this |k|, 1/m");
  v.Field("corner_ratio", &corner_ratio, "... and this ratio to the mean |k| of their support");
  v.Field("corner_max_angle_rad", &corner_max_angle_rad,
          "... and their arms meet at most at this angle, rad");
  v.Field("corner_arm_length_m", &corner_arm_length_m, "arm length measured for the angle, m");
  v.Field("corner_end_margin_m", &corner_end_margin_m,
          "corners this near a curve end are ignored, m");
  v.Field("corners_need_inflection_bounds", &corners_need_inflection_bounds,
          "paper 000: only corners with an inflection point on each side");
}

}  // namespace splam::kernel
