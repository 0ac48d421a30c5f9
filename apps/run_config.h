#ifndef SPLAM_APPS_RUN_CONFIG_H_
#define SPLAM_APPS_RUN_CONFIG_H_

#include <memory>
#include <string>
#include <vector>

#include "estimation/occupancy_grid.h"
#include "estimation/slam_method.h"
#include "io/config.h"
#include "kernel/local_safe_region.h"
#include "kernel/status.h"
#include "runtime/exploration_run.h"

// The configuration documents of `splam slam` and `splam explore` (and `splam config print`):
// which keys they hold, in one place, so that printing, reading, --set and the run's own
// config.yaml agree.
namespace splam::apps {

// `splam slam`: method, local_region (the topological SLAM's region), occupancy_grid and the
// method's options under its name.
struct SlamConfig {
  std::string method = "graph";  // the method the README recommends
  kernel::LocalRegionOptions region;
  estimation::OccupancyGridOptions grid;             // map.pgm / map.yaml of the final poses
  std::unique_ptr<estimation::SlamOptions> options;  // the method's
};
io::ConfigRoot SlamConfigRoot(SlamConfig* config);

// `splam explore`: explorer, localization, seed, odometry_noise_scale, local_region,
// exploration (the options every explorer shares, and the explorer's own under its name),
// simulator, and the SLAM method's options under its name when the localisation is one.
struct ExploreConfig {
  runtime::ExploreSetup setup;
  std::unique_ptr<kernel::AnyOptions> explorer_options;  // the explorer's own
  sim::SimulatorOptions simulator;
  std::unique_ptr<estimation::SlamOptions> slam_options;
};
// With `other_explorers`, the sections of the other registered explorers are read too (into
// their defaults) and not used: a file written for one explorer serves a run of another chosen by
// --explorer, and a key misspelt in any of them is still an error.
io::ConfigRoot ExploreConfigRoot(ExploreConfig* config, bool other_explorers = false);
// The explorer's, simulator's and SLAM method's defaults of config->setup (after explorer,
// localization, seed and odometry_noise_scale are known).
void ResetExploreDefaults(ExploreConfig* config);

// Applies each "key=value" of `sets` (--set) in order; the first problem names the key.
kernel::Status ApplySets(const io::ConfigRoot& root, const std::vector<std::string>& sets);

}  // namespace splam::apps

#endif  // SPLAM_APPS_RUN_CONFIG_H_
