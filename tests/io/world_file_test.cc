#include "io/world_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "io/trajectory.h"
#include "sim/builtin_worlds.h"
#include "sim/ray_caster.h"

namespace splam::io {
namespace {

TEST(WorldFile, ParsesEveryShape) {
  const std::string yaml = R"(
name: lab
start: [1, 2, 0.5]
route: [[3, 4], [5, 6]]
obstacles:
  - polyline: [[0, 0], [10, 0]]
  - polygon: [[2, 2], [3, 2], [3, 3]]
  - circle: {center: [5, 5], radius: 0.3}
  - ellipse: {center: [7, 3], radii: [1.0, 0.5], angle: 0.5}
  - spline: [[0, 5], [1, 6], [2, 5], [3, 6]]
  - closed_spline: [[8, 8], [9, 8], [9, 9]]
)";
  const Result<sim::World> w = ParseWorld(yaml, "lab.yaml");
  ASSERT_TRUE(w.ok()) << w.error;
  EXPECT_EQ(w.value->name, "lab");
  EXPECT_EQ(w.value->obstacles.size(), 6u);
  EXPECT_EQ(w.value->start->ToVector(), Eigen::Vector3d(1, 2, 0.5));
  EXPECT_EQ(w.value->route.size(), 2u);
  EXPECT_EQ(std::get<kernel::Ellipse2>(w.value->obstacles[3]).radius_y, 0.5);
  EXPECT_TRUE(std::get<sim::Spline>(w.value->obstacles[5]).closed);
  EXPECT_TRUE(w.value->Validate().ok());
}

TEST(WorldFile, PropertyBuiltinWorldsRoundTrip) {
  for (const std::string& name : sim::BuiltinWorldNames()) {
    const sim::World world = *sim::BuiltinWorld(name);
    const std::string text = FormatWorld(world);
    const Result<sim::World> back = ParseWorld(text, name + ".yaml");
    ASSERT_TRUE(back.ok()) << back.error;
    EXPECT_EQ(FormatWorld(*back.value), text);
    ASSERT_EQ(back.value->obstacles.size(), world.obstacles.size());
    EXPECT_EQ(back.value->start->ToVector(), world.start->ToVector());
  }
}

TEST(WorldFile, PeopleRoundTrip) {
  const std::string yaml = R"(
obstacles:
  - polyline: [[0, 0], [10, 0]]
people:
  - {path: [[1, 1], [5, 1], [5, 4]], speed: 1.2, radius: 0.3, offset: 2}
  - {path: [[2, 2], [2, 6]]}
)";
  const Result<sim::World> w = ParseWorld(yaml, "lab.yaml");
  ASSERT_TRUE(w.ok()) << w.error;
  ASSERT_EQ(w.value->people.size(), 2u);
  EXPECT_EQ(w.value->people[0].path.size(), 3u);
  EXPECT_EQ(w.value->people[0].speed_mps, 1.2);
  EXPECT_EQ(w.value->people[0].radius_m, 0.3);
  EXPECT_EQ(w.value->people[0].start_offset_m, 2.0);
  EXPECT_EQ(w.value->people[1].speed_mps, sim::Walker().speed_mps);
  const Result<sim::World> back = ParseWorld(FormatWorld(*w.value), "back.yaml");
  ASSERT_TRUE(back.ok()) << back.error;
  EXPECT_EQ(FormatWorld(*back.value), FormatWorld(*w.value));
}

// `glass: true` beside an obstacle's shape makes it glass (sim::World::glass), a floor plan's
// every obstacle; written back the same.
TEST(WorldFile, GlassRoundTrip) {
  const std::string yaml = R"(
obstacles:
  - polyline: [[0, 0], [10, 0]]
  - {polyline: [[0, 2], [10, 2]], glass: true}
  - circle: {center: [5, 5], radius: 1}
    glass: false
)";
  const Result<sim::World> w = ParseWorld(yaml, "lab.yaml");
  ASSERT_TRUE(w.ok()) << w.error;
  EXPECT_EQ(w.value->glass, std::vector<std::size_t>{1});
  const Result<sim::World> back = ParseWorld(FormatWorld(*w.value), "back.yaml");
  ASSERT_TRUE(back.ok()) << back.error;
  EXPECT_EQ(back.value->glass, std::vector<std::size_t>{1});
  EXPECT_EQ(FormatWorld(*back.value), FormatWorld(*w.value));
}

struct BadWorld {
  std::string yaml;
  std::string expected;
};

void PrintTo(const BadWorld& b, std::ostream* os) { *os << b.yaml; }

class BadWorldTest : public ::testing::TestWithParam<BadWorld> {};

TEST_P(BadWorldTest, FailsNamingFileAndLine) {
  const Result<sim::World> w = ParseWorld(GetParam().yaml, "bad.yaml");
  ASSERT_FALSE(w.ok());
  EXPECT_EQ(w.error, GetParam().expected);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadWorldTest,
    ::testing::Values(
        BadWorld{"obstacles:\n  - circle: {center: [1, 1], radius: -2}\n",
                 "bad.yaml:2: radius must be positive"},
        BadWorld{"obstacles:\n  - polyline: [[0, 0]]\n",
                 "bad.yaml:2: needs at least 2 vertices, has 1"},
        BadWorld{"obstacles:\n  - polyline: [[0, 0], [1, x]]\n",
                 "bad.yaml:2: polyline: 'x' is not a finite number"},
        BadWorld{"obstacles:\n  - hexagon: [[0, 0]]\n",
                 "bad.yaml:2: unknown obstacle kind 'hexagon'"},
        BadWorld{"obstacles:\n  - circle: {radius: 2}\n", "bad.yaml:2: circle needs 'center'"},
        BadWorld{"obstacles:\n  - spline: [[0, 0], [1, 1], [2, 0]]\n",
                 "bad.yaml:2: needs at least 4 control points, has 3"},
        BadWorld{"name: x\n", "bad.yaml:1: needs a non-empty list 'obstacles'"},
        BadWorld{"start: [1, 2]\nobstacles:\n  - circle: {center: [1, 1], radius: 2}\n",
                 "bad.yaml:1: start must be [x, y, theta]"},
        BadWorld{"obstacles: [\n", "bad.yaml:2: end of sequence flow not found"},
        BadWorld{"- 1\n- 2\n", "bad.yaml:1: a world file is a YAML map"},
        BadWorld{"obstacles:\n  - polyline: [[0, 0], [1, 0]]\npeople:\n  - {path: [[0, 1]]}\n",
                 "bad.yaml:4: path needs at least 2 points"},
        BadWorld{"obstacles:\n  - polyline: [[0, 0], [1, 0]]\npeople:\n"
                 "  - {path: [[0, 1], [1, 1]], speed: 1e9}\n",
                 "bad.yaml:4: speed must be in [0, 10] m/s"},
        BadWorld{"obstacles:\n  - polyline: [[0, 0], [1, 0]]\npeople:\n"
                 "  - {path: [[0, 1], [1, 1]], legs: 2}\n",
                 "bad.yaml:4: a person has path, speed, radius and offset, not 'legs'"},
        BadWorld{"obstacles:\n  - polyline: [[0, 0], [1, 0]]\npeople: 3\n",
                 "bad.yaml:3: people must be a list of persons"},
        BadWorld{"obstacles:\n  - ? [a, b]\n    : 1\n",
                 "bad.yaml:2: an obstacle's key must be a plain word, not a list or a map"},
        BadWorld{"obstacles:\n  - {polyline: [[0, 0], [1, 0]], glass: maybe}\n",
                 "bad.yaml:2: glass must be true or false"},
        BadWorld{
            "obstacles:\n  - {polyline: [[0, 0], [1, 0]], circle: {center: [0, 0], radius: 1}}\n",
            "bad.yaml:2: each obstacle is a map with one shape key (polyline, polygon, circle, "
            "ellipse, spline, closed_spline or floor_plan) and optionally glass: true"},
        BadWorld{
            "obstacles:\n  - glass: true\n",
            "bad.yaml:2: each obstacle is a map with one shape key (polyline, polygon, circle, "
            "ellipse, spline, closed_spline or floor_plan) and optionally glass: true"}));

TEST(WorldFile, FloorPlanEntryIsRelativeToTheFile) {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "world_file_test";
  std::filesystem::create_directories(dir);
  cv::Mat image(20, 30, CV_8UC1, cv::Scalar(255));
  image(cv::Rect(5, 5, 10, 4)).setTo(0);
  ASSERT_TRUE(cv::imwrite((dir / "plan.png").string(), image));
  ASSERT_EQ(WriteTextFile((dir / "w.yaml").string(),
                          "obstacles:\n  - floor_plan: {image: plan.png, resolution: 0.1}\n  - "
                          "circle: {center: [0, 0], radius: 1}\n")
                .message(),
            "");
  const Result<sim::World> w = ReadWorldFile((dir / "w.yaml").string());
  ASSERT_TRUE(w.ok()) << w.error;
  EXPECT_EQ(w.value->obstacles.size(), 2u);
  ASSERT_EQ(WriteTextFile((dir / "bad.yaml").string(),
                          "obstacles:\n  - floor_plan: {image: nothere.png, resolution: 0.1}\n")
                .message(),
            "");
  const Result<sim::World> bad = ReadWorldFile((dir / "bad.yaml").string());
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error.find("bad.yaml:2: "), std::string::npos);
  EXPECT_NE(bad.error.find("nothere.png: no such image file"), std::string::npos);
}

// The benchmark worlds shipped in bench/worlds load, are valid, and their routes start free of
// obstacles; the hospital floor's people walk in free space (their paths touch no wall).
TEST(LoadWorld, BenchWorldsAreValid) {
  for (const char* name : {"campus_loop", "hospital_floor", "long_corridors"}) {
    const std::string path = std::string(SPLAM_SOURCE_DIR) + "/bench/worlds/" + name + ".yaml";
    const Result<sim::World> world = LoadValidWorld(path, {});
    ASSERT_TRUE(world.ok()) << world.error;
    ASSERT_TRUE(world.value->start.has_value()) << name;
    EXPECT_FALSE(world.value->route.empty()) << name;
    const sim::RayCaster caster(*world.value);
    EXPECT_FALSE(caster.Collides(world.value->start->translation(), 0.3)) << name;
    for (const sim::Walker& w : world.value->people)
      for (double t = 0.0; t < 200.0; t += 0.5)
        EXPECT_FALSE(caster.Collides(w.PositionAt(t), w.radius_m)) << name << " at " << t << " s";
  }
}

TEST(LoadWorld, BuiltinNamesFilesAndErrors) {
  EXPECT_TRUE(LoadWorld("complex").ok());
  const Result<sim::World> missing = LoadWorld("atlantis");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error,
            "atlantis: not a built-in world (corridor, office, office-long, office-doors, complex, "
            "loop, curves, halls) "
            "and no such file");
  const std::string path = ::testing::TempDir() + "/load_world_test.yaml";
  ASSERT_EQ(WriteWorldFile(path, *sim::BuiltinWorld("office")).message(), "");
  const Result<sim::World> office = LoadWorld(path);
  ASSERT_TRUE(office.ok()) << office.error;
  EXPECT_EQ(office.value->name, "office");
}

}  // namespace
}  // namespace splam::io
