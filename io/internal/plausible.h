#ifndef SPLAM_IO_INTERNAL_PLAUSIBLE_H_
#define SPLAM_IO_INTERNAL_PLAUSIBLE_H_

#include <cstddef>
#include <string>

#include "kernel/pose2.h"
#include "kernel/scan.h"
#include "kernel/status.h"

// What the readers accept as a robot's: beyond these a value is not physical (coordinates of
// 1000 km, headings of 1600 turns, ranges of 10 km) and larger ones overflowed the map's
// arithmetic (a DXF export crashed at 1e238).
namespace splam::io::internal {

using kernel::kMaxCoordinateM;
inline constexpr double kMaxHeadingRad = 1e4;
inline constexpr double kMaxRangeM = 1e4;
// The finest angular step between beams a log may state (the finest 2-D lasers: 0.0625 deg,
// 1.1e-3 rad); a step of 1e-30 rad put every beam of a scan at one bearing.
inline constexpr double kMinAngularStepRad = 1e-4;
// The most beams a scan may hold: a full turn at 0.018 deg (the densest 2-D lasers give 3,600 a
// turn); one scan of 200,000 beams took 30-60 s through a SLAM step.
inline constexpr std::size_t kMaxBeams = 20000;

// Ok when the beams' geometry is plausible: at least one beam, a maximum range in (0, 10 km]
// above a minimum range of 0 or more, a start angle in [-2 pi, 2 pi], a finite step (positive
// with two beams or more, at least 0 with one) and beams
// within one turn (an angular resolution written in
// degrees, 0.36 for 0.36 deg, wrapped the scan 360 times and made the curve fits run out of
// memory); else what is wrong.
kernel::Status ScanGeometryProblem(const kernel::Scan& scan);
// Ok when the pose's coordinates and heading are finite and within the bounds above.
kernel::Status PoseProblem(const kernel::Pose2& pose, const std::string& what);

}  // namespace splam::io::internal

#endif  // SPLAM_IO_INTERNAL_PLAUSIBLE_H_
