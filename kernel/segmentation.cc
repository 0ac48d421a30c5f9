#include "kernel/segmentation.h"

#include <algorithm>
#include <cmath>

#include "kernel/angle.h"
#include "kernel/shapes.h"

namespace splam::kernel {

double ScanSegment::Length() const { return PolylineLength(points); }

Status SegmentationOptions::Validate() const {
  if (!(dietmayer_c0_m >= 0.0)) return Status::Error("dietmayer_c0_m must be >= 0");
  if (!(pedraza_eta >= 1.0)) return Status::Error("pedraza_eta must be >= 1");
  if (!(pedraza_alpha_max_rad >= 0.0 && pedraza_alpha_max_rad <= kPi)) {
    return Status::Error("pedraza_alpha_max_rad must be in [0, pi]");
  }
  if (!(pedraza_max_gap_m > 0.0)) return Status::Error("pedraza_max_gap_m must be positive");
  if (!(min_length_m >= 0.0)) return Status::Error("min_length_m must be >= 0");
  if (min_points < 2) return Status::Error("min_points must be at least 2");
  return Status::Ok();
}

std::vector<ScanSegment> SegmentScan(const Scan& scan, const SegmentationOptions& options) {
  std::vector<ScanSegment> segments;
  ScanSegment current;
  auto close = [&] {
    if (static_cast<int>(current.points.size()) >= options.min_points &&
        current.Length() >= options.min_length_m) {
      segments.push_back(std::move(current));
    }
    current = ScanSegment();
  };
  const double c1 = std::sqrt(2.0 * (1.0 - std::cos(scan.angular_step_rad)));
  const double cos_alpha_max = std::cos(options.pedraza_alpha_max_rad);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.IsHit(i)) {
      close();
      continue;
    }
    const Eigen::Vector2d point = PolarToCartesian({scan.ranges_m[i], scan.BeamAngle(i)});
    if (!current.points.empty()) {
      const Eigen::Vector2d gap = point - current.points.back();
      bool joins = false;
      if (options.method == SegmentationMethod::kDietmayer) {
        const double r_min = std::min(scan.ranges_m[i], scan.ranges_m[current.beams.back()]);
        joins = gap.norm() <= options.dietmayer_c0_m + c1 * r_min;
      } else if (current.points.size() == 1) {
        joins = gap.norm() <= options.pedraza_max_gap_m;
      } else {
        const Eigen::Vector2d previous =
            current.points.back() - current.points[current.points.size() - 2];
        const double a = previous.norm(), b = gap.norm();
        const bool spacing = std::max(a, b) <= options.pedraza_eta * std::min(a, b);
        const bool aligned = previous.dot(gap) >= cos_alpha_max * a * b;
        joins = spacing && aligned;
      }
      if (!joins) close();
    }
    current.points.push_back(point);
    current.beams.push_back(i);
  }
  close();
  return segments;
}

void SegmentationOptions::VisitFields(FieldVisitor& v) {
  int m = static_cast<int>(method);
  v.Choice("method", &m, {"dietmayer", "pedraza"},
           "adaptive distance (keeps corners) or spacing and alignment tests");
  method = static_cast<SegmentationMethod>(m);
  v.Field("dietmayer_c0_m", &dietmayer_c0_m, "Dietmayer: constant part of the join distance, m");
  v.Field("pedraza_eta", &pedraza_eta, "Pedraza: spacing ratio bound eta (1.5-2 in the paper)");
  v.Field("pedraza_alpha_max_rad", &pedraza_alpha_max_rad, "Pedraza: alignment bound, rad");
  v.Field("pedraza_max_gap_m", &pedraza_max_gap_m, "Pedraza: first gap of a segment at most, m");
  v.Field("min_length_m", &min_length_m, "shorter segments are dropped, m");
  v.Field("min_points", &min_points, "segments with fewer points are dropped");
}

}  // namespace splam::kernel
