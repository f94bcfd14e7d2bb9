// WarmUpSchedule — when mmae-daemon wakes to warm its caches before the next sensor frame.
//
// Sensor frames come at the flight-control rate, so frame i + 1 is expected one period after
// frame i arrived. Between frames the daemon sleeps and other processes evict its working set
// and branch history, so a step after the idle time runs from cold caches, several times slower
// than back to back (docs/results/latency.md, "Warm-up before each frame", gives the figures).
// The main loop therefore sleeps until
//     warm_at = e - lead,   e = t_i + T   (t_i: arrival of the last sensor frame, T = 1 / rate)
// warms up (Executive::warm_up), and, with a re-warm interval R > 0, again every R while
// now + R < e + lead -- so a frame that comes up to `lead` late still finds the caches warm
// (an idle vCPU loses them within a few hundred microseconds). One window per arrived frame:
// if frame i + 1 is later than that, or the flight has ended, nothing more is scheduled until
// the next frame comes. lead = 0 disables the schedule.
// Pure timing arithmetic: no I/O, no allocation.
#pragma once

#include <chrono>
#include <optional>

namespace f16mmae::daemon {

class WarmUpSchedule {
 public:
  using Clock = std::chrono::steady_clock;

  WarmUpSchedule(double rate_hz, std::chrono::nanoseconds lead,
                 std::chrono::nanoseconds rewarm = std::chrono::nanoseconds(0))
      : period_(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / rate_hz))),
        lead_(lead), rewarm_(rewarm) {}

  bool enabled() const noexcept { return lead_.count() > 0 && lead_ < period_; }

  // A sensor frame arrived at `t`: open the warm-up window of the next one.
  void on_frame(Clock::time_point t) noexcept {
    if (enabled()) {
      expected_ = t + period_;
      warm_at_ = expected_ - lead_;
    }
  }
  // When to wake and warm, if a warm-up is pending.
  std::optional<Clock::time_point> due() const noexcept { return warm_at_; }
  // The warm-up was done at `now`: the next one, if re-warming and the window is open.
  void done(Clock::time_point now) noexcept {
    warm_at_.reset();
    if (rewarm_.count() > 0 && now + rewarm_ < expected_ + lead_) warm_at_ = now + rewarm_;
  }

 private:
  Clock::duration period_;
  std::chrono::nanoseconds lead_, rewarm_;
  Clock::time_point expected_{};
  std::optional<Clock::time_point> warm_at_;
};

}  // namespace f16mmae::daemon
