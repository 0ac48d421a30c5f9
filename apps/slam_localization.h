#ifndef SPLAM_APPS_SLAM_LOCALIZATION_H_
#define SPLAM_APPS_SLAM_LOCALIZATION_H_

#include <chrono>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "apps/slam_methods.h"
#include "exploration/localization.h"

namespace splam::apps {

// The SPLAM loop (SPEC §11): a SLAM method as the explorer's localisation. Every odometry
// reading predicts, every scan corrects, and every new exploration node is handed to the method.
class SlamLocalization : public exploration::Localization {
 public:
  explicit SlamLocalization(SlamSettings settings) : settings_(std::move(settings)) {}

  std::string name() const override { return settings_.method; }
  bool needs_scans() const override { return true; }
  std::string Start(const exploration::RobotDescription& robot, const kernel::Pose2& start,
                    const exploration::Perception& first) override {
    std::string problem;
    method_ = MakeSlamMethod(settings_, start, &problem);
    robot_T_laser_ = robot.robot_T_laser;
    last_odometry_ = first.odometry_pose;
    return problem;
  }
  kernel::Pose2 Update(const exploration::Perception& perception) override {
    const auto begin = std::chrono::steady_clock::now();
    method_->Predict(last_odometry_.Between(perception.odometry_pose));
    last_odometry_ = perception.odometry_pose;
    if (!perception.scan.ranges_m.empty() && method_->healthy()) {
      method_->Update(perception.scan, robot_T_laser_);
      update_ms_.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin)
              .count());
      map_curves_.push_back(method_->MapCurves());
    }
    return method_->pose();
  }
  void AtNode(const kernel::LocalSafeRegion& lsr) override { method_->AtNode(lsr); }

  // The method (after Start), and the wall time of every scan update with the map size then.
  const SlamMethod* method() const { return method_.get(); }
  const std::vector<double>& update_ms() const { return update_ms_; }
  const std::vector<std::size_t>& map_curves() const { return map_curves_; }

 private:
  SlamSettings settings_;
  std::unique_ptr<SlamMethod> method_;
  kernel::Pose2 robot_T_laser_, last_odometry_;
  std::vector<double> update_ms_;
  std::vector<std::size_t> map_curves_;
};

}  // namespace splam::apps

#endif  // SPLAM_APPS_SLAM_LOCALIZATION_H_
