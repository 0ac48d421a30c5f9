// Options structs as YAML: defaults written and read back exactly, edits, and every kind of bad
// input named with its file, line and key.
#include "io/config.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "io/result.h"

#include "estimation/topological/topological_slam.h"
#include "exploration/explorer.h"
#include "sim/simulator.h"

namespace splam::io {
namespace {

// A document with a string, a nested options struct (enum choice, ints, doubles, groups), a
// pose, a list of doubles and an unsigned integer.
struct Doc {
  std::string method = "topological";
  estimation::TopologicalSlamOptions slam;
  sim::SimulatorOptions simulator;
  exploration::ExplorerOptions explorer;
};
ConfigRoot RootOf(Doc* d) {
  return [d](kernel::FieldVisitor& v) {
    v.Field("method", &d->method, "the method");
    v.Nested("slam", "", &d->slam);
    v.Nested("simulator", "", &d->simulator);
    v.Nested("exploration", "", &d->explorer);
  };
}

TEST(Config, DefaultsReadBackExactly) {
  Doc written;
  const std::string text = ConfigToYaml(RootOf(&written), "header line");
  EXPECT_EQ(text.rfind("# header line\n", 0), 0u);
  EXPECT_NE(text.find("correction_gain: 0.3  # "), std::string::npos) << text;
  EXPECT_NE(text.find("robot_T_laser: [0, 0, 0]"), std::string::npos);
  EXPECT_NE(text.find("linear_speeds_mps: [0, 0.1, 0.25, 0.4]"), std::string::npos);
  // Change every kind of field, write, read into fresh defaults: the same document.
  written.method = "ekf \"quoted\"";
  written.slam.correction_gain = 1.0 / 3.0;
  written.slam.extraction.segmentation.method = kernel::SegmentationMethod::kPedraza;
  written.slam.min_verified_curves = 7;
  written.simulator.enable_sonar = true;
  written.simulator.laser.robot_T_laser = kernel::Pose2(0.1, -0.2, 0.3);
  written.explorer.motion.linear_speeds_mps = {0.5, 1e-7};
  written.explorer.seed = 18446744073709551615ull;
  const std::string changed = ConfigToYaml(RootOf(&written), "");
  const Result<ConfigFile> file = ConfigFile::Parse(changed, "doc.yaml");
  ASSERT_TRUE(file.ok()) << file.error;
  Doc read;
  ASSERT_TRUE(file.value->Read(RootOf(&read)).ok());
  EXPECT_EQ(ConfigToYaml(RootOf(&read), ""), changed);
  EXPECT_EQ(read.method, written.method);
  EXPECT_EQ(read.slam.correction_gain, 1.0 / 3.0);  // bit for bit
  EXPECT_EQ(read.slam.extraction.segmentation.method, kernel::SegmentationMethod::kPedraza);
  EXPECT_EQ(read.explorer.seed, 18446744073709551615ull);
  EXPECT_EQ(read.simulator.laser.robot_T_laser.theta(), 0.3);
}

TEST(Config, RandomDoublesRoundTripBitForBit) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> exponent(-300, 300), mantissa(-1, 1);
  for (int trial = 0; trial < 500; ++trial) {
    Doc d;
    d.slam.verify_rms_m = mantissa(random) * std::pow(10.0, exponent(random));
    const Result<ConfigFile> file = ConfigFile::Parse(ConfigToYaml(RootOf(&d), ""), "r.yaml");
    ASSERT_TRUE(file.ok());
    Doc read;
    ASSERT_TRUE(file.value->Read(RootOf(&read)).ok());
    ASSERT_EQ(read.slam.verify_rms_m, d.slam.verify_rms_m);
  }
}

TEST(Config, AFileNamesOnlyWhatItChanges) {
  const Result<ConfigFile> file =
      ConfigFile::Parse("slam:\n  loss:\n    heading_scale_rad: 0.25\n", "partial.yaml");
  ASSERT_TRUE(file.ok());
  Doc d;
  ASSERT_TRUE(file.value->Read(RootOf(&d)).ok());
  EXPECT_EQ(d.slam.loss.heading_scale_rad, 0.25);
  EXPECT_EQ(d.slam.loss.translation_scale_m,
            estimation::CorrectionLossOptions().translation_scale_m);
  EXPECT_EQ(file.value->TopLevelString("method"), std::nullopt);
}

// The message of reading `text`.
std::string Problem(const std::string& text) {
  const Result<ConfigFile> file = ConfigFile::Parse(text, "bad.yaml");
  if (!file.ok()) return file.error;
  Doc d;
  return file.value->Read(RootOf(&d)).message();
}

TEST(Config, BadInputNamesFileLineAndKey) {
  EXPECT_EQ(Problem("method: a\nslam:\n  corection_gain: 0.5\n"),
            "bad.yaml:3: slam.corection_gain: unknown key");
  EXPECT_EQ(Problem("unknown: 1\n"), "bad.yaml:1: unknown: unknown key");
  // A list as a key (YAML's `? [a, b]`), at the top or nested: yaml-cpp's bad conversion aborted.
  EXPECT_EQ(Problem("? [a, b]\n: 1\n"),
            "bad.yaml:1: [...]: a key must be a plain word, not a list or a map");
  EXPECT_EQ(Problem("slam:\n  ? {a: 1}\n  : 1\n"),
            "bad.yaml:2: slam.[...]: a key must be a plain word, not a list or a map");
  EXPECT_EQ(Problem("slam:\n  correction_gain: fast\n"),
            "bad.yaml:2: slam.correction_gain: 'fast' is not a number");
  EXPECT_EQ(Problem("slam:\n  correction_gain: .nan\n"),
            "bad.yaml:2: slam.correction_gain: must be a finite number");
  EXPECT_EQ(Problem("slam:\n  min_verified_curves: 2.5\n"),
            "bad.yaml:2: slam.min_verified_curves: '2.5' is not an integer");
  EXPECT_EQ(Problem("exploration:\n  seed: -1\n"),
            "bad.yaml:2: exploration.seed: must not be negative");
  EXPECT_EQ(Problem("slam:\n  extraction:\n    segmentation:\n      method: fast\n"),
            "bad.yaml:4: slam.extraction.segmentation.method: 'fast' is not one of dietmayer, "
            "pedraza");
  EXPECT_EQ(Problem("slam: 3\n"), "bad.yaml:1: slam: expected a map of keys");
  EXPECT_EQ(Problem("simulator:\n  laser:\n    robot_T_laser: [1, 2]\n"),
            "bad.yaml:3: simulator.laser.robot_T_laser: expected [x, y, theta]");
  EXPECT_EQ(Problem("exploration:\n  motion:\n    linear_speeds_mps: [0, x]\n"),
            "bad.yaml:3: exploration.motion.linear_speeds_mps: expected finite numbers");
  EXPECT_EQ(Problem("simulator:\n  enable_sonar: maybe\n"),
            "bad.yaml:2: simulator.enable_sonar: 'maybe' is not true or false");
  EXPECT_EQ(Problem("- 1\n- 2\n"), "bad.yaml:1: expected a map of keys at the top");
  EXPECT_NE(Problem("slam: [1,\n").find("bad.yaml:"), std::string::npos);
  EXPECT_TRUE(Problem("").empty());  // an empty file changes nothing
}

TEST(Config, SetOverridesOneField) {
  Doc d;
  ASSERT_TRUE(SetConfigValue(RootOf(&d), "slam.loss.heading_scale_rad=0.5").ok());
  EXPECT_EQ(d.slam.loss.heading_scale_rad, 0.5);
  ASSERT_TRUE(SetConfigValue(RootOf(&d), "simulator.laser.robot_T_laser=[1, 2, 3]").ok());
  EXPECT_EQ(d.simulator.laser.robot_T_laser.y(), 2.0);
  EXPECT_EQ(SetConfigValue(RootOf(&d), "slam.loss.scale=1").message(),
            "--set: slam.loss.scale: unknown key");
  EXPECT_EQ(SetConfigValue(RootOf(&d), "slam.correction_gain=x").message(),
            "--set: slam.correction_gain: 'x' is not a number");
  EXPECT_EQ(SetConfigValue(RootOf(&d), "no_value").message(), "--set no_value: expected key=value");
}

// A key an options struct no longer has (FieldVisitor::Moved: the graph SLAM's options split by
// part) is refused, in a file and by --set, naming where it went; the new key reads; a writer
// shows only the new form.
TEST(Config, AMovedKeyIsRefusedNamingItsNewKey) {
  EXPECT_EQ(Problem("slam:\n  scan_matching:\n    submap_keyframes: 5\n"),
            "bad.yaml:3: slam.scan_matching.submap_keyframes: this key is now "
            "slam.scan_matching.front_end.submap_keyframes");
  EXPECT_EQ(Problem("slam:\n  scan_matching:\n    registration:\n      max_iterations: 3\n"),
            "bad.yaml:4: slam.scan_matching.registration: this key is now "
            "slam.scan_matching.front_end.registration");
  Doc d;
  EXPECT_EQ(SetConfigValue(RootOf(&d), "slam.scan_matching.loop.tell_apart_alpha=0.01").message(),
            "--set: slam.scan_matching.loop.tell_apart_alpha: this key is now "
            "slam.scan_matching.loop.advanced.tell_apart_alpha");
  EXPECT_EQ(SetConfigValue(RootOf(&d), "slam.scan_matching.trim_spacing_m=0").message(),
            "--set: slam.scan_matching.trim_spacing_m: this key is now "
            "slam.scan_matching.back_end.trim_spacing_m");
  ASSERT_TRUE(
      SetConfigValue(RootOf(&d), "slam.scan_matching.loop.advanced.tell_apart_alpha=0.01").ok());
  EXPECT_EQ(d.slam.scan_matching.loop.advanced.tell_apart_alpha, 0.01);
  const std::string text = ConfigToYaml(RootOf(&d), "");
  EXPECT_NE(text.find("\n    front_end:"), std::string::npos) << text;
  EXPECT_NE(text.find("\n      submap_keyframes: 30"), std::string::npos);
  EXPECT_EQ(text.find("\n    submap_keyframes:"), std::string::npos);
  EXPECT_NE(text.find("\n        tell_apart_alpha: 0.01"), std::string::npos);
}

TEST(Config, LoadNamesAMissingFile) {
  const Result<ConfigFile> file = ConfigFile::Load("/nonexistent/c.yaml");
  ASSERT_FALSE(file.ok());
  EXPECT_EQ(file.error, "/nonexistent/c.yaml: cannot read the file");
}

}  // namespace
}  // namespace splam::io
