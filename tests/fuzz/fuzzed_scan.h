#ifndef SPLAM_TESTS_FUZZ_FUZZED_SCAN_H_
#define SPLAM_TESTS_FUZZ_FUZZED_SCAN_H_

#include <cstddef>
#include <cstdint>
#include <limits>

#include "kernel/angle.h"
#include "kernel/scan.h"

// A scan from fuzzer bytes: any geometry the readers accept (up to 1081 beams within one turn,
// a maximum range up to 80 m) and any ranges (millimetres to 10 km, NaN, no return).
namespace splam::fuzz {

// Reads the input as a stream of little pieces; zeros when it runs out.
class Bytes {
 public:
  Bytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint16_t U16() {
    std::uint16_t v = 0;
    for (int i = 0; i < 2; ++i) v = static_cast<std::uint16_t>(v << 8 | Byte());
    return v;
  }
  std::uint8_t Byte() { return next_ < size_ ? data_[next_++] : 0; }

 private:
  const std::uint8_t* data_;
  std::size_t size_, next_ = 0;
};

inline kernel::Scan FuzzedScan(Bytes* in) {
  kernel::Scan scan;
  const int n = 2 + in->U16() % 1080;
  // Steps from 0.001 rad up to a full turn over the beams.
  scan.angular_step_rad = (1 + in->U16()) / 65536.0 * 2.0 * kernel::kPi / (n - 1);
  scan.start_angle_rad = (in->U16() / 65535.0 - 0.5) * 2.0 * kernel::kPi;
  scan.max_range_m = 0.5 + in->U16() / 65535.0 * 80.0;
  for (int i = 0; i < n; ++i) {
    const std::uint16_t r = in->U16();
    scan.ranges_m.push_back(r == 0       ? std::numeric_limits<double>::quiet_NaN()
                            : r == 65535 ? kernel::Scan::kNoReturn
                            : r >= 65000 ? (r - 64999) * 150.0  // up to 10 km
                                         : r / 1000.0);
  }
  return scan;
}

}  // namespace splam::fuzz

#endif  // SPLAM_TESTS_FUZZ_FUZZED_SCAN_H_
