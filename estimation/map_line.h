#ifndef SPLAM_ESTIMATION_MAP_LINE_H_
#define SPLAM_ESTIMATION_MAP_LINE_H_

#include <Eigen/Core>

#include "estimation/models.h"

namespace splam::estimation {

// One line landmark of a map as it is drawn and exported (SlamMap::lines).
struct MapLine {
  Line line;                   // world frame
  Eigen::Vector2d start, end;  // extent of everything seen of it
  Eigen::Matrix2d covariance;  // of (rho, theta)
  int observations = 0;
};
// One corner landmark (SlamMap::corners).
struct MapCorner {
  Eigen::Vector2d position;
  Eigen::Matrix2d covariance;
  int observations = 0;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_MAP_LINE_H_
