#include "kernel/angle.h"

#include <cmath>

namespace splam::kernel {

double WrapAngle(double angle_rad) {
  if (angle_rad > -kPi && angle_rad <= kPi) return angle_rad;
  // std::remainder gives a result in [-pi, pi]; map -pi to +pi for the half-open range.
  double wrapped = std::remainder(angle_rad, 2.0 * kPi);
  if (wrapped <= -kPi) wrapped += 2.0 * kPi;
  return wrapped;
}

}  // namespace splam::kernel
