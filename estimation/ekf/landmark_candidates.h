#ifndef SPLAM_ESTIMATION_EKF_LANDMARK_CANDIDATES_H_
#define SPLAM_ESTIMATION_EKF_LANDMARK_CANDIDATES_H_

#include <algorithm>
#include <cstddef>
#include <vector>

// Landmark candidates, shared by the two EKFs: an observation that is clearly new is kept
// outside the state (world frame) and becomes a landmark only once it has been seen in
// `min_observations` scans, none more than `max_age_scans` after the previous one. Spurious
// features (people, clutter, noise) then never enter the state.
namespace splam::estimation {

template <class Value>
class LandmarkCandidates {
 public:
  LandmarkCandidates(int min_observations, int max_age_scans)
      : min_observations_(min_observations), max_age_scans_(max_age_scans) {}

  // A new observation with world-frame `value` in scan `scan`: it matches the first candidate
  // not yet seen in this scan for which close(candidate value, value) holds, else starts one;
  // the candidate takes the new value. True when the candidate has now been seen often enough:
  // it is promoted (the caller adds the landmark) and leaves at the next Prune.
  template <class Close>
  bool Observe(const Value& value, std::size_t scan, const Close& close) {
    auto found = std::find_if(entries_.begin(), entries_.end(), [&](const Entry& e) {
      return e.last_scan != scan && close(e.value, value);
    });
    if (found == entries_.end()) {
      entries_.push_back({value, 0, scan});
      found = entries_.end() - 1;
    }
    found->value = value;
    found->last_scan = scan;
    if (++found->observations < min_observations_) return false;
    found->observations = -1;  // promoted
    return true;
  }
  // Drops the promoted candidates and those not seen for more than max_age_scans at `scan`.
  void Prune(std::size_t scan) {
    std::erase_if(entries_, [&](const Entry& e) {
      return e.observations < 0 || scan - e.last_scan > static_cast<std::size_t>(max_age_scans_);
    });
  }
  std::size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    Value value;
    int observations;
    std::size_t last_scan;
  };
  int min_observations_, max_age_scans_;
  std::vector<Entry> entries_;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_EKF_LANDMARK_CANDIDATES_H_
