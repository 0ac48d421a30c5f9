#include "exploration/explorer.h"

#include <cmath>

#include "exploration/reg.h"
#include "exploration/srt.h"

namespace splam::exploration {

kernel::Status ExplorerOptions::Validate() const {
  // Every option bounded both ways: lengths by what a robot meets indoors and what the planners'
  // grids (5 cm cells over the LSR) hold, counts and caps by what a run can use.
  if (!(lsr_radius_m > 0.0 && lsr_radius_m <= 30.0))
    return kernel::Status::Error("lsr_radius_m must be in (0, 30] m");
  if (!(alpha > 0.0 && alpha < 1.0)) return kernel::Status::Error("alpha must lie in (0, 1)");
  if (!(clearance_margin_m >= 0.0 && clearance_margin_m <= 10.0))
    return kernel::Status::Error("clearance_margin_m must be in [0, 10] m");
  if (!(min_frontier_m >= 0.0 && min_frontier_m <= 100.0) ||
      !(min_doorway_arc_m >= 0.0 && min_doorway_arc_m <= 100.0))
    return kernel::Status::Error("min_frontier_m and min_doorway_arc_m must be in [0, 100] m");
  if (!(arc_sampling_rad >= 1e-4 && arc_sampling_rad <= 1.0))
    return kernel::Status::Error("arc_sampling_rad must be in [1e-4, 1] rad");
  if (!(frontier_view_depth_m >= 0.0 && frontier_view_depth_m <= 100.0) ||
      !(shadow_edge_m > 0.0 && shadow_edge_m <= 100.0))
    return kernel::Status::Error(
        "frontier_view_depth_m must be in [0, 100] m and shadow_edge_m in (0, 100] m");
  if (retry_nodes < 0 || retry_nodes > 10000)
    return kernel::Status::Error("retry_nodes must be in [0, 10000]");
  if (max_nodes < 1 || max_nodes > 1000000)
    return kernel::Status::Error("max_nodes must be in [1, 1000000]");
  if (!(max_time_s > 0.0 && max_time_s <= 1e7))
    return kernel::Status::Error("max_time_s must be in (0, 1e7] s");
  if (max_failed_moves < 1 || max_failed_moves > 1000000)
    return kernel::Status::Error("max_failed_moves must be in [1, 1000000]");
  if (const kernel::Status problem = motion.Validate(); !problem.ok())
    return problem.Prefixed("motion");
  if (const kernel::Status problem = active_loop_closing.Validate(); !problem.ok())
    return problem.Prefixed("active_loop_closing");
  return kernel::Status::Ok();
}

std::string TerminationName(Termination termination) {
  switch (termination) {
    case Termination::kExplored:
      return "explored";
    case Termination::kIncomplete:
      return "incomplete";
    case Termination::kNodeLimit:
      return "node_limit";
    case Termination::kTimeLimit:
      return "time_limit";
    case Termination::kStuck:
      return "stuck";
    case Termination::kInterrupted:
      return "interrupted";
    case Termination::kInvalidInput:
      return "invalid_input";
  }
  return "unknown";
}

namespace {

void AddBuiltinExplorers(kernel::Registry<ExplorerInfo>* registry) {
  registry->Add(MakeExplorerInfo<SrtOptions>("srt", "Sensor-based Random Tree (Oriolo et al. 2004)",
                                             [](const ExplorerOptions& o, const SrtOptions& srt) {
                                               return std::make_unique<SrtExplorer>(o, srt);
                                             }));
  registry->Add(MakeExplorerInfo<RegOptions>("reg", "Random Exploration Graph (paper 003 §3.1)",
                                             [](const ExplorerOptions& o, const RegOptions& reg) {
                                               return std::make_unique<RegExplorer>(o, reg);
                                             }));
}

}  // namespace

ExplorerRegistry& ExplorerRegistry::Global() {
  static ExplorerRegistry registry(AddBuiltinExplorers);
  return registry;
}

kernel::Result<std::unique_ptr<Explorer>> ExplorerRegistry::Make(
    const std::string& name, const ExplorerOptions& options, const kernel::AnyOptions* own) const {
  using R = kernel::Result<std::unique_ptr<Explorer>>;
  const ExplorerInfo* info = Find(name);
  if (info == nullptr) return R::Fail("unknown explorer '" + name + "' (" + NameList() + ")");
  if (kernel::Status s = kernel::FiniteFields(options); !s.ok())
    return R::Fail(s.Prefixed("invalid explorer options"));
  if (kernel::Status s = options.Validate(); !s.ok())
    return R::Fail(s.Prefixed("invalid explorer options"));
  std::unique_ptr<kernel::AnyOptions> defaults;
  if (own == nullptr) {
    defaults = info->default_options();
    own = defaults.get();
  }
  if (kernel::Status s = own->Validate(); !s.ok())
    return R::Fail(s.Prefixed("invalid " + name + " options"));
  std::unique_ptr<Explorer> explorer = info->make(options, *own);
  if (!explorer) return R::Fail("the options given are not " + name + "'s");
  return R::Ok(std::move(explorer));
}

void RegisterExplorer(std::string name, std::string description,
                      std::function<std::unique_ptr<Explorer>(const ExplorerOptions&)> make) {
  RegisterExplorer<kernel::NoOptions>(
      std::move(name), std::move(description),
      [make = std::move(make)](const ExplorerOptions& o, const kernel::NoOptions&) {
        return make(o);
      });
}

void ExplorerOptions::VisitFields(kernel::FieldVisitor& v) {
  // lsr_radius_m and alpha are shared with the topological SLAM's local region: they are read
  // and written once, in the local_region section.
  v.Field("clearance_margin_m", &clearance_margin_m,
          "legs keep radius + this from the LSR edge, m");
  v.Field("min_frontier_m", &min_frontier_m, "shorter free arcs are not frontiers, m");
  v.Field("arc_sampling_rad", &arc_sampling_rad, "spacing of classified arc points, rad");
  v.Field("frontier_view_depth_m", &frontier_view_depth_m,
          "another LSR covers a frontier point only if it saw this far beyond it (0: inside "
          "suffices, as published), m");
  v.Field("shadow_edge_m", &shadow_edge_m,
          "LSR boundary edges longer than this with a depth jump are shadows, not obstacles, m");
  v.Field("frontiers_carry_on", &frontiers_carry_on,
          "a ray leaving another LSR across its free arc is seen only where that arc is a "
          "frontier (min_frontier_m long outside the owner's circle)");
  v.Field("shadow_frontiers", &shadow_frontiers,
          "the space hidden behind an occluder is a frontier too (false: free arcs only)");
  v.Field("grid_paths", &grid_paths,
          "paths inside an LSR searched on a 5 cm grid (false: two legs through a polar grid)");
  v.Field("exact_escapes", &exact_escapes,
          "a robot closer to the LSR edge than it needs leaves by an exactly checked straight "
          "leg when the grid's way out fails");
  v.Field("doorway_goals", &doorway_goals,
          "a free arc seen only through a door at a slant is approached on the door's axis, "
          "facing through it");
  v.Field("min_doorway_arc_m", &min_doorway_arc_m,
          "doorway_goals keeps a short arc seen through a door only from this length (one or two "
          "stray beams are none), m");
  v.Field("retry_nodes", &retry_nodes,
          "open given-up frontiers are retried from up to this many other nodes (0: as published)");
  v.Field("face_frontiers", &face_frontiers,
          "after an approach the robot turns to face the frontier before sensing");
  v.Field("unseen_frontiers", &unseen_frontiers,
          "LSR boundary bounded by the sonars only, with nothing seen beyond by a laser, is a "
          "frontier to look at (false: it counts as seen)");
  v.Field("max_nodes", &max_nodes, "cap on graph nodes");
  v.Field("max_time_s", &max_time_s, "cap on simulated exploration time, s");
  v.Field("max_failed_moves", &max_failed_moves, "cap on failed moves in a row");
  v.Field("seed", &seed, "RANDOM_DIR / FRONT_RAND draws");
  v.Nested("motion", "MOVE_TO with BEST_U", &motion);
  v.Nested("active_loop_closing", "revisits that close loops when the pose grows uncertain",
           &active_loop_closing);
}

}  // namespace splam::exploration
