// libFuzzer harness: the CARMEN reader on arbitrary text (tests/fuzz/README.md).
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/carmen.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  splam::io::ParseCarmenLog(text, "fuzz.clf");
  splam::io::CarmenReadOptions skipping;
  skipping.skip_malformed_lines = true;
  const splam::io::CarmenReadResult read = splam::io::ParseCarmenLog(text, "fuzz.clf", skipping);
  // What was read writes and reads back.
  if (read.log.ok()) splam::io::ParseCarmenLog(splam::io::FormatCarmenLog(*read.log.value), "re");
  return 0;
}
