#include "kernel/random.h"

#include <cassert>
#include <cmath>

namespace splam::kernel {

double Random::Uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

double Random::Gaussian(double stddev) {
  if (has_spare_) {
    has_spare_ = false;
    return stddev * spare_;
  }
  double u = 0.0, v = 0.0, s = 0.0;
  do {
    u = 2.0 * Uniform() - 1.0;
    v = 2.0 * Uniform() - 1.0;
    s = u * u + v * v;
  } while (s >= 1.0 || s == 0.0);
  const double factor = std::sqrt(-2.0 * std::log(s) / s);
  spare_ = v * factor;
  has_spare_ = true;
  return stddev * u * factor;
}

std::uint64_t Random::Index(std::uint64_t n) {
  assert(n > 0);
  // Rejection sampling removes the modulo bias.
  const std::uint64_t limit = UINT64_MAX - UINT64_MAX % n;
  std::uint64_t draw = 0;
  do {
    draw = engine_();
  } while (draw >= limit);
  return draw % n;
}

}  // namespace splam::kernel
