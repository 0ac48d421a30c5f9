#ifndef SPLAM_LOOP_EXPLORATION_EXPERIMENT_H_
#define SPLAM_LOOP_EXPLORATION_EXPERIMENT_H_

#include <cstdint>
#include <string>

namespace splam::loop {

// Paper 003 Fig. 18: SRT against REG, `runs` seeded trials (seeds seed .. seed + runs - 1) in
// each of the office and complex worlds with ground-truth localisation: nodes, distance, time
// and coverage per trial as a table (table.md), bar charts (fig18-<world>.svg/png), one
// report.json per trial and a summary.json.
struct ExplorationExperimentArgs {
  int runs = 10;
  std::uint64_t seed = 1;
  double alpha = 0.8;
  std::string out = "runs/experiment-exploration";
};

int RunExplorationExperiment(const ExplorationExperimentArgs& args);

}  // namespace splam::loop

#endif  // SPLAM_LOOP_EXPLORATION_EXPERIMENT_H_
