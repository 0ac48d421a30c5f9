#ifndef SPLAM_EXPLORATION_EXPLORER_H_
#define SPLAM_EXPLORATION_EXPLORER_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "exploration/active_loop_closing.h"
#include "exploration/localization.h"
#include "exploration/motion.h"
#include "exploration/robot_interface.h"
#include "graph/exploration_graph.h"
#include "kernel/angle.h"
#include "kernel/options.h"
#include "kernel/registry.h"
#include "kernel/scan.h"
#include "kernel/status.h"

// Sensor-based exploration (SPEC §9): SRT (Oriolo et al. 2004) and REG (paper 003 §3.1).
namespace splam::exploration {

// The options every explorer shares (the LSR, the robot's clearance, the frontier rules of the
// toolkit, the caps); an explorer's own options are a struct of its own (SrtOptions, RegOptions),
// registered with it.
struct ExplorerOptions {
  double lsr_radius_m = 3.0;  // r: LSRs are clipped here (below the URG-04LX's 4 m range)
  // A new node lies alpha * r from the current one, 0 < alpha < 1, and alpha * r plus the robot's
  // radius and clearance margin must stay inside r. Paper 003 gives no value; a small alpha
  // starves SRT's VALID_CONF early (new nodes fall inside old LSRs; docs/experiments.md).
  double alpha = 0.8;
  // Every straight leg the robot drives keeps its radius plus this margin from the LSR
  // boundary (covers range noise and the obstacle parts between two beams), m.
  double clearance_margin_m = 0.05;
  // Free arcs shorter than this at radius r are not frontiers (slits between obstacles that
  // the robot cannot pass), m.
  double min_frontier_m = 0.5;
  // Spacing of the arc points classified when a frontier part lies inside another LSR, rad.
  double arc_sampling_rad = kernel::DegToRad(1.0);
  // When another LSR covers a frontier point (kernel::CoverOptions): it must have seen this far
  // beyond the point, or up to an obstacle or its own free arc, not to a shadow edge (a depth
  // jump over shadow_edge_m long, kernel::IsShadowEdge). 1 m is about two robot diameters: space a
  // robot could enter. 0: the point lying inside the other LSR is enough (Oriolo et al., paper
  // 003), and a node that looked into a room through its door at a slant then covers the
  // frontier through that door of a node that faces it, though neither saw the room
  // (docs/experiments.md, Fig. 18). m.
  double frontier_view_depth_m = 1.0;
  double shadow_edge_m = 0.2;
  // With frontier_view_depth_m, a point whose ray leaves the other LSR across that LSR's own free
  // arc counts as seen only where that arc, outside the owner's circle, is at least
  // min_frontier_m long (kernel::CoverOptions::min_free_arc_m): a shorter piece is dropped as a
  // frontier, so nothing carries on there: two nodes that each saw a door near the rims of their
  // LSRs would otherwise cover each other's arc through it, and nobody enters the room
  // (docs/experiments.md, Fig. 18). false: any free arc carries on.
  bool frontiers_carry_on = true;
  // The space an LSR's sensor could not see behind an occluder (an occlusion edge at least
  // frontier_view_depth_m long, kernel::OcclusionEdges) is a frontier too, until other LSRs see
  // beyond it (FrontierRules::ShadowCovered): REG once no free arc is left, and SRT with
  // SrtOptions::relaxed_valid_conf, move as near to it as the LSR lets them. The papers' frontiers
  // are the free arcs only: the floor behind a table, and a room whose door a node saw edge-on (an
  // arc under min_frontier_m), were never visited (docs/experiments.md, Fig. 18).
  bool shadow_frontiers = true;
  // A path inside an LSR that no straight leg gives is searched on a 5 cm grid of the LSR
  // (LsrPlanner), through as many bends as it needs; false: the shortest two-leg path
  // through a polar grid of waypoints (radii 0.4-2 m, every 10 deg), which missed narrow doors
  // seen at a slant (docs/experiments.md, Fig. 18). Neither is in the papers, whose robot drives
  // straight.
  bool grid_paths = true;
  // When the grid path from a robot standing closer to the LSR boundary than its radius plus
  // margin fails the exact clearance test (the raster's clearances are a cell off, and its first
  // cells came 2-4 mm closer than the robot stood), the robot leaves by a straight leg that the
  // exact test passed (SafePaths::Escapes) and the grid search goes on from its end: otherwise a
  // node beside the sonars' boundary has no way out (docs/experiments.md, Fig. 18). false: only
  // the grid's own way out (needs grid_paths).
  bool exact_escapes = true;
  // A free arc that a node saw only through a gap at a slant (a door: the wedge between the two
  // jambs' shadow edges is narrower than the robot near the door) is approached on the gap's axis:
  // the robot stands in front of the door's middle and faces through it
  // (SafePaths::DoorwayApproach), before the plain approach to the reachable point nearest the
  // arc, which stops beside the door and looks past it again (docs/experiments.md, Fig. 18).
  // With it, a free arc shorter than min_frontier_m seen through such a gap is a frontier
  // (FrontierRules::FrontiersOf), and stays one until another LSR covers part of it
  // (FrontierRules::UncoveredParts), not only until its node's first overlap. false: only the
  // plain approach (needs grid_paths).
  bool doorway_goals = true;
  // doorway_goals keeps a free arc shorter than min_frontier_m only when it is at least this long
  // at radius r: one or two beams free past a wall that lies at the LSR radius (range noise), at
  // the edge of the laser's field of view, or through a wall junction are no view through a door,
  // and as frontiers nobody can reach they would keep a run from ending `explored`
  // (docs/experiments.md, Fig. 18). A 0.8 m door seen from 3 m at 85 deg off its axis still spans
  // 0.07 m. m.
  double min_doorway_arc_m = 0.05;
  // A frontier given up at its node (no clear leg, no approach saw behind it) and still open in
  // the explorer's map is retried from up to this many other nodes once nothing else is left: the
  // robot drives to the node whose LSR reaches nearest to it and approaches it from there
  // (Retries; needs grid_paths). A node in a doorway perceives the corridor behind it
  // with the sonars only, whose blind spikes between the cones close the way back
  // (docs/experiments.md, Fig. 18). 0: a given-up frontier stays given up, as published.
  int retry_nodes = 2;
  // After REG's approaches and every retry (grid_paths), the robot turns in place to face the
  // frontier before it senses, when the frontier is in sight (Session::InSight): its laser
  // covers 240 deg, and the sonars that see the rest leave blind spikes between their cones
  // (0.27 m), which in a doorway can close the way through the door or back into the corridor
  // (docs/experiments.md, Fig. 18). false: the robot senses as it arrived.
  bool face_frontiers = true;
  // A stretch of an LSR's boundary that only the sonars bounded (the 120 deg behind the laser)
  // and beyond which no node's laser saw, nor a laser hit within frontier_view_depth_m, is a
  // frontier too (GivenUpFrontiers, frontier_map.h): once nothing else is left the robot looks at
  // it, turning in place at the nearest node that sees it (Retries), and the done check counts it
  // open. A sonar echo may come from anywhere in its 30 deg cone: the first echoes off a desk
  // corner can close half a room the laser never looked at (docs/experiments.md, Fig. 18).
  // false: a sonar boundary counts as a seen obstacle.
  bool unseen_frontiers = true;
  // Caps, each a stated termination reason: nodes, simulated seconds, moves in a row that fail.
  int max_nodes = 400;
  double max_time_s = 3600.0;
  int max_failed_moves = 10;
  std::uint64_t seed = 1;  // RANDOM_DIR / FRONT_RAND draws
  MotionOptions motion;
  // Revisits that close loops when the localisation grows uncertain (SRT and REG; off by default:
  // the papers' explorers look for coverage only).
  ActiveLoopClosingOptions active_loop_closing;
  // Called after every new node with the number of nodes and the simulated time (progress
  // reports); may be empty.
  std::function<void(int nodes, double time_s)> on_node;
  // Asked at every cap check; true stops the run there (Ctrl-C): termination kInterrupted, the
  // record up to then kept. May be empty.
  std::function<bool()> stop;

  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

enum class Termination {
  kExplored,      // nothing left to explore, back at the start
  kIncomplete,    // the strategy ended, but frontiers it gave up are still open in its map
  kNodeLimit,     // max_nodes reached
  kTimeLimit,     // max_time_s reached
  kStuck,         // max_failed_moves moves in a row (or SRT returns from one node) failed
  kInterrupted,   // ExplorerOptions::stop asked to stop
  kInvalidInput,  // bad options or a localisation that cannot run on this robot
};
std::string TerminationName(Termination termination);

// What the explorer knew and did at one graph node (vertex i of the graph is node i).
struct NodeRecord {
  double time_s = 0.0;            // when it was perceived
  kernel::Pose2 true_pose;        // ground truth (the estimate when the robot has none)
  kernel::Scan safe_region_scan;  // the full-circle scan that bounded the node's LSR
  int parent = -1;                // the node it was reached from, -1 for the start
  // The first laser_beams beams of safe_region_scan are the laser's; the rest the sonars'.
  std::size_t laser_beams = 0;
};

// A frontier piece the explorer gave up, as its map shows it at the end of the run.
struct GivenUpFrontier {
  int node = -1;            // the node whose frontier it was
  kernel::FrontierArc arc;  // on that node's LSR circle, world frame (free arcs)
  int shadow_edge = -1;     // >= 0: the occlusion edge of the node's LSR (shadow frontiers)
  // Not empty: a stretch of the node's LSR boundary that only its sonars saw and no node's laser
  // saw beyond (GivenUpFrontiers, frontier_map.h), world frame.
  std::vector<Eigen::Vector2d> unseen;
  Eigen::Vector2d midpoint;  // its middle, world frame
  std::string reason;        // why it was given up
  bool open = true;          // no LSR covers it at the end (CoverOptions)
};

struct ExplorationRun {
  std::string explorer;      // "srt" or "reg"
  std::string localization;  // Localization::name()
  // Nodes at their estimated configurations with LSRs and remaining frontiers; edges are the
  // driven legs (SRT: the tree) and, for REG, the safe paths through overlapping LSRs.
  graph::ExplorationGraph graph;
  std::vector<NodeRecord> nodes;
  std::vector<TraceSample> trace;  // every time step, the start first
  Termination termination = Termination::kInvalidInput;
  std::string message;      // details of the termination
  double distance_m = 0.0;  // travelled (ground truth), m
  double time_s = 0.0;      // simulated exploration time, s
  int moves = 0, failed_moves = 0, blocked_steps = 0;
  int replanned_moves = 0;        // blocked moves re-planned inside a freshly perceived LSR
  int unreachable_frontiers = 0;  // frontier pieces dropped: no clear leg towards them
  // Every frontier piece given up (REG: no clear leg towards it, the move there failed, its node
  // unreachable, a shadow no approach saw behind; SRT: the arcs and shadows of a node left after
  // its draws), checked against the union of the final LSRs.
  std::vector<GivenUpFrontier> given_up;
  double planning_wall_s = 0.0;         // wall time spent deciding (not driving or sensing), s
  std::vector<RevisitRecord> revisits;  // active loop closing's, in order
  // With active loop closing: the pose's position sigma (PositionSigma) at every decision, with
  // the simulated time, s and m.
  std::vector<std::pair<double, double>> position_sigma;
};

// An exploration strategy. Run() drives the robot until the strategy terminates or a cap stops
// it; it never throws on bad input (termination kInvalidInput with a message).
class Explorer {
 public:
  virtual ~Explorer() = default;
  virtual std::string name() const = 0;
  virtual ExplorationRun Run(RobotInterface* robot, Localization* localization) = 0;
};

struct ExplorerInfo {
  std::string name;         // "reg"
  std::string description;  // one line for --help
  // The explorer's own options with their defaults (kernel::NoOptions when it has none).
  std::function<std::unique_ptr<kernel::AnyOptions>()> default_options;
  // The explorer with the shared options and its own (as default_options gives them, possibly
  // edited); nullptr when `own` is not of the explorer's type.
  std::function<std::unique_ptr<Explorer>(const ExplorerOptions&, const kernel::AnyOptions& own)>
      make;
};

// name -> explorer: the built-in SRT and REG from the start, others with RegisterExplorer or an
// ExplorerRegistration, from anywhere (kernel::Registry). The command line, `config print`,
// RunExploration, the sweeps and the experiments look explorers up here.
class ExplorerRegistry : public kernel::Registry<ExplorerInfo> {
 public:
  explicit ExplorerRegistry(std::function<void(kernel::Registry<ExplorerInfo>*)> builtins)
      : kernel::Registry<ExplorerInfo>(std::move(builtins)) {}
  static ExplorerRegistry& Global();
  // The explorer `name` with the shared `options` and its own `own` (its defaults when null); an
  // error names an unknown explorer with the known ones, or the invalid option.
  kernel::Result<std::unique_ptr<Explorer>> Make(const std::string& name,
                                                 const ExplorerOptions& options,
                                                 const kernel::AnyOptions* own = nullptr) const;
};

// The registry entry of an explorer whose own options struct is `Own` (with VisitFields and
// Validate; kernel::NoOptions for none).
template <class Own>
ExplorerInfo MakeExplorerInfo(
    std::string name, std::string description,
    std::function<std::unique_ptr<Explorer>(const ExplorerOptions&, const Own&)> make) {
  using Typed = kernel::OptionsOf<Own>;
  return {std::move(name), std::move(description), [] { return std::make_unique<Typed>(); },
          [make](const ExplorerOptions& options,
                 const kernel::AnyOptions& own) -> std::unique_ptr<Explorer> {
            const auto* typed = dynamic_cast<const Typed*>(&own);
            return typed != nullptr ? make(options, typed->options()) : nullptr;
          }};
}

// Adds an explorer to the global registry: the one line that makes it known to `splam explore`,
// `config print`, the sweeps and RunExploration. From a function (main, a test) or, as an
// ExplorerRegistration, from a namespace-scope object of any translation unit.
template <class Own>
void RegisterExplorer(
    std::string name, std::string description,
    std::function<std::unique_ptr<Explorer>(const ExplorerOptions&, const Own&)> make) {
  ExplorerRegistry::Global().Add(
      MakeExplorerInfo<Own>(std::move(name), std::move(description), std::move(make)));
}
// The same for an explorer with no options of its own.
void RegisterExplorer(std::string name, std::string description,
                      std::function<std::unique_ptr<Explorer>(const ExplorerOptions&)> make);

// RegisterExplorer as a namespace-scope object of a translation unit of its own:
//   static const ExplorerRegistration<MyOptions> kMine("mine", "...", MakeMine);
//   static const ExplorerRegistration<> kPlain("plain", "...", MakePlain);  // no own options
// (see estimation::SlamMethodRegistration for when a static library's unit is linked).
template <class Own = kernel::NoOptions>
struct ExplorerRegistration {
  ExplorerRegistration(
      std::string name, std::string description,
      std::function<std::unique_ptr<Explorer>(const ExplorerOptions&, const Own&)> make) {
    RegisterExplorer<Own>(std::move(name), std::move(description), std::move(make));
  }
  ExplorerRegistration(std::string name, std::string description,
                       std::function<std::unique_ptr<Explorer>(const ExplorerOptions&)> make) {
    RegisterExplorer(std::move(name), std::move(description), std::move(make));
  }
};

}  // namespace splam::exploration

#endif  // SPLAM_EXPLORATION_EXPLORER_H_
