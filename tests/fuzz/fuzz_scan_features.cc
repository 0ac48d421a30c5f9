// libFuzzer harness: a fuzzed scan through line and curve extraction (tests/fuzz/README.md).
#include <cstddef>
#include <cstdint>

#include "kernel/lines.h"
#include "kernel/spline_extraction.h"
#include "tests/fuzz/fuzzed_scan.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  splam::fuzz::Bytes in(data, size);
  const splam::kernel::Scan scan = splam::fuzz::FuzzedScan(&in);
  splam::kernel::ExtractLines(scan);
  splam::kernel::ExtractCurves(scan);
  return 0;
}
