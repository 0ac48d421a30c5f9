#ifndef SPLAM_ESTIMATION_TOPOLOGICAL_TOPOLOGICAL_METHODS_H_
#define SPLAM_ESTIMATION_TOPOLOGICAL_TOPOLOGICAL_METHODS_H_

#include "estimation/slam_method.h"
#include "kernel/registry.h"

namespace splam::estimation {

// The topological B-spline SLAM behind the SlamMethod interface, as the registry's built-in
// "topological" (paper 003), and with the graph SLAM's back end as "topological-graph".
void AddTopologicalMethod(kernel::Registry<SlamMethodInfo>* registry);
void AddTopologicalGraphMethod(kernel::Registry<SlamMethodInfo>* registry);

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_TOPOLOGICAL_TOPOLOGICAL_METHODS_H_
