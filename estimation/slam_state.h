#ifndef SPLAM_ESTIMATION_SLAM_STATE_H_
#define SPLAM_ESTIMATION_SLAM_STATE_H_

#include <string>
#include <vector>

#include "estimation/slam_map.h"
#include "estimation/slam_method.h"
#include "kernel/pose2.h"
#include "kernel/scan.h"
#include "kernel/status.h"

// Map once, localise many times: what a method saves of its map (`splam slam --save-state`) and
// loads back, to localise a new log in it without changing it (as slam_toolbox's localization
// mode and Cartographer's pure localisation do) or to go on mapping.
namespace splam::estimation {

// A scan of the map at its final pose: a keyframe's reading.
struct MapScan {
  kernel::Pose2 pose;           // world_T_robot, as the method finally estimated it
  kernel::Pose2 robot_T_laser;  // the laser's mounting
  kernel::Scan scan;
};

struct SlamState {
  std::string method;          // the registry name of the method that made it
  SlamMap map;                 // its map (curves, keyframes, loop edges; no run records)
  std::vector<MapScan> scans;  // the keyframes' readings, which localisation registers against
};

// A method whose map can be saved and loaded. A method implements it beside SlamMethod (as
// ExplorationNodes); PersistenceOf finds it.
class PersistentSlam {
 public:
  virtual ~PersistentSlam() = default;
  // Keep what SaveState needs from now on (the keyframes' readings: memory a run that saves
  // nothing does not spend). Called before the first Update.
  virtual void KeepStateForSaving() = 0;
  // The state after the run; fails when KeepStateForSaving was not called.
  virtual kernel::Result<SlamState> SaveState() const = 0;
  // Before the first Predict/Update. localize_only: every later scan is localised in the
  // state's map, which stays as it is (Map() returns it unchanged); otherwise mapping goes on
  // from the state's map, the new scans joined to it by registration and loop closure. The run's
  // start pose (SlamContext::start) is where the new log begins in the map's frame, to within the
  // method's initial search window. Fails on a state of another method.
  virtual kernel::Status LoadState(const SlamState& state, bool localize_only) = 0;
};

// The method's PersistentSlam side, or null when it cannot save its state.
inline PersistentSlam* PersistenceOf(SlamMethod* method) {
  return dynamic_cast<PersistentSlam*>(method);
}
inline const PersistentSlam* PersistenceOf(const SlamMethod* method) {
  return dynamic_cast<const PersistentSlam*>(method);
}

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_SLAM_STATE_H_
