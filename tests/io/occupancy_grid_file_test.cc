#include "io/occupancy_grid_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "io/trajectory.h"
#include "kernel/random.h"

namespace splam::io {
namespace {

using estimation::CellState;
using estimation::OccupancyGrid;
using estimation::OccupancyGridOptions;

std::string TempPath(const std::string& name) { return ::testing::TempDir() + "/" + name; }

// A grid of random cells: a third unknown, the others of random probability.
OccupancyGrid RandomGrid(int width, int height, std::uint64_t seed) {
  OccupancyGrid grid({-12.345678901, 3.25}, 0.05, width, height);
  kernel::Random random(seed);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (random.Uniform() > 1.0 / 3) grid.Set(x, y, static_cast<float>(random.Uniform(-4, 4)));
  return grid;
}

TEST(OccupancyGridFile, RoundTripKeepsEveryCellsStateAndTheFrame) {
  const OccupancyGridOptions t;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const OccupancyGrid grid = RandomGrid(37 + static_cast<int>(seed), 23, seed);
    const std::string yaml = TempPath("grid_round_trip.yaml");
    ASSERT_TRUE(WriteOccupancyGrid(grid, yaml, t).ok());
    const Result<OccupancyGrid> read = ReadOccupancyGrid(yaml);
    ASSERT_TRUE(read.ok()) << read.error;
    ASSERT_EQ(read->width(), grid.width());
    ASSERT_EQ(read->height(), grid.height());
    EXPECT_EQ(read->origin(), grid.origin());  // exactly: the shortest text that reads back
    EXPECT_EQ(read->resolution_m(), grid.resolution_m());
    for (int y = 0; y < grid.height(); ++y)
      for (int x = 0; x < grid.width(); ++x)
        ASSERT_EQ(read->State(x, y, t.occupied_threshold, t.free_threshold),
                  grid.State(x, y, t.occupied_threshold, t.free_threshold))
            << "cell " << x << ", " << y << " of seed " << seed;
  }
}

// The image as map_saver writes it: 0 occupied, 254 free, 205 unknown, the top row the largest y.
TEST(OccupancyGridFile, ImageIsMapSaversTrinaryPictureWithYUp) {
  OccupancyGrid grid({0, 0}, 0.1, 3, 2);
  grid.Set(0, 1, 3.0f);   // top left: occupied
  grid.Set(2, 0, -3.0f);  // bottom right: free
  const std::string yaml = TempPath("grid_pixels.yaml");
  ASSERT_TRUE(WriteOccupancyGrid(grid, yaml, {}).ok());
  const cv::Mat image = cv::imread(TempPath("grid_pixels.pgm"), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(image.type(), CV_8U);
  ASSERT_EQ(image.rows, 2);
  ASSERT_EQ(image.cols, 3);
  EXPECT_EQ(image.at<unsigned char>(0, 0), 0);
  EXPECT_EQ(image.at<unsigned char>(1, 2), 254);
  EXPECT_EQ(image.at<unsigned char>(0, 1), 205);
  std::ifstream in(yaml);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text,
            "image: grid_pixels.pgm\nmode: trinary\nresolution: 0.1\norigin: [0, 0, 0.0]\n"
            "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n");
}

// A map made elsewhere: negate, a PNG image, scale mode, read by map_server's rules.
TEST(OccupancyGridFile, ReadsMapServersModesAndNegate) {
  cv::Mat image(1, 4, CV_8U);
  image.at<unsigned char>(0, 0) = 250;  // negate: p = 250 / 255, occupied
  image.at<unsigned char>(0, 1) = 10;   // free
  image.at<unsigned char>(0, 2) = 100;  // p = 0.39: unknown in trinary, undecided in scale
  image.at<unsigned char>(0, 3) = 180;  // p = 0.71: occupied
  ASSERT_TRUE(cv::imwrite(TempPath("negated.png"), image));
  for (const std::string mode : {"trinary", "scale"}) {
    const std::string yaml = TempPath("negated_" + mode + ".yaml");
    std::ofstream(yaml) << "image: negated.png\nmode: " << mode
                        << "\nresolution: 0.5\norigin: [-1.0, 2.0, 0]\nnegate: 1\n"
                           "occupied_thresh: 0.65\nfree_thresh: 0.25\n";
    const Result<OccupancyGrid> read = ReadOccupancyGrid(yaml);
    ASSERT_TRUE(read.ok()) << read.error;
    EXPECT_EQ(read->State(0, 0, 0.65, 0.25), CellState::kOccupied);
    EXPECT_EQ(read->State(1, 0, 0.65, 0.25), CellState::kFree);
    EXPECT_EQ(read->State(2, 0, 0.65, 0.25), CellState::kUnknown);
    EXPECT_EQ(read->observed(2, 0), mode == "scale");
    if (mode == "scale") {
      EXPECT_NEAR(read->Probability(2, 0), 100.0 / 255, 1e-6);
    }
    EXPECT_EQ(read->State(3, 0, 0.65, 0.25), CellState::kOccupied);
    EXPECT_EQ(read->CenterOf(0, 0), Eigen::Vector2d(-0.75, 2.25));
  }
}

TEST(OccupancyGridFile, BadFilesAreRefusedNamingFileAndLine) {
  const OccupancyGrid grid = RandomGrid(4, 4, 1);
  ASSERT_TRUE(WriteOccupancyGrid(grid, TempPath("ok.yaml"), {}).ok());
  const auto refused = [](const std::string& name, const std::string& text) {
    const std::string yaml = TempPath(name);
    std::ofstream(yaml) << text;
    const Result<OccupancyGrid> read = ReadOccupancyGrid(yaml);
    EXPECT_FALSE(read.ok()) << text;
    return read.ok() ? std::string() : read.error;
  };
  const std::string base = "image: ok.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n";
  const std::string thresholds = "occupied_thresh: 0.65\nfree_thresh: 0.196\n";
  EXPECT_EQ(refused("a.yaml", base), TempPath("a.yaml") + ": no 'occupied_thresh' key");
  EXPECT_EQ(refused("b.yaml", "image: ok.pgm\nresolution: -1\norigin: [0, 0, 0]\n" + thresholds),
            TempPath("b.yaml") + ":2: 'resolution' must be positive");
  EXPECT_EQ(
      refused("c.yaml", "image: ok.pgm\nresolution: 0.05\norigin: [0, 0, 0.5]\n" + thresholds),
      TempPath("c.yaml") + ":3: a rotated map (yaw other than 0) is not supported");
  EXPECT_EQ(refused("d.yaml", "image: ok.pgm\nresolution: nan\norigin: [0, 0, 0]\n" + thresholds),
            TempPath("d.yaml") + ":2: 'resolution' must be a finite number");
  EXPECT_EQ(refused("e.yaml", "image: none.pgm\n" + base.substr(14) + thresholds),
            std::filesystem::path(TempPath("none.pgm")).lexically_normal().string() +
                ": no such image file");
  EXPECT_EQ(refused("f.yaml", base + thresholds + "mode: fancy\n"),
            TempPath("f.yaml") + ":6: 'mode' must be trinary, scale or raw");
  EXPECT_NE(refused("g.yaml", "image: [unclosed\n").find(TempPath("g.yaml") + ":"),
            std::string::npos);
  EXPECT_EQ(refused("h.yaml", base + "occupied_thresh: 0.1\nfree_thresh: 0.5\n"),
            TempPath("h.yaml") + ": need 0 <= free_thresh < occupied_thresh <= 1");
  EXPECT_EQ(ReadOccupancyGrid(TempPath("missing.yaml")).error,
            TempPath("missing.yaml") + ": cannot open");
}

// The picture: every cell a square of whole pixels (no blur between a wall and free space).
TEST(OccupancyGridFile, PictureDrawsCellsAsSharpSquares) {
  OccupancyGrid grid({0, 0}, 0.05, 40, 20);
  for (int x = 0; x < 40; ++x)
    for (int y = 0; y < 20; ++y) grid.Set(x, y, x == 10 ? 3.0f : -3.0f);
  const std::string png = TempPath("grid_picture.png");
  ASSERT_TRUE(SaveOccupancyGridPicture(grid, {}, "grid", {}, {png}).ok());
  const cv::Mat image = cv::imread(png, cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(image.empty());
  const int cell = 1600 / 40;  // pixels per cell
  EXPECT_EQ(image.cols, 40 * cell);
  // Along a row through the map, every pixel is black (the wall column) or white: no grey edge.
  const int row = image.rows / 2;
  for (int c = 0; c < image.cols; ++c) {
    const int v = image.at<unsigned char>(row, c);
    EXPECT_TRUE((c >= 10 * cell && c < 11 * cell) ? v == 0 : v == 255)
        << "column " << c << ": " << v;
  }
}

}  // namespace
}  // namespace splam::io
