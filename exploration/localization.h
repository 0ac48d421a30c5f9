#ifndef SPLAM_EXPLORATION_LOCALIZATION_H_
#define SPLAM_EXPLORATION_LOCALIZATION_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "exploration/robot_interface.h"
#include "kernel/exploration_nodes.h"
#include "kernel/local_safe_region.h"
#include "kernel/pose2.h"
#include "kernel/status.h"

namespace splam::exploration {

// Where the robot believes it is: the explorer plans with this estimate only. Implementations
// range from ground truth (an oracle, for studying exploration alone) to full SLAM methods. The
// explorer tells it of every node and asks where the nodes now are and what a revisit would give
// (kernel::ExplorationNodes: AtNode, NodePoses, RevisitInformation). SLAM methods may use the
// nodes (the topological SLAM associates against the map curves in the newest node's LSR and
// extends its map at the nodes; a pose graph moves them when a loop closes).
class Localization : public kernel::ExplorationNodes {
 public:
  virtual ~Localization() = default;
  virtual std::string name() const = 0;
  // True when Update() needs laser scans; otherwise the explorer reads odometry only while
  // driving (faster) and senses the laser only at the nodes.
  virtual bool needs_scans() const { return false; }
  // Starts at `start` (world frame, assumed known, as the papers do) with the first reading of
  // `robot`. Ok when ready, else why this localisation cannot run on this robot.
  virtual kernel::Status Start(const RobotDescription& robot, const kernel::Pose2& start,
                               const Perception& first) = 0;
  // The estimate after a new reading (odometry always, laser when needs_scans()).
  virtual kernel::Pose2 Update(const Perception& perception) = 0;
  // Active loop closing (ActiveLoopClosingOptions). The covariance of the current pose (x, y,
  // theta; world frame), nullopt when the localisation keeps none (ground truth, odometry). It may
  // cost a factorisation of a pose graph: asked at the explorer's decisions.
  virtual std::optional<Eigen::Matrix3d> PoseCovariance() const { return std::nullopt; }
};

// The simulator's ground truth; Perception::true_pose must be present.
class GroundTruthLocalization : public Localization {
 public:
  std::string name() const override { return "ground-truth"; }
  kernel::Status Start(const RobotDescription& robot, const kernel::Pose2& start,
                       const Perception& first) override;
  kernel::Pose2 Update(const Perception& perception) override;
};

// Dead reckoning: the start pose composed with the odometry accumulated since.
class OdometryLocalization : public Localization {
 public:
  std::string name() const override { return "odometry"; }
  kernel::Status Start(const RobotDescription& robot, const kernel::Pose2& start,
                       const Perception& first) override;
  kernel::Pose2 Update(const Perception& perception) override;

 private:
  kernel::Pose2 world_T_odometry_;  // maps the odometry frame into the world
};

}  // namespace splam::exploration

#endif  // SPLAM_EXPLORATION_LOCALIZATION_H_
