#include "runtime/slam_driver.h"

#include <chrono>

namespace splam::runtime {

SlamDriver::SlamDriver(std::unique_ptr<estimation::SlamMethod> method)
    : method_(std::move(method)) {}

bool SlamDriver::Step(const kernel::Pose2& odometry_pose, const kernel::Scan* scan,
                      const kernel::Pose2& robot_T_laser) {
  const auto begin = std::chrono::steady_clock::now();
  if (last_odometry_) method_->Predict(last_odometry_->Between(odometry_pose));
  last_odometry_ = odometry_pose;
  const kernel::Pose2 predicted = method_->pose();
  const bool update = scan != nullptr && !scan->ranges_m.empty() && method_->healthy();
  if (update) {
    method_->Update(*scan, robot_T_laser);
    update_ms_.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin)
            .count());
    map_size_.push_back(method_->MapSize());
    map_curves_.push_back(method_->MapCurves());
  }
  if (record_steps_)
    steps_.push_back(
        {predicted, method_->pose(),
         update ? method_->LastUpdate() : std::vector<std::pair<std::string, double>>{}});
  return method_->healthy();
}

}  // namespace splam::runtime
