#ifndef SPLAM_ESTIMATION_EXPLORATION_NODES_H_
#define SPLAM_ESTIMATION_EXPLORATION_NODES_H_

#include "estimation/slam_method.h"
#include "kernel/exploration_nodes.h"

namespace splam::estimation {

// A SLAM method that takes part in exploration derives from SlamMethod and from
// kernel::ExplorationNodes (AtNode, NodePoses, RevisitInformation); the explorer's localisation
// finds it with NodesOf, and methods without it never hear of the nodes.
using ExplorationNodes = kernel::ExplorationNodes;

// The method's part in exploration, or null when it takes none.
inline ExplorationNodes* NodesOf(SlamMethod& method) {
  return dynamic_cast<ExplorationNodes*>(&method);
}
inline const ExplorationNodes* NodesOf(const SlamMethod& method) {
  return dynamic_cast<const ExplorationNodes*>(&method);
}

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_EXPLORATION_NODES_H_
