// splam experiment: the published experiments, reproduced on the simulator.
//
// corridor-lines (paper 001 §6): EKF-SLAM with lines and corners on a straight run of 160 steps
// through the `corridor` world, started 2.7 deg off the corridor axis, with a SICK LMS-200.
// Reports, as 001 Table 1, nine distances between mapped corners next to their true values, and
// checks the filter's consistency: the average NEES of the robot pose over the seeded runs must
// stay inside the 95 % chi-square band for at least 90 % of the steps.
#include <fmt/core.h>

#include "apps/commands.h"
#include "apps/interrupt.h"
#include "io/world_file.h"
#include "runtime/exit_status.h"
#include "studies/bspline_experiment.h"
#include "studies/corridor_experiment.h"
#include "studies/exploration_experiment.h"
#include "studies/splam_experiment.h"

namespace splam::apps {
namespace {

struct ExperimentArgs {
  std::string name = "corridor-lines";
  int runs = 0;  // 0: the experiment's default (corridor-lines 20, complex-bspline 10)
  int max_scans = 0;
  double odometry_noise_scale = 1.0;            // complex-bspline
  double max_correspondence_distance_m = 0.15;  // complex-bspline
  int steps = 160;
  double speed_mps = 1.0;
  std::uint64_t seed = 1;
  std::string out;
  std::string world = "complex";      // splam
  double resolution_m_per_px = 0.05;  // splam, floor-plan images
  bool corners = true;
  double corner_floor_m = 0.01;
  double odometry_floor = 1e-4;
  double line_floor_scale = 1.0;            // scales the line floors of 1 mm and 0.5 mrad
  std::string association = "nearest";      // corridor-lines: nearest or jcbb
  std::string match_selection = "longest";  // complex-bspline: longest or jcbb
  int jobs = 0;                             // splam: trials at once (0: one per core)
};

int RunCorridorLines(const ExperimentArgs& args) {
  studies::CorridorOptions options;
  options.runs = args.runs;
  options.steps = args.steps;
  options.speed_mps = args.speed_mps;
  options.seed = args.seed;
  options.corners = args.corners;
  options.corner_floor_m = args.corner_floor_m;
  options.odometry_floor = args.odometry_floor;
  options.line_floor_scale = args.line_floor_scale;
  options.association = args.association == "jcbb" ? estimation::EkfAssociation::kJointCompatibility
                                                   : estimation::EkfAssociation::kNearestNeighbour;
  options.splam_binary = SplamBinary();
  options.jobs = args.jobs;
  CatchInterrupts();
  options.stop = [] { return Interrupted(); };
  return studies::RunCorridorLinesExperiment(options, args.out);
}

template <typename Args>
Args WithCommonArgs(const ExperimentArgs& given) {
  Args args;
  args.runs = given.runs > 0 ? given.runs : args.runs;
  args.seed = given.seed;
  args.out = given.out.empty() ? args.out : given.out;
  return args;
}

}  // namespace

void AddExperimentCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<ExperimentArgs>();
  CLI::App* cmd =
      app->add_subcommand("experiment", "Reproduce a published experiment on the simulator.");
  cmd->add_option("name", args->name,
                  "Experiment: corridor-lines (paper 001 section 6), complex-bspline (paper 000 "
                  "Figs. 15-17), exploration (paper 003 Fig. 18) or splam (paper 003 Figs. "
                  "19-22: SRT + ekf-lines, SRT + ekf-bspline, REG + topological; and REG + graph)")
      ->check(CLI::IsMember({"corridor-lines", "complex-bspline", "exploration", "splam"}))
      ->capture_default_str();
  cmd->add_option("--runs", args->runs, "Seeded runs (default: 20 corridor-lines, 10 the others)")
      ->check(FinitePositive());
  cmd->add_option("--max-scans", args->max_scans,
                  "complex-bspline: stop each route after this many scans (0 = the whole route)")
      ->check(FiniteNonNegative());
  cmd->add_option("--steps", args->steps, "Steps (scans) of the straight run")
      ->check(FinitePositive())
      ->capture_default_str();
  cmd->add_option("--speed", args->speed_mps, "Forward speed, m/s (0.1 s per step)")
      ->check(FinitePositive())
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "Seed of the first run; run i uses seed + i")
      ->check(Seed())
      ->capture_default_str();
  cmd->add_option("--out", args->out, "Output directory (default runs/experiment-<name>)");
  cmd->add_option("--world", args->world,
                  "splam: the world, a built-in name (corridor, office, office-long, office-doors, "
                  "complex, loop, curves, halls), a YAML world file or a floor-plan image; "
                  "complex-bspline: a built-in world with a route (complex, curves, ...)")
      ->capture_default_str();
  cmd->add_option("--resolution", args->resolution_m_per_px,
                  "splam: metres per pixel of a floor-plan image")
      ->check(FloorPlanResolution())
      ->capture_default_str();
  cmd->add_option("--jobs", args->jobs,
                  "Trials (seeds, strategies) run at once (default: one per core)")
      ->check(FinitePositive());
  cmd->add_option("--odometry-noise", args->odometry_noise_scale,
                  "complex-bspline: scale of the odometry noise (simulated and modelled)")
      ->check(FinitePositive())
      ->check(OdometryNoiseScale())
      ->capture_default_str();
  cmd->add_option("--max-correspondence", args->max_correspondence_distance_m,
                  "complex-bspline: largest distance (m) between a beam's predicted hit and the "
                  "map point its association paired it with; 10 (the largest) switches the test "
                  "off")
      ->check(CLI::Range(1e-9, 10.0))
      ->capture_default_str();
  cmd->add_flag("!--no-corners", args->corners, "Use lines only, no corner landmarks");
  cmd->add_option("--line-floor-scale", args->line_floor_scale,
                  "Scale of the line noise floors (1 mm, 0.5 mrad)")
      ->check(FinitePositive())
      ->capture_default_str();
  cmd->add_option("--corner-floor", args->corner_floor_m, "Corner measurement noise floor, m")
      ->capture_default_str();
  cmd->add_option("--association", args->association,
                  "corridor-lines: the EKF's association, nearest neighbour (paper 001) or joint "
                  "compatibility branch and bound")
      ->check(CLI::IsMember({"nearest", "jcbb"}))
      ->capture_default_str();
  cmd->add_option("--match-selection", args->match_selection,
                  "complex-bspline: which matches correct the B-spline EKF, the longest first or "
                  "the largest jointly compatible set (jcbb)")
      ->check(CLI::IsMember({"longest", "jcbb"}))
      ->capture_default_str();
  cmd->add_option("--odometry-floor", args->odometry_floor,
                  "Odometry noise floors per step (m and rad)")
      ->check(FinitePositive())
      ->capture_default_str();
  cmd->callback([args, exit_code] {
    if (args->name == "splam") {
      studies::SplamExperimentArgs s = WithCommonArgs<studies::SplamExperimentArgs>(*args);
      io::FloorPlanOptions floor_plan;
      floor_plan.resolution_m_per_px = args->resolution_m_per_px;
      io::Result<sim::World> world = io::LoadValidWorld(args->world, floor_plan);
      if (!world.ok()) {
        fmt::print(stderr, "splam experiment: {}\n", world.error);
        *exit_code = runtime::kExitBadInput;
        return;
      }
      s.world = std::move(*world.value);
      s.world_name = args->world;
      s.resolution_m_per_px = args->resolution_m_per_px;
      s.splam_binary = SplamBinary();
      s.jobs = args->jobs;
      CatchInterrupts();
      s.stop = [] { return Interrupted(); };
      *exit_code = studies::RunSplamExperiment(s);
      return;
    }
    if (args->name == "exploration") {
      studies::ExplorationExperimentArgs e =
          WithCommonArgs<studies::ExplorationExperimentArgs>(*args);
      e.splam_binary = SplamBinary();
      e.jobs = args->jobs;
      CatchInterrupts();
      e.stop = [] { return Interrupted(); };
      *exit_code = studies::RunExplorationExperiment(e);
      return;
    }
    if (args->name == "complex-bspline") {
      studies::BSplineExperimentArgs b = WithCommonArgs<studies::BSplineExperimentArgs>(*args);
      b.max_scans = args->max_scans;
      b.odometry_noise_scale = args->odometry_noise_scale;
      b.max_correspondence_distance_m = args->max_correspondence_distance_m;
      b.match_selection = args->match_selection;
      b.world = args->world;
      b.splam_binary = SplamBinary();
      b.jobs = args->jobs;
      CatchInterrupts();
      b.stop = [] { return Interrupted(); };
      *exit_code = studies::RunComplexBSpline(b);
      return;
    }
    ExperimentArgs a = *args;
    a.runs = a.runs > 0 ? a.runs : 20;
    a.out = a.out.empty() ? "runs/experiment-corridor-lines" : a.out;
    *exit_code = RunCorridorLines(a);
  });
}

}  // namespace splam::apps
