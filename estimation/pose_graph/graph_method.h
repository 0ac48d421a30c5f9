#ifndef SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_METHOD_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_METHOD_H_

#include "estimation/slam_method.h"
#include "kernel/registry.h"

namespace splam::estimation {

class GraphSlam;

// Graph SLAM behind the SlamMethod interface, as the registry's built-in "graph".
void AddGraphSlamMethod(kernel::Registry<SlamMethodInfo>* registry);

// For a method with a GraphSlam back end (topological-graph too): its keyframes, loop edges
// and loop searches as layers of *map, and its loop-closure counters, times and
// optimisations appended to *s.
void AddGraphLayers(const GraphSlam& graph, SlamMap* map);
void AddGraphStatistics(const GraphSlam& graph, SlamStatistics* s);

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_METHOD_H_
