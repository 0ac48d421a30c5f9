#ifndef SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_METHOD_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_METHOD_H_

#include <memory>

#include "estimation/pose_graph/graph_slam_options.h"
#include "estimation/slam_method.h"
#include "kernel/registry.h"

namespace splam::estimation {

class GraphSlam;
class ClosureAcceptance;

// Graph SLAM behind the SlamMethod interface, as the registry's built-in "graph".
void AddGraphSlamMethod(kernel::Registry<SlamMethodInfo>* registry);
// The sensors' noise into the options (the odometry prior's model, OdometryNoiseModel scaled):
// what the registry does for "graph", and what a variant registered with GraphSlamOptions
// passes as its `adapt`.
void AdaptGraphSlamToSensors(const SensorNoise& noise, GraphSlamOptions* options);
// The same method with another loop-closure acceptance (null: the built-in one), for a variant
// that changes only how closures are accepted; it saves, loads and localises as "graph" does.
std::unique_ptr<SlamMethod> MakeGraphSlamMethod(const GraphSlamOptions& options,
                                                const SlamContext& context,
                                                std::unique_ptr<ClosureAcceptance> acceptance);

// For a method with a GraphSlam back end (topological-graph too): its keyframes, loop edges
// and loop searches as layers of *map, and its loop-closure counters, times and
// optimisations appended to *s.
void AddGraphLayers(const GraphSlam& graph, SlamMap* map);
void AddGraphStatistics(const GraphSlam& graph, SlamStatistics* s);

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_METHOD_H_
