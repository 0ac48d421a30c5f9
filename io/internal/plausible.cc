#include "io/internal/plausible.h"

#include <algorithm>
#include <cmath>

#include "io/text.h"
#include "kernel/angle.h"

namespace splam::io::internal {

kernel::Status ScanGeometryProblem(const kernel::Scan& s) {
  if (s.size() == 0) return kernel::Status::Error("a scan without beams");
  if (s.size() > kMaxBeams)
    return kernel::Status::Error(std::to_string(s.size()) + " beams: more than the " +
                                 std::to_string(kMaxBeams) + " of any 2-D laser");
  if (!(s.max_range_m > 0.0 && s.max_range_m <= kMaxRangeM))
    return kernel::Status::Error("maximum range " + FormatDouble(s.max_range_m) +
                                 " m is not in (0, 1e4]");
  if (!(s.min_range_m >= 0.0 && s.min_range_m < s.max_range_m))
    return kernel::Status::Error("minimum range " + FormatDouble(s.min_range_m) +
                                 " m is not in [0, " + FormatDouble(s.max_range_m) +
                                 ") (the maximum range)");
  if (!(std::abs(s.start_angle_rad) <= 2.0 * kernel::kPi))
    return kernel::Status::Error("start angle " + FormatDouble(s.start_angle_rad) +
                                 " rad is not in [-2 pi, 2 pi]");
  // The step is checked whatever the number of beams: one beam with a NaN step made every later
  // stage place it at NaN (the occupancy grid indexed the cell of a NaN point).
  if (!std::isfinite(s.angular_step_rad) || s.angular_step_rad < 0.0 ||
      (s.size() > 1 && s.angular_step_rad == 0.0))
    return kernel::Status::Error("angular resolution " + FormatDouble(s.angular_step_rad) +
                                 " rad is not " +
                                 (s.size() > 1 ? "positive" : "a finite angle of 0 or more"));
  if (s.size() > 1 && s.angular_step_rad < kMinAngularStepRad)
    return kernel::Status::Error("angular resolution " + FormatDouble(s.angular_step_rad) +
                                 " rad is below 1e-4 rad (0.006 deg): no laser resolves that");
  const double span =
      s.angular_step_rad * static_cast<double>(std::max<std::size_t>(s.size(), 1) - 1);
  if (span > 2.0 * kernel::kPi + 1e-9)
    return kernel::Status::Error(
        std::to_string(s.size()) + " beams " + FormatDouble(s.angular_step_rad) +
        " rad apart span " + FormatDouble(span * 180.0 / kernel::kPi) +
        " deg, more than a full turn (a resolution in degrees instead of radians?)");
  return {};
}

kernel::Status PoseProblem(const kernel::Pose2& pose, const std::string& what) {
  for (const double c : {pose.x(), pose.y()}) {
    if (!(std::abs(c) <= kMaxCoordinateM))
      return kernel::Status::Error(what + " " + FormatDouble(c) +
                                   " is not finite or beyond +-1e+06 m");
  }
  if (!(std::abs(pose.theta()) <= kMaxHeadingRad))
    return kernel::Status::Error(what + " heading " + FormatDouble(pose.theta()) +
                                 " is not finite or beyond +-1e4 rad");
  return {};
}

}  // namespace splam::io::internal
