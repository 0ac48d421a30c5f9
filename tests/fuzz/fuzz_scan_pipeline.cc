// libFuzzer harness: a fuzzed scan (any geometry the readers accept, any ranges: tiny, huge,
// NaN, no return) through line and curve extraction and two steps of every SLAM method
// (tests/fuzz/README.md).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include "estimation/slam_method.h"
#include "kernel/angle.h"
#include "kernel/lines.h"
#include "kernel/spline_extraction.h"

namespace {

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
  bool empty() const { return next_ >= size_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_, next_ = 0;
};

splam::kernel::Scan FuzzedScan(Bytes* in) {
  splam::kernel::Scan scan;
  const int n = 2 + in->U16() % 1080;
  // Steps from 0.001 rad up to a full turn over the beams.
  scan.angular_step_rad = (1 + in->U16()) / 65536.0 * 2.0 * splam::kernel::kPi / (n - 1);
  scan.start_angle_rad = (in->U16() / 65535.0 - 0.5) * 2.0 * splam::kernel::kPi;
  scan.max_range_m = 0.5 + in->U16() / 65535.0 * 80.0;
  for (int i = 0; i < n; ++i) {
    const std::uint16_t r = in->U16();
    scan.ranges_m.push_back(r == 0       ? std::numeric_limits<double>::quiet_NaN()
                            : r == 65535 ? splam::kernel::Scan::kNoReturn
                            : r >= 65000 ? (r - 64999) * 150.0  // up to 10 km
                                         : r / 1000.0);
  }
  return scan;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes in(data, size);
  const splam::kernel::Scan first = FuzzedScan(&in);
  const splam::kernel::Scan second = FuzzedScan(&in);
  splam::kernel::ExtractLines(first);
  splam::kernel::ExtractCurves(first);
  const auto& registry = splam::estimation::SlamRegistry::Global();
  for (const std::string& name : registry.Names()) {
    auto method = registry.Make(name, nullptr, {splam::kernel::Pose2(), {}});
    if (!method.ok()) continue;
    (*method.value)->Update(first, splam::kernel::Pose2());
    (*method.value)->Predict(splam::kernel::Pose2(0.05, 0.0, 0.01));
    (*method.value)->Update(second, splam::kernel::Pose2());
    (*method.value)->Finish();
  }
  return 0;
}
