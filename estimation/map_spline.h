#ifndef SPLAM_ESTIMATION_MAP_SPLINE_H_
#define SPLAM_ESTIMATION_MAP_SPLINE_H_

#include "kernel/bspline.h"

namespace splam::estimation {

// One map spline as it is drawn and evaluated.
struct MapSpline {
  int id = 0;
  kernel::CubicBSpline spline;  // world frame
  int observations = 0;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_MAP_SPLINE_H_
