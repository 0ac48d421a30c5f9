#include "apps/run_picture.h"

#include <map>

#include "io/render.h"
#include "io/simulation_log.h"

namespace splam::apps {

std::vector<Eigen::Vector2d> ScanPointsInWorld(const io::CarmenLog& log, int every) {
  std::map<double, kernel::Pose2> truth;
  for (const io::TruePoseMessage* m : log.TruePoses())
    truth[m->stamp.ipc_timestamp_s] = m->true_pose;
  std::vector<Eigen::Vector2d> points;
  const auto lasers = log.Lasers();
  for (std::size_t i = 0; i < lasers.size(); i += static_cast<std::size_t>(std::max(every, 1))) {
    const io::LaserMessage& m = *lasers[i];
    kernel::Pose2 world_T_laser = m.laser_pose;
    if (const auto it = truth.find(m.stamp.ipc_timestamp_s); it != truth.end()) {
      world_T_laser = it->second * m.robot_pose.Between(m.laser_pose);
    }
    for (const Eigen::Vector2d& p : m.scan.HitPoints()) points.push_back(world_T_laser * p);
  }
  return points;
}

std::string SaveRunPicture(const RunPicture& picture, const std::vector<std::string>& paths) {
  kernel::Box2 area;
  if (picture.world != nullptr) area.Extend(picture.world->Bounds());
  auto extend = [&](const io::Trajectory& t) {
    for (const io::StampedPose& p : t) area.Extend(p.pose.translation());
  };
  extend(picture.truth);
  extend(picture.odometry);
  for (const auto& [label, t] : picture.estimates) extend(t);
  for (const Eigen::Vector2d& p : picture.scan_points) area.Extend(p);
  if (area.IsEmpty()) area = kernel::Box2{Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 1)};

  io::FigureOptions options;
  options.title = picture.title;
  options.pixels_per_meter = picture.pixels_per_meter;
  io::Figure figure(area, options);
  if (!picture.scan_points.empty())
    figure.DrawPoints(picture.scan_points, io::palette::kScan, 0.9, "laser hits");
  if (picture.world != nullptr) figure.DrawWorld(*picture.world);
  figure.DrawPath(io::Poses(picture.odometry), io::palette::kOdometry, 1.5, "odometry");
  for (const auto& [label, t] : picture.estimates)
    figure.DrawPath(io::Poses(t), io::palette::kEstimate, 1.5, label);
  figure.DrawPath(io::Poses(picture.truth), io::palette::kTrue, 1.5, "ground truth");
  if (picture.robot_radius_m > 0.0) {
    const io::Trajectory& last = !picture.truth.empty() ? picture.truth : picture.odometry;
    if (!last.empty())
      figure.DrawRobot(last.back().pose, picture.robot_radius_m, io::palette::kTrue);
  }
  for (const std::string& path : paths) {
    if (std::string error = figure.Save(path); !error.empty()) return error;
  }
  return "";
}

}  // namespace splam::apps
