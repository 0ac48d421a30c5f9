#ifndef SPLAM_KERNEL_ANGLE_H_
#define SPLAM_KERNEL_ANGLE_H_

#include <numbers>

namespace splam::kernel {

inline constexpr double kPi = std::numbers::pi;

// Wraps an angle to (-pi, pi]. Finite input gives finite output; NaN stays NaN.
double WrapAngle(double angle_rad);

inline constexpr double DegToRad(double deg) { return deg * kPi / 180.0; }
inline constexpr double RadToDeg(double rad) { return rad * 180.0 / kPi; }

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_ANGLE_H_
