// f16mmae-idle-jitter — this host's floor for a per-frame deadline: how long a fixed,
// register-only computation takes when it runs right after the thread has slept, as the
// executive's step does between frames.
//   f16mmae-idle-jitter [--work-us US] [--samples N] [--idle-us US[,US...]]
// The work (CpuWork) is a dependent chain of multiply-adds on one double (no memory
// traffic, nothing to cache), calibrated back to back to about --work-us (default 5, the
// executive's step). For each idle time (default 0,50,1000,15625: back to back, a short gap, 1 ms, a 64-Hz frame) it
// sleeps that long N times (default 300) and times the work after each wake-up. A p99 far
// above the p50 after a long idle is the host's doing (a halted vCPU, its core lent to other
// work), not the code's: no program of that length can have a shorter tail on this host.
// Prints one line per idle time: p50, p99, max in us and p99/p50; then the same as
// "f16mmae-idle-jitter: statistics {"work_us": W, "idle_us": {"IDLE": {count, p50, p99, max}}}".
#include "cpu_work.h"
#include "executive/step_stats.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

namespace {

int usage(const char* what) {
  std::fprintf(stderr,
               "f16mmae-idle-jitter: error: %s\n"
               "usage: f16mmae-idle-jitter [--work-us US] [--samples N] [--idle-us US[,US...]]\n",
               what);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  double work_us = 5.0;
  long samples = 300;
  std::vector<double> idles = {0.0, 50.0, 1000.0, 15625.0};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      std::printf("usage: f16mmae-idle-jitter [--work-us US] [--samples N] [--idle-us US[,US...]]\n"
                  "Times a fixed register-only computation (about --work-us, default 5) after sleeping\n"
                  "each --idle-us (default 0,50,1000,15625) --samples times (default 300): the floor a\n"
                  "host sets for any per-frame deadline.\n");
      return 0;
    }
    if (i + 1 >= argc) return usage((a + " needs a value").c_str());
    const char* v = argv[++i];
    char* end = nullptr;
    if (a == "--work-us") {
      work_us = std::strtod(v, &end);
      if (*end != '\0' || !(work_us > 0.0) || work_us > 1e5) return usage("--work-us must be in (0, 1e5]");
    } else if (a == "--samples") {
      samples = std::strtol(v, &end, 10);
      if (*end != '\0' || samples < 1) return usage("--samples must be a whole number >= 1");
    } else if (a == "--idle-us") {
      idles.clear();
      for (const char* p = v; *p;) {
        const double us = std::strtod(p, &end);
        if (end == p || !(us >= 0.0) || us > 1e6 || (*end != ',' && *end != '\0'))
          return usage("--idle-us must be a comma-separated list of microseconds in [0, 1e6]");
        idles.push_back(us);
        p = *end ? end + 1 : end;
      }
    } else {
      return usage(("unknown argument '" + a + "'").c_str());
    }
  }
  const f16mmae::tools::CpuWork work(work_us);
  std::string json;
  for (const double idle : idles) {
    f16mmae::executive::StepStats stats;
    const auto gap = std::chrono::nanoseconds(std::llround(idle * 1e3));
    for (long i = 0; i < samples; ++i) {
      if (idle > 0) std::this_thread::sleep_for(gap);
      stats.record(work.timed());
    }
    const double p50 = stats.quantile_ns(0.5), p99 = stats.quantile_ns(0.99);
    std::printf("idle %g us: work %s (p99/p50 %.1f)\n", idle, f16mmae::executive::describe_us(stats).c_str(),
                p50 > 0 ? p99 / p50 : 0.0);
    char key[48];
    std::snprintf(key, sizeof key, "%s\"%g\": ", json.empty() ? "" : ", ", idle);
    json += key + f16mmae::executive::quantiles_json_us(stats);
  }
  std::printf("f16mmae-idle-jitter: statistics {\"work_us\": %.3f, \"idle_us\": {%s}}\n", work_us, json.c_str());
  return 0;
}
