#ifndef SPLAM_ESTIMATION_POSE_GRAPH_SCAN_VIEW_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_SCAN_VIEW_H_

#include <Eigen/Core>
#include <vector>

#include "kernel/pose2.h"
#include "kernel/scan.h"

namespace splam::estimation {

// The scan's view (robot frame): from the sensor to every beam's end, a hit seen_margin_m behind
// it so that points just behind a wall count, a no-return (clipped beams included) seen_margin_m
// short of `range` (the laser's or max_range_m, whichever is shorter): the view's edge is
// rasterised to whole cells, and a wall just beyond the range, seen by the next scan, must not
// land in cells the map calls seen and empty, where its points would be pulled towards the
// nearest known outline. Between two neighbouring beams the view reaches only the shorter one's
// end (a step on the longer beam), not the chord between their ends: a beam sees along its
// ray, and the chord between two hits on a wall at grazing incidence, metres apart, runs along
// the wall itself. A scan that saw that part of the wall was held where its points met the
// last outline piece the submap had there, by the pull of points on "seen free" wall (a 60 m
// corridor with 1 deg beams clipped at 30 m: the front end stopped for metres at each
// opening).
// Without `no_returns`, the view of the beams that returned: a no-return ends at the sensor.
// What a no-return crossed is less sure to be free than what a returning beam crossed (glass,
// a dark or grazing surface returns nothing too).
std::vector<Eigen::Vector2d> ScanView(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser,
                                      double range, double seen_margin_m, bool no_returns = true);

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_SCAN_VIEW_H_
