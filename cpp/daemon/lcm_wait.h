// wait_and_handle — one turn of an LCM event loop that can also wake at a scheduled time:
// waits for traffic on `lcm` for at most 100 ms (so that the caller sees a signal or its own
// stop condition), calling `on_due()` on the way when `schedule` is due (WarmUpSchedule: a
// warm-up ahead of the next expected frame), then handles one message if one came.
// Returns lcm_handle's result (0) after a message, 0 on a timeout or a signal (EINTR), -1 on
// an error. ppoll on lcm_get_fileno, so the wake-up has nanosecond resolution (LCM's own
// lcm_handle_timeout takes milliseconds). Allocation-free.
#pragma once

#include "warm_up_schedule.h"

#include <lcm/lcm.h>
#include <poll.h>

#include <cerrno>
#include <chrono>
#include <ctime>

namespace f16mmae::daemon {

template <class OnDue>
int wait_and_handle(lcm_t* lcm, WarmUpSchedule& schedule, OnDue&& on_due) {
  using Clock = WarmUpSchedule::Clock;
  pollfd pfd{lcm_get_fileno(lcm), POLLIN, 0};
  for (;;) {
    const auto now = Clock::now();
    const auto due = schedule.due();
    if (due && *due <= now) {
      on_due();
      schedule.done(Clock::now());
      continue;
    }
    auto until = now + std::chrono::milliseconds(100);
    const bool wake_first = due && *due < until;
    if (wake_first) until = *due;
    const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(until - now).count();
    const timespec timeout{static_cast<std::time_t>(ns / 1000000000), static_cast<long>(ns % 1000000000)};
    const int n = ppoll(&pfd, 1, &timeout, nullptr);
    if (n < 0) return errno == EINTR ? 0 : -1;
    if (n > 0) return (pfd.revents & POLLIN) ? lcm_handle(lcm) : -1;
    if (!wake_first) return 0;
  }
}

}  // namespace f16mmae::daemon
