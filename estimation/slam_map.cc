#include "estimation/slam_map.h"

namespace splam::estimation {

const char* OutcomeName(LoopSearch::Outcome outcome) {
  switch (outcome) {
    case LoopSearch::Outcome::kPending:
      return "pending";
    case LoopSearch::Outcome::kAccepted:
      return "accepted";
    case LoopSearch::Outcome::kScore:
      return "score";
    case LoopSearch::Outcome::kAmbiguous:
      return "ambiguous";
    case LoopSearch::Outcome::kRegistration:
      return "registration";
    case LoopSearch::Outcome::kMisfit:
      return "misfit";
    case LoopSearch::Outcome::kUnconfirmed:
      return "unconfirmed";
    case LoopSearch::Outcome::kUndone:
      return "undone";
  }
  return "?";
}

}  // namespace splam::estimation
