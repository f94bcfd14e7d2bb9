// mmae-daemon — the MMAE executive as an LCM process (see daemon_config.h for the options).
// Loads and validates the model bank, subscribes, then handles LCM traffic until SIGINT or
// SIGTERM (then it handles what has already arrived) or --max-frames statuses, and ends with
// its statistics twice: one human line,
// then "mmae-daemon: statistics {JSON}" (LcmNode::statistics_json) for tools to parse. Between
// frames it wakes --warm-lead-us before the next sensor frame is due to warm the executive
// up, and again every --rewarm-us until the frame comes (WarmUpSchedule, Executive::warm_up).
// Exit status: 0 clean end, 1 bank or LCM unusable, 2 usage error.
#include "daemon_config.h"
#include "frame_auth.h"
#include "executive/executive.h"
#include "lcm_node.h"
#include "lcm_wait.h"
#include "warm_up_schedule.h"

#include "bankfile/bank_file.h"
#include "bankfile/bank_signature.h"
#include "bankfile/turbulence_set_file.h"

#include <lcm/lcm.h>

#include <sched.h>
#include <sys/mman.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <csignal>
#include <cstring>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <optional>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

namespace {

volatile std::sig_atomic_t g_stop = 0;

extern "C" void request_stop(int) { g_stop = 1; }

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = request_stop;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

// SCHED_FIFO at `priority` for this thread and the threads created after it (LCM's receive
// thread), and every page locked in memory. Failure is reported, not fatal.
void go_realtime(int priority) {
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0)
    std::fprintf(stderr, "mmae-daemon: warning: mlockall failed (%s); running unlocked\n", std::strerror(errno));
  sched_param sp{};
  sp.sched_priority = priority;
  if (sched_setscheduler(0, SCHED_FIFO, &sp) != 0)
    std::fprintf(stderr, "mmae-daemon: warning: SCHED_FIFO priority %d refused (%s); running time-shared\n",
                 priority, std::strerror(errno));
}

// True when the file at `path` begins with the turbulence-bank-set magic (a file that cannot be
// read, or is no regular file (a FIFO would block), is not: the bank loader then names what is
// wrong with it).
bool is_turbulence_set_path(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  char magic[sizeof f16mmae::kTurbulenceSetFileMagic] = {};
  if (!in.read(magic, sizeof magic)) return false;
  return f16mmae::is_turbulence_set_file(reinterpret_cast<const std::uint8_t*>(magic), sizeof magic);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace f16mmae::daemon;
  using namespace f16mmae::executive;
  const ParseResult parsed = parse_daemon_args(std::vector<std::string>(argv + 1, argv + argc),
                                               std::getenv("LCM_DEFAULT_URL"));
  if (!parsed.ok) {
    std::fprintf(parsed.exit_code == 0 ? stdout : stderr, "%s\n", parsed.message.c_str());
    return parsed.exit_code;
  }
  const DaemonConfig& cfg = parsed.config;
  install_signal_handlers();  // from here on a signal ends the run cleanly

  std::unique_ptr<Executive> executive;
  std::string bank_hash, tuning;
  f16mmae::ModelBank bank;
  std::optional<f16mmae::TurbulenceSetFile> set;  // --bank is a turbulence bank set file
  try {
    if (is_turbulence_set_path(cfg.bank_path)) {
      if (!cfg.bank_public_key_path.empty())
        throw std::invalid_argument("--bank-public-key: signed turbulence bank set files are not supported");
      set = f16mmae::load_turbulence_set(cfg.bank_path);
      bank = set->members[static_cast<std::size_t>(set->selector.start)];  // the start member's settings
    } else {
      if (cfg.turbulence_banks)
        throw std::invalid_argument("--turbulence-banks needs a turbulence bank set file as --bank (f16mmae design "
                                    "--turbulence-banks --out FILE); this is not one");
      bank = cfg.bank_public_key_path.empty() ? f16mmae::load_bank(cfg.bank_path)
                                              : f16mmae::load_signed_bank(cfg.bank_path, cfg.bank_public_key_path);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mmae-daemon: error: cannot use bank file '%s': %s\n", cfg.bank_path.c_str(), e.what());
    return 1;
  }
  f16mmae::HierarchicalOptions options = cfg.estimator;   // the flags over the core's defaults
  try {
    if (std::abs(bank.frame_rate_hz - cfg.rate_hz) > 1e-9 * cfg.rate_hz) {
      std::fprintf(stderr,
                   "mmae-daemon: error: --rate-hz %g does not match the bank's design rate %g Hz "
                   "(%s); the filters are discretized at that rate\n",
                   cfg.rate_hz, bank.frame_rate_hz, cfg.bank_path.c_str());
      return 1;
    }
    // the bank's recommended settings (typed fields of the bank file), the flags over them
    options.bank.p_min = cfg.p_min.value_or(bank.estimator.p_min);
    options.schedule.node_p_min = !cfg.p_min;   // a scheduled bank's node floors unless --p-min
    options.declarer.threshold = cfg.threshold.value_or(bank.estimator.threshold);
    options.declarer.dwell_s = cfg.dwell_s.value_or(bank.estimator.dwell_s);
    options.declarer.dwell_nats = cfg.dwell_nats.value_or(0.0);
    if (!cfg.dwell_nats_table_path.empty()) {   // name -> N_k (declarer.h); the bank checks the names
      options.declarer.dwell_nats_per_hypothesis = f16mmae::dwell_nats_table_argument(cfg.dwell_nats_table_path);
    } else if (!cfg.dwell_nats) {   // the bank's recommended N_k unless --dwell-nats overrides them
      for (const auto& h : bank.hypotheses)
        if (h.dwell_nats > 0.0) options.declarer.dwell_nats_per_hypothesis[h.name] = h.dwell_nats;
    }
    for (auto [flag, name, bits] : {std::make_tuple("--adapt-counted-channel", &cfg.adapt_counted_channel,
                                                    &options.bank.adaptation.counted_channels),
                                    std::make_tuple("--adapt-excluded-channel", &cfg.adapt_excluded_channel,
                                                    &options.bank.adaptation.excluded_channels),
                                    std::make_tuple("--adapt-level-scale-channel", &cfg.adapt_level_scale_channel,
                                                    &options.bank.adaptation.level_scale_channels)}) {
      if (name->empty()) continue;   // its bit in the bank's measurement order
      const auto& m = bank.measurement_names;
      std::string upper = *name;
      for (char& ch : upper) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
      const auto it = std::find(m.begin(), m.end(), upper);
      if (it == m.end()) {
        std::fprintf(stderr, "mmae-daemon: error: %s %s: the bank measures no %s (%s)\n", flag, name->c_str(),
                     upper.c_str(), cfg.bank_path.c_str());
        return 1;
      }
      *bits = 1u << static_cast<unsigned>(it - m.begin());
    }
    if (cfg.set_tempering) {   // the per-hypothesis tempering; its fully tempered ones by name, as bits
      options.bank.adaptation.hypothesis_weight = *cfg.set_tempering;
      options.bank.adaptation.spare_rho = cfg.set_tempering_rho.value_or(0.0);
      options.bank.adaptation.spare_margin = cfg.set_tempering_margin;
      options.bank.adaptation.rough_rho = cfg.set_tempering_rough.value_or(0.0);
      options.bank.adaptation.rough_weight = cfg.set_tempering_rough_weight.value_or(1.0);
      // hypothesis names as bits (level 0: NONE, then the singles, in the bank's order); false: one is not there
      const auto bits = [&](const std::vector<std::string>& names, const char* flag, std::uint32_t& out) {
        out = 0;
        for (const std::string& name : names) {
          const int k = bank.find(name);
          if (k <= 0 || k >= 32) {
            std::fprintf(stderr, "mmae-daemon: error: %s %s: the bank has no failure hypothesis %s (%s)\n", flag,
                         name.c_str(), name.c_str(), cfg.bank_path.c_str());
            return false;
          }
          out |= 1u << static_cast<unsigned>(k);
        }
        return true;
      };
      if (!bits(cfg.set_tempering_full, "--set-tempering-full", options.bank.adaptation.full_tempering) ||
          !bits(cfg.set_tempering_margin_over, "--set-tempering-margin-over", options.bank.adaptation.spare_margin_over) ||
          !bits(cfg.set_tempering_rough_full, "--set-tempering-rough-full", options.bank.adaptation.rough_tempering))
        return 1;
    }
    options.bank.start_up_s = cfg.start_up_s.value_or(bank.estimator.start_up_s);   // a schedule's recommendation
    if (set && cfg.turbulence_banks) {
      executive = std::make_unique<Executive>(*set, options);
      bank_hash = set->content_hash;
      tuning.clear();   // the members' levels: "none/light/moderate/severe"
      for (const std::string& level : set->levels) tuning += (tuning.empty() ? "" : "/") + level;
    } else {   // a set file without --turbulence-banks: its start member alone, as in process
      executive = std::make_unique<Executive>(bank, options);
      bank_hash = bank.content_hash;
      tuning = bank.tuning;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mmae-daemon: error: cannot run bank '%s': %s\n", cfg.bank_path.c_str(), e.what());
    return 1;
  }

  std::unique_ptr<FrameAuth> auth;
  if (!cfg.auth_key_path.empty()) {
    try {
      auth = std::make_unique<FrameAuth>(FrameAuth::from_key_file(cfg.auth_key_path));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "mmae-daemon: error: %s\n", e.what());
      return 1;
    }
  } else {
    std::fprintf(stderr,
                 "mmae-daemon: warning: no --auth-key: frames, commands and resets are accepted from any "
                 "sender that reaches %s\n",
                 cfg.lcm_url.c_str());
  }

  if (cfg.realtime_priority > 0) go_realtime(cfg.realtime_priority);  // before LCM's threads exist
  lcm_t* lcm = lcm_create(cfg.lcm_url.c_str());
  if (!lcm) {
    std::fprintf(stderr,
                 "mmae-daemon: error: cannot open LCM URL '%s' (for udpm, multicast must be enabled "
                 "on the interface: see LCM's multicast setup notes)\n",
                 cfg.lcm_url.c_str());
    return 1;
  }
  const Channels channels = cfg.channels();
  int rc = 0;
  {
    LcmNode node(lcm, channels, *executive, auth.get());
    if (!cfg.quiet) {
      // what the bank runs with: a turbulence bank set's member in force has the set file's
      // trim tracking and tempering applied (TurbulenceSetBank, the one place that applies them)
      const f16mmae::HierarchicalOptions& running = executive->estimator().options();
      // the steady tracking's measurements and air-data gate, when not the core's defaults
      std::string steady_on;
      if (running.trim.steady_measurements != f16mmae::TrimTrackingOptions{}.steady_measurements) {
        steady_on = " on ";
        for (std::size_t k = 0; k < running.trim.steady_measurements.size(); ++k)
          steady_on += (k ? "," : "") + running.trim.steady_measurements[k];
      }
      if (std::isinf(running.trim.steady_climb_ft_s)) steady_on += ", air-data rates off";
      const std::string tracking = running.trim.enabled()
                                   ? "trim tracking " + f16mmae::format_value(running.trim.time_constant_s) + " s (freeze above " +
                                         f16mmae::format_value(running.trim.freeze_probability) +
                                         (running.trim.steady() ? ", steady " + f16mmae::format_value(running.trim.steady_g) + " g" + steady_on
                                                                : std::string()) + ")"
                                   : std::string("no trim tracking");
      const std::string trim = tracking + (running.complete_trim_hold.enabled()
                                               ? std::string(", complete failures on the trim") +
                                                     (running.complete_trim_hold.time_constant_s > 0.0
                                                          ? " averaged over " +
                                                                f16mmae::format_value(running.complete_trim_hold.time_constant_s) + " s"
                                                          : std::string()) +
                                                     (running.complete_trim_hold.hold != f16mmae::TrimHold::kOff
                                                          ? std::string(" held while ") +
                                                                f16mmae::trim_hold_name(running.complete_trim_hold.hold)
                                                          : std::string())
                                               : std::string());
      const bool node_reference = bank.schedule && bank.schedule->has_adapt_reference() &&
                                  options.schedule.node_adapt_reference;
      const bool set_reference = executive->estimator().members() > 0 && options.schedule.node_adapt_reference;
      std::string adaptation = executive->estimator().members() > 0 && set_reference
                                         ? std::string("turbulence adaptation (the set's reference per member)")
                                     : !options.bank.adaptation.enabled ? std::string("no turbulence adaptation")
                                     : node_reference ? std::string("turbulence adaptation (reference per node)")
                                                      : "turbulence adaptation (reference " +
                                                            f16mmae::format_value(options.bank.adaptation.reference) + ")";
      if (executive->estimator().members() == 0 && options.bank.adaptation.enabled &&
          options.bank.adaptation.own_channels)   // "(...)" -> "(..., own channels[, NAME counted])"
        adaptation.insert(adaptation.size() - 1,
                          cfg.adapt_counted_channel.empty() ? std::string(", own channels")
                                                            : ", own channels, " + cfg.adapt_counted_channel + " counted");
      if (options.bank.adaptation.enabled && options.bank.adaptation.running_start)
        adaptation.insert(adaptation.size() - 1, ", running start");
      if (options.bank.adaptation.enabled && options.bank.adaptation.level_scale)
        adaptation.insert(adaptation.size() - 1, ", level scale");
      if (options.bank.adaptation.enabled && !cfg.adapt_level_scale_channel.empty())
        adaptation.insert(adaptation.size() - 1, ", " + cfg.adapt_level_scale_channel + " level scaled from " +
                                                     f16mmae::format_value(options.bank.adaptation.level_scale_from));
      if (options.bank.adaptation.enabled && options.bank.adaptation.floor_time_constant_s > 0.0)
        adaptation.insert(adaptation.size() - 1,
                          ", lull floor over " + f16mmae::format_value(options.bank.adaptation.floor_time_constant_s) +
                              " s");
      if (options.bank.adaptation.enabled && options.bank.adaptation.scale_max_from > 0.0)
        adaptation.insert(adaptation.size() - 1,
                          ", bound rising from rho " + f16mmae::format_value(options.bank.adaptation.scale_max_from));
      if (executive->estimator().members() == 0 && options.bank.adaptation.enabled && !cfg.adapt_excluded_channel.empty())
        adaptation.insert(adaptation.size() - 1, ", " + cfg.adapt_excluded_channel + " levels excluded");
      if (options.bank.adaptation.enabled && !running.calm_complete.rho.empty()) {   // calm_air_complete.h
        std::string calm;   // "(..., complete in calm air VEL 1)": the bounds, relative to a node's reference
        for (const auto& [name, rho] : running.calm_complete.rho)
          if (rho > 0.0) calm += (calm.empty() ? "" : " ") + name + " " + f16mmae::format_value(rho);
        const auto& c = running.calm_complete;   // "... VEL 1 by either (whiteness below 0.78)"
        if (!calm.empty() && c.measure != f16mmae::CalmMeasure::kPowerRatio)
          calm += std::string(" by ") + f16mmae::calm_measure_name(c.measure) + " (whiteness below " +
                  f16mmae::format_value(c.whiteness_bound) + ")";
        if (!calm.empty()) adaptation.insert(adaptation.size() - 1, ", complete in calm air " + calm);
      }
      const auto& a = running.bank.adaptation;
      if (a.hypothesis_weight < 1.0)   // the per-hypothesis tempering (turbulence_adaptation.h)
        adaptation += ", set tempering " + f16mmae::format_value(a.hypothesis_weight) + " from rho " +
                      f16mmae::format_value(a.spare_rho) + (a.spare_margin ? " margin" : "") +
                      (a.spare_margin_over ? " over " + std::to_string(a.spare_margin_over) : std::string()) +
                      " full " + std::to_string(a.full_tempering) +
                      (a.rough_tempering ? " rough " + std::to_string(a.rough_tempering) + " from rho " +
                                               f16mmae::format_value(a.rough_rho) + " weight " +
                                               f16mmae::format_value(a.rough_weight)
                                         : std::string()) +
                      (options.spare_dwell_s > 0.0 ? " dwell " + f16mmae::format_value(options.spare_dwell_s) + " s"
                                                   : std::string());
      const std::string adaptation_climb =
          options.bank.adaptation.enabled && options.climb_reference.enabled()
              ? adaptation + ", climbing " + f16mmae::format_value(options.climb_reference.reference) + " held " +
                    f16mmae::format_value(options.climb_reference.hold_s) + " s" +
                    (options.climb_reference.dwell_s > 0.0
                         ? " with dwell " + f16mmae::format_value(options.climb_reference.dwell_s) + " s"
                         : std::string())
              : adaptation;
      std::string maneuver = running.maneuver.kinematics ? "maneuver kinematics" : "no maneuver kinematics";
      if (running.maneuver.tempering_g > 0.0) maneuver += ", tempering " + f16mmae::format_value(running.maneuver.tempering_g) + " g";
      maneuver += options.actuators.enabled() ? ", actuator limits" : "";
      if (running.maneuver.tempering_deadband_g > 0.0)
        maneuver += ", tempering dead band " + f16mmae::format_value(running.maneuver.tempering_deadband_g) + " g";
      if (running.maneuver.tempering_alpha_deg > 0.0)
        maneuver += ", alpha tempering " + f16mmae::format_value(running.maneuver.tempering_alpha_deg) + " deg beyond " +
                    f16mmae::format_value(running.maneuver.tempering_alpha_deadband_deg) + " deg sqrt(s)" +
                    (running.maneuver.tempering_alpha_trim_deg > 0.0
                         ? ", its reference shrinking above a trim alpha of " +
                               f16mmae::format_value(running.maneuver.tempering_alpha_trim_deg) + " deg"
                         : std::string());
      if (running.maneuver.tempering_added_g > 0.0)
        maneuver += ", added tempering " + f16mmae::format_value(running.maneuver.tempering_added_g) + " g beyond " +
                    f16mmae::format_value(running.maneuver.tempering_added_deadband_g) + " g sqrt(s)" +
                    (running.maneuver.tempering_added_spread > 0.0
                         ? " or " + f16mmae::format_value(running.maneuver.tempering_added_spread) + " sigma_n"
                         : "");
      if (running.maneuver_dwell.dwell_s > 0.0)
        maneuver += ", maneuver dwell " + f16mmae::format_value(running.maneuver_dwell.dwell_s) + " s held " +
                    f16mmae::format_value(running.maneuver_dwell.hold_s) + " s";
      if (running.maneuver_dwell.has_reference())
        maneuver += ", maneuver reference " + f16mmae::format_value(running.maneuver_dwell.reference);
      if (running.maneuver_dwell.mach_per_s != f16mmae::AirDataRates::kMachPerS ||
          running.climb_reference.mach_per_s != f16mmae::AirDataRates::kMachPerS)   // the gates in force, off their default
        maneuver += running.maneuver_dwell.mach_per_s == running.climb_reference.mach_per_s
                        ? ", Mach-rate gate " + f16mmae::format_value(running.maneuver_dwell.mach_per_s) + "/s"
                        : ", Mach-rate gates " + f16mmae::format_value(running.maneuver_dwell.mach_per_s) +
                              "/s (maneuver dwell), " + f16mmae::format_value(running.climb_reference.mach_per_s) +
                              "/s (climb reference)";
      if (running.maneuver_dwell.climb_ft_s != f16mmae::AirDataRates::kClimbFtS ||
          running.climb_reference.climb_ft_s != f16mmae::AirDataRates::kClimbFtS)
        maneuver += running.maneuver_dwell.climb_ft_s == running.climb_reference.climb_ft_s
                        ? ", climb-rate gate " + f16mmae::format_value(running.maneuver_dwell.climb_ft_s) + " ft/s"
                        : ", climb-rate gates " + f16mmae::format_value(running.maneuver_dwell.climb_ft_s) +
                              " ft/s (maneuver dwell), " + f16mmae::format_value(running.climb_reference.climb_ft_s) +
                              " ft/s (climb reference)";
      if (running.gates_calm_scaled)
        maneuver += ", gates x sqrt(s_c)";
      else if (running.rate_gates_gust_scaled)
        maneuver += ", rate gates x sqrt(s_b)";
      if (running.maneuver_trim.enabled)
        maneuver += ", maneuver trim " + f16mmae::format_value(running.maneuver_trim.time_constant_s) + " s" +
                    (running.maneuver_trim.accel ? "" : " (climb only)") +
                    (running.maneuver_trim.inertial
                         ? ", inertial rates " + f16mmae::format_value(running.maneuver_trim.inertial_path.blend_time_constant_s) + " s"
                         : "");
      // a scheduled bank's floors are its nodes' (blended where the air data lies): their range
      std::string floor = "p_min " + f16mmae::format_value(options.bank.p_min);
      if (bank.schedule && options.schedule.node_p_min) {
        double lo = bank.schedule->nodes.front().bank.estimator.p_min, hi = lo;
        for (const auto& n : bank.schedule->nodes) {
          lo = std::min(lo, n.bank.estimator.p_min);
          hi = std::max(hi, n.bank.estimator.p_min);
        }
        floor = lo == hi ? "p_min " + f16mmae::format_value(lo) + " at every node"
                         : "p_min per node " + f16mmae::format_value(lo) + " to " + f16mmae::format_value(hi);
      }
      const std::string start_up = options.bank.start_up_s > 0.0
                                       ? "start-up " + f16mmae::format_value(options.bank.start_up_s) + " s"
                                       : std::string("no start-up");
      // the evidence dwell in force (hierarchical_bank.h: none with a climb or maneuver dwell
      // unless --evidence-dwell-in-phases)
      std::string evidence_dwell = running.declarer.dwell_nats > 0.0
                                       ? " or " + f16mmae::format_value(running.declarer.dwell_nats) + " nats"
                                       : std::string();
      std::string table;   // the per-hypothesis table: N_k by name
      for (const auto& [name, n] : running.declarer.dwell_nats_per_hypothesis)
        if (n > 0.0) table += (table.empty() ? "" : ", ") + name + " " + f16mmae::format_value(n);
      if (!table.empty()) evidence_dwell += " or per hypothesis (" + table + ") nats";
      std::string least;   // the least dwell per hypothesis: D_k by name (declarer.h)
      for (const auto& [name, d] : running.declarer.dwell_s_per_hypothesis)
        if (d > 0.0) least += (least.empty() ? "" : ", ") + name + " " + f16mmae::format_value(d);
      if (!least.empty()) evidence_dwell += ", at least " + least + " s";
      std::string rough;   // the least dwell per hypothesis in rough air: R_k by name (declarer.h)
      for (const auto& [name, d] : running.declarer.rough_dwell_s_per_hypothesis)
        if (d > 0.0) rough += (rough.empty() ? "" : ", ") + name + " " + f16mmae::format_value(d);
      if (!rough.empty())
        evidence_dwell += ", in rough air (scale >= " + f16mmae::format_value(running.declarer.rough_scale) +
                          ") at least " + rough + " s";
      std::printf("mmae-daemon: ready: bank %.12s (%s, %s of %s, %s, threshold %g, dwell %g s%s, %s, %s, %s, "
                  "schedule %s on air data low-passed %s s, %s), lcm %s, %s -> %s, %s\n",
                  bank_hash.c_str(), tuning.c_str(), executive->estimator().kind(), executive->estimator().states().c_str(), floor.c_str(),
                  options.declarer.threshold, options.declarer.dwell_s, evidence_dwell.c_str(), start_up.c_str(),
                  adaptation_climb.c_str(),
                  trim.c_str(), running.schedule.mode == f16mmae::ScheduleMode::kNearest ? "nearest" : "interpolate",
                  f16mmae::format_value(options.schedule.air_data_time_constant_s).c_str(), maneuver.c_str(), cfg.lcm_url.c_str(),
                  channels.sensors.c_str(), channels.status.c_str(),
                  auth ? "frames authenticated" : "frames NOT authenticated");
      std::fflush(stdout);
    }
    WarmUpSchedule warm_up(cfg.rate_hz, std::chrono::nanoseconds(std::llround(cfg.warm_lead_us * 1e3)),
                           std::chrono::nanoseconds(std::llround(cfg.rewarm_us * 1e3)));
    std::int64_t sensors_seen = 0;
    while (!g_stop) {
      if (cfg.max_frames > 0 && node.published() >= cfg.max_frames) break;
      const int r = wait_and_handle(lcm, warm_up, [&] { executive->warm_up(); });
      if (r < 0) {
        if (g_stop) break;  // interrupted by the signal
        std::fprintf(stderr, "mmae-daemon: error: LCM receive failed on '%s'\n", cfg.lcm_url.c_str());
        rc = 1;
        break;
      }
      if (node.sensor_messages() != sensors_seen) {
        sensors_seen = node.sensor_messages();
        warm_up.on_frame(node.last_sensor_arrival());
      }
    }
    if (g_stop) {
      // What has already arrived is handled before the statistics: a sender that stops the
      // daemon right after its last frame gets that frame applied. Until 50 ms pass without
      // a message, at most kDrainMax messages, so a flood cannot hold the daemon up.
      constexpr int kDrainMax = 100000;
      for (int i = 0; i < kDrainMax && lcm_handle_timeout(lcm, 50) > 0; ++i) {
      }
    }
    const MessageCounts& m = node.messages();
    std::printf("mmae-daemon: %s%s; messages %lld received, %lld undecodable, %lld unauthenticated, "
                "%lld replayed, %lld publish errors; "
                "%lld statuses published, sensor-to-publish %s; %lld cache warm-ups\n",
                g_stop ? "stopped by signal: " : "", executive->summary().c_str(),
                static_cast<long long>(m.received), static_cast<long long>(m.undecodable),
                static_cast<long long>(m.unauthenticated), static_cast<long long>(m.replayed),
                static_cast<long long>(m.publish_errors), static_cast<long long>(node.published()),
                describe_us(node.sensor_to_publish()).c_str(), static_cast<long long>(executive->warm_ups()));
    std::printf("mmae-daemon: statistics %s\n", node.statistics_json().c_str());
    std::fflush(stdout);
  }
  lcm_destroy(lcm);
  return rc;
}
