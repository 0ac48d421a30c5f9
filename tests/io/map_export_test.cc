#include "io/map_export.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <limits>

#include "io/plot.h"
#include "io/relations.h"
#include "io/text.h"
#include "io/trajectory.h"

namespace splam::io {
namespace {

std::vector<estimation::MapLine> SomeLines() {
  std::vector<estimation::MapLine> lines;
  for (int i = 0; i < 5; ++i) {
    estimation::MapLine l;
    l.start = Eigen::Vector2d(i * 1.25, -0.5 * i);
    l.end = Eigen::Vector2d(i * 1.25 + 3.0, 0.125 * i);
    l.covariance = Eigen::Matrix2d::Identity();
    lines.push_back(l);
  }
  return lines;
}

TEST(MapExport, TextListsSegmentsAndCornersExactly) {
  const auto lines = SomeLines();
  const std::vector<estimation::MapCorner> corners = {
      {Eigen::Vector2d(0.1, 0.2), Eigen::Matrix2d::Identity(), 3}};
  const std::string text = FormatLineMapText(lines, corners);
  std::vector<std::vector<double>> segments, points;
  const kernel::Status error =
      ForEachDataLine(text, [&](int, const std::vector<std::string_view>& tokens) {
        std::vector<double> v;
        EXPECT_EQ(ParseFiniteNumbers({tokens.begin() + 1, tokens.end()}, &v).message(), "");
        (tokens[0] == "segment" ? segments : points).push_back(v);
        return kernel::Status::Ok();
      });
  ASSERT_EQ(error.message(), "");
  ASSERT_EQ(segments.size(), 5u);
  ASSERT_EQ(points.size(), 1u);
  EXPECT_EQ(segments[3], (std::vector<double>{3.75, -1.5, 6.75, 0.375}));
  EXPECT_EQ(points[0], (std::vector<double>{0.1, 0.2}));
}

TEST(MapExport, DxfReadsBackWithDxflib) {
  const std::string path = ::testing::TempDir() + "/map_export_test.dxf";
  const auto lines = SomeLines();
  const std::vector<estimation::MapCorner> corners = {
      {Eigen::Vector2d(1, 2), Eigen::Matrix2d::Identity(), 1},
      {Eigen::Vector2d(-3, 4.5), Eigen::Matrix2d::Identity(), 1}};
  ASSERT_EQ(WriteLineMapDxf(path, lines, corners).message(), "");
  const Result<DxfContent> back = ReadDxf(path);
  ASSERT_TRUE(back.ok()) << back.error;
  ASSERT_EQ(back.value->segments.size(), lines.size());
  for (std::size_t i = 0; i < lines.size(); ++i) {
    EXPECT_LT((back.value->segments[i].first - lines[i].start).norm(), 1e-9);
    EXPECT_LT((back.value->segments[i].second - lines[i].end).norm(), 1e-9);
  }
  ASSERT_EQ(back.value->points.size(), 2u);
  EXPECT_LT((back.value->points[1] - Eigen::Vector2d(-3, 4.5)).norm(), 1e-9);
  std::string text;
  ASSERT_EQ(ReadTextFile(path, &text).message(), "");
  EXPECT_NE(text.find("AC1015"), std::string::npos);  // AutoCAD 2000
  EXPECT_NE(WriteLineMapDxf("/nonexistent/dir/m.dxf", lines, corners).message(), "");
  EXPECT_FALSE(ReadDxf("/nonexistent.dxf").ok());
}

// A map coordinate of 1e300 crashed dxflib's number formatting (SIGABRT, a truncated
// map.dxf). It is refused, naming the file, and nothing is written.
TEST(MapExport, DxfRefusesCoordinatesBeyondAMillionMetres) {
  const std::string path = ::testing::TempDir() + "/map_export_huge.dxf";
  std::remove(path.c_str());
  for (const double huge : {1e300, 2e6, std::numeric_limits<double>::quiet_NaN()}) {
    auto lines = SomeLines();
    lines[2].end.y() = huge;
    const kernel::Status error = WriteLineMapDxf(path, lines, {});
    EXPECT_EQ(error.message().rfind(path + ": ", 0), 0u) << huge << " " << error.message();
    EXPECT_NE(error.message().find("not within +-1e6 m"), std::string::npos) << error.message();
    EXPECT_FALSE(std::filesystem::exists(path));
  }
}

// The same map gives the same bytes. The dimension style's text-style handle was read
// uninitialised (valgrind); the CTest test DxfIsValgrindClean runs this one under valgrind.
TEST(MapExport, DxfIsDeterministic) {
  const std::string a = ::testing::TempDir() + "/map_export_a.dxf";
  const std::string b = ::testing::TempDir() + "/map_export_b.dxf";
  ASSERT_EQ(WriteLineMapDxf(a, SomeLines(), {}).message(), "");
  ASSERT_EQ(WriteLineMapDxf(b, SomeLines(), {}).message(), "");
  std::string text_a, text_b;
  ASSERT_EQ(ReadTextFile(a, &text_a).message(), "");
  ASSERT_EQ(ReadTextFile(b, &text_b).message(), "");
  EXPECT_EQ(text_a, text_b);
}

TEST(Relations, ParsesTheBenchmarkFormatAndNamesBadLines) {
  const auto ok =
      ParseRelations("# t1 t2 x y z roll pitch yaw\n1.5 2.5 0.3 -0.1 0 0 0 0.25\n", "r.relations");
  ASSERT_TRUE(ok.ok()) << ok.error;
  ASSERT_EQ(ok.value->size(), 1u);
  EXPECT_EQ((*ok.value)[0].t2, 2.5);
  EXPECT_EQ((*ok.value)[0].motion.ToVector(), Eigen::Vector3d(0.3, -0.1, 0.25));
  EXPECT_EQ(ParseRelations("1 2 3\n", "r.relations").error,
            "r.relations:1: expected 8 values 't1 t2 x y z roll pitch yaw', found 3");
  EXPECT_EQ(ParseRelations("1 2 3 4 5 6 7 x\n", "r.relations").error,
            "r.relations:1: 'x' is not a finite number");
}

TEST(Plot, WritesSvgAndPngWithTheRightSize) {
  const std::string svg = ::testing::TempDir() + "/plot_test.svg",
                    png = ::testing::TempDir() + "/plot_test.png";
  PlotOptions options;
  options.title = "test";
  options.x_label = "time (s)";
  const std::vector<PlotPanel> panels = {{"a", {{"one", palette::kTrue, {0, 1, 2}, {0, 1, 0}}}},
                                         {"b", {{"two", palette::kOdometry, {0, 2}, {-1, 1}}}},
                                         {"empty", {}}};
  ASSERT_EQ(SavePlot(panels, options, {svg, png}).message(), "");
  std::string text;
  ASSERT_EQ(ReadTextFile(svg, &text).message(), "");
  EXPECT_NE(text.find("<svg"), std::string::npos);
  ASSERT_EQ(ReadTextFile(png, &text).message(), "");
  ASSERT_GT(text.size(), 24u);
  // PNG header: width and height, big endian, at bytes 16-23.
  auto be32 = [&](std::size_t at) {
    return (static_cast<unsigned char>(text[at]) << 24) |
           (static_cast<unsigned char>(text[at + 1]) << 16) |
           (static_cast<unsigned char>(text[at + 2]) << 8) |
           static_cast<unsigned char>(text[at + 3]);
  };
  EXPECT_EQ(be32(16), 900);
  EXPECT_EQ(be32(20), 30 + 3 * (200 + 18) + 45);
  EXPECT_NE(SavePlot(panels, options, {::testing::TempDir() + "/plot.bmp"}).message(), "");
}

}  // namespace
}  // namespace splam::io
