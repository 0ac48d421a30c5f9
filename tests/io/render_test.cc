#include "io/render.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <regex>

#include "io/trajectory.h"
#include "sim/builtin_worlds.h"

namespace splam::io {
namespace {

std::string Draw(const std::string& file) {
  const sim::World world = *sim::BuiltinWorld("complex");
  FigureOptions options;
  options.title = "test";
  options.pixels_per_meter = 20;
  Figure figure(world.Bounds(), options);
  figure.DrawWorld(world);
  figure.DrawPath({kernel::Pose2(1.5, 2, 0), kernel::Pose2(7.5, 2, 0)}, palette::kTrue, 2.0,
                  "truth");
  figure.DrawPoints({{5, 5}}, palette::kScan, 3.0, "points");
  figure.DrawRobot(kernel::Pose2(7.5, 2, 0), 0.267, palette::kTrue);
  const std::string path = ::testing::TempDir() + "/" + file;
  EXPECT_EQ(figure.Save(path).message(), "");
  return path;
}

TEST(Figure, PngHasTheExpectedSizeAndContent) {
  const std::string path = Draw("render_test.png");
  const cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty());
  const kernel::Box2 b = sim::BuiltinWorld("complex")->Bounds();
  EXPECT_EQ(image.cols, static_cast<int>(std::ceil((b.Size().x() + 1.0) * 20)));
  EXPECT_EQ(image.rows, static_cast<int>(std::ceil((b.Size().y() + 1.0) * 20)) + 28 + 30);
  // The true path from (1.5, 2) to (7.5, 2) is blue at its midpoint (4.5, 2).
  const int x = static_cast<int>((4.5 - b.min.x() + 0.5) * 20);
  const int y = 28 + static_cast<int>((b.max.y() - 2.0 + 0.5) * 20);
  const cv::Vec3b pixel = image.at<cv::Vec3b>(y, x);  // BGR
  EXPECT_GT(pixel[0], 150);
  EXPECT_LT(pixel[2], 100);
  // Background is white.
  EXPECT_EQ(image.at<cv::Vec3b>(28 + 3, 3), cv::Vec3b(255, 255, 255));
}

TEST(Figure, SvgIsWrittenAndDeterministic) {
  const std::string a = Draw("render_a.svg"), b = Draw("render_b.svg");
  std::string ta, tb;
  ASSERT_EQ(ReadTextFile(a, &ta).message(), "");
  ASSERT_EQ(ReadTextFile(b, &tb).message(), "");
  EXPECT_NE(ta.find("<svg"), std::string::npos);
  EXPECT_NE(ta.find(" C "), std::string::npos);  // curved walls are drawn as Bezier curves
  // cairo numbers surfaces with a per-process counter; separate runs give identical files (see
  // the splam CLI test), within one process only these labels differ.
  // Every reference points at a defined element (cairo can emit dangling clip references).
  const std::regex reference("url\\(#([A-Za-z0-9_-]+)\\)");
  for (auto it = std::sregex_iterator(ta.begin(), ta.end(), reference);
       it != std::sregex_iterator(); ++it) {
    EXPECT_NE(ta.find("id=\"" + (*it)[1].str() + "\""), std::string::npos) << (*it)[1].str();
  }
  const std::regex surface_id("surface[0-9]+");
  EXPECT_EQ(std::regex_replace(ta, surface_id, "surface"),
            std::regex_replace(tb, surface_id, "surface"));
}

TEST(Figure, UnknownFormatAndUnwritablePathAreErrors) {
  Figure figure(kernel::Box2{{0, 0}, {1, 1}});
  EXPECT_NE(figure.Save(::testing::TempDir() + "/x.gif").message().find("unknown picture format"),
            std::string::npos);
  EXPECT_NE(figure.Save("/nonexistent/dir/x.png").message(), "");
}

TEST(FigureOptions, Validate) {
  EXPECT_TRUE(FigureOptions().Validate().ok());
  FigureOptions o;
  o.pixels_per_meter = 0;
  EXPECT_FALSE(o.Validate().ok());
}

}  // namespace
}  // namespace splam::io
