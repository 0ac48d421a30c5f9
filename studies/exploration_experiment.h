#ifndef SPLAM_STUDIES_EXPLORATION_EXPERIMENT_H_
#define SPLAM_STUDIES_EXPLORATION_EXPERIMENT_H_

#include <cstdint>
#include <functional>
#include <string>

#include "io/sweep_grid.h"

namespace splam::studies {

// Paper 003 Fig. 18: SRT against REG, `runs` seeded trials (seeds seed .. seed + runs - 1) in
// each of the office and complex worlds with ground-truth localisation: nodes, distance, time
// and coverage per trial as a table (table.md), bar charts (fig18-<world>.svg/png), a run
// directory per trial and a summary.json. The trials are the cells of a grid
// (ExplorationExperimentGrid, shipped as experiments/exploration.yaml), run on the sweep engine
// `jobs` at once; `out` is its sweep directory, so a second run resumes.
struct ExplorationExperimentArgs {
  int runs = 10;
  std::uint64_t seed = 1;
  double alpha = 0.8;
  std::string out = "runs/experiment-exploration";
  std::string splam_binary = "splam";  // what runs the cells
  int jobs = 0;                        // cells at once; 0: one per core
  std::function<bool()> stop;          // Ctrl-C: finished trials stay, the rest run next time
};

// `splam explore --localization ground-truth` for each world (office, office-long, office-doors,
// complex), explorer (srt, reg) and seed.
io::Grid ExplorationExperimentGrid(const ExplorationExperimentArgs& args);

int RunExplorationExperiment(const ExplorationExperimentArgs& args);

}  // namespace splam::studies

#endif  // SPLAM_STUDIES_EXPLORATION_EXPERIMENT_H_
