#ifndef SPLAM_KERNEL_RANDOM_H_
#define SPLAM_KERNEL_RANDOM_H_

#include <cstdint>
#include <random>

namespace splam::kernel {

// The only source of randomness in splam: an explicitly seeded generator whose draws are the
// same on every platform and standard library (std::*_distribution are not), so that the same
// seed gives the same run byte for byte.
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}

  // Uniform in [0, 1), 53 random bits.
  double Uniform();
  // Uniform in [lo, hi).
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  // Normal with mean 0 and the given standard deviation (Marsaglia's polar method).
  double Gaussian(double stddev);
  // Uniform integer in [0, n), n > 0.
  std::uint64_t Index(std::uint64_t n);

 private:
  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_RANDOM_H_
