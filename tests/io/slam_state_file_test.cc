#include "io/slam_state_file.h"

#include <gtest/gtest.h>

#include <cmath>

#include "io/trajectory.h"
#include "kernel/random.h"

namespace splam::io {
namespace {

std::string TempPath(const std::string& name) { return ::testing::TempDir() + "/" + name; }

// A state of random numbers: every one must come back as exactly the same double.
estimation::SlamState RandomState(std::uint64_t seed) {
  kernel::Random random(seed);
  estimation::SlamState state;
  state.method = "graph";
  for (int i = 0; i < 20; ++i)
    state.map.keyframes.emplace_back(random.Uniform(-50, 50), random.Uniform(-50, 50),
                                     random.Uniform(-3, 3));
  state.map.loop_edges = {{0, 19}, {3, 12}};
  for (int i = 0; i < 5; ++i) {
    std::vector<Eigen::Vector2d> control;
    for (int k = 0; k < 4 + i; ++k)
      control.emplace_back(random.Uniform(-9, 9), random.Uniform(-9, 9));
    state.map.splines.push_back(
        {i * 3, *kernel::CubicBSpline::ClampedUniform(std::move(control)), 0});
  }
  for (int i = 0; i < 10; ++i) {
    estimation::MapScan m;
    m.pose = kernel::Pose2(random.Uniform(-50, 50), random.Uniform(-50, 50), random.Uniform(-3, 3));
    m.robot_T_laser = kernel::Pose2(0.1, 0.0, 0.0);
    m.scan.timestamp_s = 1e9 + random.Uniform(0, 100);
    m.scan.start_angle_rad = -M_PI / 2;
    m.scan.angular_step_rad = M_PI / 180;
    m.scan.min_range_m = 0.02;
    m.scan.max_range_m = 30.0;
    for (int b = 0; b < 181; ++b)
      m.scan.ranges_m.push_back(b % 17 == 0 ? kernel::Scan::kNoReturn : random.Uniform(0.1, 30));
    state.scans.push_back(std::move(m));
  }
  return state;
}

TEST(SlamStateFile, RoundTripIsExact) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const estimation::SlamState state = RandomState(seed);
    const std::string path = TempPath("state_round_trip.state");
    ASSERT_TRUE(WriteSlamState(path, state).ok());
    const Result<estimation::SlamState> read = ReadSlamState(path);
    ASSERT_TRUE(read.ok()) << read.error;
    EXPECT_EQ(read->method, "graph");
    ASSERT_EQ(read->map.keyframes.size(), state.map.keyframes.size());
    EXPECT_EQ(read->map.loop_edges, state.map.loop_edges);
    ASSERT_EQ(read->map.splines.size(), state.map.splines.size());
    for (std::size_t i = 0; i < state.map.splines.size(); ++i) {
      EXPECT_EQ(read->map.splines[i].id, state.map.splines[i].id);
      EXPECT_EQ(read->map.splines[i].spline.control_points(),
                state.map.splines[i].spline.control_points());
      EXPECT_EQ(read->map.splines[i].spline.knots(), state.map.splines[i].spline.knots());
    }
    ASSERT_EQ(read->scans.size(), state.scans.size());
    for (std::size_t i = 0; i < state.scans.size(); ++i) {
      EXPECT_EQ(read->scans[i].pose.translation(), state.scans[i].pose.translation());
      EXPECT_EQ(read->scans[i].pose.theta(), state.scans[i].pose.theta());
      EXPECT_EQ(read->scans[i].scan.ranges_m, state.scans[i].scan.ranges_m);
      EXPECT_EQ(read->scans[i].scan.timestamp_s, state.scans[i].scan.timestamp_s);
    }
    // Written again, the same bytes.
    const std::string again = TempPath("state_again.state");
    ASSERT_TRUE(WriteSlamState(again, *read).ok());
    std::string a, b;
    ASSERT_TRUE(ReadTextFile(path, &a).ok() && ReadTextFile(again, &b).ok());
    EXPECT_EQ(a, b);
  }
}

TEST(SlamStateFile, BadFilesNameFileAndLine) {
  const auto error = [](const std::string& text) {
    const std::string path = TempPath("bad.state");
    EXPECT_TRUE(WriteTextFile(path, text).ok());
    const Result<estimation::SlamState> read = ReadSlamState(path);
    EXPECT_FALSE(read.ok()) << text;
    return read.ok() ? std::string() : read.error.substr(path.size());
  };
  EXPECT_EQ(error(""), ": empty: not a splam state file");
  EXPECT_EQ(error("time x y theta\n"),
            ":1: not a splam state file (its first line must be 'splam_state 1')");
  EXPECT_EQ(error("splam_state 2\n"), ":1: state format '2' is not known (1 is)");
  EXPECT_EQ(error("splam_state 1\nkeyframe 0 0 0\n"), ": no 'method' line");
  EXPECT_EQ(error("splam_state 1\nmethod graph\nkeyframe 0 nan 0\n"),
            ":3: 'nan' is not a finite number");
  EXPECT_EQ(error("splam_state 1\nmethod graph\nkeyframe 0 0 0\nloop_edge 0 1\n"),
            ":4: loop_edge: expected two indices of keyframes above it");
  EXPECT_EQ(error("splam_state 1\nmethod graph\nspline 1 4 0 0 1 1\n"),
            ":3: spline: expected id, n >= 4, n control points and n + 4 knots");
  EXPECT_EQ(error("splam_state 1\nmethod graph\nspline 1 4 0 0 1 1 2 2 3 3 0 0 0 0 1 1 1 0.5\n"),
            ":3: spline: knots must be finite and non-decreasing");
  // Issue 70, item 6: control points of 1e15 or 1e300 loaded, and the run ended at map.dxf.
  EXPECT_EQ(error("splam_state 1\nmethod graph\nspline 3 4 1e300 0 1 1 2 2 3 3 0 0 0 0 1 1 1 1\n"),
            ":3: spline 3: control point 0 (1e+300, 0) is not finite or beyond +-1e+06 m");
  EXPECT_EQ(error("splam_state 1\nmethod graph\nspline 3 4 0 0 1 1 2 1e15 3 3 0 0 0 0 1 1 1 1\n"),
            ":3: spline 3: control point 2 (2, 1e+15) is not finite or beyond +-1e+06 m");
  EXPECT_EQ(error("splam_state 1\nmethod graph\nscan 0 0 0 0 0 0 0 0 0.1 0 4 3 1 2\n"),
            ":3: scan: 3 ranges announced, 2 given");
  EXPECT_EQ(error("splam_state 1\nmethod graph\nscan 0 0 0 0 0 0 0 0 0.1 5 4 1 1\n"),
            ":3: scan: minimum range 5 m is not in [0, 4) (the maximum range)");
  EXPECT_EQ(error("splam_state 1\nmethod graph\nscan 2e6 0 0 0 0 0 0 0 0.1 0 4 1 1\n"),
            ":3: scan: pose 2e+06 is not finite or beyond +-1e+06 m");
  EXPECT_EQ(error("splam_state 1\nmethod graph\nkeyframe 0 1e300 0\n"),
            ":3: keyframe 1e+300 is not finite or beyond +-1e+06 m");
  EXPECT_EQ(error("splam_state 1\nmethod gr\xff"
                  "aph\n"),
            ":2: method: expected one name of letters, digits, '-' and '_', not 'gr\xff"
            "aph'");
  EXPECT_EQ(error("splam_state 1\nmethod graph\nscan 0 0 inf 0 0 0 0 0 0.1 0 4 1 1\n"),
            ":3: 'inf' is not a finite number");
  EXPECT_EQ(error("splam_state 1\nmethod graph\ncurve 1 2\n"),
            ":3: unknown line 'curve' (known: method, keyframe, loop_edge, spline, scan)");
}

}  // namespace
}  // namespace splam::io
