// The reader on the real logs of ../shared/datasets (or $SPLAM_DATA); skipped when absent.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "io/carmen.h"
#include "kernel/angle.h"

namespace splam::io {
namespace {

std::string DataPath(const std::string& file) {
  const char* env = std::getenv("SPLAM_DATA");
  return std::string(env != nullptr ? env : SPLAM_DEFAULT_DATA_DIR) + "/" + file;
}

TEST(RealLogs, IntelHasTheDocumentedContent) {
  const std::string path = DataPath("intel.clf");
  if (!std::filesystem::exists(path))
    GTEST_SKIP() << path << " not found: set SPLAM_DATA to the datasets folder";
  const CarmenReadResult r = ReadCarmenLog(path);
  ASSERT_TRUE(r.log.ok()) << r.log.error;
  const CarmenLog& log = *r.log.value;
  EXPECT_EQ(log.Lasers().size(), 13631u);
  EXPECT_EQ(log.Odometry().size(), 26915u);
  const kernel::Scan& scan = log.Lasers()[0]->scan;
  EXPECT_EQ(scan.size(), 180u);
  EXPECT_NEAR(scan.angular_step_rad, kernel::DegToRad(1.0), 1e-15);
  EXPECT_NEAR(scan.start_angle_rad, -kernel::kPi / 2, 1e-15);
  const double duration =
      log.Lasers().back()->stamp.ipc_timestamp_s - log.Lasers().front()->stamp.ipc_timestamp_s;
  EXPECT_NEAR(duration, 2691, 5);
  EXPECT_GT(r.stats.no_return_readings, 0);
  // Most readings are hits indoors.
  std::size_t hits = 0, total = 0;
  for (const LaserMessage* m : log.Lasers()) {
    hits += m->scan.HitIndices().size();
    total += m->scan.size();
  }
  EXPECT_GT(static_cast<double>(hits) / static_cast<double>(total), 0.8);
}

TEST(RealLogs, MitCsailHasTheDocumentedContent) {
  const std::string path = DataPath("mit-csail.clf");
  if (!std::filesystem::exists(path))
    GTEST_SKIP() << path << " not found: set SPLAM_DATA to the datasets folder";
  const CarmenReadResult r = ReadCarmenLog(path);
  ASSERT_TRUE(r.log.ok()) << r.log.error;
  const CarmenLog& log = *r.log.value;
  EXPECT_EQ(log.Lasers().size(), 1988u);
  EXPECT_EQ(log.Odometry().size(), 0u);
  EXPECT_EQ(log.Lasers()[0]->scan.size(), 361u);
  EXPECT_NEAR(log.Lasers()[0]->scan.angular_step_rad, kernel::DegToRad(0.5), 1e-15);
  const double duration =
      log.Lasers().back()->stamp.ipc_timestamp_s - log.Lasers().front()->stamp.ipc_timestamp_s;
  EXPECT_NEAR(duration, 424, 5);
}

}  // namespace
}  // namespace splam::io
