// WarmUpSchedule — when mmae-daemon wakes to warm its caches before the next sensor frame.
//
// Sensor frames come at the flight-control rate, so frame i + 1 is expected one period after
// frame i arrived. Between frames the daemon sleeps and other processes evict its working set
// and branch history: measured in the 60-s LCM benchmark at 64 Hz on a 2-vCPU VM, the
// executive's step took 12.6-17 us (p50) without a warm-up, 5-8 us with it (~1 us when it
// runs back to back). The main loop therefore sleeps until
//     warm_at = t_i + T - lead          (t_i: arrival of the last sensor frame, T = 1 / rate)
// warms up (Executive::warm_up), and sleeps again until the frame arrives.
// One warm-up per arrived frame: if frame i + 1 is late, or the flight has ended, nothing more
// is scheduled until the next frame comes. A frame that arrives early simply finds the caches
// as they are. lead = 0 disables the schedule.
// Pure timing arithmetic: no I/O, no allocation.
#pragma once

#include <chrono>
#include <optional>

namespace f16mmae::daemon {

class WarmUpSchedule {
 public:
  using Clock = std::chrono::steady_clock;

  WarmUpSchedule(double rate_hz, std::chrono::nanoseconds lead)
      : period_(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / rate_hz))),
        lead_(lead) {}

  bool enabled() const noexcept { return lead_.count() > 0 && lead_ < period_; }

  // A sensor frame arrived at `t`: schedule the warm-up for the next one.
  void on_frame(Clock::time_point t) noexcept {
    if (enabled()) warm_at_ = t + period_ - lead_;
  }
  // When to wake and warm, if a warm-up is pending.
  std::optional<Clock::time_point> due() const noexcept { return warm_at_; }
  // The warm-up was done.
  void done() noexcept { warm_at_.reset(); }

 private:
  Clock::duration period_;
  std::chrono::nanoseconds lead_;
  std::optional<Clock::time_point> warm_at_;
};

}  // namespace f16mmae::daemon
