#ifndef SPLAM_ESTIMATION_POSE_GRAPH_LOOP_CLOSER_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_LOOP_CLOSER_H_

#include <Eigen/Core>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <vector>

#include "estimation/pose_graph/background.h"
#include "estimation/pose_graph/correlative_matcher.h"
#include "estimation/pose_graph/distance_grid.h"
#include "estimation/pose_graph/graph_slam_options.h"
#include "estimation/pose_graph/keyframes.h"
#include "estimation/pose_graph/pose_graph.h"
#include "estimation/slam_map.h"
#include "kernel/pose2.h"

namespace splam::estimation {

// Agreement of two loop closures on keyframe c, the newer of their `to` keyframes. The older
// closure puts its own keyframe b at by_older (covariance older_covariance, of a right
// perturbation, as a closure edge's) and c at by_older * chain, where chain = b_T_c is the
// front-end chain between them (covariance chain_covariance, at c); the newer puts c at by_newer.
// Returns the difference of the two poses of c, whitened by the sum of the three covariances
// propagated to c: chi^2(3) when both closures are right.
double ClosureDisagreementChi2(const kernel::Pose2& by_older,
                               const Eigen::Matrix3d& older_covariance, const kernel::Pose2& chain,
                               const Eigen::Matrix3d& chain_covariance,
                               const kernel::Pose2& by_newer,
                               const Eigen::Matrix3d& newer_covariance);

// The largest set of closures 0..n-1 that agree pairwise (agree(i, j)), the graph as it is
// counting as one more member of a set whose every closure agrees with it (with_graph[i]); grown
// greedily from each member in turn, the graph first (so it wins ties). Empty when no set has two
// members.
std::vector<int> LargestAgreeingSet(const std::vector<bool>& with_graph,
                                    const std::function<bool(int, int)>& agree);

// Of `placed` (a query's points placed in the target's frame), the fraction that lie where the
// target saw free space (DistanceGrid::SeenFree) at least inlier_distance_m from its outline:
// points that contradict the pose (a point where the target did not look says nothing). 0 when
// `placed` is empty.
double SeenFreeMisfitFraction(const DistanceGrid& target, const std::vector<OrientedPoint>& placed,
                              double inlier_distance_m);

// A closure that passed its search's tests and waits to be added to the graph.
struct PendingClosure {
  PoseGraphEdge edge;        // from the candidate keyframe to the query keyframe
  const LoopSearch* search;  // the search that found it (window_m > near_window_m: a wide one)
};

// What an acceptance policy may read when it decides.
struct ClosureContext {
  const Keyframes& keyframes;
  const PoseGraph& graph;  // as it is, without the pending closures
  int newest = 0;          // the newest keyframe
  bool final = false;      // the data has ended: a closure told to wait is refused
  // Whether two closures put the newer of their `to` keyframes at the same pose
  // (ClosureDisagreementChi2 at most loop.max_chi2, the chain between them by the front-end
  // edge model), when their `to` keyframes are at most loop.confirm_keyframes apart.
  std::function<bool(const PoseGraphEdge&, const PoseGraphEdge&)> agree;
};

enum class ClosureVerdict {
  kAccept,  // added to the graph now
  kWait,    // kept for the next decision (refused at the end of the data)
  kRefuse,  // dropped, counted as unconfirmed
};

// How the loop closer accepts the closures its searches found: the replaceable part of loop
// closure (after Cartographer's constraint builder, which scores and the pose graph, which
// accepts). Decide is called every optimize_every_keyframes keyframes after a closure was found,
// and at the end of the data, with every closure pending; it returns one verdict per closure.
class ClosureAcceptance {
 public:
  virtual ~ClosureAcceptance() = default;
  virtual std::vector<ClosureVerdict> Decide(const std::vector<PendingClosure>& pending,
                                             const ClosureContext& context) = 0;
};

// The built-in acceptance (LoopClosureOptions::confirm_keyframes): a closure that agrees with
// the graph as it is stands alone; one that would move it needs a second that agrees with it;
// the largest agreeing set is accepted (LargestAgreeingSet), the others wait confirm_keyframes.
// A wide search's closure that disagrees with a near search's of keyframes at most
// confirm_keyframes apart is left out. At the end of the data a young closure stands alone when
// it agrees with the graph and with the set accepted.
class AgreementAcceptance : public ClosureAcceptance {
 public:
  explicit AgreementAcceptance(const LoopClosureOptions& options) : options_(options) {}
  std::vector<ClosureVerdict> Decide(const std::vector<PendingClosure>& pending,
                                     const ClosureContext& context) override;

 private:
  LoopClosureOptions options_;
};

// What the back end did with the closures it was given (GraphBackEnd::AddClosures).
struct ClosureReport {
  bool deferred = false;  // added without a whole optimisation (all stand)
  bool moved = false;     // an optimisation moved the keyframes (a submap built on them is stale)
  // The closures checked against the optimised graph (those given and those that waited in it
  // unoptimised), by their tags: the ones that stand, and the ones removed for disagreeing.
  std::vector<int> stand, undone;
};

// The loop closer of the graph SLAM (after Cartographer's ConstraintBuilder2D): for every new
// keyframe, candidates among the older keyframes, a correlative search of its query against each
// candidate's target, and the tests (LoopClosureOptions); the closures found wait until the
// acceptance (a ClosureAcceptance) lets them into the graph. The search may run on a second
// thread beside the front end (background_search); it reads keyframes at least
// min_gap_keyframes older than the new one, the new one's pose and the graph, and writes
// nothing but its target cache and those keyframes' loop-target view rasters.
class LoopCloser {
 public:
  // What the loop closer takes of the front end that feeds it: the model of its edges, chained
  // between two closures to tell whether they agree, and how many of the newest keyframes it may
  // still change (the search runs on a second thread only when it reads none of them).
  struct FrontEnd {
    EdgeModel edge;
    int settling_keyframes = 0;
  };
  static FrontEnd FrontEndOf(const FrontEndOptions& options) {
    return {options.edge, options.moving_keyframes};
  }
  // `keyframes` and `graph` outlive the loop closer; `acceptance` null: AgreementAcceptance.
  LoopCloser(const LoopClosureOptions& options, const FrontEnd& front_end,
             const Keyframes* keyframes, const PoseGraph* graph,
             std::unique_ptr<ClosureAcceptance> acceptance = nullptr);
  // Whether the keyframes must keep the view of their beams that returned
  // (GraphFrontEnd's hit_views): the correlative score of where they passed is in use.
  static bool NeedsHitViews(const LoopClosureOptions& options) {
    return options.enabled && options.advanced.seen_free_score < 0;
  }
  // A search may be running on `this`.
  LoopCloser(const LoopCloser&) = delete;
  LoopCloser& operator=(const LoopCloser&) = delete;
  ~LoopCloser();

  // Starts the searches of the new keyframe k, made when the front end had travelled
  // travelled_m; none before keyframe min_gap_keyframes, nor without `enabled`. Only
  // one runs at a time: call
  // Collect before the keyframes or the graph change.
  void Start(int k, double travelled_m);
  // Waits for the running search and records what it found. The travel of its keyframe when the
  // closures found are due for a decision (optimize_every_keyframes after the first), else
  // nullopt.
  std::optional<double> Collect();
  // The closures the acceptance lets in now, with their searches' indices as tags; those it
  // refuses are recorded, the others wait.
  struct Accepted {
    std::vector<PoseGraphEdge> closures;
    std::vector<int> tags;
  };
  Accepted Decide(bool final);
  // Records what the back end did with the `added` closures last accepted, found at travelled_m.
  void Record(const ClosureReport& report, std::size_t added, double travelled_m);
  // The closures still waiting.
  const std::vector<PoseGraphEdge>& waiting() const { return pending_; }

  const LoopClosureCounts& counts() const { return loops_; }
  // Every search, in order.
  std::vector<LoopSearch> searches() const { return {searches_.begin(), searches_.end()}; }
  // Wall time of the searches, and how long Collect waited for them, ms.
  double search_ms() const { return search_ms_; }
  double wait_ms() const { return wait_ms_; }

 private:
  // One search (MatchLoop): its record, and the closure when it passed the tests.
  struct LoopFinding {
    LoopSearch record;
    std::optional<PoseGraphEdge> edge;
    bool near = false;  // by the first search (see AddFinding)
  };
  // The searches of keyframe k, made when the front end had travelled travelled_m.
  struct LoopSearchRun {
    int keyframe = -1;
    double travelled_m = 0.0;
    std::vector<LoopFinding> findings;  // in search order
    double time_ms = 0.0;
  };
  bool BackgroundSearch() const;
  // Searches keyframe k against earlier ones, `since_m` travelled since the last closure, with
  // `query` (its points and those of the query_keyframes before it, in its frame, thinned
  // to resolution_m).
  LoopSearchRun Search(int k, double travelled_m, double since_m,
                       const std::vector<OrientedPoint>& query);
  // The wide search of LoopClosureOptions at keyframe k, whose first window was near_m wide.
  void SearchWide(int k, const std::vector<OrientedPoint>& query, double near_m,
                  std::vector<LoopFinding>* findings);
  // Searches keyframe k's query against the candidate's target within the windows; the closure
  // when the match passes the tests. Records the search in *record.
  std::optional<PoseGraphEdge> MatchLoop(int k, const std::vector<OrientedPoint>& query,
                                         int candidate, double window_m, double window_rad,
                                         LoopSearch* record);
  // Records a search of keyframe k; a closure it found waits in pending_. One found by the first
  // (`near`) search restarts, at travelled_m, the travel that widens that search's radius.
  void AddFinding(int k, LoopFinding finding, double travelled_m);
  // Whether closures a and b put the newer of their keyframes at the same pose.
  bool Agree(const PoseGraphEdge& a, const PoseGraphEdge& b) const;
  // A loop target: the candidate and up to target_keyframes keyframes holding data on
  // either side of it, none newer than `newest`.
  std::vector<int> TargetKeyframes(int candidate, int newest) const;
  // A loop target's field and likelihood pyramid, built from these keyframes at these poses;
  // kept for the next searches of the same keyframes until one of them moves (an optimisation
  // of part of the graph leaves the older keyframes where they were).
  struct LoopTarget {
    std::vector<int> keyframes;
    std::vector<Eigen::Vector3d> poses;  // PosesOf(keyframes) when it was built
    std::unique_ptr<DistanceGrid> grid;
    std::unique_ptr<LikelihoodPyramid> pyramid;  // of *grid
  };
  const LoopTarget& Target(const std::vector<int>& keyframes);

  LoopClosureOptions options_;
  FrontEnd front_end_;
  const Keyframes* keyframes_;
  const PoseGraph* graph_;
  std::unique_ptr<ClosureAcceptance> acceptance_;
  std::vector<PoseGraphEdge> pending_;  // closures found, not yet in the graph
  std::vector<int> pending_searches_;   // their searches_ indices
  std::deque<LoopSearch> searches_;     // the run's record of every search
  double closure_at_m_ = 0.0;           // travelled when the last closure was found
  std::vector<LoopTarget> targets_;     // the last loop targets built (Target; search only)
  int unflushed_since_ = -1;            // keyframe of the first closure found since the last
  LoopClosureCounts loops_;
  double search_ms_ = 0.0, wait_ms_ = 0.0;
  // The search's thread (background_search); null when it runs on the calling thread.
  std::unique_ptr<Background> background_;
  // The latest keyframe's search (Start), waited for by the destructor.
  std::future<LoopSearchRun> run_;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_LOOP_CLOSER_H_
