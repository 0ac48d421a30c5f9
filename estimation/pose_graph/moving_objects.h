#ifndef SPLAM_ESTIMATION_POSE_GRAPH_MOVING_OBJECTS_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_MOVING_OBJECTS_H_

#include <cstddef>
#include <vector>

#include "kernel/pose2.h"
#include "kernel/scan.h"
#include "kernel/status.h"

namespace splam::kernel {
class FieldVisitor;
}

namespace splam::estimation {

// Moving objects (people walking, a door swinging) told apart from the static world by two scans
// of the same place: an object is moving when the other scan's beams passed through where this
// scan saw it. Only small objects in front of what lies on both sides of them are candidates
// (ForegroundObjects): a person, a chair's leg, a column; never a wall, whose far end a slightly
// wrong pose would put in the other scan's free space.
struct MovingObjectOptions {
  // false: no scan point is ever taken for a moving object.
  bool enabled = true;
  // A candidate: hits whose neighbours in beam order lie within max_gap_m of each other, at most
  // max_size_m from end to end (a person, or the two legs of one, at a laser's height), the beams
  // on both sides farther by more than max_gap_m, without a return, or past the field of view.
  double max_size_m = 1.0;
  double max_gap_m = 0.3;
  // A point is seen through when every beam of the other scan within the bearing of
  // lateral_tolerance_m around it (at least the beams either side of it) reached at least
  // min_displacement_m beyond it; an object moves when more than half of its points are. The
  // tolerances absorb the error of the relative pose of the two scans (a few centimetres, a few
  // tenths of a degree): a static object whose edge the other scan's beams graze is not moving.
  double min_displacement_m = 0.3;
  double lateral_tolerance_m = 0.1;

  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// Beam index ranges [begin, end) of a scan's candidates, in beam order.
using BeamRanges = std::vector<std::pair<std::size_t, std::size_t>>;
// The candidates of `scan` (see MovingObjectOptions).
BeamRanges ForegroundObjects(const kernel::Scan& scan, const MovingObjectOptions& options);

// The beams of `scan` (taken from world_T_laser) in candidates that `other` (taken from
// world_T_other_laser) saw through: the object was not there when `other` was taken. A candidate
// that `other` sees under less than its beam spacing (hit by one beam: a chair's leg, a thin
// column) is never moving: the other scan's beams may have passed either side of it.
std::vector<std::size_t> SeenThroughBeams(const kernel::Scan& scan,
                                          const kernel::Pose2& world_T_laser,
                                          const kernel::Scan& other,
                                          const kernel::Pose2& world_T_other_laser,
                                          const MovingObjectOptions& options);
// As above, with the candidates of `scan` already found (ForegroundObjects).
std::vector<std::size_t> SeenThroughBeams(const kernel::Scan& scan, const BeamRanges& candidates,
                                          const kernel::Pose2& world_T_laser,
                                          const kernel::Scan& other,
                                          const kernel::Pose2& world_T_other_laser,
                                          const MovingObjectOptions& options);

// A copy of `scan` whose `beams` read NaN (no information).
kernel::Scan WithoutBeams(const kernel::Scan& scan, const std::vector<std::size_t>& beams);

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_MOVING_OBJECTS_H_
