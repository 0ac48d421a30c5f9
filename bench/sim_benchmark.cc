// Ray casting cost of the simulator. The target: one URG-04LX scan (667 beams) in the
// `complex` world in at most 100 microseconds on one core.
#include <benchmark/benchmark.h>

#include "kernel/random.h"
#include "sim/builtin_worlds.h"
#include "sim/laser.h"
#include "sim/ray_caster.h"
#include "sim/simulator.h"

namespace {

using splam::kernel::Pose2;

// Free poses spread along the built-in route of the world.
std::vector<Pose2> PosesAlongRoute(const splam::sim::World& world,
                                   const splam::sim::RayCaster& caster) {
  splam::sim::SimulatorOptions options;
  splam::sim::Simulator simulator(caster, options, *world.start, 7);
  const auto run = splam::sim::FollowRoute(&simulator, world.route, {});
  std::vector<Pose2> poses;
  for (std::size_t i = 0; i < run.frames.size(); i += 10) poses.push_back(run.frames[i].true_pose);
  return poses;
}

void BM_Urg04lxScanComplex(benchmark::State& state) {
  splam::sim::RayCasterOptions caster_options;
  caster_options.cell_size_m = static_cast<double>(state.range(0)) / 100.0;
  const splam::sim::World world = *splam::sim::BuiltinWorld("complex");
  const splam::sim::RayCaster caster(world, caster_options);
  const std::vector<Pose2> poses = PosesAlongRoute(world, caster);
  const splam::sim::LaserOptions laser = splam::sim::LaserOptions::Urg04lx();
  splam::kernel::Random random(1);
  std::size_t i = 0;
  for (auto _ : state) {
    const auto scan =
        splam::sim::SimulateLaser(caster, laser, poses[i++ % poses.size()], 0.0, &random);
    benchmark::DoNotOptimize(scan.ranges_m.data());
  }
  state.SetItemsProcessed(state.iterations() * laser.num_beams);
}
// Argument: grid cell size in centimetres.
BENCHMARK(BM_Urg04lxScanComplex)->Arg(25)->Arg(50)->Arg(100)->Unit(benchmark::kMicrosecond);

void BM_Urg04lxScanComplexBruteForce(benchmark::State& state) {
  const splam::sim::World world = *splam::sim::BuiltinWorld("complex");
  const splam::sim::RayCaster caster(world);
  const std::vector<Pose2> poses = PosesAlongRoute(world, caster);
  const splam::sim::LaserOptions laser = splam::sim::LaserOptions::Urg04lx();
  std::size_t i = 0;
  for (auto _ : state) {
    const Pose2& pose = poses[i++ % poses.size()];
    double sum = 0.0;
    for (int b = 0; b < laser.num_beams; ++b) {
      const double angle = pose.theta() + laser.start_angle_rad + b * laser.angular_step_rad;
      splam::kernel::Ray2 ray{pose.translation(), {std::cos(angle), std::sin(angle)}};
      sum += caster.CastBruteForce(ray, laser.max_range_m).range_m;
    }
    benchmark::DoNotOptimize(sum);
  }
}
BENCHMARK(BM_Urg04lxScanComplexBruteForce)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
