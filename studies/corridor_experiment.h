#ifndef SPLAM_STUDIES_CORRIDOR_EXPERIMENT_H_
#define SPLAM_STUDIES_CORRIDOR_EXPERIMENT_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "estimation/ekf/ekf_line_slam.h"
#include "io/sweep_grid.h"
#include "kernel/trajectory.h"

// Paper 001 §6 on the simulator (`splam experiment corridor-lines`): EKF-SLAM with lines and
// corners on a straight run through the `corridor` world, started 2.7 deg off its axis, with a
// SICK LMS-200. The map is scored as 001 Table 1 scores it, by nine distances between mapped
// features, and the filter's consistency by the average NEES of the pose over seeded runs.
namespace splam::studies {

// A distance between two mapped features of the corridor: two corners, or two parallel walls
// (a point on each and their normal angles).
struct CorridorDistance {
  std::string name;
  bool between_lines;
  Eigen::Vector2d a, b;                 // corners, or a point on each wall (lines)
  double a_theta = 0.0, b_theta = 0.0;  // wall normals (lines)
  double TrueValue() const;             // metres
};
// The nine distances (the corridor's width, two rooms' depths, six corner distances): driving
// along +x the robot sees the recess walls that face it, so the far-side recess corners and the
// room corners are mapped.
const std::vector<CorridorDistance>& CorridorDistances();

// The mapped line of a true wall through `point` with normal angle `theta`: the most observed
// mapped line within 5 deg and 0.2 m of it; null when none is.
const estimation::MapLine* MappedWall(const Eigen::Vector2d& point, double theta,
                                      const std::vector<estimation::MapLine>& lines);
// The mapped position of a true corner: the nearest corner landmark within 0.25 m, else the
// nearest crossing of two mapped lines at least 30 deg apart within 0.25 m.
std::optional<Eigen::Vector2d> MappedCorner(const Eigen::Vector2d& truth,
                                            const std::vector<estimation::MapCorner>& corners,
                                            const std::vector<estimation::MapLine>& lines);
// The distance `d` measured in a map; nullopt when a feature is not mapped.
std::optional<double> MeasuredDistance(const CorridorDistance& d,
                                       const std::vector<estimation::MapLine>& lines,
                                       const std::vector<estimation::MapCorner>& corners);

struct CorridorOptions {
  int runs = 20;
  int steps = 160;         // scans after the first
  double speed_mps = 1.0;  // 0.1 s per step
  std::uint64_t seed = 1;  // run i uses seed + i
  bool corners = true;     // corner landmarks
  double corner_floor_m = 0.01;
  double odometry_floor = 1e-4;   // per step, m and rad
  double line_floor_scale = 1.0;  // scales the line floors of 1 mm and 0.5 mrad
  estimation::EkfAssociation association = estimation::EkfAssociation::kNearestNeighbour;
  // RunCorridorLinesExperiment with several runs: cells on the sweep engine.
  std::string splam_binary = "splam";  // what runs the cells
  int jobs = 0;                        // cells at once; 0: one per core
  std::function<bool()> stop;          // Ctrl-C: finished runs stay, the rest run next time
};

struct CorridorResult {
  std::string error;  // non-empty when a run failed (collision, unhealthy filter)
  std::vector<std::vector<double>> measured;  // per distance, the value of every run mapping it
  std::vector<double> average_nees;           // per step, over the runs
  std::vector<std::vector<double>> nees;      // per run, per step
  std::vector<std::vector<std::optional<double>>> measured_by_run;  // per run, per distance
  std::vector<double> final_error_m, final_odometry_error_m;        // per run
  // The first run: trajectories and map.
  kernel::Trajectory truth, estimate, odometry;
  std::vector<estimation::MapLine> lines;
  std::vector<estimation::MapCorner> corners;
};

// Runs the seeded straight runs; every run is replayed through the ekf-lines method of the
// registry with the simulator's noise models.
CorridorResult RunCorridorExperiment(const CorridorOptions& options);

// The grid of `splam experiment corridor-lines` with several runs: the experiment with --runs 1
// (and the other options) for each seed.
io::Grid CorridorGrid(const CorridorOptions& options);

// `splam experiment corridor-lines`: runs the experiment and writes into `out` table1.md (the
// nine distances as 001 Table 1), report.json (with every run's numbers under per_run),
// nees.svg/png (the average NEES against its 95 % band), map.svg/png and errors.svg/png of the
// first run. One run runs here; several are the cells of CorridorGrid on the sweep engine (`out`
// its sweep directory), merged from their report.json. kExitOk, kExitIncomplete when a run
// failed or was interrupted, kExitBadInput when a file cannot be written.
int RunCorridorLinesExperiment(const CorridorOptions& options, const std::string& out);

}  // namespace splam::studies

#endif  // SPLAM_STUDIES_CORRIDOR_EXPERIMENT_H_
