// libFuzzer harness: the route, relations and trajectory readers on arbitrary text (one binary:
// they share io/text.cc's line reader; tests/fuzz/README.md).
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/relations.h"
#include "io/simulation_log.h"
#include "io/trajectory.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  splam::io::ParseRoute(text, "fuzz.route");
  splam::io::ParseRelations(text, "fuzz.relations");
  const auto trajectory = splam::io::ParseTrajectory(text, "fuzz.txt");
  if (trajectory.ok())
    splam::io::ParseTrajectory(splam::io::FormatTrajectory(*trajectory.value), "re");
  return 0;
}
