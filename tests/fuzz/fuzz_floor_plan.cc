// libFuzzer harness: the floor-plan image reader on arbitrary bytes (a PNG, PGM, BMP or JPEG as
// OpenCV decodes it; tests/fuzz/README.md).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

#include "io/floor_plan.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The reader takes a path: the input goes to a file of this process.
  static const std::string path = "/tmp/splam_fuzz_floor_plan_" + std::to_string(getpid());
  for (const char* extension : {".png", ".pgm"}) {
    std::ofstream(path + extension, std::ios::binary)
        .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    splam::io::ReadFloorPlan(path + extension, splam::io::FloorPlanOptions());
  }
  return 0;
}
