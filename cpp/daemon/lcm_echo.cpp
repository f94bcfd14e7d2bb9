// lcm-echo-f16 — the bare C++ echo the latency benchmark compares mmae-daemon against:
// republishes every message of channel IN, byte for byte, on channel OUT. Same LCM library,
// same event loop as the daemon, no decode, no estimator: the transport's own round trip.
//   lcm-echo-f16 [--lcm-url URL] [--in CHANNEL] [--out CHANNEL] [--realtime PRIORITY] [--quiet]
// --realtime gives it the same SCHED_FIFO priority and locked memory as mmae-daemon's, so
// that a benchmark compares like with like.
// Defaults: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0, ECHO_PING -> ECHO_PONG.
// Ends cleanly on SIGINT/SIGTERM with the number of messages echoed.
#include "daemon_config.h"

#include <lcm/lcm.h>
#include <sched.h>
#include <sys/mman.h>

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
};

void on_message(const lcm_recv_buf_t* rbuf, const char*, void* user) {
  auto* echo = static_cast<Echo*>(user);
  if (lcm_publish(echo->lcm, echo->out.c_str(), rbuf->data, rbuf->data_size) == 0) ++echo->count;
}

}  // namespace

int main(int argc, char** argv) {
  const char* env = std::getenv("LCM_DEFAULT_URL");
  std::string url = env && *env ? env : f16mmae::daemon::kDefaultLcmUrl;
  std::string in = "ECHO_PING", out = "ECHO_PONG";
  bool quiet = false;
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
    if ((a == "--lcm-url" || a == "--in" || a == "--out") && i + 1 < argc) {
      (a == "--lcm-url" ? url : a == "--in" ? in : out) = argv[++i];
    } else {
      std::fprintf(stderr,
                   "lcm-echo-f16: error: unknown or incomplete argument '%s'\n"
                   "usage: lcm-echo-f16 [--lcm-url URL] [--in CHANNEL] [--out CHANNEL] [--realtime P] [--quiet]\n",
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
  Echo echo{lcm, out};
  lcm_subscribe(lcm, in.c_str(), on_message, &echo);
  if (!quiet) {
    std::printf("lcm-echo-f16: ready: lcm %s, %s -> %s\n", url.c_str(), in.c_str(), out.c_str());
    std::fflush(stdout);
  }
  int rc = 0;
  while (!g_stop) {
    if (lcm_handle_timeout(lcm, 100) < 0 && !g_stop) {
      rc = 1;
      break;
    }
  }
  std::printf("lcm-echo-f16: %lld messages echoed\n", echo.count);
  lcm_destroy(lcm);
  return rc;
}
