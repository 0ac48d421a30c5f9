#include "io/sweep_grid.h"

#include <gtest/gtest.h>

#include "io/html.h"

namespace splam::io {
namespace {

constexpr char kGrid[] = R"(# a grid
command: experiment splam
options: {world: office, no-sonar: true}
set:
  exploration.alpha: -20
axes:
  strategy:
    - {name: fig19, explorer: srt, localization: ekf-lines}
    - {name: paper, explorer: reg, set.topological.prediction: odometry}
  seed: {from: 1, to: 3}
  set.exploration.min_frontier_m: [0.3, 0.5]
replicate: seed
figures: [coverage_fraction]
)";

TEST(SweepGrid, ReadsCommandOptionsAxesAndRanges) {
  const Result<Grid> read = ParseGrid(kGrid, "grid.yaml");
  ASSERT_TRUE(read.ok()) << read.error;
  const Grid& g = *read.value;
  EXPECT_EQ(g.command, (std::vector<std::string>{"experiment", "splam"}));
  ASSERT_EQ(g.options.size(), 3u);
  EXPECT_EQ(g.options[0], (GridOption{"world", "office", false}));
  EXPECT_EQ(g.options[1], (GridOption{"no-sonar", "true", false}));
  EXPECT_EQ(g.options[2], (GridOption{"exploration.alpha", "-20", true}));
  ASSERT_EQ(g.axes.size(), 3u);
  EXPECT_EQ(g.axes[0].name, "strategy");
  ASSERT_EQ(g.axes[0].values.size(), 2u);
  EXPECT_EQ(g.axes[0].values[1].label, "paper");
  EXPECT_EQ(g.axes[0].values[1].options[1],
            (GridOption{"topological.prediction", "odometry", true}));
  ASSERT_EQ(g.axes[1].values.size(), 3u);
  EXPECT_EQ(g.axes[1].values[2].label, "3");
  EXPECT_EQ(g.axes[1].values[2].options[0], (GridOption{"seed", "3", false}));
  EXPECT_EQ(g.axes[2].values[0].options[0],
            (GridOption{"exploration.min_frontier_m", "0.3", true}));
  EXPECT_EQ(g.replicate, "seed");
  EXPECT_EQ(g.figures, std::vector<std::string>{"coverage_fraction"});
}

TEST(SweepGrid, RangesOfFractionsAreWrittenShort) {
  const Result<Grid> read =
      ParseGrid("command: slam\naxes:\n  x: {from: 0.1, to: 0.5, step: 0.1}\n", "g.yaml");
  ASSERT_TRUE(read.ok()) << read.error;
  std::vector<std::string> labels;
  for (const GridValue& v : read.value->axes[0].values) labels.push_back(v.label);
  // 0.1 + 2 * 0.1 is 0.30000000000000004 in doubles; the label is what a person wrote.
  EXPECT_EQ(labels, (std::vector<std::string>{"0.1", "0.2", "0.3", "0.4", "0.5"}));
  // No axis named seed: no replicate.
  EXPECT_EQ(read.value->replicate, "");
}

TEST(SweepGrid, WritesWhatItReadsBack) {
  const Result<Grid> read = ParseGrid(kGrid, "grid.yaml");
  ASSERT_TRUE(read.ok());
  const Result<Grid> again = ParseGrid(GridToYaml(*read.value), "again.yaml");
  ASSERT_TRUE(again.ok()) << again.error << "\n" << GridToYaml(*read.value);
  EXPECT_EQ(*again.value, *read.value) << GridToYaml(*read.value);
  // No replicate, figures after it.
  const Result<Grid> plain =
      ParseGrid("command: slam\naxes: {method: [graph]}\nfigures: [scans]\n", "plain.yaml");
  ASSERT_TRUE(plain.ok());
  const Result<Grid> plain_again = ParseGrid(GridToYaml(*plain.value), "again.yaml");
  ASSERT_TRUE(plain_again.ok()) << plain_again.error << "\n" << GridToYaml(*plain.value);
  EXPECT_EQ(*plain_again.value, *plain.value);
}

TEST(SweepGrid, ProblemsNameTheFileAndLine) {
  const auto error = [](const std::string& text) {
    const Result<Grid> r = ParseGrid(text, "g.yaml");
    return r.ok() ? std::string("accepted") : r.error;
  };
  EXPECT_EQ(error("axes: {seed: [1]}\n"),
            "g.yaml:1: a grid needs a command (slam, explore, experiment NAME)");
  EXPECT_EQ(error("command: slam\nbogus: 1\n"),
            "g.yaml:2: unknown key 'bogus' (a grid has command, options, set, axes, replicate, "
            "figures)");
  // A grid of 10^9 cells was built in memory; `command: sweep` started a sweep in every cell.
  EXPECT_EQ(error("command: slam\naxes:\n  a: {from: 1, to: 1000}\n  b: {from: 1, to: 1000}\n"
                  "  c: {from: 1, to: 1000}\n"),
            "g.yaml:3: the axes make 1000000000 cells, more than 1000000 (split the grid)");
  EXPECT_EQ(error("command: sweep g.yaml\naxes:\n  seed: [1]\n"),
            "g.yaml:1: a cell runs slam, explore, simulate or experiment NAME, not 'sweep'");
  // A tab in a value became more arguments (this ran graph); a line break broke cells.tsv.
  EXPECT_EQ(error("command: slam\noptions:\n  log: \"small.clf\\t--method\\tgraph\"\n"),
            "g.yaml:3: log must not hold a tab, a line break or another control character");
  // Lists as keys (YAML's `?`) read as empty names before, and the grid ran.
  EXPECT_EQ(error("command: slam\n? [a, b]\n: 1\n"),
            "g.yaml:2: a key must be a plain word, not a list or a map");
  EXPECT_EQ(error("command: slam\naxes:\n  ? [a]\n  : [1]\n"),
            "g.yaml:3: a key must be a plain word, not a list or a map");
  EXPECT_EQ(error("command: slam\noptions:\n  ? [a]\n  : 1\naxes:\n  seed: [1]\n"),
            "g.yaml:3: a key must be a plain word, not a list or a map");
  EXPECT_EQ(error("command: slam\naxes:\n  seed: []\n"), "g.yaml:3: seed: an axis without values");
  EXPECT_EQ(error("command: slam\naxes:\n  seed: {from: 1, to: 1e9}\n"),
            "g.yaml:3: seed: a range of more than 100000 values");
  EXPECT_EQ(error("command: slam\naxes:\n  seed: {from: 1, to: nan}\n"),
            "g.yaml:3: seed.to is not a finite number");
  EXPECT_EQ(error("command: slam\naxes:\n  seed: {from: 3, to: 1}\n"),
            "g.yaml:3: seed: a range's 'to' is below its 'from'");
  EXPECT_EQ(error("command: slam\naxes:\n  seed: {from: 1, to: 3, step: 0}\n"),
            "g.yaml:3: seed: the step of a range must be above 0");
  EXPECT_EQ(error("command: slam\naxes:\n  s:\n    - {explorer: srt}\n"),
            "g.yaml:4: s: a value that sets several options needs a 'name'");
  EXPECT_EQ(error("command: slam\naxes:\n  seed: [1, 1]\n"),
            "g.yaml:3: seed: the value '1' is given twice");
  EXPECT_EQ(error("command: slam\noptions: {world: [a, b]}\n"),
            "g.yaml:2: world must be a single value, not a list or a map");
  EXPECT_EQ(error("command: slam\naxes: {seed: [1]}\nreplicate: run\n"),
            "g.yaml:3: replicate names no axis: 'run'");
  EXPECT_EQ(error("command: slam\naxes: {seed: [1]\n").rfind("g.yaml:", 0), 0u);
  EXPECT_EQ(ReadGrid("/nonexistent/grid.yaml").error,
            "/nonexistent/grid.yaml: cannot open for reading");
}

TEST(Html, EscapesAndEncodes) {
  EXPECT_EQ(HtmlEscape("<a href=\"x\">&'</a>"), "&lt;a href=&quot;x&quot;&gt;&amp;&#39;&lt;/a&gt;");
  // RFC 4648 test vectors.
  EXPECT_EQ(Base64(""), "");
  EXPECT_EQ(Base64("f"), "Zg==");
  EXPECT_EQ(Base64("fo"), "Zm8=");
  EXPECT_EQ(Base64("foo"), "Zm9v");
  EXPECT_EQ(Base64("foob"), "Zm9vYg==");
  EXPECT_EQ(Base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(Base64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(Base64(std::string("\xff\0\x80", 3)), "/wCA");
  HtmlPage page("a <title>");
  page.Table({"k"}, {{HtmlCell("v", "cells/a b/report.html")}});
  const std::string html = page.Html();
  EXPECT_NE(html.find("<title>a &lt;title&gt;</title>"), std::string::npos);
  EXPECT_NE(html.find("<a href=\"cells/a b/report.html\">v</a>"), std::string::npos);
  EXPECT_EQ(html.find("http"), std::string::npos);  // nothing from the network
}

}  // namespace
}  // namespace splam::io
