#ifndef SPLAM_APPS_EXPLORATION_RUN_H_
#define SPLAM_APPS_EXPLORATION_RUN_H_

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "apps/slam_localization.h"
#include "exploration/explorer.h"
#include "kernel/trajectory.h"
#include "sim/world.h"

namespace splam::apps {

// One simulated exploration: which explorer, localisation and seed.
struct ExploreSetup {
  std::string explorer = "reg";  // "srt" or "reg"
  // "ground-truth", "odometry", or a SLAM method: "topological", "ekf-lines", "ekf-bspline".
  std::string localization = "topological";
  std::uint64_t seed = 1;                // simulator noise and the explorer's draws
  double odometry_noise_scale = 1.0;     // times the default odometry noise
  bool sonar = true;                     // complete the LSR behind the robot with sonar
  exploration::ExplorerOptions options;  // options.seed is overwritten by `seed`
};

struct ExploreOutcome {
  std::string error;  // non-empty when the run could not start (nothing else is valid then)
  exploration::ExplorationRun run;
  double robot_radius_m = 0.0;
  // Explored fraction of the reachable free space (exploration::CoverageGrid, 10 cm cells) after
  // each node (and at the end of the run), from the LSRs placed at the nodes' true poses.
  std::vector<double> coverage_time_s, coverage_fraction;
  double reachable_area_m2 = 0.0;
  double wall_s = 0.0;  // whole run, simulation included
  // The SLAM method when the localisation is one (its map, timings); null otherwise.
  std::shared_ptr<SlamLocalization> slam;
  double coverage() const { return coverage_fraction.empty() ? 0.0 : coverage_fraction.back(); }
};

// The true, odometric and estimated trajectories of a run (from its trace).
struct Trajectories {
  kernel::Trajectory truth, odometry, estimate;
};
Trajectories TrajectoriesOf(const exploration::ExplorationRun& run);

// Runs the exploration in `world` from its start pose and evaluates its coverage.
ExploreOutcome RunExploration(const sim::World& world, const ExploreSetup& setup);

// report.json of a run.
nlohmann::json ExplorationReport(const sim::World& world, const ExploreSetup& setup,
                                 const ExploreOutcome& outcome);

// "complex | reg | topological | seed 1 | 35 nodes, 163 m, 494 s, 99.8 % explored"
std::string RunTitle(const sim::World& world, const ExploreSetup& setup,
                     const ExploreOutcome& outcome);

// Writes a run into `dir` (which must exist): `report` as report.json, graph, explored and
// errors pictures (.svg and .png), truth/odometry/estimate.txt and, with a SLAM localisation,
// map.svg/png/txt/dxf. The names written are appended to *written. Empty on success, else the
// first error (the files written before it stay).
std::string WriteExplorationRun(const sim::World& world, const ExploreSetup& setup,
                                const ExploreOutcome& outcome, const nlohmann::json& report,
                                const std::string& dir, std::vector<std::string>* written);

// The graph (or tree) over the world with the nodes' LSRs, the open frontiers and the true
// path (paper 003 Fig. 17), to each path (.svg or .png); empty on success.
std::string SaveExplorationPicture(const sim::World& world, const ExploreOutcome& outcome,
                                   const std::string& title, const std::vector<std::string>& paths);

// The SLAM map (curves, control points, features; or lines and corners) over the true world with
// the true, odometric and estimated trajectories, to each path; empty on success. Needs a SLAM
// localisation.
std::string SaveSlamMapPicture(const sim::World& world, const ExploreOutcome& outcome,
                               const std::string& title, const std::vector<std::string>& paths);

// x, y and theta error over time of the estimate and of odometry, to each path; empty on success.
std::string SaveTrajectoryErrorPlot(const ExploreOutcome& outcome, const std::string& title,
                                    const std::vector<std::string>& paths);

// Explored fraction and nodes over simulated time, to each path; empty on success.
std::string SaveCoveragePlot(const ExploreOutcome& outcome, const std::string& title,
                             const std::vector<std::string>& paths);

}  // namespace splam::apps

#endif  // SPLAM_APPS_EXPLORATION_RUN_H_
