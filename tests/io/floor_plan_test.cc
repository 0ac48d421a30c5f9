#include "io/floor_plan.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "io/trajectory.h"
#include "sim/ray_caster.h"

namespace splam::io {
namespace {

std::string TempPath(const std::string& name) { return ::testing::TempDir() + "/" + name; }

TEST(FloorPlan, DarkRectangleBecomesAPolygonAtTheRightPlace) {
  // 100 x 80 px at 5 cm: a wall 10 px thick from column 20 to 69, rows 30-39.
  cv::Mat image(80, 100, CV_8UC1, cv::Scalar(255));
  image(cv::Rect(20, 30, 50, 10)).setTo(0);
  const std::string path = TempPath("plan_rect.png");
  ASSERT_TRUE(cv::imwrite(path, image));
  FloorPlanOptions options;
  options.resolution_m_per_px = 0.05;
  options.origin_m = {1.0, 2.0};
  const Result<sim::World> w = ReadFloorPlan(path, options);
  ASSERT_TRUE(w.ok()) << w.error;
  ASSERT_EQ(w.value->obstacles.size(), 1u);
  EXPECT_TRUE(w.value->Validate().ok());
  const kernel::Box2 b = w.value->Bounds();
  // Pixel centres: columns 20..69 -> x = 1 + (20.5 .. 69.5) * 0.05; rows 30..39 from the top of
  // an 80-row image -> y = 2 + (80 - 39 - 0.5 .. 80 - 30 - 0.5) * 0.05.
  EXPECT_NEAR(b.min.x(), 1.0 + 20.5 * 0.05, 1e-9);
  EXPECT_NEAR(b.max.x(), 1.0 + 69.5 * 0.05, 1e-9);
  EXPECT_NEAR(b.min.y(), 2.0 + 40.5 * 0.05, 1e-9);
  EXPECT_NEAR(b.max.y(), 2.0 + 49.5 * 0.05, 1e-9);
  // A laser below the wall looking up hits its lower face.
  const sim::RayCaster caster(*w.value);
  const sim::RayHit hit = caster.Cast({{1.0 + 45 * 0.05, 2.0}, {0, 1}}, 10.0);
  EXPECT_NEAR(hit.range_m, 40.5 * 0.05, 1e-9);
}

TEST(FloorPlan, RoomWithHoleGivesOuterAndInnerOutlines) {
  cv::Mat image(60, 60, CV_8UC1, cv::Scalar(255));
  cv::rectangle(image, cv::Rect(5, 5, 50, 50), cv::Scalar(0), 3);
  const std::string path = TempPath("plan_room.png");
  ASSERT_TRUE(cv::imwrite(path, image));
  const Result<sim::World> w = ReadFloorPlan(path, FloorPlanOptions());
  ASSERT_TRUE(w.ok()) << w.error;
  EXPECT_EQ(w.value->obstacles.size(), 2u);
}

TEST(FloorPlan, BadInputsAreClearErrors) {
  const std::string text_file = TempPath("not_an_image.png");
  ASSERT_EQ(WriteTextFile(text_file, "this is not a PNG").message(), "");
  const Result<sim::World> garbage = ReadFloorPlan(text_file, FloorPlanOptions());
  ASSERT_FALSE(garbage.ok());
  EXPECT_EQ(garbage.error, text_file + ": not a PNG, JPEG, PGM/PPM/PBM, BMP or TIFF image");

  // Found by fuzz_floor_plan: files that no decoder of a floor-plan format takes but with "DICM"
  // at byte 128, where DICOM puts it, went to GDCM, which aborted (SIGABRT) on a failed
  // assertion: one named .png, and a "P24" file (a Netpbm magic number needs white space after
  // it). Only the formats a floor plan comes in are decoded.
  const auto with_dicm_at_128 = [](std::string head, char fill) {
    head.resize(128, fill);
    return head + "DICM";
  };
  for (const auto& [name, bytes] :
       {std::pair{"dicom.png", with_dicm_at_128("DICM", '\0')},
        std::pair{"dicom_at_128.pgm", with_dicm_at_128("P24\n+0 30\n255\n", '\xff')}}) {
    const std::string file = TempPath(name);
    ASSERT_EQ(WriteTextFile(file, bytes).message(), "");
    EXPECT_EQ(ReadFloorPlan(file, FloorPlanOptions()).error,
              file + ": not a PNG, JPEG, PGM/PPM/PBM, BMP or TIFF image");
  }
  const std::string truncated_png = TempPath("truncated.png");
  ASSERT_EQ(WriteTextFile(truncated_png, std::string("\x89PNG\r\n\x1a\n\0\0", 10)).message(), "");
  EXPECT_EQ(ReadFloorPlan(truncated_png, FloorPlanOptions()).error,
            truncated_png + ": cannot decode image (not a PNG/JPEG/... file?)");

  EXPECT_EQ(ReadFloorPlan("/nonexistent.png", FloorPlanOptions()).error,
            "/nonexistent.png: no such image file");

  cv::Mat white(10, 10, CV_8UC1, cv::Scalar(255));
  const std::string blank = TempPath("blank.png");
  ASSERT_TRUE(cv::imwrite(blank, white));
  EXPECT_NE(ReadFloorPlan(blank, FloorPlanOptions()).error.find("no dark pixels"),
            std::string::npos);
  // Issue 70: an all-black image was explored as free space (exit 3, "91 % covered").
  const std::string solid = TempPath("black.png");
  ASSERT_TRUE(cv::imwrite(solid, cv::Mat(40, 60, CV_8UC1, cv::Scalar(0))));
  EXPECT_EQ(ReadFloorPlan(solid, FloorPlanOptions()).error,
            solid +
                ": every pixel is dark (below grey level 128): a solid block with no free "
                "space");

  FloorPlanOptions bad;
  bad.resolution_m_per_px = 0.0;
  EXPECT_NE(ReadFloorPlan(blank, bad).error.find("resolution"), std::string::npos);
}

}  // namespace
}  // namespace splam::io
