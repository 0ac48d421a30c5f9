#ifndef SPLAM_IO_WORLD_FILE_H_
#define SPLAM_IO_WORLD_FILE_H_

#include <string>

#include "io/floor_plan.h"
#include "io/result.h"
#include "sim/world.h"

namespace splam::io {

// World files are YAML. Lengths in metres, angles in radians; points are [x, y].
//
//   name: lab                          # optional
//   start: [1.0, 2.0, 0.0]             # optional start pose [x, y, theta]
//   route: [[5, 2], [5, 6]]            # optional default route (waypoints)
//   obstacles:
//     - polyline: [[0, 0], [10, 0], [10, 5]]          # open chain of straight walls
//     - polygon: [[2, 2], [3, 2], [3, 3]]             # closed
//     - circle: {center: [5, 5], radius: 0.3}
//     - ellipse: {center: [7, 3], radii: [1.0, 0.5], angle: 0.5}
//     - spline: [[0, 5], [1, 6], [2, 5], [3, 6]]      # open cubic B-spline, clamped uniform
//                                                     # knots: passes through its end points
//     - closed_spline: [[8, 8], [9, 8], [9, 9]]       # closed uniform cubic B-spline
//     - floor_plan: {image: plan.png, resolution: 0.05, origin: [0, 0], threshold: 128}
//                                                     # image path relative to this file
//
// Errors name the file and the line of the offending entry.
Result<sim::World> ReadWorldFile(const std::string& path);
Result<sim::World> ParseWorld(const std::string& yaml, const std::string& name,
                              const std::string& base_directory = ".");
std::string FormatWorld(const sim::World& world);
// Ok, else why the file could not be written.
kernel::Status WriteWorldFile(const std::string& path, const sim::World& world);

// A world by name or path: a built-in name ("complex"), a .yaml/.yml world file, or a floor-plan
// image (.png, .jpg, .pgm, .bmp) read with `floor_plan`.
Result<sim::World> LoadWorld(const std::string& name_or_path,
                             const FloorPlanOptions& floor_plan = {});
// LoadWorld, then sim::World::Validate: a world to simulate in. A problem of the world is
// reported as "name_or_path: problem".
Result<sim::World> LoadValidWorld(const std::string& name_or_path,
                                  const FloorPlanOptions& floor_plan = {});
// Ok when a run can start at `start` in the world `name_or_path` names, as far as its source
// tells beyond the obstacles: for a floor-plan image, not on a dark pixel (inside a wall or a
// solid region, which the outlines alone take for free space); else why not.
kernel::Status StartProblem(const std::string& name_or_path, const FloorPlanOptions& floor_plan,
                            const kernel::Pose2& start);

}  // namespace splam::io

#endif  // SPLAM_IO_WORLD_FILE_H_
