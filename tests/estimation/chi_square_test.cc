#include "estimation/chi_square.h"

#include <gtest/gtest.h>

namespace splam::estimation {
namespace {

TEST(ChiSquareQuantile, KnownValues) {
  EXPECT_NEAR(ChiSquareQuantile(0.95, 2), 5.991, 1e-3);
  EXPECT_NEAR(ChiSquareQuantile(0.999, 2), 13.816, 1e-3);
  EXPECT_NEAR(ChiSquareQuantile(0.025, 60), 40.482, 1e-3);
  EXPECT_NEAR(ChiSquareQuantile(0.975, 60), 83.298, 1e-3);
}

}  // namespace
}  // namespace splam::estimation
