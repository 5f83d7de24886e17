// The one statistics type: numpy's conventions (what evo prints), the nearest-rank p99, and no
// numbers for an empty sample.
#include "core/statistics.h"

#include <cmath>

#include <gtest/gtest.h>

namespace slamcmp {
namespace {

TEST(Statistics, AsNumpy) {
  const Statistics even = computeStatistics({4.0, 1.0, 3.0, 2.0});
  EXPECT_EQ(even.count, 4);
  EXPECT_DOUBLE_EQ(even.mean, 2.5);
  EXPECT_DOUBLE_EQ(even.median, 2.5);  // the mean of the two middle values
  EXPECT_DOUBLE_EQ(even.std, std::sqrt(1.25));  // population std (ddof 0)
  EXPECT_DOUBLE_EQ(even.rmse, std::sqrt(7.5));
  EXPECT_DOUBLE_EQ(even.min, 1.0);
  EXPECT_DOUBLE_EQ(even.max, 4.0);
  const Statistics odd = computeStatistics({3.0, 1.0, 2.0});
  EXPECT_DOUBLE_EQ(odd.median, 2.0);
  const Statistics one = computeStatistics({0.5});
  EXPECT_DOUBLE_EQ(one.std, 0.0);
  EXPECT_DOUBLE_EQ(one.rmse, 0.5);
  EXPECT_DOUBLE_EQ(one.p99, 0.5);
}

TEST(Statistics, NearestRankP99) {
  std::vector<double> ms;
  for (int i = 200; i >= 1; --i) ms.push_back(i);
  const Statistics t = computeStatistics(ms);
  EXPECT_DOUBLE_EQ(t.median, 100.5);
  EXPECT_DOUBLE_EQ(t.mean, 100.5);
  EXPECT_DOUBLE_EQ(t.p99, 198.0);
  EXPECT_DOUBLE_EQ(t.max, 200.0);
}

TEST(Statistics, MedianAloneAgreesAndEmptyHasNone) {
  EXPECT_DOUBLE_EQ(median({5.0, 1.0, 4.0, 2.0}), 3.0);
  EXPECT_DOUBLE_EQ(median({5.0, 1.0, 4.0}), 4.0);
  EXPECT_TRUE(std::isnan(median({})));
  const Statistics none = computeStatistics({});
  EXPECT_EQ(none.count, 0);
  for (double v : {none.mean, none.median, none.std, none.rmse, none.min, none.max, none.p99})
    EXPECT_TRUE(std::isnan(v));
}

// Against the exact quantiles (scipy.stats.chi2.ppf): the filters' gates and the NEES bounds.
TEST(Statistics, ChiSquaredQuantiles) {
  EXPECT_NEAR(chiSquaredQuantile(2, 0.99), 9.2103, 0.01 * 9.2103);
  EXPECT_NEAR(chiSquaredQuantile(10, 0.99), 23.209, 0.01 * 23.209);
  EXPECT_NEAR(chiSquaredQuantile(24, 0.999), 51.179, 0.01 * 51.179);
  EXPECT_NEAR(chiSquaredQuantile(4, 0.95), 9.4877, 0.01 * 9.4877);
  EXPECT_NEAR(chiSquaredQuantile(1000, 0.025), 914.257, 0.001 * 914.257);  // a run's NEES bounds
  EXPECT_NEAR(chiSquaredQuantile(1000, 0.975), 1089.531, 0.001 * 1089.531);
}

}  // namespace
}  // namespace slamcmp
