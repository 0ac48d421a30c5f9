#ifndef SPLAM_RUNTIME_STEP_TRACE_H_
#define SPLAM_RUNTIME_STEP_TRACE_H_

#include <string>
#include <vector>

#include "kernel/status.h"
#include "kernel/trajectory.h"
#include "runtime/slam_driver.h"

namespace splam::runtime {

// Writes a per-step trace as CSV, one row per step (`steps[i]` at `times[i]`): the pose after
// the prediction and after the update; with the truth (when `truth` has a pose at that time)
// the true pose and both poses' position error (m) and signed heading error (estimate - truth,
// deg), so that a correction that made the pose worse shows as a row whose error grew; then
// the method's own values (SlamMethod::LastUpdate; the columns of the first step that has
// them, empty where a step has none). Ok, or what went wrong, naming the file.
kernel::Status WriteStepTrace(const std::string& path, const std::vector<StepRecord>& steps,
                              const std::vector<double>& times, const kernel::Trajectory& truth);

}  // namespace splam::runtime

#endif  // SPLAM_RUNTIME_STEP_TRACE_H_
