#ifndef SPLAM_GRAPH_FRONTIERS_H_
#define SPLAM_GRAPH_FRONTIERS_H_

#include <vector>

#include "kernel/local_safe_region.h"

// Frontier bookkeeping of REG (paper 003 Fig. 8): the free frontier arcs of a node shrink as
// other nodes' LSRs cover them. Arcs are angular intervals of one node's LSR (angles in that
// node's parametrisation, see kernel::FrontierArc).
namespace splam::graph {

// Arc length of `arc` on a circle of radius_m.
inline double ArcLength(const kernel::FrontierArc& arc, double radius_m) {
  return arc.AngularWidth() * radius_m;
}

// `arc` without the intervals `covered` (each widened by margin_rad at both ends, which absorbs
// the sampling step of kernel::ArcPartsInside); the pieces left, in order.
std::vector<kernel::FrontierArc> Subtract(const kernel::FrontierArc& arc,
                                          const std::vector<kernel::FrontierArc>& covered,
                                          double margin_rad);

// FRONT_RAND's target piece of a free arc (paper 003 §3.1.1): the whole arc when its angular
// width is at most max_width_rad, else the first max_width_rad of it (from its start).
kernel::FrontierArc LeadingPiece(const kernel::FrontierArc& arc, double max_width_rad);

}  // namespace splam::graph

#endif  // SPLAM_GRAPH_FRONTIERS_H_
