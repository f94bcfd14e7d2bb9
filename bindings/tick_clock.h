// TickClock: cheap timing of the parts of every frame of a loop (the closed-loop flight's
// split between the truth model and the estimator, bind_truth.cpp).
//
//   TickClock::now()       a tick count: on x86 the time-stamp counter (RDTSC, not
//                          serialising: a few ns), elsewhere steady_clock in nanoseconds.
//   start() ... stop()     bracket the loop: steady_clock and the tick count are read at
//                          both ends, and seconds(n) = n * (steady seconds / ticks) over
//                          the bracket, so the ticks need no known frequency (the counter
//                          must run at a constant rate: constant_tsc on every x86-64 CPU
//                          this runs on).
// steady_clock::now() itself can cost 100 ns or more where the clock source is virtualised,
// which a frame of a few microseconds timed in two parts would pay five times; a counter read
// costs a few ns. A part's seconds are its ticks summed over the frames, converted once.
// Everything is noexcept and allocation-free.
#pragma once

#include <chrono>
#include <cstdint>

#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#define F16MMAE_TICK_TSC 1
#else
#define F16MMAE_TICK_TSC 0
#endif

namespace f16mmae::bindings {

class TickClock {
 public:
  using Ticks = std::uint64_t;
  using Steady = std::chrono::steady_clock;

  static Ticks now() noexcept {
#if F16MMAE_TICK_TSC
    return __rdtsc();
#else
    return static_cast<Ticks>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                  Steady::now().time_since_epoch()).count());
#endif
  }

  void start() noexcept {
    steady0_ = Steady::now();
    tick0_ = now();
  }
  // Ends the bracket; seconds() converts with its rate from here on.
  void stop() noexcept {
    const Ticks ticks = now() - tick0_;
    const double s = std::chrono::duration<double>(Steady::now() - steady0_).count();
    seconds_per_tick_ = ticks > 0 ? s / static_cast<double>(ticks) : 0.0;
  }
  double seconds(Ticks n) const noexcept { return static_cast<double>(n) * seconds_per_tick_; }

 private:
  Steady::time_point steady0_{};
  Ticks tick0_ = 0;
  double seconds_per_tick_ = 0.0;
};

}  // namespace f16mmae::bindings
