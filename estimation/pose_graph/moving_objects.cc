#include "estimation/pose_graph/moving_objects.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernel/angle.h"
#include "kernel/options.h"

namespace splam::estimation {

void MovingObjectOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("enabled", &enabled, "leave out of the map objects that another scan saw through");
  v.Field("max_size_m", &max_size_m, "a moving object is at most this long, m");
  v.Field("max_gap_m", &max_gap_m, "neighbouring points of one object are this close, m");
  v.Field("min_displacement_m", &min_displacement_m,
          "the other scan's beams reached this far beyond the object, m");
  v.Field("lateral_tolerance_m", &lateral_tolerance_m,
          "beams this far to the side of a point must all have passed it, m");
}

kernel::Status MovingObjectOptions::Validate() const {
  if (!(max_size_m > 0 && max_size_m <= 100) || !(max_gap_m > 0 && max_gap_m <= 100) ||
      !(min_displacement_m > 0 && min_displacement_m <= 100) ||
      !(lateral_tolerance_m >= 0 && lateral_tolerance_m <= 100))
    return kernel::Status::Error(
        "moving objects: max_size_m, max_gap_m and min_displacement_m in (0, 100], "
        "lateral_tolerance_m in [0, 100]");
  return kernel::Status::Ok();
}

namespace {

Eigen::Vector2d HitPoint(const kernel::Scan& scan, std::size_t i) {
  return kernel::PolarToCartesian({scan.ranges_m[i], scan.BeamAngle(i)});
}

// Whether beam `i` (a hit at range r) has, on its side, a neighbour that lies farther than
// r + max_gap_m or without a return, or the field of view's edge: the object stands in front of
// what is beside it. (A person overtaking the robot enters at the edge, close by, and stands
// half outside the view for several scans.)
bool FartherBeside(const kernel::Scan& scan, std::size_t i, std::ptrdiff_t side, double max_gap_m) {
  const auto j = static_cast<std::ptrdiff_t>(i) + side;
  if (j < 0 || j >= static_cast<std::ptrdiff_t>(scan.size())) return true;
  const auto k = static_cast<std::size_t>(j);
  return scan.IsNoReturn(k) || (scan.IsHit(k) && scan.ranges_m[k] > scan.ranges_m[i] + max_gap_m);
}

// Whether `other` saw through `point` (its sensor frame): every beam within the bearing of
// lateral_tolerance_m, and at least the beams either side of it, reached min_displacement_m
// beyond it (or read no return). -1: the window is not wholly in its field of view, the point is
// out of its range, or a beam there carries no reading (an invalid one, or a moving object
// already left out: what was behind it is unknown).
int SeenThrough(const kernel::Scan& other, const Eigen::Vector2d& point,
                const MovingObjectOptions& options) {
  const kernel::Polar polar = kernel::CartesianToPolar(point);
  if (other.size() < 2 || other.angular_step_rad == 0 ||
      polar.range_m + options.min_displacement_m >= other.max_range_m)
    return -1;
  const double step = std::abs(other.angular_step_rad);
  const double half_width = std::max(std::atan2(options.lateral_tolerance_m, polar.range_m), step);
  // The bearing's beam position (a fractional index), the bearing taken past the first beam in
  // the direction the beams turn.
  const double turn = std::copysign(1.0, other.angular_step_rad);
  const double past = turn * (polar.angle_rad - other.start_angle_rad);
  const double at = (past - 2 * kernel::kPi * std::floor(past / (2 * kernel::kPi))) / step;
  const double lo = std::ceil(at - half_width / step), hi = std::floor(at + half_width / step);
  // The whole window in the field of view: at its edge, the beams that would hit the object
  // may be the ones the field cuts off.
  // (Negated: a point that is not finite has a NaN window, which is no window.)
  if (!(lo >= 0 && hi <= static_cast<double>(other.size() - 1))) return -1;
  for (auto i = static_cast<std::size_t>(lo); i <= static_cast<std::size_t>(hi); ++i) {
    if (other.IsNoReturn(i)) continue;
    if (!other.IsHit(i)) return -1;  // no reading, or a moving object already left out
    if (other.ranges_m[i] < polar.range_m + options.min_displacement_m) return 0;
  }
  return 1;
}

}  // namespace

BeamRanges ForegroundObjects(const kernel::Scan& scan, const MovingObjectOptions& options) {
  BeamRanges objects;
  std::size_t begin = 0;
  while (begin < scan.size()) {
    if (!scan.IsHit(begin)) {
      ++begin;
      continue;
    }
    std::size_t end = begin + 1;
    while (end < scan.size() && scan.IsHit(end) &&
           (HitPoint(scan, end) - HitPoint(scan, end - 1)).norm() <= options.max_gap_m)
      ++end;
    if ((HitPoint(scan, end - 1) - HitPoint(scan, begin)).norm() <= options.max_size_m &&
        FartherBeside(scan, begin, -1, options.max_gap_m) &&
        FartherBeside(scan, end - 1, 1, options.max_gap_m))
      objects.emplace_back(begin, end);
    begin = end;
  }
  return objects;
}

std::vector<std::size_t> SeenThroughBeams(const kernel::Scan& scan,
                                          const kernel::Pose2& world_T_laser,
                                          const kernel::Scan& other,
                                          const kernel::Pose2& world_T_other_laser,
                                          const MovingObjectOptions& options) {
  return SeenThroughBeams(scan, ForegroundObjects(scan, options), world_T_laser, other,
                          world_T_other_laser, options);
}

std::vector<std::size_t> SeenThroughBeams(const kernel::Scan& scan, const BeamRanges& candidates,
                                          const kernel::Pose2& world_T_laser,
                                          const kernel::Scan& other,
                                          const kernel::Pose2& world_T_other_laser,
                                          const MovingObjectOptions& options) {
  std::vector<std::size_t> beams;
  const kernel::Pose2 other_T_laser = world_T_other_laser.Inverse() * world_T_laser;
  for (const auto& [begin, end] : candidates) {
    // An object narrower than the other scan's beam spacing may have fallen between its beams.
    const Eigen::Vector2d first = other_T_laser * HitPoint(scan, begin);
    const Eigen::Vector2d last = other_T_laser * HitPoint(scan, end - 1);
    const double span =
        std::abs(std::atan2(first.x() * last.y() - first.y() * last.x(), first.dot(last)));
    if (span < std::abs(other.angular_step_rad) * (1 - 1e-6)) continue;
    std::size_t through = 0;
    for (std::size_t i = begin; i < end; ++i)
      through += SeenThrough(other, other_T_laser * HitPoint(scan, i), options) == 1;
    if (2 * through > end - begin)
      for (std::size_t i = begin; i < end; ++i) beams.push_back(i);
  }
  return beams;
}

kernel::Scan WithoutBeams(const kernel::Scan& scan, const std::vector<std::size_t>& beams) {
  kernel::Scan out = scan;
  for (std::size_t i : beams) out.ranges_m[i] = std::numeric_limits<double>::quiet_NaN();
  return out;
}

}  // namespace splam::estimation
