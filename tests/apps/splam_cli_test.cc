// End-to-end tests of the `splam` binary: exit codes, messages and the files it writes.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "io/carmen.h"
#include "io/simulation_log.h"
#include "io/trajectory.h"

namespace splam {
namespace {

namespace fs = std::filesystem;

struct Output {
  int status = -1;
  std::string text;  // stdout and stderr
};

Output Splam(const std::string& args) {
  const std::string command = std::string(SPLAM_BINARY) + " " + args + " 2>&1";
  Output out;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return out;
  std::array<char, 4096> buffer;
  while (std::size_t n = fread(buffer.data(), 1, buffer.size(), pipe))
    out.text.append(buffer.data(), n);
  const int status = pclose(pipe);
  out.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

fs::path Temp(const std::string& name) {
  const fs::path p = fs::path(::testing::TempDir()) / ("splam_cli_" + name);
  fs::remove_all(p);
  return p;
}

std::string Slurp(const fs::path& p) {
  std::string text;
  EXPECT_EQ(io::ReadTextFile(p.string(), &text), "") << p;
  return text;
}

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
      io::WriteTextFile((dir / "route.txt").string(), "# start pose then waypoints\n1 6 0\n5 6\n"),
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
                              "obstacles:\n  - circle: {center: [1, 1], radius: -2}\n"),
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

  ASSERT_EQ(io::WriteTextFile((dir / "route.txt").string(), "1 6 0\n5 six\n"), "");
  r = Splam("simulate --world office --route " + (dir / "route.txt").string() + " --out " +
            (dir / "o").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("route.txt:2: 'six' is not a finite number"), std::string::npos) << r.text;

  ASSERT_EQ(io::WriteTextFile((dir / "bad.clf").string(), "ODOM 1 2 3 0 0 0 1 h 1\nFLASER 3 1 2\n"),
            "");
  r = Splam("render --log " + (dir / "bad.clf").string() + " --out " + (dir / "x.png").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("bad.clf:2: FLASER: line ends early"), std::string::npos) << r.text;

  ASSERT_EQ(io::WriteTextFile((dir / "plan.png").string(), "not an image"), "");
  r = Splam("simulate --world " + (dir / "plan.png").string() + " --route " +
            (dir / "route.txt").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.text.find("plan.png: cannot decode image"), std::string::npos) << r.text;

  r = Splam("simulate --laser lidar9000");
  EXPECT_EQ(r.status, 2);
  r = Splam("frobnicate");
  EXPECT_EQ(r.status, 2);
}

TEST(SplamCli, CollisionStopsTheRunButWritesWhatWasDone) {
  const fs::path dir = Temp("collide");
  fs::create_directories(dir);
  // Straight through the office wall at y = 5.
  ASSERT_EQ(io::WriteTextFile((dir / "route.txt").string(), "1 6 -1.5707963\n1 2\n"), "");
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
}

TEST(SplamCli, EveryCommandHasHelp) {
  for (const char* command : {"", "simulate", "render"}) {
    const Output r = Splam(std::string(command) + " --help");
    EXPECT_EQ(r.status, 0) << command;
    EXPECT_NE(r.text.find("Usage"), std::string::npos) << r.text;
  }
}

}  // namespace
}  // namespace splam
