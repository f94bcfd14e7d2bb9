// DaemonConfig — the settings of mmae-daemon and the parsing of its command line.
//
// The flags are one table in daemon_config.cpp: a row names a flag, its value's range or choices,
// the field it sets, what it needs (e.g. --trim-freeze-probability applies with --trim-tracking only)
// and its help; `mmae-daemon --help` (daemon_usage) prints the table.
//
// The LCM URL defaults as LCM's own tools do: $LCM_DEFAULT_URL, else
// udpm://239.255.76.67:7667?ttl=0. Channels are UPPER_SNAKE names with the prefix prepended:
// P + F16_SENSORS, F16_COMMANDS, MMAE_STATUS, MMAE_RESET (the executive never subscribes to
// F16_RUN_MARKER, which carries the failure truth of a run).
// parse_daemon_args never throws and never exits: it returns the config, or the text to
// print (help, or an error naming the bad value and the valid choices) and the exit code.
#pragma once

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
  std::string dwell_nats_table_path;  // non-empty: the per-hypothesis evidence dwell's table (declarer.h)
  // The estimator's on-line options, as 'f16mmae run' has them (off: the bank as designed).
  bool adapt_turbulence = false;     // turbulence_adaptation.h
  bool turbulence_banks = false;     // FILE is a turbulence bank set file: fly the set (turbulence_bank_set.h)
  std::optional<double> adapt_reference;  // its rho_0, with adapt_turbulence only
  bool adapt_own_channels = false;   // its rho per channel each filter reads, with adapt_turbulence only
  std::string adapt_counted_channel;  // a measurement (lower case) still counted in m_k, with adapt_own_channels only
  std::optional<double> adapt_reference_climb;  // rho_0 while climbing (climb_reference.h), with adapt_turbulence
  std::optional<double> adapt_reference_climb_hold_s;  // its hold, with adapt_reference_climb
  std::optional<double> adapt_reference_climb_dwell_s; // the level-0 dwell while it is in force, with it
  std::optional<double> adapt_channel_weight;  // the per-channel tempering's weight G (turbulence_adaptation.h)
  std::optional<double> set_tempering;         // the per-hypothesis tempering's weight W (turbulence_adaptation.h), with turbulence_banks
  std::vector<std::string> set_tempering_full; // hypotheses (upper case) kept at the full s, with set_tempering
  std::optional<double> set_tempering_rho;     // the sparing only while the measured rho >= this, with set_tempering
  bool set_tempering_own_fit = false;          // the spared hypothesis by its form per channel it reads, with set_tempering
  std::optional<double> set_tempering_burst;   // the sparing only while the quarter-second power <= C rho, with set_tempering
  bool set_tempering_margin = false;           // the spared evidence over the best of NONE and the full ones, with set_tempering
  std::optional<double> maneuver_dwell_s;      // the level-0 dwell while maneuvering (maneuver_dwell.h)
  std::optional<double> maneuver_dwell_hold_s, maneuver_dwell_g, maneuver_dwell_time_constant_s;  // with it
  std::optional<double> maneuver_reference;    // rho_0 while maneuvering, with adapt_turbulence
  std::optional<double> maneuver_mach_per_s;   // |M_dot| opening the maneuver dwell's and climb reference's gates
  std::optional<double> level1_p_min;          // the floor while a level-1 bank is on line (hierarchical_bank.h)
  std::optional<double> level1_dwell_s;        // the dwell while a level-1 bank is on line
  std::optional<double> level1_allowance;      // the duals' drift allowance at level 1, nats a frame (level1_allowance.h)
  std::optional<bool> departure_hold;          // the level-1 departure hold (on by default in the core)
  bool declare_components = false;   // a partial hypothesis and its single declared as one (hierarchical_bank.h)
  std::optional<double> partial_p_min;  // the partial hypotheses' floor at level 0 (level_floors.h); unset: the floor
  double trim_time_constant_s = 0.0; // trim_tracker.h; 0 = off
  std::optional<double> trim_freeze_probability;  // with trim tracking only
  double trim_steady_g = 0.0;        // with trim tracking only: steady tracking's load-factor gate; 0 = off
  std::optional<bool> trim_load_factor;  // with steady trim tracking only: the offset applied as n times the 1-g one
  bool schedule_nearest = false;     // a scheduled bank: nearest node instead of interpolation
  std::optional<double> air_data_time_constant_s;  // its air-data low-pass (scheduled_filters.h); unset: the core's
  bool maneuver_kinematics = false;  // maneuver_kinematics.h
  double maneuver_tempering_g = 0.0; // 0 = off
  std::optional<double> maneuver_tempering_deadband_g;  // its dead band, with maneuver_tempering_g
  bool maneuver_trim = false;        // maneuver_trim.h
  std::optional<double> maneuver_trim_time_constant_s;  // its rates' low-pass, with maneuver_trim
  std::optional<bool> maneuver_trim_accel;     // its acceleration part (on in the core), with maneuver_trim
  std::optional<bool> maneuver_trim_inertial;  // its rates from inertial_flight_path.h, with maneuver_trim
  std::optional<double> maneuver_trim_blend_s; // that filter's blend time constant, with maneuver_trim
  std::optional<double> maneuver_trim_accel_airspeed_rad_s;  // w0 of the airspeed's acceleration, with maneuver_trim
  std::optional<bool> maneuver_trim_gamma_load_factor;       // the load factor's climb angle, with maneuver_trim
  std::optional<double> start_up_s;  // filter_bank.h: updates that weigh nothing after a start; unset: the bank's
  // actuator_limits.h: one value per input (rad/s, rad); both empty = off
  std::vector<double> actuator_rate_limits_rad_s, actuator_position_limits_rad;
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
