// StepStats — step-time statistics (p50, p99, max) of the executive without per-frame
// allocation: a fixed log-linear histogram of durations in nanoseconds.
//
// Values below 2^kSubBits ns have one bucket each (exact). A value v >= 2^kSubBits with
// e = floor(log2 v) falls in one of 2^kSubBits equal buckets spanning [2^e, 2^(e+1)):
//     bucket(v) = 2^kSubBits * (e - kSubBits + 1) + (v >> (e - kSubBits)) - 2^kSubBits
// so a quantile is known to within a relative 2^-kSubBits (1.6 %); it is reported as the
// bucket's midpoint (clamped to the exact max). Values beyond 2^kMaxExp ns (~18 min) land
// in the last bucket. The counts live in a std::array: record() is O(1), allocation-free.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <string>

namespace f16mmae::executive {

class StepStats {
 public:
  static constexpr int kSubBits = 6;
  static constexpr int kMaxExp = 40;
  static constexpr std::uint64_t kSub = std::uint64_t{1} << kSubBits;
  static constexpr std::size_t kBuckets = kSub * static_cast<std::size_t>(kMaxExp - kSubBits + 2);

  void record(std::int64_t ns) {
    const std::uint64_t v = ns > 0 ? static_cast<std::uint64_t>(ns) : 0;
    ++counts_[bucket(v)];
    ++count_;
    max_ns_ = std::max(max_ns_, v);
  }

  std::int64_t count() const { return count_; }
  std::int64_t max_ns() const { return static_cast<std::int64_t>(max_ns_); }

  // The q-quantile (0 < q <= 1): the smallest recorded value with at least q*count values
  // at or below it, to the bucket resolution. 0 when nothing was recorded.
  double quantile_ns(double q) const {
    if (count_ == 0) return 0.0;
    const double target = q * static_cast<double>(count_);
    std::int64_t rank = static_cast<std::int64_t>(target);
    if (static_cast<double>(rank) < target) ++rank;
    rank = std::clamp<std::int64_t>(rank, 1, count_);
    std::int64_t seen = 0;
    for (std::size_t b = 0; b < kBuckets; ++b) {
      seen += counts_[b];
      if (seen >= rank) {
        const double lo = static_cast<double>(lower(b));
        const double width = static_cast<double>(lower(b + 1) - lower(b));
        const double mid = width <= 1.0 ? lo : lo + 0.5 * width;
        return std::min(mid, static_cast<double>(max_ns_));
      }
    }
    return static_cast<double>(max_ns_);
  }

  void clear() {
    counts_.fill(0);
    count_ = 0;
    max_ns_ = 0;
  }

  static std::size_t bucket(std::uint64_t v) {
    if (v < kSub) return static_cast<std::size_t>(v);
    int e = 63 - __builtin_clzll(v);
    if (e > kMaxExp) return kBuckets - 1;
    const int shift = e - kSubBits;
    return static_cast<std::size_t>(kSub * static_cast<std::uint64_t>(shift + 1) + (v >> shift) - kSub);
  }
  // Smallest value of bucket b.
  static std::uint64_t lower(std::size_t b) {
    if (b < kSub) return b;
    const std::uint64_t group = b / kSub;  // >= 1
    const std::uint64_t sub = b % kSub;
    return (kSub + sub) << (group - 1);
  }

 private:
  std::array<std::int64_t, kBuckets> counts_{};
  std::int64_t count_ = 0;
  std::uint64_t max_ns_ = 0;
};

// "p50 X us, p99 Y us, max Z us": how the daemon's and the echo's human summaries state a
// StepStats.
inline std::string describe_us(const StepStats& s) {
  char text[96];
  std::snprintf(text, sizeof text, "p50 %.1f us, p99 %.1f us, max %.1f us", s.quantile_ns(0.5) / 1e3,
                s.quantile_ns(0.99) / 1e3, static_cast<double>(s.max_ns()) / 1e3);
  return text;
}

// {"count": N, "p50": X, "p99": Y, "max": Z} in us (JSON): the machine-read twin of describe_us.
inline std::string quantiles_json_us(const StepStats& s) {
  char text[160];
  std::snprintf(text, sizeof text, "{\"count\": %lld, \"p50\": %.3f, \"p99\": %.3f, \"max\": %.3f}",
                static_cast<long long>(s.count()), s.quantile_ns(0.5) / 1e3, s.quantile_ns(0.99) / 1e3,
                static_cast<double>(s.max_ns()) / 1e3);
  return text;
}

}  // namespace f16mmae::executive
