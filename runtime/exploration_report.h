#ifndef SPLAM_RUNTIME_EXPLORATION_REPORT_H_
#define SPLAM_RUNTIME_EXPLORATION_REPORT_H_

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "exploration/explorer.h"
#include "kernel/status.h"
#include "kernel/trajectory.h"
#include "runtime/exploration_run.h"
#include "sim/world.h"

namespace splam::runtime {

// report.json of a run.
nlohmann::json ExplorationReport(const sim::World& world, const ExploreSetup& setup,
                                 const ExploreOutcome& outcome);

// "complex | reg | topological | seed 1 | 35 nodes, 163 m, 494 s, 99.8 % explored"
std::string RunTitle(const sim::World& world, const ExploreSetup& setup,
                     const ExploreOutcome& outcome);

// Writes a run into `dir` (which must exist): `report` as report.json, graph, explored and
// errors pictures (.svg and .png), truth/odometry/estimate.txt and, with a SLAM localisation,
// map.svg/png/txt/dxf, and steps.csv when setup.trace_steps (WriteStepTrace). The names written are
// appended to *written. Ok, else the first error (the files written before it stay).
kernel::Status WriteExplorationRun(const sim::World& world, const ExploreSetup& setup,
                                   const ExploreOutcome& outcome, const nlohmann::json& report,
                                   const std::string& dir, std::vector<std::string>* written);

// The graph (or tree) over the world with the nodes' LSRs, the open frontiers and the true
// path (paper 003 Fig. 17), to each path (.svg or .png); ok, else the first error.
kernel::Status SaveExplorationPicture(const sim::World& world, const ExploreOutcome& outcome,
                                      const std::string& title,
                                      const std::vector<std::string>& paths);

// The SLAM map (curves, control points, features; or lines and corners) over the true world with
// the true, odometric and estimated trajectories, to each path; ok, else the first error. Needs a
// SLAM localisation.
kernel::Status SaveSlamMapPicture(const sim::World& world, const ExploreOutcome& outcome,
                                  const std::string& title, const std::vector<std::string>& paths);

// x, y and theta error over time of the estimate and of odometry, to each path; ok, else the first
// error.
kernel::Status SaveTrajectoryErrorPlot(const ExploreOutcome& outcome, const std::string& title,
                                       const std::vector<std::string>& paths);

// Explored fraction and nodes over simulated time, to each path; ok, else the first error.
kernel::Status SaveCoveragePlot(const ExploreOutcome& outcome, const std::string& title,
                                const std::vector<std::string>& paths);

}  // namespace splam::runtime

#endif  // SPLAM_RUNTIME_EXPLORATION_REPORT_H_
