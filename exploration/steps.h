#ifndef SPLAM_EXPLORATION_STEPS_H_
#define SPLAM_EXPLORATION_STEPS_H_

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "exploration/session.h"
#include "graph/exploration_graph.h"
#include "kernel/local_safe_region.h"
#include "kernel/random.h"

// The named steps of SRT and REG (paper 003 §2.1 and §3.1, SPEC §9) as functions of the graph,
// so that tests check each on hand-made LSRs, and a variant of either reuses them. The session
// gives the robot's geometry (Session::paths: clear legs, paths inside an LSR), the frontier
// rules (Session::rules) and the options.
namespace splam::exploration {

// --- SRT -------------------------------------------------------------------------------------
// RANDOM_DIR: a direction uniform over the union of the arcs (drawing uniform directions until
// one falls in a free arc gives the same distribution). `arcs` must not be empty.
double RandomDirection(const std::vector<kernel::FrontierArc>& arcs, kernel::Random* random);
// VALID_CONF's first test: `candidate` lies outside the LSR of every node but `current`.
bool OutsideOtherLsrs(const graph::ExplorationGraph& g, graph::Vertex current,
                      const Eigen::Vector2d& candidate);

// --- REG -------------------------------------------------------------------------------------
// CURR_INTERSECTION at `current`: for every node whose LSR overlaps current's, the frontier
// parts of either inside the other's LSR are removed, and an edge is added along a safe path
// through the overlap when one exists.
void CurrIntersection(const Session& session, graph::ExplorationGraph* g, graph::Vertex current);
// The shortest path a -> w -> b with w in both LSRs and both legs clear (candidate waypoints on
// and beside the segment a-b); nullopt when none works.
std::optional<std::vector<Eigen::Vector2d>> SafePath(const Session& session,
                                                     const graph::ExplorationGraph& g,
                                                     graph::Vertex a, graph::Vertex b);
// Takes arc k of `frontiers`, returns its leading piece (at most max_piece_rad wide) and puts the
// rest of the arc back when it is long enough (FrontierRules::LongEnough).
kernel::FrontierArc TakePiece(const Session& session, std::vector<kernel::FrontierArc>* frontiers,
                              std::size_t k, double max_piece_rad);
// FRONT_RAND: TakePiece of a random arc of `frontiers`.
kernel::FrontierArc FrontRand(const Session& session, std::vector<kernel::FrontierArc>* frontiers,
                              kernel::Random* random, double max_piece_rad);
// DISPLACEMENT: the path to q_dest, alpha r from the node towards the piece's midpoint, or
// towards the direction of the piece nearest to it that the robot can reach inside the LSR
// (straight legs first, then bent paths; failing that, half as far); nullopt when none.
std::optional<std::vector<Eigen::Vector2d>> Displacement(const Session& session,
                                                         const graph::NodeData& node,
                                                         const kernel::FrontierArc& piece);

}  // namespace splam::exploration

#endif  // SPLAM_EXPLORATION_STEPS_H_
