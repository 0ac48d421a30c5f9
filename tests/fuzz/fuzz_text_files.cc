// libFuzzer harness: the route, relations, trajectory and SLAM state readers on arbitrary text
// (one binary: they share io/text.cc's line reader; tests/fuzz/README.md).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/relations.h"
#include "io/simulation_log.h"
#include "io/slam_state_file.h"
#include "io/trajectory.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  splam::io::ParseRoute(text, "fuzz.route");
  splam::io::ParseRelations(text, "fuzz.relations");
  // A state read is written back to the same state: the text it formats reads back unchanged.
  if (const auto state = splam::io::ParseSlamState(text, "fuzz.state"); state.ok()) {
    const std::string formatted = splam::io::FormatSlamState(*state);
    const auto back = splam::io::ParseSlamState(formatted, "re.state");
    if (!back.ok() || splam::io::FormatSlamState(*back) != formatted) __builtin_trap();
  }
  // A trajectory read in any format is finite, and written in each format it reads back.
  const auto trajectory = splam::io::ParseTrajectory(text, "fuzz.txt");
  if (!trajectory.ok()) return 0;
  for (const splam::kernel::StampedPose& p : *trajectory)
    if (!std::isfinite(p.time_s) || !p.pose.ToVector().allFinite()) __builtin_trap();
  for (const auto format : {splam::io::TrajectoryFormat::kSplam, splam::io::TrajectoryFormat::kTum,
                            splam::io::TrajectoryFormat::kKitti}) {
    const auto back =
        splam::io::ParseTrajectory(splam::io::FormatTrajectory(*trajectory, "", format), "re");
    if (!back.ok() || back->size() != trajectory->size()) __builtin_trap();
  }
  return 0;
}
