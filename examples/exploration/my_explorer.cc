// Tutorial: write an explorer of your own, register it in one line, and compare it with REG on a
// built-in world.
//
// The variant is REG with one step changed: at a node it takes the longest free arc first (REG's
// FRONT_RAND draws one at random). Everything else comes from the exploration toolkit:
// exploration::Session (the robot, the localisation, the nodes and the run's record),
// steps.h (REG's CURR_INTERSECTION and DISPLACEMENT), FrontierRules (what is a frontier, what
// covers it), Retries (frontiers given up, tried again from other nodes) and
// graph::BidirectionalAStar (FIND_PATH).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "exploration/explorer.h"
#include "exploration/retries.h"
#include "exploration/session.h"
#include "exploration/steps.h"
#include "graph/bidirectional_astar.h"
#include "runtime/exploration_report.h"
#include "runtime/exploration_run.h"
#include "sim/builtin_worlds.h"

namespace {

using splam::exploration::ExplorationRun;
using splam::exploration::ExplorerOptions;
using splam::exploration::Session;
using splam::graph::Vertex;
using splam::kernel::FrontierArc;

// Step 1: the variant's own options (the shared ones, r, alpha, the caps, ... are
// ExplorerOptions). VisitFields gives them their YAML form, `--set exploration.longest.KEY=V`.
struct LongestOptions {
  // The piece driven towards is the leading part of the longest arc, at most this times the arc a
  // new LSR alpha r away covers, 2 acos(alpha / 2) (REG's piece_factor).
  double piece_factor = 1.0;

  void VisitFields(splam::kernel::FieldVisitor& v) {
    v.Field("piece_factor", &piece_factor, "piece length, times 2 acos(alpha / 2)");
  }
  splam::kernel::Status Validate() const {
    if (!(piece_factor > 0.0 && piece_factor <= 100.0))
      return splam::kernel::Status::Error("piece_factor must be in (0, 100]");
    return splam::kernel::Status::Ok();
  }
};

// The index of the longest arc of `arcs` (not empty).
std::size_t Longest(const std::vector<FrontierArc>& arcs) {
  const auto longest =
      std::max_element(arcs.begin(), arcs.end(), [](const FrontierArc& a, const FrontierArc& b) {
        return a.AngularWidth() < b.AngularWidth();
      });
  return static_cast<std::size_t>(longest - arcs.begin());
}

// Step 2: the explorer. Run() is a loop over a Session: plan (inside a PlanningTimer), drive,
// add a node, until nothing is left or a cap stops it.
class LongestFrontierFirst : public splam::exploration::Explorer {
 public:
  LongestFrontierFirst(const ExplorerOptions& options, const LongestOptions& own)
      : options_(options), own_(own) {}
  std::string name() const override { return "longest"; }

  ExplorationRun Run(splam::exploration::RobotInterface* robot,
                     splam::exploration::Localization* localization) override {
    Session session(name(), options_, robot, localization);
    splam::exploration::Retries retries;
    if (!session.Start()) return session.Finish();  // bad options: the run says why
    splam::graph::ExplorationGraph& g = session.graph();
    const Vertex start = session.AddNodeHere(-1);
    Vertex current = start;
    const double max_piece = own_.piece_factor * 2.0 * std::acos(options_.alpha / 2.0);
    while (!session.CapReached()) {
      std::optional<std::vector<Eigen::Vector2d>> path;
      FrontierArc piece;
      {
        Session::PlanningTimer timer(&session);
        // REG's CURR_INTERSECTION: overlapping LSRs remove each other's covered frontier parts
        // and are joined by safe paths.
        splam::exploration::CurrIntersection(session, &g, current);
        std::vector<FrontierArc>& arcs = g[current].frontiers;
        while (!arcs.empty() && !path) {
          // The one changed step: REG's FrontRand takes a random arc's piece.
          piece = splam::exploration::TakePiece(session, &arcs, Longest(arcs), max_piece);
          path = splam::exploration::Displacement(session, g[current], piece);
          if (!path) session.GiveUp(current, piece, "no clear leg from its node");
        }
      }
      if (path) {
        const Vertex previous = current;
        const bool reached = session.Drive(*path).reached;
        current = reached ? session.AddNodeHere(static_cast<int>(previous))
                          : session.NodeAfterFailedMove(previous);
        // What the new LSR does not cover of the piece stays a frontier of the node it left.
        if (reached) {
          for (const FrontierArc& rest :
               session.rules().UncoveredParts(g[previous].lsr, piece, {&g[current].lsr}))
            g[previous].frontiers.push_back(rest);
        } else {
          session.GiveUp(previous, piece, "the move towards it failed");
        }
        continue;
      }
      // Nothing left here: FIND_PATH to the nearest node with frontiers; when no node has one, a
      // frontier given up but still open is retried from another node (Retries), and at the end
      // the robot returns home.
      std::vector<Vertex> pending;
      for (Vertex v = 0; v < g.num_nodes(); ++v)
        if (!g[v].frontiers.empty()) pending.push_back(v);
      if (pending.empty()) {
        std::optional<splam::exploration::Retry> retry;
        {
          Session::PlanningTimer timer(&session);
          retry = retries.Next(session);
        }
        if (retry) {
          current = splam::exploration::DriveRetry(&session, current, *retry);
          continue;
        }
      }
      const auto route = splam::graph::BidirectionalAStar(
          g, current, pending.empty() ? std::vector<Vertex>{start} : pending);
      if (pending.empty() || !route) {
        if (route && route->vertices.size() > 1) session.Drive(g.Waypoints(route->vertices));
        return session.Finish(splam::exploration::Termination::kExplored,
                              pending.empty() ? "no frontier left; returned to the start"
                                              : "the nodes with frontiers are unreachable");
      }
      current = session.Drive(g.Waypoints(route->vertices)).reached
                    ? route->vertices.back()
                    : session.NodeAfterFailedMove(current);
    }
    return session.Finish();  // a cap: the run says which
  }

 private:
  ExplorerOptions options_;
  LongestOptions own_;
};

// Step 3: the one registration line. From here on `longest` is an explorer like SRT and REG:
// RunExploration, the sweeps and, in a program that calls splam::apps::Main, `splam explore
// --explorer longest` and `splam config print --explorer longest` find it by name.
const splam::exploration::ExplorerRegistration<LongestOptions> kLongest(
    "longest", "REG taking the longest frontier first (examples/exploration)",
    [](const ExplorerOptions& options, const LongestOptions& own) {
      return std::make_unique<LongestFrontierFirst>(options, own);
    });

}  // namespace

// Step 4: run it and REG in the same world with the same seed, ground truth as the localisation,
// and draw the variant's graph (argv[1], default example_exploration.png).
int main(int argc, char** argv) {
  const std::string picture = argc > 1 ? argv[1] : "example_exploration.png";
  const splam::sim::World world = *splam::sim::BuiltinWorld("office");
  int status = 0;
  for (const char* explorer : {"longest", "reg"}) {
    splam::runtime::ExploreSetup setup;
    setup.explorer = explorer;
    setup.localization = "ground-truth";  // or any registered SLAM method: the SPLAM loop
    setup.seed = 1;
    const splam::runtime::ExploreOutcome outcome = splam::runtime::RunExploration(world, setup);
    if (!outcome.error.empty()) {
      std::fprintf(stderr, "%s: %s\n", explorer, outcome.error.c_str());
      return 1;
    }
    const ExplorationRun& run = outcome.run;
    std::printf("%-8s %3zu nodes, %6.1f m, %4.0f s simulated, %5.1f %% explored: %s (%s)\n",
                explorer, run.graph.num_nodes(), run.distance_m, run.time_s,
                100.0 * outcome.coverage(),
                splam::exploration::TerminationName(run.termination).c_str(), run.message.c_str());
    if (std::string(explorer) == "longest") {
      const splam::kernel::Status error = splam::runtime::SaveExplorationPicture(
          world, outcome, splam::runtime::RunTitle(world, setup, outcome), {picture});
      if (!error.ok()) {
        std::fprintf(stderr, "%s\n", error.message().c_str());
        return 1;
      }
      std::printf("wrote %s\n", picture.c_str());
    }
    if (outcome.coverage() < 0.9) status = 1;  // the tutorial is also a test
  }
  return status;
}
