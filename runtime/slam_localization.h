#ifndef SPLAM_RUNTIME_SLAM_LOCALIZATION_H_
#define SPLAM_RUNTIME_SLAM_LOCALIZATION_H_

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "estimation/slam_method.h"
#include "exploration/localization.h"
#include "kernel/status.h"
#include "runtime/slam_driver.h"

namespace splam::runtime {

// The SPLAM loop (SPEC §11): any registered SLAM method as the explorer's localisation. Every
// odometry reading predicts, every scan corrects, and every new exploration node is handed to
// the method.
class SlamLocalization : public exploration::Localization {
 public:
  // `method` names a registered method; `options` are its options (null: its defaults for the
  // simulated sensors); `region` is the explorer's LSR radius and step.
  SlamLocalization(std::string method, std::shared_ptr<const estimation::SlamOptions> options,
                   const kernel::LocalRegionOptions& region);

  std::string name() const override { return method_; }
  bool needs_scans() const override { return true; }
  kernel::Status Start(const exploration::RobotDescription& robot, const kernel::Pose2& start,
                       const exploration::Perception& first) override;
  kernel::Pose2 Update(const exploration::Perception& perception) override;
  void AtNode(const kernel::LocalSafeRegion& lsr) override;
  std::vector<kernel::Pose2> NodePoses() const override;
  // The method's (SlamMethod::PoseCovariance).
  std::optional<Eigen::Matrix3d> PoseCovariance() const override;
  std::vector<std::optional<double>> RevisitInformation(
      const std::vector<int>& nodes, const std::vector<double>& path_m) const override;
  // At the end of the run (after Start): the method's last optimisation (SlamMethod::Finish).
  void Finish() { driver_->method().Finish(); }

  // The driver (after Start): the method, the wall time of every update and the map sizes.
  const SlamDriver* driver() const { return driver_ ? &*driver_ : nullptr; }
  // Keep every step (SlamDriver::steps) and its time from Start on; call before Start.
  void RecordSteps(bool on) { record_steps_ = on; }
  const std::vector<double>& step_times() const { return step_times_; }

 private:
  std::string method_;
  std::shared_ptr<const estimation::SlamOptions> options_;
  kernel::LocalRegionOptions region_;
  kernel::Pose2 robot_T_laser_;
  std::optional<SlamDriver> driver_;
  bool record_steps_ = false;
  std::vector<double> step_times_;  // s, of every recorded step
};

}  // namespace splam::runtime

#endif  // SPLAM_RUNTIME_SLAM_LOCALIZATION_H_
