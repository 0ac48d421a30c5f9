#include "studies/sweep.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/trajectory.h"
#include "runtime/json_text.h"
#include "runtime/run_html.h"
#include "studies/bspline_experiment.h"
#include "studies/corridor_experiment.h"
#include "studies/exploration_experiment.h"
#include "studies/slurm.h"
#include "studies/splam_experiment.h"
#include "studies/sweep_merge.h"

namespace splam::studies {
namespace {

using runtime::kMaxJsonDepth;
using runtime::ReadJson;
using runtime::RunFigures;

namespace fs = std::filesystem;

io::Grid Parse(const std::string& text) {
  io::Result<io::Grid> g = io::ParseGrid(text, "grid.yaml");
  EXPECT_TRUE(g.ok()) << g.error;
  return g.ok() ? *g.value : io::Grid{};
}

TEST(SweepCells, EveryCombinationNamedAfterItsValues) {
  const io::Grid grid = Parse(R"(command: explore
options: {world: office, explorer: reg, trace: true, sonar: false}
set: {exploration.alpha: -20}
axes:
  explorer: [reg, srt]
  seed: {from: 1, to: 3}
  set.exploration.alpha: [-25]
  world: [/some/where/floor plan.png]
)");
  const std::vector<SweepCell> cells = GridCells(grid);
  ASSERT_EQ(cells.size(), 6u);  // 2 x 3 x 1 x 1, the last axis fastest
  EXPECT_EQ(cells[0].name, "explorer-reg_seed-1_alpha--25_world-floor-plan");
  EXPECT_EQ(cells[5].name, "explorer-srt_seed-3_alpha--25_world-floor-plan");
  EXPECT_EQ(cells[4].values[1], (std::pair<std::string, std::string>{"seed", "2"}));
  // A fixed option the axes also set is given once, with the axis's value; `true` is a flag and
  // `false` leaves the option out.
  EXPECT_EQ(cells[5].args, (std::vector<std::string>{
                               "explore", "--trace", "--explorer", "srt", "--seed", "3", "--set",
                               "exploration.alpha=-25", "--world", "/some/where/floor plan.png"}));
  // Without axes: one cell.
  const std::vector<SweepCell> single = GridCells(Parse("command: slam\n"));
  ASSERT_EQ(single.size(), 1u);
  EXPECT_EQ(single[0].name, "single");
  // Values whose names clash stay apart.
  const std::vector<SweepCell> clash =
      GridCells(Parse("command: slam\naxes: {log: [a/x.clf, b/x.clf]}\n"));
  ASSERT_EQ(clash.size(), 2u);
  EXPECT_NE(clash[0].name, clash[1].name);
}

TEST(SweepStats, MedianAndPopulationStd) {
  FigureStats s = StatsOf({4.0, 1.0, 3.0, 2.0});
  EXPECT_EQ(s.n, 4);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 4.0);
  s = StatsOf({5.0, 1.0, 2.0});
  EXPECT_DOUBLE_EQ(s.median, 2.0);
  EXPECT_EQ(StatsOf({}).n, 0);
}

TEST(SweepRun, RunsResumesRecordsFailuresAndMerges) {
  const std::string dir = ::testing::TempDir() + "/splam_sweep_run";
  fs::remove_all(dir);
  // Two worlds, one that does not exist, times two seeds: the failures are recorded, the others
  // still run.
  const io::Grid grid = Parse(R"(command: simulate
options: {max-steps: 40}
axes:
  world: [corridor, no_such_world.yaml]
  seed: [1, 2]
)");
  ASSERT_TRUE(WriteSweepPlan(dir, grid).ok());
  SweepRunOptions options;
  options.splam_binary = SPLAM_BINARY;
  options.jobs = 2;
  std::vector<std::string> events;
  options.progress = [&](const SweepProgress& p) {
    EXPECT_EQ(p.total, 4);
    EXPECT_LE(p.running, 2);
    if (!p.event.empty()) events.push_back(p.event);
  };
  kernel::Result<SweepRunSummary> run = RunSweepLocally(dir, options);
  ASSERT_TRUE(run.ok()) << run.error;
  EXPECT_EQ(run.value->done, 2);
  EXPECT_EQ(run.value->failed, 2);
  EXPECT_EQ(run.value->skipped, 0);
  EXPECT_EQ(events.size(), 4u);
  const std::optional<CellRecord> bad =
      ReadCellRecord(dir + "/cells/world-no-such-world.yaml_seed-1");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->exit_status, 2);
  EXPECT_NE(bad->message.find("no_such_world.yaml"), std::string::npos) << bad->message;
  const std::optional<CellRecord> good = ReadCellRecord(dir + "/cells/world-corridor_seed-2");
  ASSERT_TRUE(good);
  // --max-steps cut the route short: exit 3, a result that stopped early, counted as done.
  EXPECT_EQ(good->exit_status, 3);
  EXPECT_TRUE(good->ok());
  EXPECT_TRUE(fs::exists(dir + "/cells/world-corridor_seed-2/log.clf"));

  kernel::Result<SweepStatus> status = ReadSweepStatus(dir);
  ASSERT_TRUE(status.ok());
  EXPECT_EQ(status.value->done, 2);
  EXPECT_EQ(status.value->failed, 2);
  ASSERT_EQ(status.value->failures.size(), 2u);

  // Again: the finished cells are skipped, the failed ones run again.
  run = RunSweepLocally(dir, options);
  ASSERT_TRUE(run.ok());
  EXPECT_EQ(run.value->skipped, 2);
  EXPECT_EQ(run.value->failed, 2);

  // The same directory does not take another grid.
  io::Grid other = grid;
  other.axes[1].values.pop_back();
  EXPECT_NE(WriteSweepPlan(dir, other).message().find("holds the cells of another grid"),
            std::string::npos);

  // Merge: grouped by world (seed is the replicate); the corridor's two seeds are averaged.
  kernel::Result<MergedSweep> merged = MergeSweep(dir);
  ASSERT_TRUE(merged.ok()) << merged.error;
  ASSERT_EQ(merged.value->groups.size(), 2u);
  const MergedGroup& corridor = merged.value->groups[0];
  EXPECT_EQ(corridor.values[0].second, "corridor");
  EXPECT_EQ(corridor.cells, 2);
  EXPECT_EQ(merged.value->groups[1].failed, 2);
  const auto figures = RunFigures(dir + "/cells/world-corridor_seed-1");
  ASSERT_FALSE(figures.empty());
  const std::string figure = figures.begin()->first;
  const double a = figures.at(figure);
  const double b = RunFigures(dir + "/cells/world-corridor_seed-2").at(figure);
  EXPECT_EQ(corridor.figures.at(figure).n, 2);
  EXPECT_DOUBLE_EQ(corridor.figures.at(figure).mean, 0.5 * (a + b));
  kernel::Result<std::vector<std::string>> written = WriteMergedSweep(*merged.value);
  ASSERT_TRUE(written.ok()) << written.error;
  std::string csv;
  ASSERT_EQ(io::ReadTextFile(dir + "/table.csv", &csv).message(), "");
  EXPECT_EQ(csv.rfind("world,figure,n,mean,std,median,min,max,cells,failed,not_run\n", 0), 0u);
  EXPECT_NE(csv.find("\ncorridor," + figure + ",2,"), std::string::npos) << csv;
  std::string html;
  ASSERT_EQ(io::ReadTextFile(dir + "/report.html", &html).message(), "");
  EXPECT_NE(html.find("data:image/svg+xml;base64,"), std::string::npos);
  EXPECT_NE(html.find("cells/world-corridor_seed-1"), std::string::npos);
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
}

// The experiments' grids are the ones shipped in experiments/: `splam sweep experiments/X.yaml`
// runs the trials of `splam experiment X`.
// A truncated or edited cells.tsv ran other command lines than grid.yaml says
// and filed their figures under other cells; the cells now come from grid.yaml and cells.tsv
// must match it.
TEST(SweepState, CellsTsvMustSayWhatGridYamlSays) {
  const fs::path dir = fs::temp_directory_path() / "splam_sweep_tsv_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const io::Grid grid = Parse("command: simulate\naxes:\n  seed: [1, 2, 3]\n");
  ASSERT_TRUE(WriteSweepPlan(dir.string(), grid).ok());
  const std::string tsv = (dir / "cells.tsv").string();
  std::string text;
  ASSERT_EQ(io::ReadTextFile(tsv, &text).message(), "");
  const kernel::Result<SweepPlan> plan = ReadSweepPlan(dir.string());
  ASSERT_TRUE(plan.ok()) << plan.error;
  EXPECT_EQ(plan.value->cells.size(), 3u);
  std::ofstream(tsv) << text.substr(0, text.rfind('\n', text.size() - 2) + 1);  // the last cell cut
  EXPECT_NE(ReadSweepPlan(dir.string()).error.find("lists 2 cells"), std::string::npos);
  std::string edited = text;
  edited.replace(edited.find("--seed\t2"), 9, "--seed\t9");
  std::ofstream(tsv) << edited;
  EXPECT_NE(ReadSweepPlan(dir.string()).error.find("not cell 1 of"), std::string::npos)
      << ReadSweepPlan(dir.string()).error;
  fs::remove_all(dir);
}

// Sweep state is read with a schema. A cell.json whose message is a number or
// wall time a string aborted `sweep status`, resume and merge; such a record is now none (the cell
// runs again). A summary.json nested 10^6 deep segfaulted `merge`; values deeper than
// kMaxJsonDepth are now left out.
TEST(SweepState, RecordsOfOtherTypesAreNoneAndDeepDocumentsAreCut) {
  const fs::path dir = fs::temp_directory_path() / "splam_sweep_state_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto record = [&](const std::string& text) {
    std::ofstream(dir / "cell.json") << text;
    return ReadCellRecord(dir.string());
  };
  const std::optional<CellRecord> good =
      record(R"({"exit_status": 3, "wall_s": 1.5, "message": "stopped", "host": "h"})");
  ASSERT_TRUE(good.has_value());
  EXPECT_EQ(good->exit_status, 3);
  EXPECT_EQ(good->message, "stopped");
  for (const std::string bad :
       {R"({"exit_status": 0, "wall_s": 1.5, "message": 7, "host": "h"})",
        R"({"exit_status": 0, "wall_s": "slow", "message": "", "host": "h"})",
        R"({"exit_status": 0, "wall_s": 1, "message": ""})",
        R"({"exit_status": 1e300, "wall_s": 1, "message": "", "host": ""})",
        R"({"exit_status": -4, "wall_s": 1, "message": "", "host": ""})", R"([1, 2])", "{"})
    EXPECT_FALSE(record(bad).has_value()) << bad;
  std::string deep = std::string(1000000, '[') + std::string(1000000, ']');
  std::istringstream in("{\"a\": 1, \"b\": " + deep + "}");
  const nlohmann::json j = ReadJson(in);
  ASSERT_TRUE(j.is_object());
  EXPECT_EQ(j["a"], 1);
  int depth = 0;
  for (const nlohmann::json* v = &j["b"]; v->is_array() && !v->empty(); v = &(*v)[0]) ++depth;
  EXPECT_LE(depth, kMaxJsonDepth);
  fs::remove_all(dir);
}

// A newline in the sweep directory (or the working directory, or the binary's path) would end an
// #SBATCH comment and run the rest as a shell command when the job starts: such a path is
// refused, naming it, before anything is written or submitted; every path an #SBATCH line
// carries is in double quotes (spaces stay one argument).
TEST(SlurmSweep, APathThatCouldEndAnSbatchLineIsRefusedBeforeAnythingIsWritten) {
  const fs::path base = fs::temp_directory_path() / "splam_slurm_path_test";
  fs::remove_all(base);
  SlurmOptions options;
  options.sbatch = "false";  // never reached
  for (const std::string& bad :
       std::vector<std::string>{"x\ntouch /tmp/pwned #", "x\ry", "a\"b", "t\x01"}) {
    const std::string dir = (base / bad).string();
    const kernel::Result<std::string> r = SubmitSweepToSlurm(dir, "/usr/bin/splam", {0}, options);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_NE(r.error.find("the sweep directory"), std::string::npos) << r.error;
    EXPECT_EQ(r.error.find('\n'), std::string::npos) << "the path is printed escaped: " << r.error;
    EXPECT_FALSE(fs::exists(dir)) << bad;
  }
  const std::string script = SlurmScript("/data/my sweeps/a", "/opt/splam", 3, "/home/me", options);
  EXPECT_NE(script.find("#SBATCH --output=\"/data/my sweeps/a/slurm/task-%A_%a.out\"\n"),
            std::string::npos)
      << script;
  EXPECT_NE(script.find("#SBATCH --chdir=\"/home/me\"\n"), std::string::npos) << script;
  EXPECT_TRUE(CheckScriptPath("a path", "/data/my sweeps/a").ok());
  fs::remove_all(base);
}

TEST(SweepExperiments, TheShippedGridIsTheExperimentsGrid) {
  const io::Result<io::Grid> shipped = io::ReadGrid(SPLAM_SOURCE_DIR "/experiments/splam.yaml");
  ASSERT_TRUE(shipped.ok()) << shipped.error;
  EXPECT_EQ(*shipped.value, SplamExperimentGrid(SplamExperimentArgs()));
  EXPECT_EQ(GridCells(*shipped.value).size(), 60u);
  const io::Result<io::Grid> fig18 = io::ReadGrid(SPLAM_SOURCE_DIR "/experiments/exploration.yaml");
  ASSERT_TRUE(fig18.ok()) << fig18.error;
  EXPECT_EQ(*fig18.value, ExplorationExperimentGrid(ExplorationExperimentArgs()));
  EXPECT_EQ(GridCells(*fig18.value).size(), 80u);
  const io::Result<io::Grid> corridor =
      io::ReadGrid(SPLAM_SOURCE_DIR "/experiments/corridor-lines.yaml");
  ASSERT_TRUE(corridor.ok()) << corridor.error;
  EXPECT_EQ(*corridor.value, CorridorGrid(CorridorOptions()))
      << io::GridToYaml(CorridorGrid(CorridorOptions()));
  const io::Result<io::Grid> bspline =
      io::ReadGrid(SPLAM_SOURCE_DIR "/experiments/complex-bspline.yaml");
  ASSERT_TRUE(bspline.ok()) << bspline.error;
  EXPECT_EQ(*bspline.value, ComplexBSplineGrid(BSplineExperimentArgs()))
      << io::GridToYaml(ComplexBSplineGrid(BSplineExperimentArgs()));
}

}  // namespace
}  // namespace splam::studies
