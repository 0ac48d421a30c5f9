// libFuzzer harness: the ROS bag reader on arbitrary bytes (tests/fuzz/README.md).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

#include "io/ros_bag.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/splam_fuzz_" + std::to_string(getpid()) + ".bag";
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  splam::io::ReadRosBag(path);
  return 0;
}
