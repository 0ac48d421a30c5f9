// libFuzzer harness: two fuzzed scans through two steps of every SLAM method
// (tests/fuzz/README.md).
#include <cstddef>
#include <cstdint>
#include <string>

#include "estimation/slam_method.h"
#include "tests/fuzz/fuzzed_scan.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  splam::fuzz::Bytes in(data, size);
  const splam::kernel::Scan first = splam::fuzz::FuzzedScan(&in);
  const splam::kernel::Scan second = splam::fuzz::FuzzedScan(&in);
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
