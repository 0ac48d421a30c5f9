#ifndef SPLAM_STUDIES_SPLAM_EXPERIMENT_H_
#define SPLAM_STUDIES_SPLAM_EXPERIMENT_H_

#include <cstdint>
#include <functional>
#include <string>

#include "io/sweep_grid.h"
#include "sim/builtin_worlds.h"
#include "sim/world.h"

namespace splam::studies {

// Paper 003 §4.2 (Figs. 19-22): exploration coupled with SLAM in a world (`complex` as the
// paper), three strategies as the paper compares them: SRT + EKF-SLAM with lines and corners
// (Fig. 19), SRT + the B-spline EKF (Fig. 20) and REG + the topological B-spline SLAM (Fig. 21),
// with the topological SLAM's default correction and paper 003's formulation side by side; and
// REG + graph. `runs` seeded trials each (seeds seed .. seed + runs - 1, the same seeds for every
// strategy).
//
// The trials are the cells of a grid (SplamExperimentGrid, shipped as experiments/splam.yaml):
// `splam explore` runs on the sweep engine, `jobs` at once; `out` is its sweep directory, so a
// second run resumes. Writes into `out`: the sweep's grid.yaml and cells.tsv, a full run
// directory per trial (cells/strategy-<figure>_seed-<N>/: report.json, report.html,
// config.yaml, map, graph, x/y/theta errors, trajectories); <figure>-map.png and
// -errors.png (figure: fig19, fig20, fig21, fig21-paper, graph), the first seed's map with the
// true, odometric and estimated trajectories and its errors over time, and <figure>-worst-map.png
// and -errors.png, those of the trial with the largest position RMSE; fig22.svg/png, the errors,
// map size and wall time of every trial (Fig. 22); table.md with mean +- std per strategy;
// summary.json with every trial's numbers.
struct SplamExperimentArgs {
  sim::World world = *sim::BuiltinWorld("complex");
  std::string world_name = "complex";  // as the user gave it: a name or a path
  int runs = 10;
  std::uint64_t seed = 1;
  std::string out = "runs/experiment-splam";
  double resolution_m_per_px = 0.05;   // of a floor-plan image world
  std::string splam_binary = "splam";  // what runs the cells
  int jobs = 0;                        // cells at once; 0: one per core
  std::function<bool()> stop;          // Ctrl-C: finished trials stay, the rest run next time
};

// The grid of the experiment: `splam explore --world <world>` for each strategy (axis
// `strategy`, named after its figure) and seed (axis `seed`, seed .. seed + runs - 1).
io::Grid SplamExperimentGrid(const SplamExperimentArgs& args);

// kExitOk when every trial explored the world with a healthy SLAM method, kExitIncomplete
// otherwise (all results are still written) or when interrupted, kExitBadInput when files cannot
// be written or a trial cannot run.
int RunSplamExperiment(const SplamExperimentArgs& args);

}  // namespace splam::studies

#endif  // SPLAM_STUDIES_SPLAM_EXPERIMENT_H_
