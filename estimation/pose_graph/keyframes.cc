#include "estimation/pose_graph/keyframes.h"

#include "estimation/pose_graph/scan_registration.h"

#include <cmath>
#include <unordered_map>

namespace splam::estimation {

std::vector<OrientedPoint> WorldRaster(const Keyframes& keyframes, const std::vector<int>& ids) {
  std::vector<OrientedPoint> raster;
  for (int i : ids) {
    const Keyframe& kf = keyframes[static_cast<std::size_t>(i)];
    if (!kf.data) continue;
    const std::vector<OrientedPoint> placed = Placed(kf.pose, kf.data->raster);
    raster.insert(raster.end(), placed.begin(), placed.end());
  }
  return raster;
}

std::vector<const ViewCells*> ViewsOf(const Keyframes& keyframes, const std::vector<int>& ids,
                                      int slot, double resolution_m, double seen_margin_m,
                                      bool by_hits) {
  std::vector<const ViewCells*> views;
  for (int i : ids) {
    const Keyframe& kf = keyframes[static_cast<std::size_t>(i)];
    if (!kf.data) continue;
    Keyframe::ViewRaster& raster = kf.data->rasters[static_cast<std::size_t>(slot)];
    const bool moved = !(raster.pose.x() == kf.pose.x() && raster.pose.y() == kf.pose.y() &&
                         raster.pose.theta() == kf.pose.theta());
    if (!raster.valid || moved || raster.seen.resolution_m != resolution_m) {
      raster = {};
      raster.seen = RasteriseView(kf.pose * kf.data->seen, resolution_m, seen_margin_m);
      raster.pose = kf.pose;
      raster.valid = true;
    }
    if (by_hits && !raster.by_hits_valid) {
      raster.by_hits = RasteriseView(kf.pose * kf.data->seen_by_hits, resolution_m, seen_margin_m);
      raster.by_hits_valid = true;
    }
    views.push_back(by_hits ? &raster.by_hits : &raster.seen);
  }
  return views;
}

std::vector<Eigen::Vector3d> PosesOf(const Keyframes& keyframes, const std::vector<int>& ids) {
  std::vector<Eigen::Vector3d> poses;
  poses.reserve(ids.size());
  for (int i : ids) poses.push_back(keyframes[static_cast<std::size_t>(i)].pose.ToVector());
  return poses;
}

std::vector<int> AreaKeyframes(const Keyframes& keyframes, const Eigen::Vector2d& center,
                               double radius_m, int newest) {
  std::vector<int> area;
  for (int i = 0; i <= newest; ++i) {
    const Keyframe& kf = keyframes[static_cast<std::size_t>(i)];
    if (!kf.trimmed && (kf.pose.translation() - center).norm() <= radius_m) area.push_back(i);
  }
  return area;
}

// Keeping the first element of each cell instead of the mean biases the outline: with a laser's
// range noise, the first point of a cell in beam order is more often one that the noise pushed
// in from the previous cell along its beam, so behind the wall on one side of the robot and in
// front of it on the other, and the map turned a little at every keyframe (the front end's
// heading drifted by -3.3 deg over the `complex` route with a points-only map, +0.8 to +1.6 deg
// with the beam order reversed).
std::vector<OrientedPoint> Thinned(const std::vector<OrientedPoint>& elements, double spacing) {
  std::unordered_map<long long, std::size_t> cell_of;
  std::vector<OrientedPoint> out;
  std::vector<int> count;
  for (const OrientedPoint& e : elements) {
    const long long key =
        (static_cast<long long>(std::floor(e.point.x() / spacing)) << 32) ^
        (static_cast<long long>(std::floor(e.point.y() / spacing)) & 0xffffffffLL);
    const auto [it, inserted] = cell_of.emplace(key, out.size());
    if (inserted) {
      out.push_back({Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()});
      count.push_back(0);
    }
    out[it->second].point += e.point;
    out[it->second].normal += e.normal;
    ++count[it->second];
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i].point /= count[i];
    if (out[i].normal.norm() > 1e-12) out[i].normal.normalize();
  }
  return out;
}

std::vector<Eigen::Vector2d> Positions(const std::vector<OrientedPoint>& oriented) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(oriented.size());
  for (const OrientedPoint& o : oriented) out.push_back(o.point);
  return out;
}

bool Within(const kernel::Pose2& a, const kernel::Pose2& b, double distance_m, double angle_rad) {
  return (a.translation() - b.translation()).norm() < distance_m &&
         std::abs(a.Between(b).theta()) < angle_rad;
}

Eigen::Matrix3d Diagonal(double sigma_m, double sigma_rad) {
  return Eigen::Vector3d(sigma_m * sigma_m, sigma_m * sigma_m, sigma_rad * sigma_rad).asDiagonal();
}

}  // namespace splam::estimation
