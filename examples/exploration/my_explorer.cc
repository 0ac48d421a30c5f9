// Tutorial: an explorer of your own as one override of REG's steps, registered in one line and
// compared with REG on a built-in world. REG's run loop asks its steps which frontier next
// (NextPiece), where to step (StepTowards) and where to go when a node has nothing left
// (NextNode); this variant changes the first: it takes the frontier nearest the robot's heading
// (the least turn) where REG draws one at random (FRONT_RAND).
// Usage: example_exploration [PICTURE.png]
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "exploration/reg.h"
#include "exploration/session.h"
#include "exploration/steps.h"
#include "kernel/angle.h"
#include "runtime/exploration_report.h"
#include "runtime/exploration_run.h"
#include "sim/builtin_worlds.h"

namespace {

using splam::kernel::FrontierArc;

class NearestFrontierFirst : public splam::exploration::RegExplorer {
 public:
  using RegExplorer::RegExplorer;
  std::string name() const override { return "nearest"; }
  FrontierArc NextPiece(splam::exploration::Session& session, splam::graph::Vertex node,
                        std::vector<FrontierArc>* frontiers, double max_piece_rad) override {
    const double heading = session.graph()[node].configuration.theta();
    std::size_t nearest = 0;
    double least = 10.0;
    for (std::size_t k = 0; k < frontiers->size(); ++k) {
      const FrontierArc& arc = (*frontiers)[k];
      const double mid = 0.5 * (arc.start_angle_rad + arc.end_angle_rad);
      const double turn = std::abs(splam::kernel::WrapAngle(mid - heading));
      if (turn < least) least = turn, nearest = k;
    }
    return splam::exploration::TakePiece(session, frontiers, nearest, max_piece_rad);
  }
};

// The one registration line: REG's options (its YAML section), this explorer's name.
const splam::exploration::ExplorerRegistration<splam::exploration::RegOptions> kNearest(
    "nearest", "REG taking first the frontier nearest the robot's heading (examples/exploration)",
    [](const splam::exploration::ExplorerOptions& options,
       const splam::exploration::RegOptions& reg) {
      return std::make_unique<NearestFrontierFirst>(options, reg);
    });

}  // namespace

// Both explorers in `office`, seed 1, localised by the truth; the variant's graph is drawn.
int main(int argc, char** argv) {
  const splam::sim::World world = *splam::sim::BuiltinWorld("office");
  int status = 0;
  for (const char* explorer : {"nearest", "reg"}) {
    splam::runtime::ExploreSetup setup;
    setup.explorer = explorer;
    setup.localization = "ground-truth";  // or any registered SLAM method: the SPLAM loop
    setup.seed = 1;
    const splam::runtime::ExploreOutcome outcome = splam::runtime::RunExploration(world, setup);
    if (!outcome.error.empty()) return std::fprintf(stderr, "%s\n", outcome.error.c_str()), 1;
    std::printf("%-8s %3zu nodes, %6.1f m, %4.0f s simulated, %5.1f %% explored: %s\n", explorer,
                outcome.run.graph.num_nodes(), outcome.run.distance_m, outcome.run.time_s,
                100.0 * outcome.coverage(),
                splam::exploration::TerminationName(outcome.run.termination).c_str());
    if (std::string(explorer) == "nearest" &&
        !splam::runtime::SaveExplorationPicture(world, outcome,
                                                splam::runtime::RunTitle(world, setup, outcome),
                                                {argc > 1 ? argv[1] : "example_exploration.png"})
             .ok())
      return 1;
    if (outcome.coverage() < 0.9) status = 1;  // the tutorial is also a test
  }
  return status;
}
