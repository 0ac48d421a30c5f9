// End-to-end tests of the `splam` binary: exit codes, messages and the files it writes.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "io/carmen.h"
#include "io/map_export.h"
#include "io/occupancy_grid_file.h"
#include "io/simulation_log.h"
#include "io/text.h"
#include "io/trajectory.h"
#include "tests/apps/cli_util.h"

namespace splam {
namespace {

namespace fs = std::filesystem;
using namespace cli_test;  // NOLINT: the helpers of every CLI test

TEST(SplamCli, SimulateComplexWritesAReproducibleRun) {
  const fs::path a = Temp("sim_a"), b = Temp("sim_b"), c = Temp("sim_c");
  const Output ra = Splam("simulate --world complex --seed 4 --out " + a.string());
  ASSERT_EQ(ra.status, 0) << ra.text;
  EXPECT_NE(ra.text.find("14/14 waypoints"), std::string::npos) << ra.text;
  ASSERT_EQ(Splam("simulate --world complex --seed 4 --out " + b.string()).status, 0);
  ASSERT_EQ(Splam("simulate --world complex --seed 5 --out " + c.string()).status, 0);
  for (const char* file : {"log.clf", "truth.txt", "odometry.txt", "world.yaml", "run.svg",
                           "run.png", "summary.json"}) {
    ASSERT_TRUE(fs::exists(a / file)) << file;
    EXPECT_EQ(Slurp(a / file), Slurp(b / file))
        << file << " differs between two runs with the same seed";
  }
  EXPECT_NE(Slurp(a / "log.clf"), Slurp(c / "log.clf"));

  // The log holds what the summary says, with ground truth that follows the route.
  const auto summary = nlohmann::json::parse(Slurp(a / "summary.json"));
  EXPECT_TRUE(summary["completed"].get<bool>());
  const io::CarmenReadResult log = io::ReadCarmenLog((a / "log.clf").string());
  ASSERT_TRUE(log.log.ok()) << log.log.error;
  EXPECT_EQ(log.log.value->Lasers().size(), summary["scans"].get<std::size_t>());
  EXPECT_EQ(log.log.value->Lasers()[0]->scan.size(), 667u);
  const io::Trajectory truth = io::TrueTrajectory(*log.log.value);
  EXPECT_LT((truth.back().pose.translation() - Eigen::Vector2d(1.5, 2.0)).norm(), 0.1);
  const io::Result<io::Trajectory> truth_file = io::ReadTrajectory((a / "truth.txt").string());
  ASSERT_TRUE(truth_file.ok());
  EXPECT_EQ(truth_file.value->size(), truth.size());
  // Odometry drifts, but by a few per cent of the distance at most.
  const double drift = summary["final_odometry_error"]["position_m"].get<double>();
  EXPECT_GT(drift, 0.0);
  EXPECT_LT(drift, 0.1 * summary["distance_m"].get<double>());
}

TEST(SplamCli, SimulateWithRouteFileLaserChoiceAndSonar) {
  const fs::path dir = Temp("route");
  fs::create_directories(dir);
  ASSERT_EQ(
      io::WriteTextFile((dir / "route.txt").string(), "# start pose then waypoints\n1 6 0\n5 6\n")
          .message(),
      "");
  const Output r = Splam("simulate --world office --route " + (dir / "route.txt").string() +
                         " --laser lms200 --sonar --out " + (dir / "run").string());
  ASSERT_EQ(r.status, 0) << r.text;
  const io::CarmenReadResult log = io::ReadCarmenLog((dir / "run" / "log.clf").string());
  ASSERT_TRUE(log.log.ok());
  EXPECT_EQ(log.log.value->Lasers()[0]->scan.size(), 361u);
  int sonar = 0;
  for (const auto& m : log.log.value->messages)
    sonar += std::holds_alternative<io::SonarMessage>(m);
  EXPECT_EQ(sonar, static_cast<int>(log.log.value->Lasers().size()));
}

TEST(SplamCli, BadInputGivesAClearMessageAndExitCode2) {
  const fs::path dir = Temp("bad");
  fs::create_directories(dir);
  ASSERT_EQ(io::WriteTextFile((dir / "w.yaml").string(),
                              "obstacles:\n  - circle: {center: [1, 1], radius: -2}\n")
                .message(),
            "");
  Output r =
      Splam("simulate --world " + (dir / "w.yaml").string() + " --out " + (dir / "o").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find((dir / "w.yaml").string() + ":2: radius must be positive"),
            std::string::npos)
      << r.text;

  r = Splam("simulate --world atlantis");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("atlantis: not a built-in world"), std::string::npos) << r.text;

  ASSERT_EQ(io::WriteTextFile((dir / "route.txt").string(), "1 6 0\n5 six\n").message(), "");
  r = Splam("simulate --world office --route " + (dir / "route.txt").string() + " --out " +
            (dir / "o").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("route.txt:2: 'six' is not a finite number"), std::string::npos) << r.text;

  ASSERT_EQ(io::WriteTextFile((dir / "bad.clf").string(), "ODOM 1 2 3 0 0 0 1 h 1\nFLASER 3 1 2\n")
                .message(),
            "");
  r = Splam("render --log " + (dir / "bad.clf").string() + " --out " + (dir / "x.png").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("bad.clf:2: FLASER: line ends early"), std::string::npos) << r.text;

  ASSERT_EQ(io::WriteTextFile((dir / "plan.png").string(), "not an image").message(), "");
  r = Splam("simulate --world " + (dir / "plan.png").string() + " --route " +
            (dir / "route.txt").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("plan.png: not a PNG, JPEG, PGM/PPM/PBM, BMP or TIFF image"),
            std::string::npos)
      << r.text;

  r = Splam("simulate --laser lidar9000");
  EXPECT_EQ(r.status, 2);
  r = Splam("frobnicate");
  EXPECT_EQ(r.status, 2);
}

TEST(SplamCli, CollisionStopsTheRunButWritesWhatWasDone) {
  const fs::path dir = Temp("collide");
  fs::create_directories(dir);
  // Straight through the office wall at y = 5.
  ASSERT_EQ(io::WriteTextFile((dir / "route.txt").string(), "1 6 -1.5707963\n1 2\n").message(), "");
  const Output r = Splam("simulate --world office --route " + (dir / "route.txt").string() +
                         " --out " + (dir / "o").string());
  EXPECT_EQ(r.status, 3) << r.text;
  EXPECT_NE(r.text.find("collision at t ="), std::string::npos) << r.text;
  EXPECT_TRUE(fs::exists(dir / "o" / "log.clf"));
  EXPECT_TRUE(fs::exists(dir / "o" / "run.png"));
  const auto summary = nlohmann::json::parse(Slurp(dir / "o" / "summary.json"));
  EXPECT_FALSE(summary["completed"].get<bool>());
}

TEST(SplamCli, RenderDrawsWorldsAndLogs) {
  const fs::path dir = Temp("render");
  ASSERT_EQ(
      Splam("simulate --world corridor --laser lms200 --out " + (dir / "sim").string()).status, 0);
  const Output r = Splam("render --world corridor --log " + (dir / "sim" / "log.clf").string() +
                         " --trajectory " + (dir / "sim" / "odometry.txt").string() + " --out " +
                         (dir / "r.png").string() + " " + (dir / "r.svg").string());
  ASSERT_EQ(r.status, 0) << r.text;
  EXPECT_GT(fs::file_size(dir / "r.png"), 1000u);
  EXPECT_GT(fs::file_size(dir / "r.svg"), 1000u);
  EXPECT_EQ(Splam("render").status, 2);
  // An empty log, a directory or binary junk drew a blank picture with exit 0.
  ASSERT_EQ(io::WriteTextFile((dir / "empty.clf").string(), "").message(), "");
  ASSERT_EQ(
      io::WriteTextFile((dir / "junk.clf").string(), std::string("\x7f\x01\x02\0x", 5)).message(),
      "");
  for (const std::string log : {"empty.clf", "junk.clf", "."}) {
    const Output bad =
        Splam("render --log " + (dir / log).string() + " --out " + (dir / "bad.png").string());
    EXPECT_EQ(bad.status, 2) << log << ": " << bad.text;
    EXPECT_FALSE(fs::exists(dir / "bad.png")) << log;
  }
}

// A ROS bag in, the same trajectory out. A simulated log converted to a bag and back:
// SLAM on the bag and on the bag's CARMEN conversion give the same file; against the original
// log (float32 ranges in the bag) it agrees to 0.1 mm when both use the same laser noise (a bag
// carries no laser model, so the defaults differ).
// A simulated run as a ROS 1 bag, a ROS 2 MCAP file and a ROS 2 SQLite3 bag: the same
// trajectory as from the CARMEN log (ranges are float32 in ROS messages: within 1e-4 m), and
// exactly the same after a round trip back to CARMEN.
class RosBagFormats : public ::testing::TestWithParam<const char*> {};

TEST_P(RosBagFormats, SlamOnABagGivesTheSameTrajectoryAsOnTheLog) {
  const fs::path dir = Temp(std::string("bag_") + (GetParam() + 1));
  ASSERT_EQ(Splam("simulate --world office --seed 2 --out " + (dir / "sim").string()).status, 0);
  const std::string log = (dir / "sim" / "log.clf").string();
  const std::string bag = (dir / (std::string("run") + GetParam())).string();
  const std::string back = (dir / "back.clf").string();
  Output r = Splam("convert " + log + " " + bag);
  ASSERT_EQ(r.status, 0) << r.text;
  EXPECT_NE(r.text.find("2006 scans"), std::string::npos) << r.text;
  ASSERT_EQ(Splam("convert " + bag + " " + back).status, 0);
  const std::string noise = " --method ekf-lines --range-sigma 0.003 --range-sigma-fraction 0.01";
  for (const auto& [in, out] :
       {std::pair{bag, "from_bag"}, {back, "from_back"}, {log, "from_log"}}) {
    r = Splam("slam " + in + noise + " --out " + (dir / out).string());
    ASSERT_EQ(r.status, 0) << r.text;
  }
  const auto poses = [&](const char* run) {
    const auto t = io::ReadTrajectory((dir / run / "trajectory.txt").string());
    EXPECT_TRUE(t.ok());
    return t.ok() ? *t.value : io::Trajectory{};
  };
  const io::Trajectory from_bag = poses("from_bag"), from_back = poses("from_back"),
                       from_log = poses("from_log");
  ASSERT_EQ(from_bag.size(), 2006u);
  ASSERT_EQ(from_back.size(), from_bag.size());
  ASSERT_EQ(from_log.size(), from_bag.size());
  for (std::size_t i = 0; i < from_bag.size(); ++i) {
    EXPECT_EQ(from_bag[i].pose.ToVector(), from_back[i].pose.ToVector()) << i;
    EXPECT_NEAR(from_bag[i].time_s, from_log[i].time_s, 1e-9) << i;  // ROS time: ns
    EXPECT_LT((from_bag[i].pose.translation() - from_log[i].pose.translation()).norm(), 1e-4) << i;
  }
  // The bag's topics are listed when one cannot be chosen.
  r = Splam("slam " + bag + " --scan-topic /front --out " + (dir / "bad").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("no topic /front; the bag's topics: /ground_truth (nav_msgs/Odometry"),
            std::string::npos)
      << r.text;
}

INSTANTIATE_TEST_SUITE_P(SplamCli, RosBagFormats, ::testing::Values(".bag", ".mcap", ".db3"),
                         [](const auto& format) { return std::string(format.param + 1); });

TEST(SplamCli, SlamWithLinesOnASimulatedOfficeBeatsOdometry) {
  const fs::path dir = Temp("slam");
  ASSERT_EQ(Splam("simulate --world office --seed 2 --out " + (dir / "sim").string()).status, 0);
  const Output r = Splam("slam --method ekf-lines " + (dir / "sim" / "log.clf").string() +
                         " --out " + (dir / "ekf").string());
  ASSERT_EQ(r.status, 0) << r.text;
  for (const char* file : {"trajectory.txt", "odometry.txt", "truth.txt", "map.txt", "map.dxf",
                           "map.svg", "map.png", "errors.svg", "errors.png", "summary.json"}) {
    EXPECT_TRUE(fs::exists(dir / "ekf" / file)) << file;
  }
  const auto summary = nlohmann::json::parse(Slurp(dir / "ekf" / "summary.json"));
  EXPECT_TRUE(summary["health"]["healthy"].get<bool>());
  const double ekf = summary["error"]["estimate"]["rmse_position_m"].get<double>();
  const double odometry = summary["error"]["odometry"]["rmse_position_m"].get<double>();
  EXPECT_LT(ekf, 0.05);
  EXPECT_LT(ekf, odometry / 3);
  EXPECT_GT(summary["map"]["lines"].get<int>(), 15);
  EXPECT_GT(summary["associations"]["accepted"].get<int>(), 1000);
  EXPECT_GT(summary["nees"]["mean"].get<double>(), 0.0);
  const auto dxf = io::ReadDxf((dir / "ekf" / "map.dxf").string());
  ASSERT_TRUE(dxf.ok());
  EXPECT_EQ(dxf.value->segments.size(), summary["map"]["lines"].get<std::size_t>());

  // splam eval on the run directory: against the truth, and with relations built from it.
  std::string relations;
  const auto truth = io::ReadTrajectory((dir / "ekf" / "truth.txt").string());
  ASSERT_TRUE(truth.ok());
  for (std::size_t i = 0; i + 20 < truth.value->size(); i += 20) {
    const auto& a = (*truth.value)[i];
    const auto& b = (*truth.value)[i + 20];
    const kernel::Pose2 m = a.pose.Between(b.pose);
    relations += io::FormatDouble(a.time_s) + " " + io::FormatDouble(b.time_s) + " " +
                 io::FormatDouble(m.x()) + " " + io::FormatDouble(m.y()) + " 0 0 0 " +
                 io::FormatDouble(m.theta()) + "\n";
  }
  ASSERT_EQ(io::WriteTextFile((dir / "run.relations").string(), relations).message(), "");
  const Output e =
      Splam("eval " + (dir / "ekf").string() + " --relations " + (dir / "run.relations").string());
  ASSERT_EQ(e.status, 0) << e.text;
  const auto report = nlohmann::json::parse(Slurp(dir / "ekf" / "eval.json"));
  EXPECT_NEAR(report["truth"]["estimate"]["rmse_position_m"].get<double>(), ekf, 1e-9);
  EXPECT_EQ(report["relations"]["estimate"]["relations_used"].get<std::size_t>(),
            truth.value->size() / 20);
  EXPECT_LT(report["relations"]["estimate"]["translation_m"]["mean"].get<double>(),
            report["relations"]["odometry"]["translation_m"]["mean"].get<double>());
  EXPECT_TRUE(fs::exists(dir / "ekf" / "eval_errors.png"));
}

TEST(SplamCli, SlamWithBSplinesOnTheComplexWorldBeatsOdometry) {
  const fs::path dir = Temp("slam_bspline");
  ASSERT_EQ(Splam("simulate --world complex --seed 4 --out " + (dir / "sim").string()).status, 0);
  for (const char* association : {"pedraza", "curvature"}) {
    const fs::path out = dir / association;
    const Output r = Splam("slam --method ekf-bspline --association " + std::string(association) +
                           " " + (dir / "sim" / "log.clf").string() + " --out " + out.string());
    ASSERT_EQ(r.status, 0) << r.text;
    for (const char* file : {"trajectory.txt", "map.txt", "map.dxf", "map.png", "errors.png"})
      EXPECT_TRUE(fs::exists(out / file)) << file;
    const auto summary = nlohmann::json::parse(Slurp(out / "summary.json"));
    EXPECT_EQ(summary["association"], association);
    EXPECT_TRUE(summary["health"]["healthy"].get<bool>());
    const double ekf = summary["error"]["estimate"]["rmse_position_m"].get<double>();
    const double odometry = summary["error"]["odometry"]["rmse_position_m"].get<double>();
    EXPECT_LT(ekf, 0.06);
    EXPECT_LT(ekf, odometry / 4);
    const int splines = summary["map"]["splines"].get<int>();
    EXPECT_GT(splines, 8);
    EXPECT_GT(summary["associations"]["beams_used"].get<int>(), 10000);
    // The text map has one line per spline; the DXF one POINT per control point.
    const std::string text = Slurp(out / "map.txt");
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), splines + 2);
    const auto dxf = io::ReadDxf((out / "map.dxf").string());
    ASSERT_TRUE(dxf.ok());
    EXPECT_EQ(dxf.value->points.size(), summary["map"]["control_points"].get<std::size_t>());
    EXPECT_GT(dxf.value->segments.size(), 100u);
  }
}

TEST(SplamCli, ComplexBSplineExperimentComparesBothAssociations) {
  const fs::path dir = Temp("experiment_bspline");
  const Output r =
      Splam("experiment complex-bspline --runs 2 --max-scans 800 --out " + dir.string());
  ASSERT_EQ(r.status, 0) << r.text;
  const auto report = nlohmann::json::parse(Slurp(dir / "report.json"));
  for (const char* method : {"pedraza", "curvature"}) {
    EXPECT_LT(report[method]["rmse_position_m"].get<double>(),
              report["odometry"]["rmse_position_m"].get<double>())
        << method;
    EXPECT_LT(report[method]["map_error_m"].get<double>(), 0.05) << method;
    EXPECT_LT(report[method]["wrong_association_fraction"].get<double>(), 0.05) << method;
    EXPECT_EQ(report[method]["per_seed_rmse_position_m"].size(), 2u);
  }
  for (const char* file : {"table.md", "errors.png", "map_pedraza.png", "map_curvature.png"})
    EXPECT_TRUE(fs::exists(dir / file)) << file;
}

// Option values that are not numbers a run can use. CLI11's PositiveNumber and
// NonNegativeNumber let NaN through, and an unsigned seed read "-1" as 2^64 - 1.
TEST(SplamCli, OptionValuesMustBeFiniteAndInRange) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"simulate --seed -1", "--seed: must be an integer from 0"},
      {"explore --seed -3", "--seed: must be an integer from 0"},
      {"experiment exploration --seed x1", "--seed: must be an integer from 0"},
      {"slam --range-sigma nan x.clf", "--range-sigma: must be a finite number at least 0"},
      {"slam --odometry-noise nan x.clf", "--odometry-noise: must be a finite number in [0, 100]"},
      {"slam --flaser-step-deg nan x.clf", "--flaser-step-deg: must be a finite number at least 0"},
      {"slam --flaser-max-range inf x.clf", "--flaser-max-range: must be a finite number above 0"},
      {"simulate --resolution 1e-9", "--resolution: must be a finite number in [0.0001, 10]"},
      {"simulate --resolution 1e300", "--resolution: must be a finite number in [0.0001, 10]"},
      {"explore --alpha nan", "--alpha: must be a finite number in [0, 1]"},
      {"explore --odometry-noise inf", "--odometry-noise: must be a finite number in [0, 100]"},
      // Wrote poses of 1e304 m, a log its own readers refuse.
      {"simulate --odometry-noise 1e308", "--odometry-noise: must be a finite number in [0, 100]"},
      {"experiment complex-bspline --odometry-noise 1e308",
       "--odometry-noise: must be a finite number in [0, 100]"},
      // Said "alpha must be below -30.700000".
      {"explore --lsr-radius 0.01", "the LSR radius r = 0.01 m leaves no room for the robot"}};
  for (const auto& [args, message] : cases) {
    const Output r = Splam(args);
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_NE(r.text.find(message), std::string::npos) << args << ": " << r.text;
  }
}

// Worlds that were accepted and then broke the run, and explore on a floor-plan image
// (it always said "has no start pose", with no way to give one).
TEST(SplamCli, WorldsThatCannotBeRunAreRefusedAndAFloorPlanTakesAStart) {
  const fs::path dir = Temp("worlds");
  fs::create_directories(dir);
  const auto write = [&](const std::string& name, const std::string& text) {
    return WriteIn(dir, name, text);
  };
  const std::vector<std::pair<std::string, std::string>> refused = {
      {"simulate --world " +
           write("bow.yaml", "obstacles:\n  - polygon: [[0, 0], [2, 2], [2, 0], [0, 2]]\n"),
       "bow.yaml:2: edges 0 and 2 cross: a polygon must not intersect itself"},
      {"simulate --world " +
           write("dot.yaml", "obstacles:\n  - spline: [[1, 1], [1, 1], [1, 1], [1, 1]]\n"),
       "dot.yaml:2: all control points are the same point"},
      {"render --world " +
           write("far.yaml", "obstacles:\n  - circle: {center: [1e300, 0], radius: 1}\n"),
       "far.yaml:2: not finite or beyond +-1e6 m"},
      {"explore --localization ground-truth --world " +
           write("outside.yaml",
                 "start: [-0.3, 5, 0]\nobstacles:\n  - polyline: [[0, 0], [10, 0], "
                 "[10, 8], [0, 8], [0, 0]]\n"),
       "is not enclosed by walls"},
      {"explore --localization ground-truth --world " +
           write("away.yaml",
                 "start: [100, 100, 0]\nobstacles:\n  - polyline: [[0, 0], [10, 0], [10, 8], [0, "
                 "8], [0, 0]]\n"),
       "lies outside the world"},
      // A 200 km world's coverage grid of 0.1 m cells (4e12) was allocated;
      // it now has at most 2^22 cells, and says so when the start is lost in one.
      {"explore --localization ground-truth --world " +
           write("huge.yaml",
                 "start: [10, 10, 0]\nobstacles:\n  - polyline: [[0, 0], [200000, 0], [200000, "
                 "200000], [0, 200000], [0, 0]]\n  - circle: {center: [14, 10], radius: 1}\n"),
       "whose cells are 97.7 m in a world of 200000 m x 200000 m"}};
  for (const auto& [args, message] : refused) {
    // render writes a picture, the others a directory.
    const fs::path out = dir / (args.starts_with("render") ? "out.svg" : "out");
    const Output r = Splam(args + " --out " + out.string());
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_NE(r.text.find(message), std::string::npos) << args << ": " << r.text;
  }
  // A 6 m x 4 m floor plan at 5 cm per pixel: two rooms behind a 1 m door; and a solid block.
  cv::Mat plan(80, 120, CV_8U, cv::Scalar(255));
  cv::rectangle(plan, cv::Rect(0, 0, 120, 80), cv::Scalar(0), 4);
  cv::rectangle(plan, cv::Rect(59, 0, 2, 30), cv::Scalar(0), cv::FILLED);
  cv::rectangle(plan, cv::Rect(59, 50, 2, 30), cv::Scalar(0), cv::FILLED);
  ASSERT_TRUE(cv::imwrite((dir / "plan.png").string(), plan));
  ASSERT_TRUE(cv::imwrite((dir / "solid.png").string(), cv::Mat(80, 120, CV_8U, cv::Scalar(0))));
  const std::string explore = "explore --localization ground-truth --out " + (dir / "e").string();
  Output r = Splam(explore + " --world " + (dir / "plan.png").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("has no start pose: give one with --start X,Y,THETA"), std::string::npos)
      << r.text;
  r = Splam(explore + " --world " + (dir / "plan.png").string() + " --start 0.05,0.05,0");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("the start pose (0.05, 0.05) lies on a dark pixel"), std::string::npos)
      << r.text;
  // Issue 70: an all-black image was explored as free space; it is refused wherever the start.
  for (const char* start : {"2,2,0", "-1,-1,0", "6.5,2,0"}) {
    r = Splam(explore + " --world " + (dir / "solid.png").string() + " --start " + start);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.text.find("every pixel is dark (below grey level 128): a solid block"),
              std::string::npos)
        << r.text;
  }
  r = Splam(explore + " --world " + (dir / "plan.png").string() + " --start 1.5,2,0");
  EXPECT_NE(r.status, 2) << r.text;
  const auto report = nlohmann::json::parse(Slurp(dir / "e" / "report.json"));
  EXPECT_GT(report["coverage_fraction"].get<double>(), 0.9) << r.text;
}

// Work already done is written. A malformed line halfway through a log: the scans
// before it are processed and written, exit 3. Ctrl-C during slam or explore: the same.
TEST(SplamCli, ABadLineHalfwayOrCtrlCStillWritesTheWorkDone) {
  const fs::path dir = Temp("partial");
  ASSERT_EQ(Splam("simulate --world corridor --out " + (dir / "sim").string()).status, 0);
  std::string text = Slurp(dir / "sim" / "log.clf");
  const std::size_t half = text.find("\nROBOTLASER1", text.size() / 2);
  ASSERT_NE(half, std::string::npos);
  text.insert(half + 1, "ODOM 1 2\n");
  const int bad_line =
      static_cast<int>(std::count(text.begin(), text.begin() + half + 1, '\n')) + 1;
  ASSERT_EQ(io::WriteTextFile((dir / "cut.clf").string(), text).message(), "");
  Output r = Splam("slam --method ekf-lines " + (dir / "cut.clf").string() + " --out " +
                   (dir / "cut").string());
  EXPECT_EQ(r.status, 3) << r.text;
  EXPECT_NE(r.text.find("cut.clf:" + std::to_string(bad_line) + ": ODOM: line ends early"),
            std::string::npos)
      << r.text;
  const auto all = io::ReadCarmenLog((dir / "sim" / "log.clf").string());
  ASSERT_TRUE(all.log.ok());
  const auto done = io::ReadTrajectory((dir / "cut" / "trajectory.txt").string());
  ASSERT_TRUE(done.ok());
  EXPECT_GT(done.value->size(), all.log.value->Lasers().size() / 3);
  EXPECT_LT(done.value->size(), all.log.value->Lasers().size());
  const auto summary = nlohmann::json::parse(Slurp(dir / "cut" / "summary.json"));
  EXPECT_NE(summary["stopped_early"].get<std::string>().find("line ends early"), std::string::npos);

  // Ctrl-C: a B-spline EKF run over `complex` (3.4 s alone) and an exploration, each stopped
  // after a second (the run's, once it has written config.yaml: on a loaded machine the second
  // could pass before it started, and the SIGINT killed it).
  ASSERT_EQ(Splam("simulate --world complex --out " + (dir / "complex").string()).status, 0);
  const auto started = std::chrono::steady_clock::now();
  EXPECT_EQ(
      SplamInterruptedWhen("slam --method ekf-bspline " + (dir / "complex" / "log.clf").string() +
                               " --out " + (dir / "int").string(),
                           [&] {
                             return fs::exists(dir / "int" / "config.yaml") &&
                                    std::chrono::steady_clock::now() - started >=
                                        std::chrono::milliseconds(1000);
                           }),
      3);
  const auto interrupted = nlohmann::json::parse(Slurp(dir / "int" / "summary.json"));
  EXPECT_NE(interrupted["stopped_early"].get<std::string>().find("interrupted before scan"),
            std::string::npos);
  EXPECT_TRUE(fs::exists(dir / "int" / "map.png"));
  EXPECT_EQ(SplamInterrupted("explore --world complex --localization topological --out " +
                                 (dir / "explore").string(),
                             std::chrono::milliseconds(1000)),
            3);
  const auto report = nlohmann::json::parse(Slurp(dir / "explore" / "report.json"));
  EXPECT_EQ(report["termination"], "interrupted");
  EXPECT_TRUE(fs::exists(dir / "explore" / "graph.png"));
}

// Bytes that are not UTF-8 (a world's Latin-1 name, a log's Latin-1 file
// name, a binary junk line quoted in an error) aborted the run with nlohmann's type_error.316
// and left its JSON empty. They are written as U+FFFD now, and every JSON stays valid.
TEST(SplamCli, BytesThatAreNotUtf8AreWrittenAsReplacementCharacters) {
  const fs::path dir = Temp("latin1");
  fs::create_directories(dir);
  const std::string replaced = "caf\xef\xbf\xbd";  // "caf" and U+FFFD
  ASSERT_EQ(io::WriteTextFile((dir / "w.yaml").string(),
                              "name: caf\xe9\nstart: [1, 1, 0]\nroute: [[4, 1]]\nobstacles:\n"
                              "  - polyline: [[0, 0], [5, 0], [5, 3], [0, 3], [0, 0]]\n")
                .message(),
            "");
  const Output simulated =
      Splam("simulate --world " + (dir / "w.yaml").string() + " --out " + (dir / "sim").string());
  ASSERT_EQ(simulated.status, 0) << simulated.text;
  EXPECT_EQ(nlohmann::json::parse(Slurp(dir / "sim" / "summary.json"))["world"], replaced);

  const fs::path latin = dir / "caf\xe9.clf";
  fs::copy_file(dir / "sim" / "log.clf", latin);
  const Output run =
      Splam("slam --method graph " + latin.string() + " --out " + (dir / "slam").string());
  ASSERT_EQ(run.status, 0) << run.text;
  const auto summary = nlohmann::json::parse(Slurp(dir / "slam" / "summary.json"));
  EXPECT_NE(summary["log"].get<std::string>().find(replaced + ".clf"), std::string::npos);

  std::string text = Slurp(dir / "sim" / "log.clf");
  const std::size_t half = text.find("\nROBOTLASER1", text.size() / 2);
  ASSERT_NE(half, std::string::npos);
  text.insert(half + 1, "\xff\xfe\x01 junk\n");
  ASSERT_EQ(io::WriteTextFile((dir / "junk.clf").string(), text).message(), "");
  const Output junk = Splam("slam --method graph " + (dir / "junk.clf").string() + " --out " +
                            (dir / "junk").string());
  EXPECT_EQ(junk.status, 3) << junk.text;
  const auto stopped = nlohmann::json::parse(Slurp(dir / "junk" / "summary.json"));
  EXPECT_NE(stopped["stopped_early"].get<std::string>().find("not a CARMEN message"),
            std::string::npos)
      << stopped["stopped_early"];
}

// A write that fails when the file is closed (a full disk: here the file is a
// link to /dev/full) left an empty summary.json, map.txt or eval.json and exit 0. Each now gives
// exit status 4 (kExitWriteFailed) and names the file.
TEST(SplamCli, AFullDiskGivesExitStatus4NamingTheFile) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this machine";
  const fs::path dir = Temp("full_disk");
  ASSERT_EQ(Splam("simulate --world corridor --out " + (dir / "sim").string()).status, 0);
  const std::string log = (dir / "sim" / "log.clf").string();
  // config.yaml: read back for report.html, /dev/full grew the page to 24 GB.
  for (const std::string file : {"summary.json", "map.txt", "config.yaml"}) {
    const fs::path out = dir / ("slam-" + file);
    fs::create_directories(out);
    fs::create_symlink("/dev/full", out / file);
    const Output r = Splam("slam --method graph " + log + " --out " + out.string());
    EXPECT_EQ(r.status, 4) << r.text;
    EXPECT_NE(r.text.find((out / file).string() + ": write failed"), std::string::npos) << r.text;
  }
  const fs::path sim = dir / "sim-full";
  fs::create_directories(sim);
  fs::create_symlink("/dev/full", sim / "summary.json");
  const Output simulated = Splam("simulate --world corridor --out " + sim.string());
  EXPECT_EQ(simulated.status, 4) << simulated.text;
  EXPECT_NE(simulated.text.find("summary.json: write failed"), std::string::npos);
  const fs::path eval = dir / "eval-full";
  fs::create_directories(eval);
  fs::create_symlink("/dev/full", eval / "eval.json");
  const Output evaluated =
      Splam("eval --truth " + (dir / "sim" / "truth.txt").string() + " --estimate " +
            (dir / "sim" / "odometry.txt").string() + " --out " + eval.string());
  EXPECT_EQ(evaluated.status, 4) << evaluated.text;
  EXPECT_NE(evaluated.text.find("eval.json: write failed"), std::string::npos) << evaluated.text;
  // Written with unchecked streams before, exit 0 with an empty file.
  const auto full = [&](const std::string& name, const std::string& file) {
    const fs::path out = dir / name;
    fs::create_directories(out);
    fs::create_symlink("/dev/full", out / file);
    return out;
  };
  const fs::path explored = full("explore-full", "report.json");
  const Output explore = Splam(
      "explore --world corridor --explorer srt --localization "
      "ground-truth --max-nodes 2 --out " +
      explored.string());
  EXPECT_EQ(explore.status, 4) << explore.text;
  EXPECT_NE(explore.text.find("report.json: write failed"), std::string::npos) << explore.text;
  const fs::path experiment = full("experiment-full", "report.json");
  const Output experimented =
      Splam("experiment corridor-lines --runs 1 --steps 20 --out " + experiment.string());
  EXPECT_EQ(experimented.status, 4) << experimented.text;
  EXPECT_NE(experimented.text.find("report.json: write failed"), std::string::npos)
      << experimented.text;
  fs::create_symlink("/dev/full", dir / "render.png");
  const Output rendered = Splam("render --world corridor --out " + (dir / "render.png").string());
  EXPECT_EQ(rendered.status, 4) << rendered.text;
  EXPECT_NE(rendered.text.find("render.png: cannot write picture"), std::string::npos)
      << rendered.text;
  EXPECT_EQ(Splam("render --world corridor --out " + (dir / "render.jpg").string()).status, 2);
  fs::create_symlink("/dev/full", dir / "converted.clf");
  const Output converted = Splam("convert " + log + " " + (dir / "converted.clf").string());
  EXPECT_EQ(converted.status, 4) << converted.text;
  EXPECT_NE(converted.text.find("converted.clf: write failed"), std::string::npos)
      << converted.text;
  // A bag: rosbag's exception (it aborted before) is caught and named.
  fs::create_symlink("/dev/full", dir / "converted.bag");
  const Output bagged = Splam("convert " + log + " " + (dir / "converted.bag").string());
  EXPECT_EQ(bagged.status, 4) << bagged.text;
  EXPECT_NE(bagged.text.find("converted.bag: cannot write the bag"), std::string::npos)
      << bagged.text;
  // Issue 70, item 7: simulate's and explore's config.yaml, eval's picture on a full disk, and
  // an output directory that cannot be made, said "bad input" (2); eval's named no file.
  const fs::path sim_config = full("sim-config", "config.yaml");
  const Output simulated_config = Splam("simulate --world corridor --out " + sim_config.string());
  EXPECT_EQ(simulated_config.status, 4) << simulated_config.text;
  EXPECT_NE(simulated_config.text.find("config.yaml: write failed"), std::string::npos)
      << simulated_config.text;
  const fs::path explore_config = full("explore-config", "config.yaml");
  const Output explored_config = Splam(
      "explore --world corridor --explorer srt --localization ground-truth --max-nodes 2 --out " +
      explore_config.string());
  EXPECT_EQ(explored_config.status, 4) << explored_config.text;
  EXPECT_NE(explored_config.text.find("config.yaml: write failed"), std::string::npos)
      << explored_config.text;
  const fs::path eval_picture = full("eval-picture", "eval_errors.png");
  const Output pictured =
      Splam("eval --truth " + (dir / "sim" / "truth.txt").string() + " --estimate " +
            (dir / "sim" / "odometry.txt").string() + " --out " + eval_picture.string());
  EXPECT_EQ(pictured.status, 4) << pictured.text;
  EXPECT_NE(pictured.text.find("eval_errors.png"), std::string::npos) << pictured.text;
  const std::string regular = WriteIn(dir, "a_file", "x");
  for (const std::string& command :
       {"eval --truth " + (dir / "sim" / "truth.txt").string() + " --estimate " +
            (dir / "sim" / "odometry.txt").string() + " --out " + regular + "/eval",
        "simulate --world corridor --out " + regular + "/sim",
        "slam " + log + " --out " + regular + "/slam"}) {
    const Output under_a_file = Splam(command);
    EXPECT_EQ(under_a_file.status, 4) << command << "\n" << under_a_file.text;
    EXPECT_NE(under_a_file.text.find("cannot create " + regular + "/"), std::string::npos)
        << under_a_file.text;
  }
  // A file-size limit (ulimit -f): SIGXFSZ killed splam; where it was ignored (as Python does
  // for its children) rosbag's second exception, from the bag's destructor, aborted.
  for (const char* file : {"limited.bag", "limited.clf", "limited.mcap"}) {
    int status = 0;
    const std::string text = Shell("sh -c 'ulimit -f 20; exec " + std::string(SPLAM_BINARY) +
                                       " convert " + log + " " + (dir / file).string() + "' 2>&1",
                                   &status);
    ASSERT_TRUE(WIFEXITED(status)) << file << ": ended by signal " << WTERMSIG(status);
    EXPECT_EQ(WEXITSTATUS(status), 4) << file << ": " << text;
    EXPECT_NE(text.find(file), std::string::npos) << text;
  }
}

// Issue 70, item 8: `slam LOG --save-state LOG` overwrote the log and exited 0. Any output that
// is an input file, by any name, is refused before anything is written.
TEST(SplamCli, AnOutputThatIsAnInputIsRefusedBeforeAnythingIsWritten) {
  const fs::path dir = Temp("output_is_input");
  ASSERT_EQ(Splam("simulate --world corridor --out " + (dir / "sim").string()).status, 0);
  const std::string log = (dir / "sim" / "log.clf").string();
  const std::string before = Slurp(log);
  fs::create_symlink(log, dir / "link.clf");
  for (const std::string& command :
       {"slam " + log + " --save-state " + log + " --out " + (dir / "a").string(),
        "slam " + log + " --save-state " + (dir / "link.clf").string() + " --out " +
            (dir / "b").string(),
        "slam " + (dir / "sim" / "." / "log.clf").string() + " --relations " +
            (dir / "c" / "summary.json").string() + " --out " + (dir / "c").string(),
        "convert " + log + " " + (dir / "link.clf").string(),
        "simulate --world " + (dir / "sim" / "world.yaml").string() + " --out " +
            (dir / "sim").string(),
        "eval --truth " + (dir / "sim" / "truth.txt").string() + " --estimate " +
            (dir / "sim" / "odometry.txt").string() + " --out " + (dir / "sim").string() +
            " --odometry " + WriteIn(dir / "sim", "eval.json", "")}) {
    if (command.find("--relations") != std::string::npos) {
      fs::create_directories(dir / "c");
      WriteIn(dir / "c", "summary.json", "0 0 1 0 0 0 0 0\n");
    }
    const Output r = Splam(command);
    EXPECT_EQ(r.status, 2) << command << "\n" << r.text;
    EXPECT_NE(r.text.find("would overwrite"), std::string::npos) << r.text;
    EXPECT_NE(r.text.find("nothing was written"), std::string::npos) << r.text;
  }
  EXPECT_EQ(Slurp(log), before);
  EXPECT_FALSE(fs::exists(dir / "a"));
  EXPECT_FALSE(fs::exists(dir / "b"));
  EXPECT_EQ(Slurp(dir / "c" / "summary.json"), "0 0 1 0 0 0 0 0\n");
  // A run repeated in its own directory from its own config.yaml renews that record.
  ASSERT_EQ(Splam("slam " + log + " --max-scans 20 --out " + (dir / "d").string()).status, 0);
  const Output again =
      Splam("slam " + log + " --max-scans 20 --config " + (dir / "d" / "config.yaml").string() +
            " --out " + (dir / "d").string());
  EXPECT_EQ(again.status, 0) << again.text;
}

// Issue 70, item 9: a second SIGINT during the final write left only config.yaml (rc 130);
// SIGHUP was not handled (rc 129, nothing written); `simulate` handled neither SIGINT nor
// SIGTERM (rc 143, no summary.json).
TEST(SplamCli, EverySignalToStopWritesTheFilesWholeAndExits3) {
  const fs::path dir = Temp("signals");
  ASSERT_EQ(Splam("simulate --world complex --out " + (dir / "complex").string()).status, 0);
  const std::string log = (dir / "complex" / "log.clf").string();
  // The first signal after the first progress line, the second once the message that the
  // results are being written is out.
  EXPECT_EQ(SplamSignalledWhenSaid(
                "slam --method ekf-bspline " + log + " --out " + (dir / "twice").string(),
                {{" scans, ", SIGINT}, {"the results so far are written", SIGINT}}),
            3);
  EXPECT_EQ(SplamSignalledWhenSaid(
                "slam --method ekf-bspline " + log + " --out " + (dir / "hup").string(),
                {{" scans, ", SIGHUP}}),
            3);
  for (const fs::path& out : {dir / "twice", dir / "hup"}) {
    const auto summary = nlohmann::json::parse(Slurp(out / "summary.json"));
    EXPECT_NE(summary["stopped_early"].get<std::string>().find("interrupted before scan"),
              std::string::npos);
    for (const char* file : {"trajectory.txt", "map.png", "map.dxf", "report.html"})
      EXPECT_TRUE(fs::exists(out / file)) << out / file;
  }
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    const fs::path out = dir / ("sim-" + std::to_string(signal));
    EXPECT_EQ(SplamSignalledWhenSaid("simulate --world office-long --out " + out.string(),
                                     {{"500 steps", signal}}),
              3);
    const auto summary = nlohmann::json::parse(Slurp(out / "summary.json"));
    EXPECT_NE(summary["message"].get<std::string>().find("interrupted at t = "), std::string::npos);
    const auto truth = io::ReadTrajectory((out / "truth.txt").string());
    ASSERT_TRUE(truth.ok()) << truth.error;
    EXPECT_GT(truth.value->size(), 1u);
  }
}

// Standard output on a full disk (`config print > /dev/full`) aborted with
// std::system_error; `--help` and `slam` lost their output and exited 0. Now exit 4, said on
// standard error.
TEST(SplamCli, AFullStandardOutputGivesExitStatus4) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this machine";
  const fs::path dir = Temp("full_stdout");
  ASSERT_EQ(Splam("simulate --world corridor --out " + (dir / "sim").string()).status, 0);
  for (const std::string& args : {std::string("config print --method graph"), std::string("--help"),
                                  "slam --method graph " + (dir / "sim" / "log.clf").string() +
                                      " --out " + (dir / "slam").string()}) {
    // Standard error to the pipe, standard output to /dev/full.
    int status = 0;
    const std::string text =
        Shell(std::string(SPLAM_BINARY) + " " + args + " 2>&1 >/dev/full", &status);
    ASSERT_TRUE(WIFEXITED(status)) << args << ": ended by a signal";
    EXPECT_EQ(WEXITSTATUS(status), 4) << args << "\n" << text;
    EXPECT_NE(text.find("writing to standard output or error failed"), std::string::npos)
        << args << "\n"
        << text;
  }
}

// `sweep --slurm` with a newline in its sweep directory is refused before the
// sweep's plan is written (it made the directory, grid.yaml and cells.tsv, then refused).
TEST(SplamCli, SweepSlurmRefusesANewlineInItsDirectoryBeforeWritingIt) {
  const fs::path dir = Temp("slurm_path");
  fs::create_directories(dir);
  const std::string grid = WriteIn(dir, "g.yaml", "command: simulate\naxes:\n  seed: [1]\n");
  const fs::path out = dir / "a\nb";
  const Output r = Splam("sweep " + grid + " --slurm --out '" + out.string() + "'");
  EXPECT_EQ(r.status, 2) << r.text;
  EXPECT_NE(r.text.find("holds a control character"), std::string::npos) << r.text;
  EXPECT_FALSE(fs::exists(out));
}

// Time stamps that go backwards gave "-12 s of data, -250x real time".
// The second half of a log stamped so that its last scan is 12 s before its first: the span is
// the latest stamp minus the earliest, and the backward step is counted in summary.json.
TEST(SplamCli, BackwardTimeStampsAreCountedNotANegativeSpan) {
  const fs::path dir = Temp("backward_time");
  ASSERT_EQ(Splam("simulate --world corridor --out " + (dir / "sim").string()).status, 0);
  io::CarmenReadResult read = io::ReadCarmenLog((dir / "sim" / "log.clf").string());
  ASSERT_TRUE(read.log.ok());
  io::CarmenLog log = *read.log.value;
  const double span =
      log.Lasers().back()->stamp.ipc_timestamp_s - log.Lasers().front()->stamp.ipc_timestamp_s;
  ASSERT_GT(span, 30.0);
  for (std::size_t i = log.messages.size() / 2; i < log.messages.size(); ++i)
    std::visit([&](auto& m) { m.stamp.ipc_timestamp_s -= span + 12.0; }, log.messages[i]);
  ASSERT_EQ(io::WriteCarmenLog((dir / "back.clf").string(), log).message(), "");
  const Output r = Splam("slam --method graph " + (dir / "back.clf").string() + " --out " +
                         (dir / "slam").string());
  ASSERT_EQ(r.status, 0) << r.text;
  EXPECT_NE(r.text.find("1 scans are stamped earlier than the scan before them"), std::string::npos)
      << r.text;
  const auto summary = nlohmann::json::parse(Slurp(dir / "slam" / "summary.json"));
  EXPECT_EQ(summary["backward_time_stamps"], 1);
  EXPECT_NEAR(summary["data_duration_s"].get<double>(), span + 12.0, 0.2);
  EXPECT_GT(summary["real_time_factor"].get<double>(), 0.0);
}

// Eval gave "0.0000 +- 0.0000, used 0" and exit 0 for an empty or non-matching
// relations file, a directory, an empty estimate; a huge estimate wrote null. A metric over
// nothing, or one that is not finite, is an error (exit 2, the reason in eval.json).
// `splam split`: a log cut into sessions that share no frame (io::SplitLog), each a log of its
// own; split.json's motions undo the move; bad requests are refused before anything is written.
TEST(SplamCli, SplitCutsALogIntoSessionsThatShareNoFrame) {
  const fs::path sim = Temp("split_sim"), out = Temp("split_out");
  ASSERT_EQ(Splam("simulate --world complex --seed 4 --out " + sim.string()).status, 0);
  const std::string log = (sim / "log.clf").string();
  const Output r = Splam("split " + log + " --sessions 3 --seed 7 --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.text;
  const io::CarmenReadResult whole = io::ReadCarmenLog(log);
  ASSERT_TRUE(whole.log.ok());
  const auto lasers = whole.log.value->Lasers();
  const auto manifest = nlohmann::json::parse(Slurp(out / "split.json"));
  ASSERT_EQ(manifest["sessions"].size(), 3u);
  std::size_t first = 0;
  for (const auto& s : manifest["sessions"]) {
    const io::CarmenReadResult session =
        io::ReadCarmenLog((out / s["file"].get<std::string>()).string());
    ASSERT_TRUE(session.log.ok()) << session.log.error;
    const auto scans = session.log.value->Lasers();
    ASSERT_EQ(scans.size(), s["scans"].get<std::size_t>());
    const auto t = s["log_T_session"].get<std::vector<double>>();
    const kernel::Pose2 log_T_session(t[0], t[1], t[2]);
    // The session's first and last poses, moved back, are the log's (to the file's precision).
    for (const std::size_t i : {std::size_t{0}, scans.size() - 1}) {
      const kernel::Pose2 back = log_T_session * scans[i]->robot_pose;
      EXPECT_NEAR((back.translation() - lasers[first + i]->robot_pose.translation()).norm(), 0.0,
                  1e-4);
      EXPECT_EQ(scans[i]->stamp.ipc_timestamp_s, lasers[first + i]->stamp.ipc_timestamp_s);
    }
    const double moved_m =
        (scans[0]->robot_pose.translation() - lasers[first]->robot_pose.translation()).norm();
    EXPECT_GE(moved_m, 50.0 - 1e-3);
    EXPECT_LE(moved_m, 150.0 + 1e-3);
    first += scans.size();
  }
  EXPECT_EQ(first, lasers.size());
  EXPECT_TRUE(fs::exists(out / "sessions.png"));
  const Output one = Splam("split " + log + " --sessions 1 --out " + Temp("split_one").string());
  EXPECT_EQ(one.status, 2);
  EXPECT_NE(one.text.find("sessions must be in [2, 10]"), std::string::npos) << one.text;
  const Output over = Splam("split " + (out / "session1.clf").string() + " --out " + out.string());
  EXPECT_EQ(over.status, 2);
  EXPECT_NE(over.text.find("would overwrite"), std::string::npos) << over.text;
}

TEST(SplamCli, EvalScoresNothingFromNothing) {
  const fs::path dir = Temp("eval_nothing");
  fs::create_directories(dir);
  const auto write = [&](const std::string& name, const std::string& text) {
    return WriteIn(dir, name, text);
  };
  const std::string estimate = write("t.txt", "0 0 0 0\n1 1 0 0\n");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--estimate " + estimate + " --relations " + write("far.rel", "5 6 1 0 0 0 0 0\n"),
       "no relation of " + (dir / "far.rel").string() + " matches a time"},
      {"--estimate " + estimate + " --relations " + write("empty.rel", "# none\n"),
       "empty.rel: no relations"},
      {"--estimate " + estimate + " --relations " + dir.string(), "is a directory, not a file"},
      {"--estimate " + write("e.txt", "") + " --relations " + (dir / "far.rel").string(),
       "e.txt: no poses"},
      {"--estimate " + write("h.txt", "0 1e300 0 0\n1 -1e300 0 0\n") + " --relations " +
           write("r.rel", "0 1 1 0 0 0 0 0\n") + " --out " + (dir / "o").string(),
       "is not finite"},
      {"--estimate " + estimate + " --truth " + write("late.txt", "50 0 0 0\n"),
       "no pose of " + (dir / "late.txt").string() + " matches a time"}};
  for (const auto& [args, message] : cases) {
    const Output r = Splam("eval " + args);
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_NE(r.text.find(message), std::string::npos) << args << ": " << r.text;
    EXPECT_EQ(r.text.find("used 0"), std::string::npos) << r.text;
  }
  const std::string json = Slurp(dir / "o" / "eval.json");
  EXPECT_EQ(json.find("null"), std::string::npos) << json;
  EXPECT_NE(json.find("\"error\""), std::string::npos) << json;
}

// Trajectories as evo reads them: slam writes trajectory.tum and truth.tum beside its own
// format; convert turns them into KITTI and back; eval reads any of the three, scores the
// absolute trajectory error after SE(2) alignment, and takes a trajectory file where a run
// directory goes (the README's `eval --relations R run/trajectory.txt`).
TEST(SplamCli, TrajectoriesInTumAndKittiAndTheAlignedError) {
  const fs::path dir = Temp("evo");
  ASSERT_EQ(Splam("simulate --world corridor --out " + (dir / "sim").string()).status, 0);
  const fs::path run = dir / "run";
  Output r = Splam("slam " + (dir / "sim" / "log.clf").string() + " --method ekf-lines --out " +
                   run.string());
  ASSERT_EQ(r.status, 0) << r.text;
  const auto own = io::ReadTrajectory((run / "trajectory.txt").string());
  const auto tum = io::ReadTrajectory((run / "trajectory.tum").string());
  ASSERT_TRUE(own.ok() && tum.ok());
  ASSERT_EQ(own->size(), tum->size());
  for (std::size_t i = 0; i < own->size(); ++i) {
    EXPECT_EQ((*tum)[i].time_s, (*own)[i].time_s);
    EXPECT_LT(((*tum)[i].pose.translation() - (*own)[i].pose.translation()).norm(), 1e-12);
  }
  for (const char* name : {"trajectory", "truth"}) {
    r = Splam("convert " + (run / (std::string(name) + ".tum")).string() + " " +
              (dir / (std::string(name) + ".kitti")).string());
    ASSERT_EQ(r.status, 0) << r.text;
  }
  // The same ATE from splam's files, TUM's and KITTI's (KITTI pairs poses by their order).
  std::vector<double> rmse;
  for (const auto& [estimate, truth] : {std::pair{run / "trajectory.txt", run / "truth.txt"},
                                        std::pair{run / "trajectory.tum", run / "truth.tum"},
                                        std::pair{dir / "trajectory.kitti", dir / "truth.kitti"}}) {
    const fs::path out = dir / ("eval-" + estimate.extension().string().substr(1));
    r = Splam("eval " + estimate.string() + " --truth " + truth.string() + " --out " +
              out.string());
    ASSERT_EQ(r.status, 0) << r.text;
    EXPECT_NE(r.text.find("absolute trajectory error after SE(2) alignment"), std::string::npos)
        << r.text;
    const nlohmann::json report = nlohmann::json::parse(Slurp(out / "eval.json"));
    rmse.push_back(report["ate"]["estimate"]["rmse_m"].get<double>());
    // Aligned, the error is at most the unaligned one.
    EXPECT_LE(rmse.back(), report["truth"]["estimate"]["rmse_position_m"].get<double>() + 1e-12);
  }
  EXPECT_GT(rmse[0], 0.0);
  EXPECT_NEAR(rmse[1], rmse[0], 1e-9);
  EXPECT_NEAR(rmse[2], rmse[0], 1e-9);
  // A log to an unknown format is refused with the known ones (it wrote CARMEN text before).
  r = Splam("convert " + (dir / "sim" / "log.clf").string() + " " + (dir / "x.mp4").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("unknown output format; known: .bag"), std::string::npos) << r.text;
  EXPECT_FALSE(fs::exists(dir / "x.mp4"));
}

// map.yaml / map.pgm from slam, the same from render for any trajectory, readable as map_server
// reads them; the resolution an option.
TEST(SplamCli, SlamAndRenderWriteOccupancyGrids) {
  const fs::path dir = Temp("grids");
  ASSERT_EQ(Splam("simulate --world corridor --out " + (dir / "sim").string()).status, 0);
  const fs::path run = dir / "run";
  Output r =
      Splam("slam " + (dir / "sim" / "log.clf").string() +
            " --method ekf-lines --set occupancy_grid.resolution_m=0.1 --out " + run.string());
  ASSERT_EQ(r.status, 0) << r.text;
  const io::Result<estimation::OccupancyGrid> slam_grid =
      io::ReadOccupancyGrid((run / "map.yaml").string());
  ASSERT_TRUE(slam_grid.ok()) << slam_grid.error;
  EXPECT_EQ(slam_grid->resolution_m(), 0.1);
  EXPECT_TRUE(fs::exists(run / "grid.png"));
  const nlohmann::json summary = nlohmann::json::parse(Slurp(run / "summary.json"));
  EXPECT_GT(summary["occupancy_grid"]["occupied_cells"].get<int>(), 100);
  // render: the grid at the true poses (TUM), 5 cm by default.
  r = Splam("render --log " + (dir / "sim" / "log.clf").string() + " --trajectory " +
            (run / "truth.tum").string() + " --grid " + (dir / "truth_grid.yaml").string() +
            " --out " + (dir / "render.png").string());
  ASSERT_EQ(r.status, 0) << r.text;
  const io::Result<estimation::OccupancyGrid> truth_grid =
      io::ReadOccupancyGrid((dir / "truth_grid.yaml").string());
  ASSERT_TRUE(truth_grid.ok()) << truth_grid.error;
  EXPECT_EQ(truth_grid->resolution_m(), 0.05);
  EXPECT_TRUE(fs::exists(dir / "truth_grid.png"));
  r = Splam("render --log " + (dir / "sim" / "log.clf").string() + " --grid " +
            (dir / "g.yaml").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("--grid needs --log (the scans) and --trajectory"), std::string::npos)
      << r.text;
  r = Splam("slam " + (dir / "sim" / "log.clf").string() +
            " --set occupancy_grid.hit_probability=0.2 --out " + (dir / "bad").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("occupancy_grid: need 0 < min_probability"), std::string::npos) << r.text;
  // A grid too large to build is said, and not listed as written.
  r = Splam("slam " + (dir / "sim" / "log.clf").string() +
            " --set occupancy_grid.resolution_m=1e-6 --out " + (dir / "tiny").string());
  EXPECT_EQ(r.status, 0) << r.text;
  EXPECT_NE(r.text.find("no map.pgm: occupancy grid:"), std::string::npos) << r.text;
  EXPECT_EQ(r.text.find("map.pgm, grid.png"), std::string::npos) << r.text;
  EXPECT_FALSE(fs::exists(dir / "tiny" / "map.pgm"));
}

// Map once, localise many times: `complex` mapped along its route, a second log along another
// route (the reverse, other noise) localised in the saved map, which stays as it was; and the
// same log mapped on from it.
TEST(SplamCli, ASavedMapLocalisesASecondRunAndStaysUnchanged) {
  const fs::path dir = Temp("state");
  fs::create_directories(dir);
  ASSERT_EQ(io::WriteTextFile((dir / "reverse.txt").string(),
                              "1.5 2.0 1.57\n2.5 6.2\n1.2 8.0\n1.5 13.2\n6.0 13.0\n7.5 10.6\n"
                              "12.2 10.2\n13.0 12.8\n18.3 12.6\n18.3 7.5\n16.0 6.6\n13.0 6.3\n"
                              "9.0 5.2\n7.5 2.0\n")
                .message(),
            "");
  ASSERT_EQ(Splam("simulate --world complex --out " + (dir / "a").string()).status, 0);
  ASSERT_EQ(Splam("simulate --world complex --seed 7 --route " + (dir / "reverse.txt").string() +
                  " --out " + (dir / "b").string())
                .status,
            0);
  const std::string state = (dir / "complex.state").string();
  Output r = Splam("slam " + (dir / "a" / "log.clf").string() + " --save-state " + state +
                   " --out " + (dir / "map").string());
  ASSERT_EQ(r.status, 0) << r.text;
  const std::string saved = Slurp(state);
  ASSERT_NE(saved.find("\nscan "), std::string::npos);
  const auto rmse = [](const fs::path& run) {
    const nlohmann::json j = nlohmann::json::parse(Slurp(run / "summary.json"));
    return std::pair(j["error"]["estimate"]["rmse_position_m"].get<double>(),
                     j["error"]["odometry"]["rmse_position_m"].get<double>());
  };
  r = Splam("slam " + (dir / "b" / "log.clf").string() + " --load-state " + state +
            " --localize-only --out " + (dir / "localised").string());
  ASSERT_EQ(r.status, 0) << r.text;
  const auto [localised, odometry] = rmse(dir / "localised");
  EXPECT_LT(localised, 0.05);  // measured 0.021 m; SLAM on the log alone 0.040 m
  EXPECT_LT(localised, odometry / 5);
  // The map unchanged byte for byte: the state file, and the map the run reports.
  EXPECT_EQ(Slurp(state), saved);
  EXPECT_EQ(Slurp(dir / "localised" / "map.txt"), Slurp(dir / "map" / "map.txt"));
  // A start half a metre and 0.2 rad off is found by the first scan's search.
  r = Splam("slam " + (dir / "b" / "log.clf").string() + " --load-state " + state +
            " --localize-only --initial-pose 1.2 1.8 1.4 --out " + (dir / "off").string());
  ASSERT_EQ(r.status, 0) << r.text;
  EXPECT_LT(rmse(dir / "off").first, 0.05);
  // A start wrong by metres and a turn (the kidnapped robot): the start search near it takes a
  // look-alike corner, and the search of the whole map at one of the first scans relocalises
  // (MapLocalizer::ConfirmStart), the scans before moving with it. Measured 0.034 m (18.5 m
  // without the confirmation); the right starts above are confirmed and left as they were.
  r = Splam("slam " + (dir / "b" / "log.clf").string() + " --load-state " + state +
            " --localize-only --initial-pose 12 3 -2.5 --out " + (dir / "kidnapped").string());
  ASSERT_EQ(r.status, 0) << r.text;
  EXPECT_LT(rmse(dir / "kidnapped").first, 0.05);
  const auto associations = [&](const char* run) {
    return nlohmann::json::parse(Slurp(dir / run / "summary.json"))["associations"];
  };
  EXPECT_EQ(associations("kidnapped")["relocalized"].get<int>(), 1);
  for (const char* right : {"localised", "off"}) {
    EXPECT_EQ(associations(right)["start_confirmed"].get<int>(), 1) << right;
    EXPECT_EQ(associations(right)["relocalized"].get<int>(), 0) << right;
  }
  // Mapping on from the saved map: the second log joins it by loop closures.
  r = Splam("slam " + (dir / "b" / "log.clf").string() + " --load-state " + state +
            " --save-state " + (dir / "both.state").string() + " --out " +
            (dir / "continued").string());
  ASSERT_EQ(r.status, 0) << r.text;
  EXPECT_LT(rmse(dir / "continued").first, 0.1);
  const nlohmann::json continued = nlohmann::json::parse(Slurp(dir / "continued" / "summary.json"));
  const nlohmann::json first = nlohmann::json::parse(Slurp(dir / "map" / "summary.json"));
  EXPECT_GT(continued["map"]["keyframes"].get<int>(), first["map"]["keyframes"].get<int>());
  EXPECT_EQ(continued["scans"].get<int>(), 1329);  // one pose per scan of the second log
  // Refused clearly.
  r = Splam("slam " + (dir / "b" / "log.clf").string() + " --localize-only");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("--localize-only needs --load-state"), std::string::npos) << r.text;
  r = Splam("slam " + (dir / "b" / "log.clf").string() + " --load-state " + state +
            " --localize-only --initial-pose nan 0 0 --out " + (dir / "nan").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("--initial-pose"), std::string::npos) << r.text;
  r = Splam("slam " + (dir / "b" / "log.clf").string() + " --method ekf-lines --save-state " +
            (dir / "x.state").string() + " --out " + (dir / "x").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("method 'ekf-lines' cannot save or load its state"), std::string::npos)
      << r.text;
  ASSERT_EQ(
      io::WriteTextFile((dir / "bad.state").string(), "splam_state 1\nmethod graph\nscan 1 2\n")
          .message(),
      "");
  r = Splam("slam " + (dir / "b" / "log.clf").string() + " --load-state " +
            (dir / "bad.state").string() + " --localize-only --out " + (dir / "y").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("bad.state:3: scan: expected 12 values, found 2"), std::string::npos)
      << r.text;
}

TEST(SplamCli, SlamAndEvalRejectBadInput) {
  const fs::path dir = Temp("slam_bad");
  fs::create_directories(dir);
  ASSERT_EQ(io::WriteTextFile((dir / "bad.clf").string(),
                              "FLASER 3 1 2 3 0 0 0 0 0 0 1 h 1\nFLASER 2 1\n")
                .message(),
            "");
  // The scan before the bad line is processed and written: exit 3, stopped early.
  Output r = Splam("slam " + (dir / "bad.clf").string() + " --out " + (dir / "o").string());
  EXPECT_EQ(r.status, 3);
  EXPECT_NE(r.text.find("bad.clf:2: FLASER: line ends early"), std::string::npos) << r.text;
  EXPECT_TRUE(fs::exists(dir / "o" / "trajectory.txt"));
  ASSERT_EQ(io::WriteTextFile((dir / "bad_first.clf").string(), "FLASER 2 1\n").message(), "");
  r = Splam("slam " + (dir / "bad_first.clf").string() + " --out " + (dir / "o1").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("bad_first.clf:1: FLASER: line ends early"), std::string::npos) << r.text;
  ASSERT_EQ(io::WriteTextFile((dir / "empty.clf").string(), "# nothing\n").message(), "");
  r = Splam("slam " + (dir / "empty.clf").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("no laser scans"), std::string::npos) << r.text;
  r = Splam("slam --method magic " + (dir / "empty.clf").string());
  EXPECT_EQ(r.status, 2);
  // A device never ends: read, it aborted with bad_alloc.
  if (fs::exists("/dev/zero")) {
    r = Splam("slam /dev/zero --out " + (dir / "zero").string());
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.text.find("/dev/zero: is a device, not a file"), std::string::npos) << r.text;
  }
  ASSERT_EQ(io::WriteTextFile((dir / "t.txt").string(), "0 0 0 0\n").message(), "");
  ASSERT_EQ(io::WriteTextFile((dir / "r.relations").string(), "0 1 2\n").message(), "");
  r = Splam("eval --estimate " + (dir / "t.txt").string() + " --relations " +
            (dir / "r.relations").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("r.relations:1: expected 8 values"), std::string::npos) << r.text;
  r = Splam("eval --estimate " + (dir / "t.txt").string());
  EXPECT_EQ(r.status, 2);
}

TEST(SplamCli, CorridorExperimentRecoversTheMapDistancesConsistently) {
  const fs::path dir = Temp("experiment");
  const Output r = Splam("experiment corridor-lines --runs 20 --out " + dir.string());
  ASSERT_EQ(r.status, 0) << r.text;
  const auto report = nlohmann::json::parse(Slurp(dir / "report.json"));
  ASSERT_EQ(report["distances"].size(), 9u);
  for (const auto& d : report["distances"]) {
    ASSERT_GT(d["mapped_runs"].get<int>(), 0) << d["name"];
    EXPECT_LT(d["error_percent"].get<double>(), 1.0) << d["name"];
  }
  // Filter consistency: the average NEES over 20 runs inside the 95 % band for at
  // least 90 % of the steps.
  EXPECT_TRUE(report["nees"]["passed"].get<bool>());
  EXPECT_GE(report["nees"]["fraction_of_steps_inside"].get<double>(), 0.9);
  EXPECT_LT(report["final_position_error_m"]["ekf_lines_mean"].get<double>(),
            report["final_position_error_m"]["odometry_mean"].get<double>());
  for (const char* file : {"table1.md", "nees.png", "map.png", "errors.png"})
    EXPECT_TRUE(fs::exists(dir / file)) << file;
}

TEST(SplamCli, SlamRunsOnTheRealMitLog) {
  const char* env = std::getenv("SPLAM_DATA");
  const fs::path data = env != nullptr ? env : SPLAM_DEFAULT_DATA_DIR;
  if (!fs::exists(data / "mit-csail.clf"))
    GTEST_SKIP() << data / "mit-csail.clf"
                 << " not found: set SPLAM_DATA";
  const fs::path dir = Temp("mit");
  const Output r =
      Splam("slam " + (data / "mit-csail.clf").string() + " --max-scans 300 --out " + dir.string());
  ASSERT_EQ(r.status, 0) << r.text;
  const auto summary = nlohmann::json::parse(Slurp(dir / "summary.json"));
  EXPECT_TRUE(summary["health"]["healthy"].get<bool>());
  EXPECT_EQ(summary["scans"].get<int>(), 300);
  EXPECT_EQ(summary["odometry_noise_scale"].get<double>(), 3.0);  // real FLASER log
  const Output e =
      Splam("eval " + dir.string() + " --relations " + (data / "mit-csail.relations").string());
  ASSERT_EQ(e.status, 0) << e.text;
  const auto report = nlohmann::json::parse(Slurp(dir / "eval.json"));
  EXPECT_GT(report["relations"]["estimate"]["relations_used"].get<int>(), 50);
}

// The graph SLAM on all of mit-csail: every relation scored, with the accuracy of the published
// graph-based systems (measured 0.0301 m, 0.41 deg; Cartographer 0.0319 m), and still so with
// keyframes 2 cm farther apart. Before the front end checked registrations whose points contradict
// the submap (FrontEndOptions::Advanced::verify_misfit_fraction), a fast turn's wrong local minimum
// at scan 1350 was accepted or not depending on such details: 0.0295 m at 0.30 m, 0.49 m at 0.32 m.
TEST(SplamCli, GraphSlamClosesTheMitLoopsToCentimetres) {
  const char* env = std::getenv("SPLAM_DATA");
  const fs::path data = env != nullptr ? env : SPLAM_DEFAULT_DATA_DIR;
  if (!fs::exists(data / "mit-csail.clf"))
    GTEST_SKIP() << data / "mit-csail.clf"
                 << " not found: set SPLAM_DATA";
  for (const std::string keyframes : {"", " --set graph.front_end.keyframe_distance_m=0.32"}) {
    const fs::path dir = Temp("mit_graph");
    const Output r = Splam("slam --method graph " + (data / "mit-csail.clf").string() + keyframes +
                           " --out " + dir.string());
    ASSERT_EQ(r.status, 0) << r.text;
    const auto summary = nlohmann::json::parse(Slurp(dir / "summary.json"));
    EXPECT_GT(summary["associations"]["loop_accepted"].get<int>(), 50);
    EXPECT_FALSE(summary["optimizations"].empty());
    for (const char* f : {"map.png", "map.dxf", "map.txt", "trajectory.txt"})
      EXPECT_TRUE(fs::exists(dir / f)) << f;
    const Output e =
        Splam("eval " + dir.string() + " --relations " + (data / "mit-csail.relations").string());
    ASSERT_EQ(e.status, 0) << e.text;
    const auto report = nlohmann::json::parse(Slurp(dir / "eval.json"));
    const auto& estimate = report["relations"]["estimate"];
    EXPECT_EQ(estimate["relations_used"].get<int>(), 1172);
    EXPECT_LT(estimate["translation_m"]["mean"].get<double>(), 0.05) << keyframes;
    EXPECT_LT(estimate["rotation_deg"]["mean"].get<double>(), 1.0) << keyframes;
  }
}

TEST(SplamCli, ExploreWritesTheGraphCoverageAndReport) {
  // Seed 1: seeds 2 and 5 end `incomplete` at 100.0 % since REG keeps short door arcs, each for
  // a one-beam arc past a wall junction that no LSR covers (docs/experiments.md, a named gap).
  const fs::path out = Temp("explore");
  const Output run = Splam(
      "explore --explorer reg --localization ground-truth --world complex "
      "--seed 1 --out " +
      out.string());
  ASSERT_EQ(run.status, 0) << run.text;
  for (const char* f : {"report.json", "graph.svg", "graph.png", "explored.svg", "explored.png",
                        "truth.txt", "odometry.txt", "estimate.txt"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  const nlohmann::json report = nlohmann::json::parse(Slurp(out / "report.json"));
  EXPECT_EQ(report["termination"], "explored");
  EXPECT_GT(report["coverage_fraction"].get<double>(), 0.97);
  EXPECT_GT(report["distance_m"].get<double>(), 50.0);
  EXPECT_GT(report["nodes"].get<int>(), 20);
  EXPECT_EQ(report["blocked_steps"].get<int>(), 0);
  // A cap is a stated, non-zero exit; bad options name the problem.
  const Output capped =
      Splam("explore --explorer srt --max-nodes 3 --out " + Temp("explore_cap").string());
  EXPECT_EQ(capped.status, 3) << capped.text;
  EXPECT_NE(capped.text.find("node_limit"), std::string::npos) << capped.text;
  const Output bad = Splam("explore --alpha 0.95 --out " + Temp("explore_bad").string());
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.text.find("alpha"), std::string::npos) << bad.text;
  const Output no_world = Splam("explore --world nowhere.yaml");
  EXPECT_EQ(no_world.status, 2);
  EXPECT_NE(no_world.text.find("nowhere.yaml"), std::string::npos) << no_world.text;
}

TEST(SplamCli, ExploreWithoutArgumentsRunsTheMainJob) {
  // REG with topological B-spline SLAM in `complex` (seed 1 measured: 0.093 m position RMSE
  // against odometry's 0.250 m, 14 curves 0.056 m from the true obstacles on average).
  const fs::path dir = Temp("explore_main");
  fs::create_directories(dir);
  const Output run = Splam("explore", dir);
  ASSERT_EQ(run.status, 0) << run.text;
  EXPECT_NE(run.text.find("position RMSE"), std::string::npos) << run.text;
  const fs::path out = dir / "runs/explore-reg-complex";
  for (const char* f : {"report.json", "graph.png", "map.png", "map.svg", "map.txt", "map.dxf",
                        "errors.png", "explored.png", "estimate.txt"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  const nlohmann::json report = nlohmann::json::parse(Slurp(out / "report.json"));
  EXPECT_EQ(report["localization"], "topological");
  EXPECT_GT(report["coverage_fraction"].get<double>(), 0.95);
  const nlohmann::json& map = report["slam"]["map"];
  EXPECT_GT(map["curves"].get<int>(), 10);
  EXPECT_GT(map["control_points"].get<int>(), 100);
  EXPECT_LT(map["mean_distance_to_obstacles_m"].get<double>(), 0.2);
  EXPECT_GE(map["curves_per_obstacle"].get<double>(), 1.0);
  EXPECT_LT(map["curves_per_obstacle"].get<double>(), 3.0);
  const nlohmann::json& error = report["trajectory_error"];
  EXPECT_LT(error["estimate"]["rmse_position_m"].get<double>(),
            0.5 * error["odometry"]["rmse_position_m"].get<double>());
  EXPECT_GT(report["slam"]["localization_steps"].get<int>(), 1000);
}

TEST(SplamCli, ExploreTraceWritesEverySlamStepWithItsErrors) {
  const fs::path out = Temp("explore_trace");
  const Output run = Splam("explore --max-nodes 4 --trace --out " + out.string());
  ASSERT_EQ(run.status, 3) << run.text;  // the node cap: a stated, non-zero exit
  const nlohmann::json report = nlohmann::json::parse(Slurp(out / "report.json"));
  std::istringstream csv(Slurp(out / "steps.csv"));
  std::string header, line, last;
  std::getline(csv, header);
  EXPECT_NE(header.find("position_error_m,"), std::string::npos) << header;
  EXPECT_NE(header.find("verified_curves"), std::string::npos) << header;
  int rows = 0, updates = 0;  // every step; those with a scan (the method's values filled)
  while (std::getline(csv, line)) {
    ++rows;
    updates += line.find(",,") == std::string::npos;
    last = line;
  }
  EXPECT_EQ(updates, report["slam"]["localization_steps"].get<int>());
  // The last row's position error is the final estimate's distance to the truth.
  std::vector<double> v;
  std::istringstream fields(last);
  for (std::string f; std::getline(fields, f, ',') && v.size() < 13;) v.push_back(std::stod(f));
  ASSERT_EQ(v.size(), 13u);
  EXPECT_NEAR(v[12], std::hypot(v[5] - v[8], v[6] - v[9]), 1e-5);
  EXPECT_GT(rows, 100);
}

TEST(SplamCli, SplamExperimentComparesTheStrategies) {
  // One trial (seed 1) of paper 003 Figs. 19-22 (the topological SLAM with its default
  // correction and with the paper's), REG + graph and REG + topological-graph, run as cells of
  // the sweep engine.
  // Measured (session 42): position RMSE 0.076 m (ekf-lines, odometry 0.749 m), 0.041 m
  // (ekf-bspline, odometry 0.747 m), 0.044 m (topological, odometry 0.288 m; the paper's
  // formulation 0.380 m, odometry 0.412 m), 0.054 m (graph, odometry 0.368 m), 0.074 m
  // (topological-graph, odometry 0.604 m).
  const fs::path out = Temp("experiment_splam");
  const Output run = Splam("experiment splam --world complex --runs 1 --out " + out.string());
  ASSERT_EQ(run.status, 0) << run.text;
  for (const char* f : {"table.md",
                        "summary.json",
                        "fig19-map.png",
                        "fig19-errors.png",
                        "fig20-map.png",
                        "fig21-map.png",
                        "fig21-errors.svg",
                        "fig21-paper-map.png",
                        "fig21-worst-map.png",
                        "fig22.png",
                        "graph-map.png",
                        "topological-graph-map.png",
                        "report.html",
                        "grid.yaml",
                        "cells.tsv",
                        "cells/strategy-topological-graph_seed-1/report.json",
                        "cells/strategy-graph_seed-1/report.json",
                        "cells/strategy-fig21_seed-1/report.html",
                        "cells/strategy-fig21-paper_seed-1/config.yaml",
                        "cells/strategy-fig19_seed-1/map.dxf"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  // The paper's formulation is what its run says it used.
  const std::string paper = Slurp(out / "cells/strategy-fig21-paper_seed-1/config.yaml");
  EXPECT_NE(paper.find("correction: \"paper\""), std::string::npos);
  EXPECT_NE(paper.find("prediction: \"odometry\""), std::string::npos);
  const nlohmann::json summary = nlohmann::json::parse(Slurp(out / "summary.json"));
  EXPECT_EQ(summary["world"], "complex");
  ASSERT_EQ(summary["strategies"].size(), 6u);
  for (const auto& [name, s] : summary["strategies"].items()) {
    EXPECT_EQ(s["explored_and_healthy"].get<int>(), 1) << name;
    // The paper's formulation is reported beside the default, not held to its accuracy (seed 1:
    // 0.330 m against odometry's 0.233 m).
    if (s.contains("options")) continue;
    // Lines are the baseline that curved walls defeat (paper 003 Fig. 19): below odometry only.
    const double factor = s["method"] == "ekf-lines" ? 1.0 : 0.5;
    EXPECT_LT(s["rmse_position_m"][0].get<double>(),
              factor * s["odometry_rmse_position_m"][0].get<double>())
        << name;
    EXPECT_GT(s["map_size"][0].get<double>(), 100.0) << name;
    if (s["method"] != "ekf-lines") {
      EXPECT_GT(s["map_curves"][0].get<double>(), 10.0) << name;
      // The graph SLAM's map of this trial was 0.47 m off when a recovery search's wrong basin
      // was a stiff front-end edge (FrontEndOptions::Advanced::robust_recovery_edges).
      EXPECT_LT(s["map_accuracy_m"][0].get<double>(), 0.15) << name;
    }
  }
}

TEST(SplamCli, SplamExperimentNamesAWorldItCannotRead) {
  const fs::path out = Temp("experiment_splam_bad_world");
  const Output run = Splam("experiment splam --world no_such_world.yaml --out " + out.string());
  EXPECT_EQ(run.status, 2) << run.text;
  EXPECT_NE(run.text.find("no_such_world.yaml"), std::string::npos) << run.text;
}

TEST(SplamCli, ConfigFileEditedChangesTheRunAndAMisspeltKeyIsRefused) {
  const fs::path dir = Temp("config");
  fs::create_directories(dir);
  ASSERT_EQ(Splam("simulate --world office --seed 3 --out " + (dir / "sim").string()).status, 0);
  const std::string log = (dir / "sim" / "log.clf").string();
  // The simulation's own config.yaml repeats it to the byte.
  ASSERT_EQ(Splam("simulate --world office --seed 3 --config " +
                  (dir / "sim" / "config.yaml").string() + " --out " + (dir / "sim2").string())
                .status,
            0);
  EXPECT_EQ(Slurp(dir / "sim2" / "log.clf"), Slurp(dir / "sim" / "log.clf"));
  const Output printed = Splam("config print --method topological");
  ASSERT_EQ(printed.status, 0) << printed.text;
  EXPECT_NE(printed.text.find("correction_gain: 0.3  # "), std::string::npos) << printed.text;
  EXPECT_NE(printed.text.find("radius_m: 3  # "), std::string::npos);
  // One value edited: the run uses it and writes it into its own config.yaml.
  std::string edited = printed.text;
  edited.replace(edited.find("correction_gain: 0.3"), 20, "correction_gain: 0.55");
  ASSERT_EQ(io::WriteTextFile((dir / "t.yaml").string(), edited).message(), "");
  const Output run =
      Splam("slam --method topological --max-scans 150 --config " + (dir / "t.yaml").string() +
            " --out " + (dir / "a").string() + " " + log);
  ASSERT_EQ(run.status, 0) << run.text;
  const std::string used = Slurp(dir / "a" / "config.yaml");
  EXPECT_NE(used.find("correction_gain: 0.55"), std::string::npos) << used;
  // The run's config.yaml repeats it exactly.
  const Output again =
      Splam("slam --max-scans 150 --config " + (dir / "a" / "config.yaml").string() + " --out " +
            (dir / "b").string() + " " + log);
  ASSERT_EQ(again.status, 0) << again.text;
  EXPECT_EQ(Slurp(dir / "b" / "trajectory.txt").substr(100),
            Slurp(dir / "a" / "trajectory.txt").substr(100));
  EXPECT_EQ(Slurp(dir / "b" / "config.yaml").substr(200), used.substr(200));
  // --set overrides the file.
  const Output set =
      Splam("slam --max-scans 20 --config " + (dir / "t.yaml").string() +
            " --set topological.correction_gain=0.7 --out " + (dir / "c").string() + " " + log);
  ASSERT_EQ(set.status, 0) << set.text;
  EXPECT_NE(Slurp(dir / "c" / "config.yaml").find("correction_gain: 0.7"), std::string::npos);
  // A misspelt key: file, line and key, exit 2, nothing run.
  std::string misspelt = printed.text;
  const std::size_t at = misspelt.find("correction_gain");
  misspelt.replace(at, 15, "corection_gain");
  const int line = 1 + static_cast<int>(std::count(misspelt.begin(), misspelt.begin() + at, '\n'));
  ASSERT_EQ(io::WriteTextFile((dir / "bad.yaml").string(), misspelt).message(), "");
  const Output bad = Splam("slam --config " + (dir / "bad.yaml").string() + " --out " +
                           (dir / "d").string() + " " + log);
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.text.find((dir / "bad.yaml").string() + ":" + std::to_string(line) +
                          ": topological.corection_gain: unknown key"),
            std::string::npos)
      << bad.text;
  // A file of another method: its section is named, not silently dropped.
  const Output other = Splam("slam --method ekf-lines --config " + (dir / "t.yaml").string() +
                             " --out " + (dir / "e").string() + " " + log);
  EXPECT_EQ(other.status, 2);
  const std::string t_yaml = Slurp(dir / "t.yaml");
  const int section =
      1 + static_cast<int>(
              std::count(t_yaml.begin(), t_yaml.begin() + t_yaml.find("\ntopological:") + 1, '\n'));
  EXPECT_NE(other.text.find("t.yaml:" + std::to_string(section) + ": topological: unknown key"),
            std::string::npos)
      << other.text;
  const Output wrong_type =
      Splam("slam --method topological --set topological.min_verified_curves=two " + log);
  EXPECT_EQ(wrong_type.status, 2);
  EXPECT_NE(wrong_type.text.find("--set: topological.min_verified_curves: 'two' is not an integer"),
            std::string::npos)
      << wrong_type.text;
  const Output invalid =
      Splam("slam --method topological --set topological.correction_rounds=0 " + log);
  EXPECT_EQ(invalid.status, 2);
  EXPECT_NE(invalid.text.find("correction_rounds must be in [1, 100]"), std::string::npos)
      << invalid.text;
  // The graph SLAM's keys of before its options were split by part are refused with the new one.
  const Output moved = Splam("slam --method graph --set graph.trim_spacing_m=0 " + log);
  EXPECT_EQ(moved.status, 2);
  EXPECT_NE(
      moved.text.find("--set: graph.trim_spacing_m: this key is now graph.back_end.trim_spacing_m"),
      std::string::npos)
      << moved.text;
  const Output part = Splam("slam --method graph --set graph.front_end.truncation_m=20 " + log);
  EXPECT_EQ(part.status, 2);
  EXPECT_NE(part.text.find("graph: front_end: submap_keyframes >= 1"), std::string::npos)
      << part.text;
}

TEST(SplamCli, ExploreReadsItsConfigAndWritesTheOneItUsed) {
  const fs::path dir = Temp("explore_config");
  fs::create_directories(dir);
  const Output printed = Splam("config print --explorer srt --method ekf-lines");
  ASSERT_EQ(printed.status, 0);
  EXPECT_NE(printed.text.find("explorer: \"srt\""), std::string::npos) << printed.text;
  EXPECT_NE(printed.text.find("ekf-lines:"), std::string::npos);
  std::string edited = printed.text;
  edited.replace(edited.find("max_nodes: 400"), 14, "max_nodes: 4");
  ASSERT_EQ(io::WriteTextFile((dir / "e.yaml").string(), edited).message(), "");
  const Output run = Splam("explore --world corridor --lsr-radius 2.5 --config " +
                           (dir / "e.yaml").string() + " --out " + (dir / "run").string());
  EXPECT_EQ(run.status, 3) << run.text;  // the node cap stops it
  const auto report = nlohmann::json::parse(Slurp(dir / "run" / "report.json"));
  EXPECT_EQ(report["explorer"], "srt");
  EXPECT_EQ(report["localization"], "ekf-lines");
  EXPECT_EQ(report["nodes"], 4);
  EXPECT_EQ(report["options"]["lsr_radius_m"], 2.5);  // the flag overrides the file
  const std::string used = Slurp(dir / "run" / "config.yaml");
  EXPECT_NE(used.find("radius_m: 2.5"), std::string::npos) << used;
  EXPECT_NE(used.find("max_nodes: 4"), std::string::npos);
  // Flags win over the file's top-level values too (explorer, seed).
  const Output flags = Splam("explore --world corridor --explorer reg --seed 5 --config " +
                             (dir / "e.yaml").string() + " --out " + (dir / "flags").string());
  EXPECT_EQ(flags.status, 3) << flags.text;
  const auto flagged = nlohmann::json::parse(Slurp(dir / "flags" / "report.json"));
  EXPECT_EQ(flagged["explorer"], "reg");
  EXPECT_EQ(flagged["seed"], 5);
  EXPECT_EQ(flagged["nodes"], 4);  // the file's cap still holds
  const Output bad = Splam("explore --set exploration.max_nodez=3");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.text.find("--set: exploration.max_nodez: unknown key"), std::string::npos)
      << bad.text;
  // The explorer's own options are in its section, checked by its own rules.
  const std::string reg_used = Slurp(dir / "flags" / "config.yaml");
  EXPECT_NE(reg_used.find("  reg:  # options of the explorer\n    piece_factor: 1"),
            std::string::npos)
      << reg_used;
  const Output own = Splam("explore --explorer reg --set exploration.reg.piece_factor=0");
  EXPECT_EQ(own.status, 2);
  EXPECT_NE(own.text.find("exploration.reg: piece_factor must be in (0, 100]"), std::string::npos)
      << own.text;
  const Output other = Splam("explore --explorer reg --set exploration.srt.max_attempts=3");
  EXPECT_EQ(other.status, 2);  // --set reaches the chosen explorer's section only
  EXPECT_NE(other.text.find("exploration.srt: unknown key"), std::string::npos) << other.text;
}

TEST(SplamCli, EveryCommandHasHelp) {
  for (const char* command :
       {"", "simulate", "render", "slam", "eval", "experiment", "explore", "config print"}) {
    const Output r = Splam(std::string(command) + " --help");
    EXPECT_EQ(r.status, 0) << command;
    EXPECT_NE(r.text.find("Usage"), std::string::npos) << r.text;
  }
}

}  // namespace
}  // namespace splam
