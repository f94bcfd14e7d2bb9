// lcm-echo-f16 — the bare C++ echo the latency benchmark compares mmae-daemon against:
// republishes every message of channel IN, byte for byte, on channel OUT. Same LCM library,
// same event loop as the daemon, no decode, no estimator: the transport's own round trip.
//   lcm-echo-f16 [--lcm-url URL] [--in CHANNEL] [--out CHANNEL] [--realtime PRIORITY]
//                [--wake-lead-us US [--rewake-us US] [--rate-hz HZ]] [--work-us US] [--quiet]
// --realtime gives it the same SCHED_FIFO priority and locked memory as mmae-daemon's, so
// that a benchmark compares like with like. --wake-lead-us makes it wake on mmae-daemon's
// warm-up schedule (US before the next message is due, one period of --rate-hz, default 64,
// after the last), and again every --rewake-us as the daemon re-warms (default 0: once), and
// do nothing: the control that separates what the daemon's warm-up gains from merely being
// awake (default 0: a bare echo).
// --work-us spends about US of register-only work (CpuWork) before each echo, as the executive
// spends its step: an echo that costs what the executive costs but touches no data, to tell
// the executive's own cost from what its time in the callback costs on this host.
// Defaults: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0, ECHO_PING -> ECHO_PONG.
// Ends cleanly on SIGINT/SIGTERM with the number of messages echoed and the time from each
// message's callback to its echo published (p50/p99/max), the daemon's sensor-to-publish twin,
// first as a human line, then as "lcm-echo-f16: statistics {JSON}" for the benchmark.
#include "cpu_work.h"
#include "daemon/daemon_config.h"
#include "daemon/lcm_wait.h"
#include "executive/step_stats.h"
#include "daemon/warm_up_schedule.h"

#include <lcm/lcm.h>
#include <sched.h>
#include <sys/mman.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

volatile std::sig_atomic_t g_stop = 0;
extern "C" void request_stop(int) { g_stop = 1; }

struct Echo {
  lcm_t* lcm;
  std::string out;
  long long count = 0;
  std::chrono::steady_clock::time_point last{};
  f16mmae::executive::StepStats in_to_publish;  // message in (the callback) -> echo published
  const f16mmae::tools::CpuWork* work = nullptr;  // spent before each echo (--work-us)
};

void on_message(const lcm_recv_buf_t* rbuf, const char*, void* user) {
  auto* echo = static_cast<Echo*>(user);
  echo->last = std::chrono::steady_clock::now();
  if (echo->work) echo->work->run();
  if (lcm_publish(echo->lcm, echo->out.c_str(), rbuf->data, rbuf->data_size) == 0) {
    ++echo->count;
    echo->in_to_publish.record(std::chrono::duration_cast<std::chrono::nanoseconds>(
        std::chrono::steady_clock::now() - echo->last).count());
  }
}

}  // namespace

int main(int argc, char** argv) {
  const char* env = std::getenv("LCM_DEFAULT_URL");
  std::string url = env && *env ? env : f16mmae::daemon::kDefaultLcmUrl;
  std::string in = "ECHO_PING", out = "ECHO_PONG";
  bool quiet = false;
  double wake_lead_us = 0.0, rewake_us = 0.0, rate_hz = 64.0, work_us = 0.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quiet") {
      quiet = true;
      continue;
    }
    if (a == "--realtime" && i + 1 < argc) {
      const int p = std::atoi(argv[++i]);
      if (p < 1 || p > 99) {
        std::fprintf(stderr, "lcm-echo-f16: error: --realtime must be 1-99, got '%s'\n", argv[i]);
        return 2;
      }
      mlockall(MCL_CURRENT | MCL_FUTURE);
      sched_param sp{};
      sp.sched_priority = p;
      if (sched_setscheduler(0, SCHED_FIFO, &sp) != 0)
        std::fprintf(stderr, "lcm-echo-f16: warning: SCHED_FIFO priority %d refused\n", p);
      continue;
    }
    if ((a == "--wake-lead-us" || a == "--rewake-us" || a == "--rate-hz" || a == "--work-us") && i + 1 < argc) {
      char* end = nullptr;
      const double x = std::strtod(argv[++i], &end);
      if (*end != '\0' || !(x >= 0.0) || !std::isfinite(x) || (a == "--rate-hz" && x == 0.0)) {
        std::fprintf(stderr, "lcm-echo-f16: error: %s must be a finite number %s, got '%s'\n", a.c_str(),
                     a == "--rate-hz" ? "> 0" : ">= 0", argv[i]);
        return 2;
      }
      if (a == "--work-us" && x > 1e5) {
        std::fprintf(stderr, "lcm-echo-f16: error: --work-us must be at most 100000 (0.1 s of work per message), "
                     "got '%s'\n", argv[i]);
        return 2;
      }
      (a == "--rate-hz" ? rate_hz : a == "--rewake-us" ? rewake_us : a == "--work-us" ? work_us : wake_lead_us) = x;
      continue;
    }
    if ((a == "--lcm-url" || a == "--in" || a == "--out") && i + 1 < argc) {
      (a == "--lcm-url" ? url : a == "--in" ? in : out) = argv[++i];
    } else {
      std::fprintf(stderr,
                   "lcm-echo-f16: error: unknown or incomplete argument '%s'\n"
                   "usage: lcm-echo-f16 [--lcm-url URL] [--in CHANNEL] [--out CHANNEL] [--realtime P]\n"
                   "                    [--wake-lead-us US [--rewake-us US] [--rate-hz HZ]] [--work-us US]\n"
                   "                    [--quiet]\n",
                   a.c_str());
      return 2;
    }
  }
  lcm_t* lcm = lcm_create(url.c_str());
  if (!lcm) {
    std::fprintf(stderr, "lcm-echo-f16: error: cannot open LCM URL '%s'\n", url.c_str());
    return 1;
  }
  struct sigaction sa {};
  sa.sa_handler = request_stop;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  const f16mmae::tools::CpuWork work(work_us);  // calibrated before the first message
  Echo echo{lcm, out};
  if (work_us > 0.0) echo.work = &work;
  lcm_subscribe(lcm, in.c_str(), on_message, &echo);
  if (!quiet) {
    std::printf("lcm-echo-f16: ready: lcm %s, %s -> %s\n", url.c_str(), in.c_str(), out.c_str());
    std::fflush(stdout);
  }
  f16mmae::daemon::WarmUpSchedule wake(rate_hz, std::chrono::nanoseconds(std::llround(wake_lead_us * 1e3)),
                                       std::chrono::nanoseconds(std::llround(rewake_us * 1e3)));
  long long seen = 0, wakes = 0;
  int rc = 0;
  while (!g_stop) {
    if (f16mmae::daemon::wait_and_handle(lcm, wake, [&] { ++wakes; }) < 0 && !g_stop) {
      rc = 1;
      break;
    }
    if (echo.count != seen) {
      seen = echo.count;
      wake.on_frame(echo.last);
    }
  }
  std::printf("lcm-echo-f16: %lld messages echoed, message-to-publish %s; %lld scheduled wake-ups\n", echo.count,
              f16mmae::executive::describe_us(echo.in_to_publish).c_str(), wakes);
  std::printf("lcm-echo-f16: statistics {\"echoed\": %lld, \"wake_ups\": %lld, \"message_to_publish_us\": %s}\n",
              echo.count, wakes, f16mmae::executive::quantiles_json_us(echo.in_to_publish).c_str());
  lcm_destroy(lcm);
  return rc;
}
