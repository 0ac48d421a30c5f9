#include "estimation/spline_association.h"

#include <algorithm>
#include <cmath>

namespace splam::estimation {
namespace {

using kernel::SplineCurve;

Eigen::Vector2d PointAt(const SplineCurve& c, double s) {
  return c.spline.Point(c.spline.ParameterAtArcLength(s));
}
double ArcOf(const SplineCurve& c, const Eigen::Vector2d& p) {
  return c.spline.ArcLengthAt(c.spline.Closest(p).t);
}

// Correspondences along the observed stretch [start, end], map arc lengths from `map_arc`.
template <class MapArc>
CurveMatch Correspond(const SplineCurve& observed, const SplineCurve& map, double start, double end,
                      MapArc map_arc, double epsilon) {
  CurveMatch m;
  m.observed = {start, end};
  m.map = {map_arc(start), map_arc(end)};
  for (double s = start; s <= end + 1e-9; s += epsilon)
    m.pairs.emplace_back(PointAt(observed, s), PointAt(map, map_arc(s)));
  return m;
}

// Pedraza's fine association (see the header); nullopt when the overlap is shorter than epsilon.
std::optional<CurveMatch> EndPointMatch(const SplineCurve& observed, const SplineCurve& map,
                                        double epsilon) {
  const double lo = observed.spline.Length(), lm = map.spline.Length();
  const double at_end = 2.0 * epsilon;  // a projection this close to a map end is at the end
  auto anchor = [&](double s_obs) {
    const double s_map = ArcOf(map, PointAt(observed, s_obs));
    if (s_map < at_end || s_map > lm - at_end) {
      const Eigen::Vector2d b = PointAt(map, s_map);
      return std::pair{ArcOf(observed, b), s_map};
    }
    return std::pair{s_obs, s_map};
  };
  const auto [o1, m1] = anchor(0.0);
  const auto [o2, m2] = anchor(lo);
  const double sign = m2 >= m1 ? 1.0 : -1.0;
  const double length = std::min(o2 - o1, std::abs(m2 - m1));  // trim to equal lengths
  if (!(length >= epsilon)) return std::nullopt;
  const double from = o1, to = m1;  // lambdas cannot capture structured bindings in Clang 14
  return Correspond(
      observed, map, o1, o1 + length, [&](double s) { return to + sign * (s - from); }, epsilon);
}

}  // namespace

kernel::Status SplineAssociationOptions::Validate() const {
  // An infinite d_min_m put the topological SLAM's index lookups at -inf (UBSan).
  if (!(d_min_m > 0.0 && d_min_m <= 10.0) || mu_min < 1)
    return kernel::Status::Error("association needs d_min_m in (0, 10] m and mu_min >= 1");
  if (!(curvature_tolerance >= 0.0) || !(max_feature_distance_m > 0.0))
    return kernel::Status::Error("bad feature pairing tolerances");
  // Correspondences every epsilon_m along the overlap: a micrometre is 10^6 per metre.
  if (!(epsilon_m >= 1e-3 && epsilon_m <= 10.0))
    return kernel::Status::Error("epsilon_m must be in [0.001, 10] m");
  return kernel::Status::Ok();
}

int RelatedControlPoints(const SplineCurve& observed, const SplineCurve& map, double d_min_m) {
  int related = 0;
  for (const Eigen::Vector2d& a : observed.spline.control_points()) {
    for (const Eigen::Vector2d& b : map.spline.control_points()) {
      if ((a - b).norm() <= d_min_m) {
        ++related;
        break;
      }
    }
  }
  return related;
}

std::optional<CurveMatch> PedrazaAssociation::Match(const SplineCurve& observed,
                                                    const SplineCurve& map) const {
  const int related = RelatedControlPoints(observed, map, options_.d_min_m);
  if (related < 1) return std::nullopt;
  std::optional<CurveMatch> m = EndPointMatch(observed, map, options_.epsilon_m);
  if (m) m->related_control_points = related;
  return m;
}

std::optional<CurveMatch> CurvatureAssociation::Match(const SplineCurve& observed,
                                                      const SplineCurve& map) const {
  const int related = RelatedControlPoints(observed, map, options_.d_min_m);
  if (related < options_.mu_min) return std::nullopt;

  // Which way the map runs relative to the observation, from where the observation's ends
  // project onto it. A curve traversed the other way has curvatures of the other sign.
  const double direction =
      ArcOf(map, PointAt(observed, observed.spline.Length())) >= ArcOf(map, PointAt(observed, 0.0))
          ? 1.0
          : -1.0;
  // Pair features by type, curvature sign and magnitude, nearest first, one to one.
  struct Pair {
    double distance, s_obs, s_map;
    std::size_t o, m;
  };
  std::vector<Pair> pairs;
  for (std::size_t i = 0; i < observed.features.size(); ++i) {
    for (std::size_t j = 0; j < map.features.size(); ++j) {
      const kernel::CurveFeature& a = observed.features[i];
      const kernel::CurveFeature& b = map.features[j];
      const double ka = a.curvature, kb = direction * b.curvature;
      if (a.type != b.type || ka * kb <= 0.0) continue;
      if (std::abs(ka - kb) > options_.curvature_tolerance * std::max(std::abs(ka), std::abs(kb)))
        continue;
      const double d = (a.position - b.position).norm();
      if (d <= options_.max_feature_distance_m)
        pairs.push_back({d, a.arc_length_m, b.arc_length_m, i, j});
    }
  }
  std::sort(pairs.begin(), pairs.end(),
            [](const Pair& a, const Pair& b) { return a.distance < b.distance; });
  std::vector<Pair> chosen;
  for (const Pair& p : pairs) {
    if (std::none_of(chosen.begin(), chosen.end(),
                     [&](const Pair& c) { return c.o == p.o || c.m == p.m; })) {
      chosen.push_back(p);
    }
  }
  std::sort(chosen.begin(), chosen.end(),
            [](const Pair& a, const Pair& b) { return a.s_obs < b.s_obs; });
  const double sign = direction;
  // Keep the pairs whose map positions run monotonically in that direction.
  std::vector<Pair> anchors;
  for (const Pair& p : chosen) {
    if (anchors.empty() || sign * (p.s_map - anchors.back().s_map) > 0.0) anchors.push_back(p);
  }
  if (anchors.empty()) {
    std::optional<CurveMatch> m = EndPointMatch(observed, map, options_.epsilon_m);  // fallback
    if (m) m->related_control_points = related;
    return m;
  }
  const double lo = observed.spline.Length(), lm = map.spline.Length();
  const Pair& first = anchors.front();
  const Pair& last = anchors.back();
  // From the outermost features towards each end, as far as the shorter curve allows.
  const double back = std::min(first.s_obs, sign > 0 ? first.s_map : lm - first.s_map);
  const double forward = std::min(lo - last.s_obs, sign > 0 ? lm - last.s_map : last.s_map);
  auto map_arc = [&](double s) {
    if (s <= first.s_obs) return first.s_map + sign * (s - first.s_obs);
    if (s >= last.s_obs) return last.s_map + sign * (s - last.s_obs);
    for (std::size_t k = 0; k + 1 < anchors.size(); ++k) {
      const Pair& a = anchors[k];
      const Pair& b = anchors[k + 1];
      if (s <= b.s_obs) return a.s_map + (s - a.s_obs) * (b.s_map - a.s_map) / (b.s_obs - a.s_obs);
    }
    return last.s_map;
  };
  CurveMatch m = Correspond(observed, map, first.s_obs - back, last.s_obs + forward, map_arc,
                            options_.epsilon_m);
  m.used_features = true;
  m.related_control_points = related;
  return m;
}

std::unique_ptr<SplineAssociation> MakeSplineAssociation(const std::string& name,
                                                         const SplineAssociationOptions& options) {
  if (name == "pedraza") return std::make_unique<PedrazaAssociation>(options);
  if (name == "curvature") return std::make_unique<CurvatureAssociation>(options);
  return nullptr;
}

void SplineAssociationOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("d_min_m", &d_min_m, "coarse test: control points at most this far apart are related, m");
  v.Field("mu_min", &mu_min, "... and curves with this many related pairs are candidates");
  v.Field("curvature_tolerance", &curvature_tolerance,
          "paired features' curvatures differ by at most this fraction");
  v.Field("max_feature_distance_m", &max_feature_distance_m,
          "paired features at most this apart, m");
  v.Field("epsilon_m", &epsilon_m, "spacing of the correspondences, m");
}

}  // namespace splam::estimation
