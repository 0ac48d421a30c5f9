// The registry of SLAM methods: the built-in methods, adding one, and errors as values.
#include <gtest/gtest.h>

#include <algorithm>

#include "estimation/ekf/ekf_line_slam.h"
#include "estimation/slam_method.h"
#include "estimation/topological/topological_slam.h"
#include "tests/estimation/echo_slam_method.h"

namespace splam::estimation {
namespace {

using test_methods::Echo;
using test_methods::EchoOptions;

TEST(SlamRegistry, ListsTheBuiltInMethodsInOrder) {
  const SlamRegistry& registry = SlamRegistry::Global();
  const std::vector<std::string> names = registry.Names();
  ASSERT_GE(names.size(), 3u);
  EXPECT_EQ(std::vector<std::string>(names.begin(), names.begin() + 3),
            (std::vector<std::string>{"ekf-lines", "ekf-bspline", "topological"}));
  for (const std::string& name : names) {
    EXPECT_NE(registry.Describe().find(name + ": "), std::string::npos);
    auto made = registry.Make(name, nullptr, {kernel::Pose2(1, 2, 0.5), {}});
    ASSERT_TRUE(made.ok()) << made.error;
    EXPECT_TRUE((*made.value)->healthy());
    EXPECT_EQ((*made.value)->pose().x(), 1.0);  // starts at the context's pose
    EXPECT_EQ((*made.value)->MapSize(), 0u);
  }
}

TEST(SlamRegistry, ErrorsAreValues) {
  const SlamRegistry& registry = SlamRegistry::Global();
  auto unknown = registry.Make("fastslam", nullptr, {});
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(
      unknown.error.rfind("unknown SLAM method 'fastslam' (ekf-lines, ekf-bspline, topological", 0),
      0u);
  auto options = registry.Find("topological")->default_options({});
  static_cast<SlamOptionsOf<TopologicalSlamOptions>*>(options.get())->options().correction_rounds =
      0;
  auto invalid = registry.Make("topological", options.get(), {});
  ASSERT_FALSE(invalid.ok());
  EXPECT_EQ(invalid.error, "topological options: correction_rounds must be in [1, 100]");
  // Options of one method given to another.
  auto lines = registry.Find("ekf-lines")->default_options({});
  auto mismatch = registry.Make("topological", lines.get(), {});
  ASSERT_FALSE(mismatch.ok());
  EXPECT_EQ(mismatch.error, "the options given are not topological's");
}

TEST(SlamRegistry, SensorNoiseReachesTheOptions) {
  SensorNoise noise;
  noise.odometry_noise_scale = 3.0;
  noise.range_sigma_m = 0.01;
  noise.range_sigma_fraction = 0.0;
  auto options = SlamRegistry::Global().Find("ekf-lines")->default_options(noise);
  const EkfLineSlamOptions& o =
      static_cast<SlamOptionsOf<EkfLineSlamOptions>*>(options.get())->options();
  EXPECT_EQ(o.extraction.range_sigma_m, 0.01);
  EXPECT_EQ(o.extraction.range_sigma_fraction, 0.0);
  EXPECT_DOUBLE_EQ(o.odometry.forward_per_m, 3.0 * OdometryNoiseModel().forward_per_m);
}

TEST(SlamRegistry, OneLineRegistersAMethod) {
  RegisterSlamMethod<EchoOptions>(
      "echo", "test method",
      [](const EchoOptions& o, const SlamContext& c) { return std::make_unique<Echo>(o, c); });
  const SlamMethodInfo* info = SlamRegistry::Global().Find("echo");
  ASSERT_NE(info, nullptr);
  EXPECT_EQ(SlamRegistry::Global().Names().back(), "echo");
  auto options = info->default_options({});
  static_cast<SlamOptionsOf<EchoOptions>*>(options.get())->options().gain = 4.0;
  auto made = SlamRegistry::Global().Make("echo", options.get(), {});
  ASSERT_TRUE(made.ok());
  EXPECT_EQ((*made.value)->Statistics().map[0].second, 4);
  static_cast<SlamOptionsOf<EchoOptions>*>(options.get())->options().gain = -1.0;
  EXPECT_EQ(SlamRegistry::Global().Make("echo", options.get(), {}).error,
            "echo options: gain must be positive");
  // Registering the same name again replaces it (no duplicate in the list).
  RegisterSlamMethod<EchoOptions>("echo", "again", [](const EchoOptions& o, const SlamContext& c) {
    return std::make_unique<Echo>(o, c);
  });
  const auto names = SlamRegistry::Global().Names();
  EXPECT_EQ(std::count(names.begin(), names.end(), "echo"), 1);
}

// A method registered by a static object in a translation unit of its own
// (slam_registration_elsewhere.cc) is there before main, after the built-in methods.
TEST(SlamRegistry, AMethodRegisteredInAnotherUnitIsThere) {
  const SlamRegistry& registry = SlamRegistry::Global();
  ASSERT_NE(registry.Find("echo-elsewhere"), nullptr);
  const std::vector<std::string> names = registry.Names();
  EXPECT_GT(std::find(names.begin(), names.end(), "echo-elsewhere") - names.begin(),
            std::find(names.begin(), names.end(), "topological-graph") - names.begin());
  auto made = registry.Make("echo-elsewhere", nullptr, {kernel::Pose2(1, 0, 0), {}});
  ASSERT_TRUE(made.ok()) << made.error;
  EXPECT_EQ((*made.value)->pose().x(), 1.0);
}

TEST(Status, CarriesTheFirstError) {
  EXPECT_TRUE(kernel::Status().ok());
  EXPECT_EQ(kernel::Status::Error("bad").Prefixed("file").message(), "file: bad");
  EXPECT_TRUE(kernel::Status::Ok().Prefixed("file").ok());
  EXPECT_EQ(kernel::FirstError(kernel::Status::Ok(), kernel::Status::Error("a"),
                               kernel::Status::Error("b"))
                .message(),
            "a");
  EXPECT_FALSE(kernel::Status::Error("").ok());  // an error always has a message
}

}  // namespace
}  // namespace splam::estimation
