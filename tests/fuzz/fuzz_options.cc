// libFuzzer harness: option YAML (ConfigFile) read into the explorer's and every SLAM method's
// options, then their validity checks (tests/fuzz/README.md).
#include <cstddef>
#include <cstdint>
#include <string>

#include "estimation/slam_method.h"
#include "exploration/explorer.h"
#include "io/config.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const auto file = splam::io::ConfigFile::Parse(text, "fuzz.yaml");
  if (!file.ok()) return 0;
  splam::exploration::ExplorerOptions explorer;
  if (file.value->Read([&](splam::kernel::FieldVisitor& v) { explorer.VisitFields(v); }, true).ok())
    static_cast<void>(explorer.Validate());
  const auto& explorers = splam::exploration::ExplorerRegistry::Global();
  for (const std::string& name : explorers.Names()) {
    auto own = explorers.Find(name)->default_options();
    if (file.value->Read([&](splam::kernel::FieldVisitor& v) { own->VisitFields(v); }, true).ok())
      static_cast<void>(own->Validate());
  }
  const auto& registry = splam::estimation::SlamRegistry::Global();
  for (const std::string& name : registry.Names()) {
    auto options = registry.Find(name)->default_options({});
    if (file.value->Read([&](splam::kernel::FieldVisitor& v) { options->VisitFields(v); }, true)
            .ok())
      static_cast<void>(options->Validate());
  }
  return 0;
}
