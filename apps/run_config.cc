#include "apps/run_config.h"

namespace splam::apps {

io::ConfigRoot SlamConfigRoot(SlamConfig* config) {
  // The method's section is named after the method chosen when the root is made (a file naming
  // another method then has an unknown section).
  return [config, name = config->method](kernel::FieldVisitor& v) {
    v.Field("method", &config->method,
            "SLAM method: " + estimation::SlamRegistry::Global().NameList());
    v.Nested("local_region", "the explorers' LSR radius and step (topological SLAM's region)",
             &config->region);
    v.Nested("occupancy_grid", "the occupancy grid written from the final poses (map.pgm)",
             &config->grid);
    if (config->options) {
      v.Group(name, "options of the SLAM method",
              [&](kernel::FieldVisitor& f) { config->options->VisitFields(f); });
    }
  };
}

io::ConfigRoot ExploreConfigRoot(ExploreConfig* config, bool other_explorers) {
  // The explorer's and the method's sections are named after those chosen when the root is made.
  return [config, other_explorers, explorer = config->setup.explorer,
          name = config->setup.localization](kernel::FieldVisitor& v) {
    runtime::ExploreSetup& s = config->setup;
    v.Field("explorer", &s.explorer,
            "exploration strategy: " + exploration::ExplorerRegistry::Global().NameList());
    v.Field("localization", &s.localization,
            "where the explorer believes it is: " + runtime::LocalizationNames());
    v.Field("seed", &s.seed, "simulator noise and the explorer's draws");
    v.Field("odometry_noise_scale", &s.odometry_noise_scale,
            "times the default odometry noise, simulated and modelled (the sections below "
            "override single fields)");
    v.Nested("local_region", "LSR radius r and step alpha r, shared by explorer and SLAM",
             &s.region);
    v.Group("exploration", "the options every explorer shares, and the explorer's own",
            [&](kernel::FieldVisitor& f) {
              s.options.VisitFields(f);
              if (config->explorer_options) {
                f.Group(explorer, "options of the explorer",
                        [&](kernel::FieldVisitor& e) { config->explorer_options->VisitFields(e); });
              }
              const auto& registry = exploration::ExplorerRegistry::Global();
              for (const std::string& other : registry.Names()) {
                if (!other_explorers || other == explorer) continue;
                std::unique_ptr<kernel::AnyOptions> unused =
                    registry.Find(other)->default_options();
                f.Group(other, "", [&](kernel::FieldVisitor& e) { unused->VisitFields(e); });
              }
            });
    v.Nested("simulator", "the simulated robot and its sensors", &config->simulator);
    if (config->slam_options) {
      v.Group(name, "options of the SLAM method",
              [&](kernel::FieldVisitor& f) { config->slam_options->VisitFields(f); });
    }
  };
}

void ResetExploreDefaults(ExploreConfig* config) {
  const exploration::ExplorerInfo* explorer =
      exploration::ExplorerRegistry::Global().Find(config->setup.explorer);
  config->explorer_options = explorer != nullptr ? explorer->default_options() : nullptr;
  config->simulator = runtime::DefaultSimulator(config->setup);
  config->slam_options = runtime::DefaultSlamOptions(config->setup);
}

kernel::Status ApplySets(const io::ConfigRoot& root, const std::vector<std::string>& sets) {
  for (const std::string& assignment : sets) {
    if (kernel::Status s = io::SetConfigValue(root, assignment); !s.ok()) return s;
  }
  return kernel::Status::Ok();
}

}  // namespace splam::apps
