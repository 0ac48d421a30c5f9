// Option values that passed Validate and then crashed, hung or allocated without bound, found by
// tests/fuzz/fuzz_option_values.cc: each is refused now, or made harmless
// where it is used.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <vector>

#include "estimation/ekf/ekf_bspline_slam.h"
#include "estimation/models.h"
#include "estimation/pose_graph/correlative_matcher.h"
#include "estimation/pose_graph/distance_grid.h"
#include "estimation/pose_graph/graph_slam.h"
#include "estimation/pose_graph/pose_graph.h"
#include "estimation/pose_graph/scan_registration.h"
#include "estimation/slam_method.h"
#include "estimation/spline_association.h"
#include "estimation/topological/topological_slam.h"
#include "exploration/explorer.h"
#include "exploration/motion.h"
#include "exploration/reg.h"
#include "exploration/srt.h"
#include "kernel/bspline_fit.h"
#include "kernel/curvature.h"
#include "kernel/curve_features.h"
#include "kernel/lines.h"
#include "kernel/local_safe_region.h"
#include "kernel/spline_extraction.h"
#include "sim/ray_caster.h"
#include "sim/simulator.h"

namespace splam::estimation {
namespace {

// Each option, defaults otherwise: the value the fuzzer found (or one like it) is refused, the
// default and a sensible other value pass.
template <class Options, class Field>
void ExpectDomain(Field Options::*field, std::vector<Field> refused, std::vector<Field> accepted,
                  const char* name) {
  EXPECT_TRUE(Options{}.Validate().ok()) << name;
  for (const Field& value : refused) {
    Options o;
    o.*field = value;
    EXPECT_FALSE(o.Validate().ok()) << name << " = " << ::testing::PrintToString(value);
  }
  for (const Field& value : accepted) {
    Options o;
    o.*field = value;
    EXPECT_TRUE(o.Validate().ok()) << name << " = " << ::testing::PrintToString(value);
  }
}

TEST(OptionDomains, ValuesTheFuzzerFoundAreRefused) {
  const double nan = std::nan("");
  // The topological SLAM walked its curve index cell by cell: 1e-300 m cells, a region of 1e212 m
  // (UBSan: a double beyond `long`).
  ExpectDomain(&TopologicalSlamOptions::index_cell_m, {1e-300, 0.0, 1e6, nan}, {0.5, 5.0},
               "index_cell_m");
  ExpectDomain(&TopologicalSlamOptions::region_margin_m, {1e12, -1.0, nan}, {0.0, 2.0},
               "region_margin_m");
  ExpectDomain(&kernel::LocalRegionOptions::radius_m, {100.0, 1000.0, 1e21, 0.0, nan}, {1.0, 30.0},
               "local region radius_m");
  // Correspondences every 1e-12 m along a curve: a hang.
  ExpectDomain(&SplineAssociationOptions::epsilon_m, {1e-12, 0.0, 100.0, nan}, {0.005, 0.1},
               "association epsilon_m");
  // Kernels of 3 sigma in samples, samples every epsilon: 10^11 of them.
  ExpectDomain(&kernel::CurvatureOptions::sigma_m, {1e9, 0.0, nan}, {0.01, 1.0}, "sigma_m");
  ExpectDomain(&kernel::CurvatureOptions::padding_fwhm, {1e9, -1.0, nan}, {0.0, 4.0},
               "padding_fwhm");
  ExpectDomain(&kernel::SplineExtractionOptions::epsilon_m, {1e-9, 1e-4, 10.0, nan}, {0.001, 0.05},
               "extraction epsilon_m");
  // 0.1 mm samples under a 5 cm smoothing: 3,000 taps at every sample of every curve, a hang
  // (found in the long run); a sigma of more than 1000 samples is refused with it.
  kernel::SplineExtractionOptions wide;
  wide.epsilon_m = 0.001;
  wide.curvature.sigma_m = 2.0;
  EXPECT_FALSE(wide.Validate().ok());
  wide.curvature.sigma_m = 0.5;
  EXPECT_TRUE(wide.Validate().ok());
  // The explorer: a move's step budget of 8e13 (UBSan: beyond `int`), an LSR of 1000 m (a
  // 6.4e9-cell planner grid).
  ExpectDomain(&exploration::MotionOptions::timeout_base_s, {1e12, 0.0, nan}, {1.0, 600.0},
               "timeout_base_s");
  ExpectDomain(&exploration::MotionOptions::timeout_per_meter_s, {1e12, -1.0, nan}, {0.0, 30.0},
               "timeout_per_meter_s");
  ExpectDomain(&exploration::MotionOptions::horizon_s, {1e6, 0.0, nan}, {0.5, 10.0}, "horizon_s");
  // A slowest turn rate of 1e-6 rad/s: TurnTowards' bound of a full turn at it was 1.3e8 steps,
  // an out-of-memory trace.
  ExpectDomain(&exploration::MotionOptions::angular_speeds_radps,
               {{1e-6, 0.8}, {0.0, -1e-9}, {20.0}, {nan}}, {{0.0, 0.001, -0.5}, {-10.0, 10.0}},
               "angular_speeds_radps");
  ExpectDomain(&exploration::ExplorerOptions::lsr_radius_m, {100.0, 1000.0, 0.0, nan}, {2.0, 30.0},
               "lsr_radius_m");
  ExpectDomain(&exploration::ExplorerOptions::arc_sampling_rad, {1e-12, 0.0, 10.0, nan},
               {0.001, 0.1}, "arc_sampling_rad");
  ExpectDomain(&exploration::ExplorerOptions::max_nodes, {0, -1, 2000000000}, {1, 1000},
               "max_nodes");
  ExpectDomain(&exploration::SrtOptions::max_attempts, {0, 1 << 30}, {1, 100}, "max_attempts");
  ExpectDomain(&exploration::RegOptions::piece_factor, {0.0, -1.0, 1e9, nan}, {0.5, 2.0},
               "piece_factor");
  ExpectDomain(&exploration::ExplorerOptions::max_time_s, {1e308, 0.0, nan}, {60.0, 1e6},
               "max_time_s");
  // ekf-lines: 1.9e9 RANSAC draws per line, a hang; counts of iterations and control points.
  ExpectDomain(&kernel::LineExtractionOptions::ransac_iterations, {0, 1885693042}, {1, 500},
               "ransac_iterations");
  ExpectDomain(&RegistrationOptions::max_iterations, {0, 1 << 30}, {1, 100}, "max_iterations");
  ExpectDomain(&PoseGraphOptions::max_iterations, {0, 1 << 30}, {1, 100}, "max_iterations");
  ExpectDomain(&kernel::BSplineFitOptions::max_control_points, {3, 1 << 30}, {8, 500},
               "max_control_points");
  ExpectDomain(&TopologicalSlamOptions::correction_rounds, {0, 1 << 30}, {1, 10},
               "correction_rounds");
  // A point sigma of 1e308 m: weights of 1e-616, a NaN pose (UBSan, found in the long run).
  // ... and 1e-300 m, whose square is zero (session 33: a NaN pose cast to a cell index).
  ExpectDomain(&TopologicalSlamOptions::point_sigma_m, {1e308, 0.0, 1e-300, 1e-7, nan},
               {1e-6, 0.01, 1.0}, "topological point_sigma_m");
  ExpectDomain(&RegistrationOptions::point_sigma_m, {1e308, 0.0, 1e-300, 1e-7, nan},
               {1e-6, 0.01, 1.0}, "registration point_sigma_m");
  // A corner margin of 1e308 m in samples: beyond size_t (UBSan, found in the long run).
  ExpectDomain(&kernel::FeatureOptions::corner_end_margin_m, {1e308, -1.0, nan}, {0.0, 0.5},
               "corner_end_margin_m");
  ExpectDomain(&kernel::FeatureOptions::corner_arm_length_m, {1e308, 0.0, nan}, {0.1, 1.0},
               "corner_arm_length_m");
  ExpectDomain(&EkfBSplineSlamOptions::extension_sample_spacing_m, {1e-29, 0.0, 100.0, nan},
               {0.01, 0.1}, "extension_sample_spacing_m");
  // Correction points every 1e-20 m along the curves: out of memory (found in the long run).
  ExpectDomain(&TopologicalSlamOptions::point_spacing_m, {1e-20, 1e-4, -1.0, nan}, {0.0, 0.05},
               "point_spacing_m");
  // A scale of 1.8e200: its square is infinite, the prediction's covariance and then the pose
  // NaN, cast to a beam index in the moving-object test (UBSan, found in the 10^5 run).
  ExpectDomain(&TopologicalSlamOptions::scan_matching_noise_scale, {1.8e200, 1e3, 0.0, nan},
               {0.1, 100.0}, "scan_matching_noise_scale");
  // Related control points at most infinitely far apart: the index lookups at -inf (UBSan).
  ExpectDomain(&SplineAssociationOptions::d_min_m,
               {std::numeric_limits<double>::infinity(), 100.0, 0.0, nan}, {0.4, 10.0}, "d_min_m");
  // A curve weight of 1e308: an infinite correction cost, a NaN pose cast to a cell (UBSan).
  ExpectDomain(&TopologicalSlamOptions::curve_weight, {1e308, 1e4, 0.0, nan}, {1.0, 1000.0},
               "curve_weight");
  // ekf-bspline: a control point floor of 1e6 m with 52 beams per match: the corrections threw
  // control points kilometres and resampling the curves took 100 s for 30 scans (a hang).
  ExpectDomain(&EkfBSplineSlamOptions::control_point_sigma_floor_m, {1e6, 11.0, -1.0, nan},
               {0.0, 10.0}, "control_point_sigma_floor_m");
  ExpectDomain(&EkfBSplineSlamOptions::model_sigma_m, {1e308, 11.0, -1.0, nan}, {0.0, 1.0},
               "model_sigma_m");
  ExpectDomain(&EkfBSplineSlamOptions::range_sigma_fraction, {1e308, 1.5, nan}, {0.0, 0.1},
               "range_sigma_fraction");
  ExpectDomain(&EkfBSplineSlamOptions::max_beams_per_match, {0, 1 << 30}, {1, 10000},
               "max_beams_per_match");
  ExpectDomain(&EkfBSplineSlamOptions::max_correspondence_distance_m, {1e308, 0.0, nan},
               {0.01, 10.0}, "max_correspondence_distance_m");
  // The odometry model's sigmas likewise (a variance of 1e400 is infinite).
  ExpectDomain(&OdometryNoiseModel::forward_per_m, {1e200, -0.1, nan}, {0.0, 0.3}, "forward_per_m");
  ExpectDomain(&OdometryNoiseModel::translation_floor_m, {1e200, 0.0, nan}, {1e-4, 0.1},
               "translation_floor_m");
}

// A heading step of 1e-12 rad (graph.front_end.advanced.recovery_step_rad) made 10^11 headings (a
// segfault as the count overflowed `int`): a step finer than a sixteenth of the one that moves the
// 90 % farthest point by a cell moves no point to another cell, and is raised to it.
TEST(OptionDomains, AHeadingStepFinerThanAnyCellChangeIsRaised) {
  std::vector<Eigen::Vector2d> points;
  for (double x = -3; x <= 3; x += 0.05) {
    points.emplace_back(x, 2.0);
    points.emplace_back(x, -2.0);
  }
  for (double y = -2; y <= 2; y += 0.05) points.emplace_back(3.0, y);
  const DistanceGrid grid = DistanceGrid::Build(points, 0.1, 0.5, 0.5);
  const LikelihoodPyramid pyramid(grid, 0.05, 5);
  const auto search = [&](double step) {
    return SearchCorrelative(points, pyramid, kernel::Pose2(0.1, 0.05, 0.02), 0.5, 0.1, 0.1, 0.9,
                             {.angular_step_rad = step});
  };
  const CorrelativeMatch tiny = search(1e-12), fine = search(1e-3);
  ASSERT_TRUE(tiny.found);
  EXPECT_LT(tiny.evaluated, 10 * fine.evaluated + 100000);
  EXPECT_LT(tiny.pose.translation().norm(), 0.15);
  EXPECT_LT(std::abs(tiny.pose.theta()), 0.01);
}

// Samples every 1 mm along the observed curves with 100 correction rounds (and control points
// every micrometre) took 16 s a scan under ASan: each round paired every sample with the map.
// A curve is now sampled no finer than its measured points lie apart (SampleSpacing): the dense
// refinement pairs at most as many samples as the scan has points.
TEST(OptionDomains, CurveSamplesAreNoDenserThanTheirPoints) {
  sim::World world;
  world.obstacles.push_back(sim::Polyline{{{-2, 1.5}, {2, 1.5}}, false});
  world.obstacles.push_back(sim::Polyline{{{-2, -1.5}, {2, -1.5}}, false});
  world.obstacles.push_back(sim::Polyline{{{2.5, -1}, {2.5, 1}}, false});
  const sim::RayCaster caster(world);
  sim::SimulatorOptions sim_options;
  sim_options.laser = sim::LaserOptions::Urg04lx();
  sim::Simulator simulator(caster, sim_options, kernel::Pose2(), 1);
  const kernel::Scan scan = simulator.Sense().scan;
  TopologicalSlamOptions options;
  options.point_spacing_m = 1e-3;
  options.correction_rounds = 100;
  options.extraction.fit.control_point_spacing_m = 1e-6;
  ASSERT_TRUE(options.Validate().ok());
  TopologicalSlam slam(kernel::Pose2(), options);
  ASSERT_GT(slam.Update(scan).added_curves, 0);
  const TopologicalUpdateReport report = slam.Update(scan);
  EXPECT_TRUE(report.dense);
  EXPECT_LE(report.dense_points, static_cast<int>(scan.HitPoints().size()));
  EXPECT_GT(report.dense_points, 100);
  EXPECT_LT(slam.pose().translation().norm(), 0.01);
}

// Sets the `target`-th number field of a visited struct (doubles, their lists and poses counted
// in visiting order) to `value`; counts them.
class NumberSetter : public kernel::FieldVisitor {
 public:
  NumberSetter(int target, double value) : target_(target), value_(value) {}
  int count() const { return next_; }
  void Field(std::string_view, double* v, std::string_view) override {
    if (next_++ == target_) *v = value_;
  }
  void Field(std::string_view, int*, std::string_view) override {}
  void Field(std::string_view, std::uint64_t*, std::string_view) override {}
  void Field(std::string_view, bool*, std::string_view) override {}
  void Field(std::string_view, std::string*, std::string_view) override {}
  void Field(std::string_view, std::vector<double>* v, std::string_view) override {
    if (next_++ == target_) v->assign(2, value_);
  }
  void Choice(std::string_view, int*, std::initializer_list<std::string_view>,
              std::string_view) override {}
  void Field(std::string_view, kernel::Pose2* v, std::string_view) override {
    if (next_++ == target_) *v = kernel::Pose2(value_, 0.0, 0.0);
  }
  void Group(std::string_view, std::string_view,
             const std::function<void(FieldVisitor&)>& fields) override {
    fields(*this);
  }

 private:
  int target_;
  double value_;
  int next_ = 0;
};

// Session 34's option fuzzer: a loop target of INT_MAX keyframes either side (its sum with
// min_gap_keyframes overflowed an int, UBSan) and the topological front end's seen margin of
// infinity (a view's vertex NaN, cast to a cell, UBSan). Every method's options refuse, before
// their own checks (SlamOptionsOf::Validate), any number that is not finite and any integer beyond
// kernel::kMaxCount, naming the field: each number field of each method set to +inf, -inf and
// NaN in turn.
TEST(OptionDomains, EveryMethodRefusesNumbersThatAreNotFiniteAndHugeCounts) {
  GraphSlamOptions graph;
  graph.loop.target_keyframes = std::numeric_limits<int>::max();
  EXPECT_EQ(SlamOptionsOf<GraphSlamOptions>(graph).Validate().message(),
            "loop.target_keyframes must be a finite number (an integer at most 100000000 in "
            "magnitude)");
  graph.loop.target_keyframes = kernel::kMaxCount;
  EXPECT_TRUE(kernel::FiniteFields(graph).ok());
  TopologicalSlamOptions topological;
  topological.scan_matching.front_end.advanced.seen_margin_m =
      std::numeric_limits<double>::infinity();
  EXPECT_FALSE(SlamOptionsOf<TopologicalSlamOptions>(topological).Validate().ok());
  const SlamRegistry& registry = SlamRegistry::Global();
  int refused = 0;
  for (const std::string& name : registry.Names()) {
    const std::unique_ptr<SlamOptions> defaults = registry.Find(name)->default_options({});
    ASSERT_TRUE(defaults->Validate().ok()) << name;
    NumberSetter counter(-1, 0.0);
    defaults->VisitFields(counter);
    for (int i = 0; i < counter.count(); ++i)
      for (const double value : {std::numeric_limits<double>::infinity(),
                                 -std::numeric_limits<double>::infinity(), std::nan("")}) {
        const std::unique_ptr<SlamOptions> options = defaults->Clone();
        NumberSetter setter(i, value);
        options->VisitFields(setter);
        const kernel::Status status = options->Validate();
        ASSERT_FALSE(status.ok()) << name << " field " << i << " = " << value;
        ASSERT_NE(status.message().find("must be a finite number"), std::string::npos)
            << status.message();
        ++refused;
      }
  }
  EXPECT_GT(refused, 300);
}

}  // namespace
}  // namespace splam::estimation
