// Feature-extraction cost per scan: a URG-04LX scan of the `complex` world
// through segmentation, B-spline fitting, resampling, smoothing, curvature and features in at
// most 1 ms, and line extraction from an LMS-200 scan in at most 0.5 ms, on one core.
#include <benchmark/benchmark.h>

#include "kernel/lines.h"
#include "kernel/spline_extraction.h"
#include "sim/builtin_worlds.h"
#include "sim/simulator.h"

namespace {

// Scans taken along the built-in route of a world, every 10th frame.
std::vector<splam::kernel::Scan> ScansAlongRoute(const std::string& name,
                                                 const splam::sim::LaserOptions& laser) {
  const splam::sim::World world = *splam::sim::BuiltinWorld(name);
  const splam::sim::RayCaster caster(world);
  splam::sim::SimulatorOptions options;
  options.laser = laser;
  splam::sim::Simulator simulator(caster, options, *world.start, 3);
  const auto run = splam::sim::FollowRoute(&simulator, world.route, {});
  std::vector<splam::kernel::Scan> scans;
  for (std::size_t i = 0; i < run.frames.size(); i += 10) scans.push_back(run.frames[i].scan);
  return scans;
}

void BM_SplineFeaturesUrg04lxComplex(benchmark::State& state) {
  const auto scans = ScansAlongRoute("complex", splam::sim::LaserOptions::Urg04lx());
  const splam::kernel::SplineExtractionOptions options;
  std::size_t i = 0, curves = 0;
  for (auto _ : state) {
    const auto result = splam::kernel::ExtractCurves(scans[i++ % scans.size()], options);
    curves += result.size();
    benchmark::DoNotOptimize(result.data());
  }
  state.counters["curves_per_scan"] =
      static_cast<double>(curves) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_SplineFeaturesUrg04lxComplex)->Unit(benchmark::kMicrosecond);

void BM_LinesLms200(benchmark::State& state) {
  const auto scans = ScansAlongRoute(state.range(0) == 0 ? "office" : "corridor",
                                     splam::sim::LaserOptions::Lms200());
  const splam::kernel::LineExtractionOptions options;
  std::size_t i = 0, lines = 0;
  for (auto _ : state) {
    const auto result = splam::kernel::ExtractLines(scans[i++ % scans.size()], options);
    lines += result.lines.size();
    benchmark::DoNotOptimize(result.lines.data());
  }
  state.counters["lines_per_scan"] =
      static_cast<double>(lines) / static_cast<double>(state.iterations());
}
// Argument: 0 = office, 1 = corridor.
BENCHMARK(BM_LinesLms200)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
