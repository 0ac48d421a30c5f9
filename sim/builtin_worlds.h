#ifndef SPLAM_SIM_BUILTIN_WORLDS_H_
#define SPLAM_SIM_BUILTIN_WORLDS_H_

#include <optional>
#include <string>
#include <vector>

#include "sim/world.h"

namespace splam::sim {

// Names of the worlds compiled into splam: "corridor", "office", "complex".
std::vector<std::string> BuiltinWorldNames();

// The built-in world of that name, with its start pose and default route; nullopt if unknown.
//  - corridor: a straight 24 m x 2.4 m corridor with recesses and doors 1, 2 and 3 m wide,
//    closed at both ends; route: a straight run started 2.7 deg off the axis (paper 001 §6).
//  - office: 16 m x 12 m, six rooms off a central corridor through 0.9 m doors, tables.
//  - complex: about 20 m x 15 m with curved walls, round pillars, an ellipse, irregular smooth
//    obstacles and a free-standing curved wall (the environments of papers 000 and 003).
//  - loop: a ring corridor 3 m wide, about 100 m round, around a 34 m x 20 m block with recesses,
//    pillars along the outer wall and one rounded corner: a long loop (active loop closing).
//  - curves: two 12 m x 14 m halls joined by a corridor, with obstacles rich in curvature
//    features (lobed outlines, S-shaped walls, star polygons, wavy walls); route: round the west
//    hall, out round the east one and back (paper 000's association compared).
//  - halls: two round halls 14 m and 13 m across, wider than the URG-04LX's range, joined by a
//    corridor, with rings of round pillars (the topological SLAM's hard case).
std::optional<World> BuiltinWorld(const std::string& name);

}  // namespace splam::sim

#endif  // SPLAM_SIM_BUILTIN_WORLDS_H_
