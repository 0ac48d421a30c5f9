#ifndef SPLAM_RUNTIME_SLAM_DRIVER_H_
#define SPLAM_RUNTIME_SLAM_DRIVER_H_

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "estimation/slam_method.h"
#include "kernel/pose2.h"
#include "kernel/scan.h"

namespace splam::runtime {

// One step as the method saw it (SlamDriver::RecordSteps): its pose after the prediction and
// after the update, and what the update did (SlamMethod::LastUpdate; empty without a scan).
struct StepRecord {
  kernel::Pose2 predicted, corrected;
  std::vector<std::pair<std::string, double>> values;
};

// The predict/update step of every SLAM run, written once: log replay, the SPLAM loop, tests,
// benchmarks and examples feed readings through it. Each reading predicts with the odometry
// increment since the previous one (none before the first) and, when it has a scan and the
// method is healthy, updates with it; the wall time of every update and the map size after it
// are kept.
class SlamDriver {
 public:
  explicit SlamDriver(std::unique_ptr<estimation::SlamMethod> method);

  // The odometry pose the next increment starts from (the SPLAM loop starts at its first
  // reading, so that its first step predicts a zero increment).
  void SetOdometryOrigin(const kernel::Pose2& odometry_pose) { last_odometry_ = odometry_pose; }
  // One reading: the integrated odometry pose, and the scan (may be null or empty) of a laser
  // mounted at robot_T_laser. True when the method is still healthy afterwards.
  bool Step(const kernel::Pose2& odometry_pose, const kernel::Scan* scan,
            const kernel::Pose2& robot_T_laser);

  estimation::SlamMethod& method() { return *method_; }
  const estimation::SlamMethod& method() const { return *method_; }
  // Per update: wall time (ms, predict included), and MapSize() and MapCurves() after it.
  const std::vector<double>& update_ms() const { return update_ms_; }
  const std::vector<std::size_t>& map_size() const { return map_size_; }
  const std::vector<std::size_t>& map_curves() const { return map_curves_; }
  // Keep a StepRecord of every Step from now on (off by default: a few hundred bytes a step).
  void RecordSteps(bool on) { record_steps_ = on; }
  const std::vector<StepRecord>& steps() const { return steps_; }

 private:
  std::unique_ptr<estimation::SlamMethod> method_;
  std::optional<kernel::Pose2> last_odometry_;
  std::vector<double> update_ms_;
  std::vector<std::size_t> map_size_, map_curves_;
  bool record_steps_ = false;
  std::vector<StepRecord> steps_;
};

}  // namespace splam::runtime

#endif  // SPLAM_RUNTIME_SLAM_DRIVER_H_
