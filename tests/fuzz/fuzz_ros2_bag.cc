// libFuzzer harness: the ROS 2 bag reader on arbitrary bytes as an MCAP file (records, chunks
// in zstd and lz4, CRCs, CDR messages; tests/fuzz/README.md). Seeds: the fixtures of
// tests/data/ros2, written by independent libraries.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

#include "io/ros_bag.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/splam_fuzz_" + std::to_string(getpid()) + ".mcap";
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  splam::io::ReadRosBag(path);
  return 0;
}
