#ifndef SPLAM_ESTIMATION_SPLINE_ASSOCIATION_H_
#define SPLAM_ESTIMATION_SPLINE_ASSOCIATION_H_

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "kernel/options.h"
#include "kernel/spline_extraction.h"
#include "kernel/status.h"

// Data association between an observed curve and a map curve (SPEC §7), both in the same frame
// (the observation moved by the predicted robot pose).
namespace splam::estimation {

// An interval of arc length along a curve, metres from its start. On the map curve `end` may be
// smaller than `start`: the map curve then runs the other way round.
struct CurveStretch {
  double start_m = 0.0;
  double end_m = 0.0;
};

struct CurveMatch {
  CurveStretch observed, map;
  // Point-to-point correspondences (observed point, map point), epsilon apart along the
  // observed stretch.
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> pairs;
  bool used_features = false;  // paper 000's association found paired features
  int related_control_points = 0;
};

struct SplineAssociationOptions {
  // Coarse test: an observed and a map control point are related when they are at most d_min
  // apart; the curves are candidates with at least mu_min related pairs (Pedraza: 1; paper 000:
  // more).
  double d_min_m = 0.4;
  int mu_min = 2;
  // Features pair when they are of the same type, their curvatures have the same sign and differ
  // by at most this fraction of the larger one, and they are at most max_feature_distance_m apart.
  double curvature_tolerance = 0.5;
  double max_feature_distance_m = 0.3;
  double epsilon_m = 0.01;  // spacing of the correspondences

  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// One interface, two methods: Pedraza et al. 2009 and paper 000.
class SplineAssociation {
 public:
  virtual ~SplineAssociation() = default;
  virtual std::string name() const = 0;
  // The matched stretches and their correspondences, or nullopt when the curves are unrelated.
  virtual std::optional<CurveMatch> Match(const kernel::SplineCurve& observed,
                                          const kernel::SplineCurve& map) const = 0;
};

// Pedraza: coarse by control points within d_min; fine by end-point projection. From the
// observed curve's start a, b is the closest map point; if b is an end of the map curve the
// pair is (c, b) with c the closest observed point to b, else (a, b); likewise from the other
// end. The two stretches are then trimmed to the same length.
class PedrazaAssociation : public SplineAssociation {
 public:
  explicit PedrazaAssociation(const SplineAssociationOptions& options = {}) : options_(options) {}
  std::string name() const override { return "pedraza"; }
  std::optional<CurveMatch> Match(const kernel::SplineCurve& observed,
                                  const kernel::SplineCurve& map) const override;

 private:
  SplineAssociationOptions options_;
};

// Paper 000 (§3.3): coarse as Pedraza's with mu_min related control points; fine by pairing
// inflection points and corners by type and curvature. From the outermost paired features the
// stretch extends towards each end by as much as fits in the shorter of the two curves; the
// correspondences follow arc length between paired features. Without paired features it falls
// back to Pedraza's fine association.
class CurvatureAssociation : public SplineAssociation {
 public:
  explicit CurvatureAssociation(const SplineAssociationOptions& options = {}) : options_(options) {}
  std::string name() const override { return "curvature"; }
  std::optional<CurveMatch> Match(const kernel::SplineCurve& observed,
                                  const kernel::SplineCurve& map) const override;

 private:
  SplineAssociationOptions options_;
};

// Related control-point pairs of the coarse test (each observed control point counted once).
int RelatedControlPoints(const kernel::SplineCurve& observed, const kernel::SplineCurve& map,
                         double d_min_m);

// "pedraza" or "curvature"; nullptr for other names.
std::unique_ptr<SplineAssociation> MakeSplineAssociation(
    const std::string& name, const SplineAssociationOptions& options = {});

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_SPLINE_ASSOCIATION_H_
