// libFuzzer harness: the ROS 2 bag reader on arbitrary bytes, as an SQLite3 .db3 when they start
// with SQLite's header and as an MCAP file otherwise (records, chunks in zstd and lz4, CRCs, CDR
// messages; tests/fuzz/README.md). Seeds: the fixtures of tests/data/ros2, written by independent
// libraries, and bags splam wrote with the inputs of issue 70 (a one-beam scan with a NaN step,
// a NaN mounting, a newline in a topic name, a topic nobody reads, a view for a table).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>
#include <string_view>

#include "io/ros_bag.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const bool sqlite = bytes.starts_with(std::string_view("SQLite format 3\0", 16));
  static const std::string stem = "/tmp/splam_fuzz_" + std::to_string(getpid());
  const std::string path = stem + (sqlite ? ".db3" : ".mcap");
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(size));
  splam::io::ReadRosBag(path);
  return 0;
}
