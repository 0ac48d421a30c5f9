#ifndef SPLAM_EXPLORATION_SRT_H_
#define SPLAM_EXPLORATION_SRT_H_

#include "exploration/explorer.h"

namespace splam::exploration {

// Sensor-based Random Tree (Oriolo et al. 2004; paper 003 §2.1, Figs 1-2; SPEC §9). At the
// current node: RANDOM_DIR draws directions uniformly over the node's free arcs; the candidate
// lies alpha * r along it (the LSR radius in a free direction is r); VALID_CONF accepts it when
// it lies outside the LSRs of all other nodes and the straight leg to it is clear for the
// robot's disc. After srt_max_attempts rejected draws, or with no free arc, the robot backtracks
// to the parent along the tree edge. The run ends back at the root with nothing left.
class SrtExplorer : public Explorer {
 public:
  explicit SrtExplorer(const ExplorerOptions& options) : options_(options) {}
  std::string name() const override { return "srt"; }
  ExplorationRun Run(RobotInterface* robot, Localization* localization) override;

 private:
  ExplorerOptions options_;
};

}  // namespace splam::exploration

#endif  // SPLAM_EXPLORATION_SRT_H_
