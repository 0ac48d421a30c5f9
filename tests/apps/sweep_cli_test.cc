// End-to-end tests of `splam sweep`: a grid on all cores, resumed, interrupted, merged,
// and its report opened in a real browser.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "tests/apps/cli_util.h"

namespace splam {
namespace {

using namespace cli_test;  // NOLINT

// A simulated corridor log and a grid of SLAM runs over it: two methods x two odometry noise
// scales, three figures.
fs::path SlamGrid(const std::string& name) {
  const fs::path dir = Temp(name);
  fs::create_directories(dir);
  EXPECT_EQ(Splam("simulate --world corridor --out " + (dir / "sim").string()).status, 0);
  WriteIn(dir, "grid.yaml", R"(command: slam
options: {log: sim/log.clf}
axes:
  method: [ekf-lines, graph]
  odometry-noise: [1, 2]
figures: [error.estimate.rmse_position_m, error.odometry.rmse_position_m, scans]
)");
  return dir;
}

TEST(SweepCli, GridRunsOnAllCoresResumesAndMerges) {
  const fs::path dir = SlamGrid("sweep_grid");
  Output run = Splam("sweep grid.yaml --out out --jobs 2", dir);
  ASSERT_EQ(run.status, 0) << run.text;
  // Output is not a terminal: one plain line per cell.
  EXPECT_NE(run.text.find("[4/4 done, 0 failed, 0 running, 0 skipped; "), std::string::npos)
      << run.text;
  EXPECT_EQ(run.text.find('\r'), std::string::npos);
  const std::string md = Slurp(dir / "out/table.md");
  EXPECT_EQ(md.rfind("| figure | ekf-lines, 1 | ekf-lines, 2 | graph, 1 | graph, 2 |", 0), 0u)
      << md;
  // Each cell's numbers are its own run's: the table's figure is the cell's summary.json.
  const nlohmann::json cell =
      nlohmann::json::parse(Slurp(dir / "out/cells/method-graph_odometry-noise-2/summary.json"));
  const double rmse = cell["error"]["estimate"]["rmse_position_m"];
  EXPECT_LT(rmse, cell["error"]["odometry"]["rmse_position_m"].get<double>());
  const std::string csv = Slurp(dir / "out/table.csv");
  EXPECT_NE(csv.find(fmt::format("graph,2,error.estimate.rmse_position_m,1,{:.6g},0,", rmse)),
            std::string::npos)
      << csv;
  for (const char* f :
       {"report.html", "cells/method-ekf-lines_odometry-noise-1/report.html",
        "cells/method-ekf-lines_odometry-noise-1/config.yaml", "grid.yaml", "cells.tsv"})
    EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
  // Again: nothing left to run.
  run = Splam("sweep grid.yaml --out out", dir);
  ASSERT_EQ(run.status, 0) << run.text;
  EXPECT_NE(run.text.find("0 run now (0 failed), 4 skipped"), std::string::npos) << run.text;
  run = Splam("sweep status out", dir);
  EXPECT_EQ(run.status, 0) << run.text;
  EXPECT_NE(run.text.find("4 cells: 4 done, 0 failed, 0 running, 0 not started"), std::string::npos)
      << run.text;
  // A bad grid names its file and line; a directory that is no sweep is refused.
  WriteIn(dir, "bad.yaml", "command: slam\naxes:\n  seed: {from: 1}\n");
  run = Splam("sweep bad.yaml", dir);
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.text.find("bad.yaml:3: seed: a range needs 'to'"), std::string::npos) << run.text;
  run = Splam("sweep merge sim", dir);
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.text.find("is sim a sweep directory?"), std::string::npos) << run.text;
  // An axis the command has no option for is refused before a cell runs, with the options it has;
  // a figure no cell reports is refused at the merge, with the figures they do (it gave a "-"
  // column and an empty panel).
  WriteIn(dir, "axis.yaml",
          "command: slam\noptions: {log: sim/log.clf}\naxes:\n  methd: [graph]\n");
  run = Splam("sweep axis.yaml --out axis", dir);
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.text.find("axis.yaml: axis methd: --methd is not an option of `splam slam`; its "
                          "options: method,"),
            std::string::npos)
      << run.text;
  EXPECT_FALSE(fs::exists(dir / "axis"));
  std::string grid = Slurp(dir / "out/grid.yaml");
  grid.replace(grid.find("scans"), 5, "scanz");
  WriteIn(dir / "out", "grid.yaml", grid);
  run = Splam("sweep merge out", dir);
  EXPECT_EQ(run.status, 2) << run.text;
  EXPECT_NE(run.text.find("figures: scanz is not among the figures the cells report: "),
            std::string::npos)
      << run.text;
}

// Issue 70, item 7: a sweep whose cells could not write their results (a full disk) exited 3, as
// if stopped early; a merge that could not be written said bad input (2). Both are exit 4.
TEST(SweepCli, CellsOrAMergeThatCannotBeWrittenGiveExitStatus4) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this machine";
  const fs::path dir = SlamGrid("sweep_full");
  const fs::path cell = dir / "out/cells/method-graph_odometry-noise-1";
  fs::create_directories(cell);
  fs::create_symlink("/dev/full", cell / "summary.json");
  Output run = Splam("sweep grid.yaml --out out --jobs 2", dir);
  EXPECT_EQ(run.status, 4) << run.text;
  EXPECT_NE(run.text.find("1 cells could not write their results (exit 4)"), std::string::npos)
      << run.text;
  fs::remove(cell / "summary.json");
  fs::remove(dir / "out/table.md");
  fs::create_symlink("/dev/full", dir / "out/table.md");
  run = Splam("sweep merge out", dir);
  EXPECT_EQ(run.status, 4) << run.text;
  EXPECT_NE(run.text.find("table.md"), std::string::npos) << run.text;
}

TEST(SweepCli, CtrlCKeepsFinishedCellsAndTheNextRunResumes) {
  const fs::path dir = Temp("sweep_interrupt");
  fs::create_directories(dir);
  WriteIn(dir, "grid.yaml",
          "command: simulate\noptions: {world: complex}\naxes:\n  seed: {from: 1, to: 6}\n");
  // Each cell takes about 1.5 s, two at once: Ctrl-C once the first has finished.
  const int status = SplamInterruptedWhen(
      "sweep " + (dir / "grid.yaml").string() + " --jobs 2 --out " + (dir / "out").string(), [&] {
        for (int seed = 1; seed <= 6; ++seed)
          if (fs::exists(dir / "out/cells" / ("seed-" + std::to_string(seed)) / "cell.json"))
            return true;
        return false;
      });
  EXPECT_EQ(status, 3);
  int finished = 0;
  for (int seed = 1; seed <= 6; ++seed) {
    const fs::path cell = dir / "out/cells" / ("seed-" + std::to_string(seed));
    if (fs::exists(cell / "cell.json")) {
      ++finished;
      EXPECT_TRUE(fs::exists(cell / "log.clf")) << cell;
    } else {
      EXPECT_FALSE(fs::exists(cell / "cell.started"))
          << cell << ": an interrupted cell is not running";
    }
  }
  EXPECT_GE(finished, 1);
  EXPECT_LT(finished, 6);
  const Output again = Splam("sweep grid.yaml --out out --no-merge", dir);
  ASSERT_EQ(again.status, 0) << again.text;
  EXPECT_NE(
      again.text.find(fmt::format("{} run now (0 failed), {} skipped", 6 - finished, finished)),
      std::string::npos)
      << again.text;
}

// The reports open in a real browser without errors, and show their plots.
TEST(SweepCli, ReportsOpenInHeadlessChromiumWithTheirPlots) {
  if (Splam("--help").status != 0 || std::system("chromium --version > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "chromium is not installed (scripts/setup.sh installs it)";
  const fs::path dir = SlamGrid("sweep_browser");
  ASSERT_EQ(Splam("sweep grid.yaml --out out --jobs 2", dir).status, 0);
  const auto browse = [&](const fs::path& page, const std::string& png) {
    const std::string command =
        "cd '" + dir.string() +
        "' && timeout 120 chromium --headless=new --no-sandbox --disable-gpu "
        "--enable-logging=stderr --v=0 --window-size=1300,1400 --screenshot=" +
        png + " file://" + fs::absolute(page).string() + " 2> browser.log > /dev/null";
    return std::system(command.c_str());
  };
  for (const fs::path& page :
       {dir / "out/report.html", dir / "out/cells/method-graph_odometry-noise-1/report.html"}) {
    const std::string png = (dir / "shot.png").string();
    fs::remove(png);
    if (browse(page, png) != 0 || !fs::exists(png))
      GTEST_SKIP() << "chromium cannot run here: " << Slurp(dir / "browser.log");
    const std::string log = Slurp(dir / "browser.log");
    // Console messages (a script error, a picture that does not load) come as CONSOLE lines.
    EXPECT_EQ(log.find(":CONSOLE("), std::string::npos) << page << "\n" << log;
    const std::string html = Slurp(page);
    EXPECT_EQ(html.find("http://"), std::string::npos) << page;
    EXPECT_EQ(html.find("https://"), std::string::npos) << page;
    if (page.filename() != "report.html" || page.parent_path().filename() != "out") continue;
    // The merged report: its strip plots are drawn (blue dots per cell, red medians).
    const cv::Mat shot = cv::imread(png, cv::IMREAD_COLOR);
    ASSERT_FALSE(shot.empty());
    int blue = 0, red = 0;
    for (int r = 0; r < shot.rows; ++r) {
      for (int c = 0; c < shot.cols; ++c) {
        const cv::Vec3b p = shot.at<cv::Vec3b>(r, c);  // BGR
        blue += p[0] > 150 && p[1] < 120 && p[2] < 80;
        red += p[2] > 180 && p[1] < 60 && p[0] < 60;
      }
    }
    EXPECT_GT(blue, 100) << "no dots of cells in the screenshot";
    EXPECT_GT(red, 100) << "no medians in the screenshot";
  }
}

}  // namespace
}  // namespace splam
