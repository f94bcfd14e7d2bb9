// StepStats: quantiles of a fixed log-linear histogram against exact order statistics.
#include "executive/step_stats.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using f16mmae::executive::StepStats;

TEST(StepStats, BucketsTileTheLineAndContainTheirValues) {
  std::mt19937_64 rng(7);
  for (int i = 0; i < 200000; ++i) {
    const std::uint64_t v = i < 5000 ? static_cast<std::uint64_t>(i) : rng() >> (rng() % 64);
    const std::size_t b = StepStats::bucket(v);
    ASSERT_LT(b, StepStats::kBuckets);
    if (b + 1 < StepStats::kBuckets) {
      ASSERT_LE(StepStats::lower(b), v) << v;
      ASSERT_LT(v, StepStats::lower(b + 1)) << v;
    }
  }
  EXPECT_EQ(StepStats::lower(StepStats::bucket(63)), 63u);  // small values are exact
}

TEST(StepStats, QuantilesMatchExactOrderStatisticsWithinTheBucketResolution) {
  std::mt19937_64 rng(11);
  std::lognormal_distribution<double> dist(std::log(4000.0), 0.6);  // ~4 us steps
  std::vector<std::int64_t> values;
  StepStats s;
  for (int i = 0; i < 100000; ++i) {
    const auto v = static_cast<std::int64_t>(dist(rng));
    values.push_back(v);
    s.record(v);
  }
  std::sort(values.begin(), values.end());
  for (double q : {0.5, 0.9, 0.99, 0.999}) {
    const std::size_t rank = static_cast<std::size_t>(std::ceil(q * values.size()));
    const double exact = static_cast<double>(values[rank - 1]);
    EXPECT_NEAR(s.quantile_ns(q), exact, exact / 64.0) << "q = " << q;
  }
  EXPECT_EQ(s.max_ns(), values.back());
  EXPECT_EQ(s.count(), 100000);
}

TEST(StepStats, SmallSamplesAndEmpty) {
  StepStats s;
  EXPECT_EQ(s.quantile_ns(0.5), 0.0);
  for (int v : {10, 20, 30}) s.record(v);
  EXPECT_EQ(s.quantile_ns(0.5), 20.0);
  EXPECT_EQ(s.quantile_ns(0.99), 30.0);
  EXPECT_EQ(s.max_ns(), 30);
  s.record(5000000);  // 5 ms outlier: max exact, quantile clamped to it
  EXPECT_EQ(s.max_ns(), 5000000);
  EXPECT_LE(s.quantile_ns(1.0), 5000000.0);
  EXPECT_GE(s.quantile_ns(1.0), 5000000.0 * (1 - 1.0 / 64));
  s.clear();
  EXPECT_EQ(s.count(), 0);
}

// The form the daemon's and the echo's summary lines use, which the latency benchmark reads.
TEST(StepStats, DescribedInMicroseconds) {
  StepStats s;
  EXPECT_EQ(f16mmae::executive::describe_us(s), "p50 0.0 us, p99 0.0 us, max 0.0 us");
  for (int i = 0; i < 99; ++i) s.record(5000);
  s.record(20000);
  // p50: 5000 ns in the bucket [4992, 5056), reported at its midpoint; p99 and max: 20000 exact
  EXPECT_EQ(f16mmae::executive::describe_us(s), "p50 5.0 us, p99 5.0 us, max 20.0 us");
  s.record(20000);
  EXPECT_EQ(f16mmae::executive::describe_us(s), "p50 5.0 us, p99 20.0 us, max 20.0 us");
}
