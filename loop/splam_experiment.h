#ifndef SPLAM_LOOP_SPLAM_EXPERIMENT_H_
#define SPLAM_LOOP_SPLAM_EXPERIMENT_H_

#include <cstdint>
#include <string>

namespace splam::loop {

// Paper 003 §4.2 (Figs. 19-22): exploration coupled with SLAM in the `complex` world, three
// strategies as the paper compares them: SRT + EKF-SLAM with lines and corners (Fig. 19), SRT +
// the B-spline EKF (Fig. 20) and REG + the topological B-spline SLAM (Fig. 21), `runs` seeded
// trials each (seeds seed .. seed + runs - 1, the same seeds for every strategy).
//
// Writes into `out`: a full run directory per trial (<explorer>-<method>-seed<N>/: report.json,
// map, graph, x/y/theta errors, trajectories); fig19/20/21-map.png and -errors.png, the first
// seed's map with the true, odometric and estimated trajectories and its errors over time;
// fig22.svg/png, the errors, map size and wall time of every trial (Fig. 22); table.md with
// mean +- std per strategy; summary.json with every trial's numbers.
struct SplamExperimentArgs {
  int runs = 10;
  std::uint64_t seed = 1;
  std::string out = "runs/experiment-splam";
};

// kExitOk when every trial explored the world with a healthy SLAM method, kExitIncomplete
// otherwise (all results are still written), kExitBadInput when files cannot be written.
int RunSplamExperiment(const SplamExperimentArgs& args);

}  // namespace splam::loop

#endif  // SPLAM_LOOP_SPLAM_EXPERIMENT_H_
