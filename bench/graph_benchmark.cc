// Graph SLAM parts (issues 16 and 49): one scan-to-submap registration, one submap build and one
// keyframe inserted into it, one loop-closure search and one optimisation of a 1,000- and a
// 5,000-keyframe pose graph. Run with --benchmark_repetitions=5 for medians.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "estimation/pose_graph/correlative_matcher.h"
#include "estimation/pose_graph/distance_grid.h"
#include "estimation/pose_graph/graph_slam.h"
#include "estimation/pose_graph/pose_graph.h"
#include "estimation/pose_graph/scan_registration.h"
#include "estimation/pose_graph/scan_view.h"
#include "kernel/random.h"
#include "sim/builtin_worlds.h"
#include "sim/laser.h"
#include "sim/ray_caster.h"

namespace splam::estimation {
namespace {

using kernel::Pose2;

// Scans of the simulated LMS-200 (361 beams, 8 m) in `complex` from poses along x.
struct Scans {
  Scans() : world(*sim::BuiltinWorld("complex")), caster(world) {}
  std::vector<Eigen::Vector2d> At(const Pose2& pose) { return ScanAt(pose).HitPoints(); }
  kernel::Scan ScanAt(const Pose2& pose) {
    return sim::SimulateLaser(caster, sim::LaserOptions::Lms200(), pose, 0.0, &random);
  }
  std::vector<OrientedPoint> WorldAt(const Pose2& pose) {
    std::vector<OrientedPoint> points = OrientTowards(At(pose), Eigen::Vector2d::Zero(), 0.3);
    for (auto& p : points) p = {pose * p.point, pose.Rotation() * p.normal};
    return points;
  }
  sim::World world;
  sim::RayCaster caster;
  kernel::Random random{5};
};

void BM_GraphRegistration(benchmark::State& state) {
  Scans scans;
  std::vector<OrientedPoint> submap;
  for (int i = 0; i < 10; ++i) {
    const auto part = scans.WorldAt(Pose2(4.0 + 0.3 * i, 3.0, 0.2));
    submap.insert(submap.end(), part.begin(), part.end());
  }
  const DistanceGrid grid = DistanceGrid::Build(submap, 0.1, 0.5, 0.5);
  const Pose2 truth(5.5, 3.05, 0.22);
  const std::vector<Eigen::Vector2d> scan = scans.At(truth);
  const Pose2 prior = truth * Pose2(0.08, -0.05, 0.03);
  for (auto _ : state) {
    const RegistrationResult r = RegisterPoints(scan, grid, prior, RegistrationOptions{});
    benchmark::DoNotOptimize(r.pose);
  }
  state.counters["points"] = static_cast<double>(scan.size());
}
BENCHMARK(BM_GraphRegistration)->Unit(benchmark::kMillisecond);

// A submap as the graph SLAM makes it (GraphFrontEnd::UpdateSubmap): the points of 30 keyframes
// 0.3 m apart with their views (the part of the plane they saw, rasterised once per keyframe),
// into a 10 cm field truncated at 0.5 m with 1.2 m of room for the inserts; then the 31st
// keyframe, 0.3 m on, inserted into it.
struct Submap {
  explicit Submap(int keyframes) {
    Scans scans;
    for (int i = 0; i < keyframes; ++i) {
      const Pose2 at(2.0 + 0.3 * i, 3.0 + 0.1 * std::sin(i), 0.1 * std::sin(i));
      points.push_back(scans.WorldAt(at));
      const kernel::Scan scan = scans.ScanAt(at);
      views.push_back(RasteriseView(at * ScanView(scan, Pose2(), scan.max_range_m, 0.2), 0.1, 0.2));
    }
  }
  DistanceGrid Build(int keyframes) const {
    std::vector<OrientedPoint> all;
    std::vector<const ViewCells*> seen;
    for (int i = 0; i < keyframes; ++i) {
      all.insert(all.end(), points[i].begin(), points[i].end());
      seen.push_back(&views[i]);
    }
    return DistanceGrid::Build(all, 0.1, 0.5, 1.7, seen, false, {});
  }
  std::vector<std::vector<OrientedPoint>> points;
  std::vector<ViewCells> views;
};

void BM_GraphSubmapBuild(benchmark::State& state) {
  const Submap submap(30);
  for (auto _ : state) {
    const DistanceGrid grid = submap.Build(30);
    benchmark::DoNotOptimize(grid.values().data());
  }
  state.counters["cells"] = static_cast<double>(submap.Build(30).values().size());
}
BENCHMARK(BM_GraphSubmapBuild)->Unit(benchmark::kMillisecond);

void BM_GraphSubmapInsert(benchmark::State& state) {
  const Submap submap(31);
  const DistanceGrid built = submap.Build(30);
  for (auto _ : state) {
    state.PauseTiming();
    DistanceGrid grid = built;
    state.ResumeTiming();
    if (!grid.Insert(submap.points[30], {&submap.views[30]})) state.SkipWithError("no room");
    benchmark::DoNotOptimize(grid.values().data());
  }
}
BENCHMARK(BM_GraphSubmapInsert)->Unit(benchmark::kMillisecond);

// A loop-closure search as the graph SLAM runs it: target grid and pyramid built from 31
// keyframes, query of 11, a 3 m x 3 m x +-0.35 rad window, down to the score a closure needs
// when half the query's points fall where the target has seen (the target's views, which
// the graph SLAM rasterises as well, are left out).
void BM_GraphLoopSearch(benchmark::State& state) {
  Scans scans;
  std::vector<OrientedPoint> target;
  for (int i = 0; i < 31; ++i) {
    const auto part = scans.WorldAt(Pose2(3.0 + 0.2 * i, 3.0, 0.1 * std::sin(i)));
    target.insert(target.end(), part.begin(), part.end());
  }
  const Pose2 truth(5.0, 3.1, 0.05);
  std::vector<Eigen::Vector2d> query;
  for (int i = 0; i < 11; ++i) {
    const Pose2 at = truth * Pose2(-0.2 * i, 0.0, 0.0);
    for (const auto& p : scans.At(at)) query.push_back(truth.Inverse() * (at * p));
  }
  const Pose2 guess = truth * Pose2(1.2, -0.8, 0.25);
  const GraphSlamOptions options;
  for (auto _ : state) {
    const DistanceGrid grid = DistanceGrid::Build(target, 0.1, 0.5, 0.5);
    const LikelihoodPyramid pyramid(grid, 0.05, 5);
    const CorrelativeMatch m = SearchCorrelative(
        query, pyramid, guess, 3.0, 0.35, options.loop.min_score * options.loop.min_overlap, 0.9);
    benchmark::DoNotOptimize(m.pose);
  }
  state.counters["query_points"] = static_cast<double>(query.size());
}
BENCHMARK(BM_GraphLoopSearch)->Unit(benchmark::kMillisecond);

// N keyframes on a random walk with 2 cm / 0.3 deg edges and N / 5 loop closures between random
// keyframes, at their dead-reckoning poses.
PoseGraph RandomWalkGraph(int n) {
  std::mt19937 gen(11);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<Pose2> truth = {Pose2()};
  for (int i = 1; i < n; ++i)
    truth.push_back(truth.back() * Pose2(0.3, 0.0, 0.3 * std::sin(0.05 * i)));
  const Eigen::Matrix3d information = Eigen::Vector3d(2500, 2500, 40000).asDiagonal();
  PoseGraph base;
  Pose2 dead = truth.front();
  base.AddNode(dead);
  for (std::size_t i = 1; i < truth.size(); ++i) {
    const Pose2 m = truth[i - 1].Between(truth[i]) *
                    Pose2(0.02 * noise(gen), 0.02 * noise(gen), 0.005 * noise(gen));
    dead = dead * m;
    base.AddNode(dead);
    base.AddEdge({static_cast<int>(i) - 1, static_cast<int>(i), m, information, false});
  }
  std::uniform_int_distribution<int> node(0, n - 1);
  for (int k = 0; k < n / 5; ++k) {
    const int a = node(gen), b = node(gen);
    if (std::abs(a - b) < 50) continue;
    base.AddEdge({a, b,
                  truth[static_cast<std::size_t>(a)].Between(truth[static_cast<std::size_t>(b)]),
                  information, true});
  }
  return base;
}

// The graph above optimised from dead reckoning.
void BM_PoseGraph(benchmark::State& state) {
  const PoseGraph base = RandomWalkGraph(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    PoseGraph graph = base;
    const PoseGraphSummary s = graph.Optimize(PoseGraphOptions{});
    benchmark::DoNotOptimize(s.final_cost);
  }
}
BENCHMARK(BM_PoseGraph)->Arg(1000)->Arg(5000)->Unit(benchmark::kMillisecond);

// What active loop closing asks at a decision (GraphSlam::RevisitInformation): the joint
// covariances of the newest keyframe with every 8th keyframe (an exploration node every 2.4 m
// of 0.3 m keyframes), one factorisation of the optimised graph.
void BM_RevisitCovariances(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  PoseGraph graph = RandomWalkGraph(n);
  graph.Optimize(PoseGraphOptions{});
  std::vector<int> nodes;
  for (int i = 1; i < n - 1; i += 8) nodes.push_back(i);
  for (auto _ : state) {
    const auto joints = graph.JointCovariancesWith(n - 1, nodes, PoseGraphOptions{});
    benchmark::DoNotOptimize(joints);
  }
}
BENCHMARK(BM_RevisitCovariances)->Arg(500)->Arg(2000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace splam::estimation

BENCHMARK_MAIN();
