// CpuWork — a fixed amount of register-only computation, calibrated to a duration: a dependent
// chain of multiply-adds on one double (no memory traffic, nothing a cache could hold), so
// that its time after a wake-up says what the host, not the code, costs. Used by
// f16mmae-idle-jitter (the host's floor) and by lcm-echo-f16 --work-us (an echo that spends
// the executive's step time before it replies).
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <vector>

namespace f16mmae::tools {

class CpuWork {
 public:
  using Clock = std::chrono::steady_clock;

  // Iterations for about `us` back to back: the median of 51 timings of a trial length.
  explicit CpuWork(double us) : n_(us > 0.0 ? calibrate(us) : 0) {}

  void run() const noexcept { chain(n_); }
  long iterations() const noexcept { return n_; }
  // Time one run, ns.
  std::int64_t timed() const noexcept {
    const auto t0 = Clock::now();
    run();
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count();
  }

 private:
  __attribute__((noinline)) static void chain(long n) noexcept {
    double x = 1.0;
    for (long i = 0; i < n; ++i) x = x * 1.0000001 + 1e-9;
    sink_ = x;
  }
  static long calibrate(double us) {
    constexpr long kTrial = 100000;
    std::vector<std::int64_t> t;
    for (int i = 0; i < 51; ++i) {
      const auto t0 = Clock::now();
      chain(kTrial);
      t.push_back(std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count());
    }
    std::nth_element(t.begin(), t.begin() + 25, t.end());
    return std::max(1L, std::lround(kTrial * us * 1e3 / static_cast<double>(std::max<std::int64_t>(t[25], 1))));
  }
  static inline volatile double sink_ = 0.0;
  long n_;
};

}  // namespace f16mmae::tools
