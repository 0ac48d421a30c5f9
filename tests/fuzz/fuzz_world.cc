// libFuzzer harness: the world YAML reader, then the world's validity check and a ray cast
// (tests/fuzz/README.md).
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/world_file.h"
#include "sim/ray_caster.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  // base_directory: a floor_plan entry may name an image; none exists there.
  const auto world = splam::io::ParseWorld(text, "fuzz.yaml", "/nonexistent");
  if (!world.ok() || !world.value->Validate().ok()) return 0;
  const splam::sim::RayCaster caster(*world.value);
  caster.Cast({Eigen::Vector2d(0.1, 0.2), Eigen::Vector2d(1.0, 0.5).normalized()}, 100.0);
  return 0;
}
