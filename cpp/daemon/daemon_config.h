// DaemonConfig — the settings of mmae-daemon and the parsing of its command line.
//
// The flags are one table in daemon_config.cpp: a row names a flag, its value's range or choices,
// the field it sets (most of them a field of the estimator's HierarchicalOptions), what it needs (e.g. --trim-freeze-probability applies with --trim-tracking only)
// and its help; `mmae-daemon --help` (daemon_usage) prints the table.
//
// The LCM URL defaults as LCM's own tools do: $LCM_DEFAULT_URL, else
// udpm://239.255.76.67:7667?ttl=0. Channels are UPPER_SNAKE names with the prefix prepended:
// P + F16_SENSORS, F16_COMMANDS, MMAE_STATUS, MMAE_RESET (the executive never subscribes to
// F16_RUN_MARKER, which carries the failure truth of a run).
// parse_daemon_args never throws and never exits: it returns the config, or the text to
// print (help, or an error naming the bad value and the valid choices) and the exit code.
#pragma once

#include "f16mmae/hierarchical_bank.h"

#include <optional>
#include <string>
#include <vector>

namespace f16mmae::daemon {

inline constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0";

struct Channels {
  std::string sensors, commands, status, reset;
  static Channels with_prefix(const std::string& prefix) {
    return {prefix + "F16_SENSORS", prefix + "F16_COMMANDS", prefix + "MMAE_STATUS", prefix + "MMAE_RESET"};
  }
};

struct DaemonConfig {
  std::string bank_path;
  std::string lcm_url;              // resolved: never empty after parsing
  std::string channel_prefix;
  double rate_hz = 64.0;            // must equal the bank's frame_rate_hz
  // Estimator settings over the bank's recommended ones (ModelBank::estimator); unset: the bank's.
  std::optional<double> p_min, threshold, dwell_s;
  std::optional<double> dwell_nats;  // the evidence dwell (declarer.h); unset: off
  std::string dwell_nats_table_path;  // non-empty: the per-hypothesis evidence dwell: a file, or NAME=N,... inline (declarer.h)
  // The estimator: the core's defaults (hierarchical_bank.h), the flags written over them. What
  // depends on the bank (its recommended settings above, names turned into indices below) main.cpp
  // applies once the bank is loaded.
  HierarchicalOptions estimator;
  bool turbulence_banks = false;     // FILE is a turbulence bank set file: fly the set (turbulence_bank_set.h)
  std::string adapt_counted_channel;  // a measurement (lower case) still counted in m_k, with adapt_own_channels only
  std::string adapt_excluded_channel;  // a measurement (lower case): hypotheses reading it as a free level leave the adaptation's minimum
  std::string adapt_level_scale_channel;  // a measurement (lower case): hypotheses reading it as a level gain (1/2) ln max(s / s_0, 1) at every level
  std::optional<double> set_tempering;         // the per-hypothesis tempering's weight W (turbulence_adaptation.h), with turbulence_banks
  std::vector<std::string> set_tempering_full; // hypotheses (upper case) kept at the full s, with set_tempering
  std::optional<double> set_tempering_rho;     // the sparing only while the measured rho >= this, with set_tempering
  std::optional<double> set_tempering_rough;   // the air's rho from which set_tempering_rough_full keep s, with set_tempering
  std::vector<std::string> set_tempering_rough_full;  // hypotheses (upper case) kept at s in rough air, with set_tempering_rough
  std::optional<double> set_tempering_rough_weight;  // their share of s - 1 in rough air, with set_tempering_rough
  bool set_tempering_margin = false;           // the spared evidence over the best of NONE and the full ones, with set_tempering
  std::vector<std::string> set_tempering_margin_over;  // hypotheses (upper case) of the margin's reference, with set_tempering_margin
  std::optional<double> start_up_s;  // filter_bank.h: updates that weigh nothing after a start; unset: the bank's
  long long max_frames = 0;         // exit after this many status frames; 0 = run until signalled
  int realtime_priority = 0;        // > 0: SCHED_FIFO at this priority and memory locked
  double warm_lead_us = 500.0;      // cache warm-up this long before a frame is due; 0 = off
  double rewarm_us = 100.0;         // then again this often until the frame comes; 0 = once
  std::string auth_key_path;        // non-empty: the pre-shared key of FrameAuth (frame_auth.h)
  std::string bank_public_key_path; // non-empty: the bank must carry a valid signature (bank_signature.h)
  bool quiet = false;               // no "ready" line on stdout
  Channels channels() const { return Channels::with_prefix(channel_prefix); }
};

struct ParseResult {
  bool ok = false;        // run with `config`
  int exit_code = 0;      // when !ok: 0 after --help/--version, 2 on a usage error
  std::string message;    // when !ok: the help text or "mmae-daemon: error: ..."
  DaemonConfig config;
};

// `default_url` is what $LCM_DEFAULT_URL holds (nullptr if unset).
ParseResult parse_daemon_args(const std::vector<std::string>& args, const char* default_url);

std::string daemon_usage();

// Every flag of the table, in the help's order.
std::vector<std::string> daemon_flag_names();

}  // namespace f16mmae::daemon
