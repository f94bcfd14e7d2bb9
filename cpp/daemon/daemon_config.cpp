#include "daemon_config.h"

#include "f16mmae/declarer.h"
#include "f16mmae/estimator_settings.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <optional>
#include <sstream>
#include <utility>

namespace f16mmae::daemon {

std::string daemon_usage() {
  return "usage: mmae-daemon --bank FILE [--turbulence-banks] [--lcm-url URL] [--channel-prefix P]\n"
         "                   [--rate-hz HZ]\n"
         "                   [--p-min P] [--threshold T] [--dwell-s S] [--dwell-nats N] [--start-up-s S]\n"
         "                   [--adapt-turbulence] [--adapt-reference RHO] [--adapt-own-channels]\n"
         "                   [--adapt-reference-climb RHO]\n"
         "                   [--adapt-reference-climb-hold S] [--adapt-reference-climb-dwell S]\n"
         "                   [--adapt-channel-weight G]\n"
         "                   [--set-tempering W] [--set-tempering-full NAME,...] [--set-tempering-rho RHO]\n"
         "                   [--set-tempering-own-fit] [--set-tempering-burst C]\n"
         "                   [--maneuver-dwell S] [--maneuver-dwell-hold S] [--maneuver-dwell-g G]\n"
         "                   [--maneuver-dwell-time-constant TAU_S] [--maneuver-reference RHO]\n"
         "                   [--maneuver-mach-rate MACH_PER_S]\n"
         "                   [--level1-p-min P] [--level1-dwell-s S] [--level1-allowance K]\n"
         "                   [--departure-hold on|off] [--declare-components] [--partial-p-min P]\n"
         "                   [--trim-tracking TAU_S] [--trim-freeze-probability P] [--trim-tracking-steady G]\n"
         "                   [--trim-tracking-load-factor on|off]\n"
         "                   [--schedule-mode interpolate|nearest] [--air-data-time-constant TAU_S]\n"
         "                   [--maneuver-kinematics] [--maneuver-tempering G] [--maneuver-tempering-deadband D]\n"
         "                   [--maneuver-trim] [--maneuver-trim-time-constant T_S] [--maneuver-trim-accel on|off]\n"
         "                   [--maneuver-trim-rates air|inertial] [--maneuver-trim-blend T_S]\n"
         "                   [--actuator-rate-limits R1,...,R5[,inf]]\n"
         "                   [--actuator-position-limits L1,...,L5[,inf]]\n"
         "                   [--max-frames N] [--realtime PRIORITY] [--warm-lead-us US]\n"
         "                   [--rewarm-us US] [--auth-key FILE] [--bank-public-key FILE] [--quiet]\n"
         "\n"
         "The MMAE executive of f16mmae: steps the hierarchical bank of FILE once per sensor\n"
         "frame received over LCM and publishes the hypothesis probabilities and z_hat.\n"
         "\n"
         "  --bank FILE          model-bank file (f16mmae design --out FILE), validated on load;\n"
         "                       or a turbulence bank set file (f16mmae design --turbulence-banks\n"
         "                       --out FILE), whose start member runs alone without the next flag\n"
         "  --turbulence-banks   fly the turbulence bank set of --bank FILE: one member in force,\n"
         "                       chosen on line by its measured turbulence intensity (the status\n"
         "                       carries the set's hash)\n"
         "  --lcm-url URL        LCM provider (default $LCM_DEFAULT_URL, else\n"
         "                       udpm://239.255.76.67:7667?ttl=0)\n"
         "  --channel-prefix P   prepended to F16_SENSORS, F16_COMMANDS, MMAE_STATUS, MMAE_RESET\n"
         "  --rate-hz HZ         frame rate; must equal the bank's design rate (default 64)\n"
         "  --p-min P            probability floor     } default: the bank's recommendation\n"
         "  --threshold T        declaration threshold } (its typed fields p_min, threshold,\n"
         "  --dwell-s S          declaration dwell, s  } dwell_s) -- as 'f16mmae run'\n"
         "  --dwell-nats N       ... or until the candidate's log-odds above the threshold's,\n"
         "                       summed over those frames, reach N nats (declarer.h; 0-1e6;\n"
         "                       given, for every hypothesis; default: the bank's N_k)\n"
         "  --dwell-nats-per-hypothesis FILE  ... per hypothesis: 'NAME N' lines, N nats for\n"
         "                       NAME (0: the dwell alone); others take --dwell-nats (declarer.h;\n"
         "                       default: the bank's own N_k, its hypotheses' dwell_nats)\n"
         "  --start-up-s S       the first S seconds of frames after a start or reset update\n"
         "                       the filters but weigh no hypothesis (0-3600; default: the\n"
         "                       bank's recommendation, a scheduled-bank file's start_up_s, else 0)\n"
         "  --adapt-turbulence   scale the likelihoods on line to the turbulence intensity\n"
         "                       (default off: the bank as designed)\n"
         "  --adapt-reference RHO  with --adapt-turbulence: the residual power ratio above which\n"
         "                       the likelihoods are tempered (0-100; default: a scheduled\n"
         "                       bank's per-node references where it carries them, else 0.6)\n"
         "  --adapt-own-channels  with --adapt-turbulence: each filter's residual power counts per\n"
         "                       channel it reads, so a hypothesis whose failed sensor's channel is\n"
         "                       uninformative does not read the air calmer than it is (default off;\n"
         "                       a turbulence bank set's members always run with it)\n"
         "  --adapt-counted-channel NAME  with --adapt-own-channels: the failed NAME's uninformative\n"
         "                       channel still counts in each filter's channel count (vel, aoa, pit,\n"
         "                       az, rol, yaw, ay; 'f16mmae hil' gives vel with a scheduled bank's\n"
         "                       --adapt-turbulence, its default in process)\n"
         "  --adapt-reference-climb RHO  with --adapt-turbulence: the reference while the air\n"
         "                       data climb or descend faster than 300 ft/min or change Mach faster\n"
         "                       than 0.001/s (0-100; default: off, the reference above everywhere)\n"
         "  --adapt-reference-climb-hold S  with --adapt-reference-climb: keep it S s after the\n"
         "                       climb or speed change ends (0-3600; default 0)\n"
         "  --adapt-reference-climb-dwell S  with --adapt-reference-climb: a level-0 declaration\n"
         "                       while that reference is in force (the climb, descent or speed\n"
         "                       change and its hold) needs S s above the threshold instead of\n"
         "                       the dwell (0-60; default 0: the dwell everywhere)\n"
         "  --adapt-channel-weight G  with --adapt-turbulence or --turbulence-banks: temper each\n"
         "                       channel by s^(1-G) s_j^G, s_j its own scale (0-1; default 0: one\n"
         "                       scale common to all)\n"
         "  --set-tempering W    with --turbulence-banks: each frame the best-fitting failure\n"
         "                       hypothesis at level 0 has its evidence against NONE tempered by\n"
         "                       1 + W (s - 1) in place of the adaptation's s (0 < W <= 1; default 1: off)\n"
         "  --set-tempering-full NAME,...  with --set-tempering: the hypotheses kept at the full s\n"
         "                       (names of the bank's level-0 hypotheses; 'f16mmae hil' gives LS,RS,LF,RF)\n"
         "  --set-tempering-rho RHO  with --set-tempering: only while the member's measured rho is\n"
         "                       at least RHO (0-100; default 0: at any rho)\n"
         "  --set-tempering-own-fit  with --set-tempering: the spared hypothesis is the one of least\n"
         "                       residual form per channel it reads (default: least form)\n"
         "  --set-tempering-burst C  with --set-tempering: only while the residual power over the\n"
         "                       last quarter second is at most C times the member's rho (1-100;\n"
         "                       default off)\n"
         "  --maneuver-dwell S   a level-0 declaration needs S s above the threshold while the\n"
         "                       aircraft maneuvers (the estimated load factor, low-passed, off\n"
         "                       the trim by more than --maneuver-dwell-g, or the air data climb\n"
         "                       or change Mach) and for --maneuver-dwell-hold after; elsewhere\n"
         "                       the dwell (0-60; default 0: the dwell everywhere)\n"
         "  --maneuver-dwell-hold S  with --maneuver-dwell: its hold after a maneuver (0-3600; default 0)\n"
         "  --maneuver-dwell-g G  with --maneuver-dwell: the load-factor gate, g (> 0, <= 10; default 0.1)\n"
         "  --maneuver-dwell-time-constant TAU_S  with --maneuver-dwell: the load factor's low-pass\n"
         "                       (s, 0-60; 0: none; default 2)\n"
         "  --maneuver-reference RHO  with --adapt-turbulence: the adaptation's reference while\n"
         "                       the aircraft maneuvers (that gate), unless the climb reference is\n"
         "                       in force (0-100; default: off)\n"
         "  --maneuver-mach-rate MACH_PER_S  the air data's Mach changing faster than this, per s,\n"
         "                       opens the gates of --maneuver-dwell and --adapt-reference-climb\n"
         "                       (air_data_rates.h; > 0, <= 1; default 0.001)\n"
         "  --level1-p-min P     the floor while a failure's level-1 (dual) bank is on line\n"
         "                       (>= 0, below (1 - threshold)/12; default 0: the level-0 floor)\n"
         "  --level1-dwell-s S   the dwell while it is on line (0-60; default 0: the dwell)\n"
         "  --level1-allowance K  the duals' drift allowance while it is on line: each dual's\n"
         "                       log-odds against the failure drift down K nats a frame unless\n"
         "                       its evidence outgrows it (0-5; default 0: none)\n"
         "  --departure-hold on|off  level 1: declare nothing while the measurements leave the\n"
         "                       linearization, nor 1 s after (default on)\n"
         "  --trim-tracking TAU_S  track the trim on line with time constant TAU_S s (e.g. 30),\n"
         "                       frozen while a failure hypothesis rises or is declared\n"
         "  --trim-freeze-probability P  with --trim-tracking: a failure hypothesis above P\n"
         "                       freezes the trim estimate (0 < P <= 1; default 0.05)\n"
         "  --trim-tracking-steady G  with --trim-tracking: track only in steady level flight,\n"
         "                       frozen while the estimated load factor is more than G g off the\n"
         "                       trim, the roll rate above 5 deg/s or the air data climb or change\n"
         "                       Mach; of the measurements only AOA (0 < G <= 10; default: off)\n"
         "  --trim-tracking-load-factor on|off  with --trim-tracking-steady: on applies the\n"
         "                       tracked AOA offset as n times the 1-g offset, n the measured AZ\n"
         "                       low-passed (a lighter aircraft's alpha offset grows with the\n"
         "                       load factor; default off)\n"
         "  --schedule-mode M    a scheduled bank (*.f16sched): interpolate between grid points\n"
         "                       on the frames' air data (default) or nearest (switch with\n"
         "                       hysteresis)\n"
         "  --air-data-time-constant TAU_S  a scheduled bank: the time constant of the air\n"
         "                       data's low-pass the schedule follows (s, 0-60; a running mean\n"
         "                       for its first TAU_S; 0: none; default: the core's, 2)\n"
         "  --maneuver-kinematics  add the turn kinematics and gravity terms the wings-level\n"
         "                       linearization drops to every filter's propagation\n"
         "  --maneuver-tempering G  divide every likelihood by 1 + (dn/G)^2, dn the estimated\n"
         "                       load factor off trim, g (> 0; default: off, with\n"
         "                       --turbulence-banks the set file's recommended tempering)\n"
         "  --maneuver-tempering-deadband D  with --maneuver-tempering: only the load factor\n"
         "                       beyond D g tempers (0-10; default 0: no dead band)\n"
         "  --maneuver-trim      the filters' trim follows the climb and acceleration the air data\n"
         "                       show (each node's climb and acceleration trim offsets)\n"
         "  --maneuver-trim-time-constant T_S  with --maneuver-trim: the rates' low-passes, T_S\n"
         "                       and 5 T_S s (0.05-60; default 0.5)\n"
         "  --maneuver-trim-accel on|off  with --maneuver-trim: off keeps the climb's trim only\n"
         "                       (default on)\n"
         "  --maneuver-trim-rates air|inertial  with --maneuver-trim: the climb angle and\n"
         "                       acceleration from the air data (default) or from the rate gyros,\n"
         "                       AOA and VEL against the air data (inertial_flight_path.h)\n"
         "  --maneuver-trim-blend T_S  with --maneuver-trim: the inertial rates' blend time\n"
         "                       constant (0.05-600; default 2)\n"
         "  --declare-components  a bank with partial-loss hypotheses: declare a surface's forms\n"
         "                       (complete and partial) as one component, naming the heavier form\n"
         "                       (declarer.h; default: each hypothesis alone)\n"
         "  --partial-p-min P    such a bank: its partial hypotheses' floor at level 0, the others\n"
         "                       keeping theirs (0-0.1; the core refuses a floor that leaves no\n"
         "                       room for a declaration; default 0: the level-0 floor)\n"
         "  --actuator-rate-limits R1,...,R5 and --actuator-position-limits L1,...,L5\n"
         "                       the actuators' rate (rad/s) and position (rad) limits, one per\n"
         "                       input, applied to the commands the filters see (both or none;\n"
         "                       inf for both: an input without actuator, e.g. the throttle);\n"
         "                       these on-line options as 'f16mmae run' has them (f16mmae hil\n"
         "                       --start-daemon passes its own on)\n"
         "  --max-frames N       exit after publishing N status frames (default: until signalled)\n"
         "  --realtime PRIORITY  run SCHED_FIFO at PRIORITY (1-99) with memory locked (needs\n"
         "                       CAP_SYS_NICE / root; a warning, not an error, without it)\n"
         "  --warm-lead-us US    wake US microseconds before the next sensor frame is due (one\n"
         "                       period after the last) and touch the estimator's working set,\n"
         "                       so the step runs from cache after the idle time (default 500;\n"
         "                       0: off)\n"
         "  --rewarm-us US       after that warm-up, warm up again every US microseconds until the\n"
         "                       frame arrives (at most --warm-lead-us past its due time), so\n"
         "                       the caches stay warm however the frame jitters (default 100;\n"
         "                       0: one warm-up per frame)\n"
         "  --auth-key FILE      accept only frames, commands and resets signed with the key in\n"
         "                       FILE (16-64 bytes, e.g. head -c 32 /dev/urandom > FILE), each\n"
         "                       with a sequence above the last; sign every status with it.\n"
         "                       Without it the daemon obeys any sender that reaches the URL\n"
         "  --bank-public-key FILE  load the bank only if FILE.sig beside it is an Ed25519\n"
         "                       signature of its bytes by this public key (32 bytes; see\n"
         "                       docs/INTERFACES.md: f16mmae.core.sign_bank_file)\n"
         "  --quiet              do not print the ready line\n"
         "\n"
         "SIGINT or SIGTERM ends it with a summary line (messages by fate, step time p50/p99/max)\n"
         "and the same as one JSON line, 'mmae-daemon: statistics {...}'. Exit status 0 on a clean end, 1 if the bank or the LCM URL\n"
         "cannot be used, 2 on a usage error.\n";
}

namespace {

// `text` as a finite number, or nothing (empty, trailing characters, out of range, inf, nan).
std::optional<double> finite_number(const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno != 0 || !std::isfinite(x)) return std::nullopt;
  return x;
}

ParseResult usage_error(const std::string& what) {
  ParseResult r;
  r.exit_code = 2;
  r.message = "mmae-daemon: error: " + what + "\n(run 'mmae-daemon --help' for the options)";
  return r;
}

}  // namespace

ParseResult parse_daemon_args(const std::vector<std::string>& args, const char* default_url) {
  DaemonConfig c;
  bool have_bank = false, have_url = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "-h" || a == "--help") {
      ParseResult r;
      r.message = daemon_usage();
      return r;
    }
    if (a == "--quiet") {
      c.quiet = true;
      continue;
    }
    if (a == "--adapt-turbulence") {
      c.adapt_turbulence = true;
      continue;
    }
    if (a == "--adapt-own-channels") {
      c.adapt_own_channels = true;
      continue;
    }
    if (a == "--turbulence-banks") {
      c.turbulence_banks = true;
      continue;
    }
    if (a == "--maneuver-kinematics") {
      c.maneuver_kinematics = true;
      continue;
    }
    if (a == "--maneuver-trim") {
      c.maneuver_trim = true;
      continue;
    }
    if (a == "--declare-components") {
      c.declare_components = true;
      continue;
    }
    if (a == "--set-tempering-own-fit") {
      c.set_tempering_own_fit = true;
      continue;
    }
    std::string key = a, value;
    bool inline_value = false;
    if (a.rfind("--", 0) == 0) {
      const auto eq = a.find('=');
      if (eq != std::string::npos) {
        key = a.substr(0, eq);
        value = a.substr(eq + 1);
        inline_value = true;
      }
    }
    const bool known = key == "--bank" || key == "--lcm-url" || key == "--channel-prefix" ||
                       key == "--rate-hz" || key == "--max-frames" || key == "--realtime" ||
                       key == "--p-min" || key == "--threshold" || key == "--dwell-s" || key == "--dwell-nats" ||
                       key == "--dwell-nats-per-hypothesis" || key == "--warm-lead-us" || key == "--rewarm-us" || key == "--auth-key" ||
                       key == "--bank-public-key" || key == "--trim-tracking" ||
                       key == "--trim-freeze-probability" || key == "--trim-tracking-steady" ||
                       key == "--trim-tracking-load-factor" ||
                       key == "--schedule-mode" || key == "--adapt-reference" ||
                       key == "--adapt-reference-climb" || key == "--adapt-reference-climb-hold" ||
                       key == "--adapt-reference-climb-dwell" ||
                       key == "--maneuver-tempering" || key == "--actuator-rate-limits" ||
                       key == "--actuator-position-limits" || key == "--start-up-s" ||
                       key == "--air-data-time-constant" || key == "--adapt-channel-weight" ||
                       key == "--maneuver-dwell" || key == "--maneuver-dwell-hold" || key == "--maneuver-dwell-g" ||
                       key == "--maneuver-dwell-time-constant" || key == "--maneuver-reference" ||
                       key == "--maneuver-mach-rate" || key == "--maneuver-tempering-deadband" || key == "--level1-p-min" ||
                       key == "--level1-dwell-s" || key == "--level1-allowance" || key == "--partial-p-min" ||
                       key == "--departure-hold" ||
                       key == "--maneuver-trim-time-constant" || key == "--maneuver-trim-accel" ||
                       key == "--maneuver-trim-rates" || key == "--maneuver-trim-blend" ||
                       key == "--adapt-counted-channel" || key == "--set-tempering" || key == "--set-tempering-full" ||
                       key == "--set-tempering-rho" || key == "--set-tempering-burst";
    if (!known)
      return usage_error("unknown argument '" + a +
                         "'; valid options: --bank, --lcm-url, --channel-prefix, --rate-hz, "
                         "--p-min, --threshold, --dwell-s, --dwell-nats, --dwell-nats-per-hypothesis, --start-up-s, --max-frames, --realtime, --warm-lead-us, --rewarm-us, "
                         "--auth-key, --bank-public-key, --adapt-turbulence, --adapt-reference, --adapt-own-channels, "
                         "--adapt-counted-channel, --adapt-reference-climb, "
                         "--adapt-reference-climb-hold, --adapt-reference-climb-dwell, --adapt-channel-weight, --turbulence-banks, "
                         "--set-tempering, --set-tempering-full, --set-tempering-rho, --set-tempering-own-fit, --set-tempering-burst, "
                         "--maneuver-dwell, --maneuver-dwell-hold, --maneuver-dwell-g, --maneuver-dwell-time-constant, "
                         "--maneuver-reference, --maneuver-mach-rate, --maneuver-tempering-deadband, --level1-p-min, --level1-dwell-s, "
                         "--level1-allowance, --departure-hold, --declare-components, --partial-p-min, --trim-tracking, "
                         "--trim-freeze-probability, --trim-tracking-steady, --trim-tracking-load-factor, --schedule-mode, --air-data-time-constant, --maneuver-kinematics, "
                         "--maneuver-tempering, --maneuver-trim, --maneuver-trim-time-constant, --maneuver-trim-accel, --maneuver-trim-rates, --maneuver-trim-blend, --actuator-rate-limits, --actuator-position-limits, --quiet, --help");
    if (!inline_value) {
      if (i + 1 >= args.size()) return usage_error(key + " needs a value");
      value = args[++i];
    }
    if (key == "--bank") {
      if (value.empty()) return usage_error("--bank needs a file name, got ''");
      c.bank_path = value;
      have_bank = true;
    } else if (key == "--lcm-url") {
      if (value.empty()) return usage_error("--lcm-url needs a URL such as memq:// or udpm://239.255.76.67:7667?ttl=0");
      c.lcm_url = value;
      have_url = true;
    } else if (key == "--bank-public-key") {
      if (value.empty()) return usage_error("--bank-public-key needs a key file name, got ''");
      c.bank_public_key_path = value;
    } else if (key == "--dwell-nats-per-hypothesis") {
      if (value.empty()) return usage_error("--dwell-nats-per-hypothesis needs a table file name, got ''");
      c.dwell_nats_table_path = value;
    } else if (key == "--auth-key") {
      if (value.empty()) return usage_error("--auth-key needs a key file name, got ''");
      c.auth_key_path = value;
    } else if (key == "--channel-prefix") {
      c.channel_prefix = value;
    } else if (key == "--rate-hz") {
      const std::optional<double> hz = finite_number(value);
      if (!hz || *hz <= 0.0)
        return usage_error("--rate-hz must be a positive number of frames per second, got '" + value + "'");
      c.rate_hz = *hz;
    } else if (key == "--p-min" || key == "--threshold" || key == "--dwell-s") {
      const std::optional<double> x = finite_number(value);
      if (!x || *x < 0.0)
        return usage_error(key + " must be a finite number >= 0, got '" + value + "'");
      (key == "--p-min" ? c.p_min : key == "--threshold" ? c.threshold : c.dwell_s) = *x;
    } else if (key == "--dwell-nats") {
      const std::optional<double> n = finite_number(value);
      if (!n || *n < 0.0 || *n > f16mmae::kMaxDwellNats)
        return usage_error("--dwell-nats must be a number of nats in [0, " + f16mmae::format_value(f16mmae::kMaxDwellNats) +
                           "] (0: the dwell alone), got '" + value + "'");
      c.dwell_nats = *n;
    } else if (key == "--start-up-s") {
      const std::optional<double> s = finite_number(value);
      if (!s || *s < 0.0 || *s > 3600.0)
        return usage_error("--start-up-s must be a time in seconds in [0, 3600], got '" + value + "'");
      c.start_up_s = *s;
    } else if (key == "--trim-tracking") {
      const std::optional<double> tau = finite_number(value);
      if (!tau || *tau <= 0.0 || *tau > 1e6)
        return usage_error("--trim-tracking must be a time constant in seconds, > 0 and <= 1e6, got '" + value + "'");
      c.trim_time_constant_s = *tau;
    } else if (key == "--trim-freeze-probability") {
      const std::optional<double> p = finite_number(value);
      if (!p || !(*p > 0.0 && *p <= 1.0))
        return usage_error("--trim-freeze-probability must lie in (0, 1], got '" + value + "'");
      c.trim_freeze_probability = *p;
    } else if (key == "--trim-tracking-steady") {
      const std::optional<double> g = finite_number(value);
      if (!g || !(*g > 0.0 && *g <= 10.0))
        return usage_error("--trim-tracking-steady must be a load factor in g, > 0 and <= 10, got '" + value + "'");
      c.trim_steady_g = *g;
    } else if (key == "--adapt-reference") {
      const std::optional<double> rho = finite_number(value);
      if (!rho || *rho < 0.0 || *rho > 100.0)
        return usage_error("--adapt-reference must be a power ratio in [0, 100], got '" + value + "'");
      c.adapt_reference = *rho;
    } else if (key == "--adapt-reference-climb") {
      const std::optional<double> rho = finite_number(value);
      if (!rho || *rho < 0.0 || *rho > 100.0)
        return usage_error("--adapt-reference-climb must be a power ratio in [0, 100], got '" + value + "'");
      c.adapt_reference_climb = *rho;
    } else if (key == "--adapt-reference-climb-hold") {
      const std::optional<double> hold = finite_number(value);
      if (!hold || *hold < 0.0 || *hold > 3600.0)
        return usage_error("--adapt-reference-climb-hold must be a time in seconds in [0, 3600], got '" + value + "'");
      c.adapt_reference_climb_hold_s = *hold;
    } else if (key == "--adapt-reference-climb-dwell") {
      const std::optional<double> dwell = finite_number(value);
      if (!dwell || *dwell < 0.0 || *dwell > f16mmae::kMaxDwellS)
        return usage_error("--adapt-reference-climb-dwell must be a time in seconds in [0, " +
                           f16mmae::format_value(f16mmae::kMaxDwellS) + "] (0: the dwell), got '" + value + "'");
      c.adapt_reference_climb_dwell_s = *dwell;
    } else if (key == "--adapt-channel-weight") {
      const std::optional<double> w = finite_number(value);
      if (!w || *w < 0.0 || *w > 1.0)
        return usage_error("--adapt-channel-weight must be a weight in [0, 1], got '" + value + "'");
      c.adapt_channel_weight = *w;
    } else if (key == "--set-tempering") {
      const std::optional<double> w = finite_number(value);
      if (!w || *w <= 0.0 || *w > 1.0)
        return usage_error("--set-tempering must be a weight in (0, 1], got '" + value + "'");
      c.set_tempering = *w;
    } else if (key == "--set-tempering-rho") {
      const std::optional<double> rho = finite_number(value);
      if (!rho || *rho < 0.0 || *rho > 100.0)
        return usage_error("--set-tempering-rho must be a power ratio in [0, 100], got '" + value + "'");
      c.set_tempering_rho = *rho;
    } else if (key == "--set-tempering-burst") {
      const std::optional<double> ratio = finite_number(value);
      if (!ratio || *ratio < 1.0 || *ratio > 100.0)
        return usage_error("--set-tempering-burst must be a ratio in [1, 100], got '" + value + "'");
      c.set_tempering_burst = *ratio;
    } else if (key == "--set-tempering-full") {
      c.set_tempering_full.clear();
      std::string name;
      for (std::size_t k = 0; k <= value.size(); ++k) {
        if (k == value.size() || value[k] == ',') {
          if (name.empty())
            return usage_error("--set-tempering-full must be hypothesis names separated by commas, got '" + value + "'");
          c.set_tempering_full.push_back(name);
          name.clear();
        } else {
          name += static_cast<char>(std::toupper(static_cast<unsigned char>(value[k])));
        }
      }
    } else if (key == "--maneuver-dwell" || key == "--level1-dwell-s") {
      const std::optional<double> dwell = finite_number(value);
      if (!dwell || *dwell < 0.0 || *dwell > f16mmae::kMaxDwellS)
        return usage_error(key + " must be a time in seconds in [0, " + f16mmae::format_value(f16mmae::kMaxDwellS) +
                           "] (0: the dwell), got '" + value + "'");
      (key == "--maneuver-dwell" ? c.maneuver_dwell_s : c.level1_dwell_s) = *dwell;
    } else if (key == "--maneuver-dwell-hold") {
      const std::optional<double> hold = finite_number(value);
      if (!hold || *hold < 0.0 || *hold > 3600.0)
        return usage_error("--maneuver-dwell-hold must be a time in seconds in [0, 3600], got '" + value + "'");
      c.maneuver_dwell_hold_s = *hold;
    } else if (key == "--maneuver-dwell-g") {
      const std::optional<double> g = finite_number(value);
      if (!g || *g <= 0.0 || *g > 10.0)
        return usage_error("--maneuver-dwell-g must be a load factor in g, > 0 and <= 10, got '" + value + "'");
      c.maneuver_dwell_g = *g;
    } else if (key == "--maneuver-dwell-time-constant") {
      const std::optional<double> tau = finite_number(value);
      if (!tau || *tau < 0.0 || *tau > 60.0)
        return usage_error("--maneuver-dwell-time-constant must be a time constant in seconds in [0, 60] (0: no "
                           "low-pass), got '" + value + "'");
      c.maneuver_dwell_time_constant_s = *tau;
    } else if (key == "--maneuver-trim-accel") {
      if (value != "on" && value != "off")
        return usage_error("--maneuver-trim-accel must be 'on' or 'off', got '" + value + "'");
      c.maneuver_trim_accel = value == "on";
    } else if (key == "--maneuver-trim-rates") {
      if (value != "air" && value != "inertial")
        return usage_error("--maneuver-trim-rates must be 'air' or 'inertial', got '" + value + "'");
      c.maneuver_trim_inertial = value == "inertial";
    } else if (key == "--maneuver-trim-blend") {
      const std::optional<double> tau = finite_number(value);
      if (!tau || *tau < 0.05 || *tau > 600.0)
        return usage_error("--maneuver-trim-blend must be a time constant in seconds in [0.05, 600], got '" + value +
                           "'");
      c.maneuver_trim_blend_s = *tau;
    } else if (key == "--maneuver-trim-time-constant") {
      const std::optional<double> tau = finite_number(value);
      if (!tau || *tau < 0.05 || *tau > 60.0)
        return usage_error("--maneuver-trim-time-constant must be a time constant in seconds in [0.05, 60], got '" +
                           value + "'");
      c.maneuver_trim_time_constant_s = *tau;
    } else if (key == "--maneuver-reference") {
      const std::optional<double> rho = finite_number(value);
      if (!rho || *rho < 0.0 || *rho > 100.0)
        return usage_error("--maneuver-reference must be a power ratio in [0, 100], got '" + value + "'");
      c.maneuver_reference = *rho;
    } else if (key == "--maneuver-mach-rate") {
      const std::optional<double> rate = finite_number(value);
      if (!rate || *rate <= 0.0 || *rate > 1.0)
        return usage_error("--maneuver-mach-rate must be a Mach rate per second, > 0 and <= 1, got '" + value + "'");
      c.maneuver_mach_per_s = *rate;
    } else if (key == "--maneuver-tempering-deadband") {
      const std::optional<double> d = finite_number(value);
      if (!d || *d < 0.0 || *d > 10.0)
        return usage_error("--maneuver-tempering-deadband must be a load factor in g in [0, 10], got '" + value + "'");
      c.maneuver_tempering_deadband_g = *d;
    } else if (key == "--level1-p-min") {
      const std::optional<double> p = finite_number(value);
      // the bound (1 - threshold)/(K - 1) depends on the threshold and the bank: the core checks it
      if (!p || *p < 0.0 || *p >= 1.0)
        return usage_error("--level1-p-min must be a probability in [0, 1) (and below (1 - threshold)/12 for the "
                           "F-16 bank), got '" + value + "'");
      c.level1_p_min = *p;
    } else if (key == "--level1-allowance") {
      const std::optional<double> k = finite_number(value);
      if (!k || *k < 0.0 || *k > 5.0)
        return usage_error("--level1-allowance must be a number of nats a frame in [0, 5], got '" + value + "'");
      c.level1_allowance = *k;
    } else if (key == "--partial-p-min") {
      const std::optional<double> p = finite_number(value);
      // the bound that leaves room for a declaration depends on the bank: the core checks it
      if (!p || *p < 0.0 || *p > 0.1)
        return usage_error("--partial-p-min must be a probability in [0, 0.1], got '" + value + "'");
      c.partial_p_min = *p;
    } else if (key == "--trim-tracking-load-factor") {
      if (value != "on" && value != "off")
        return usage_error("--trim-tracking-load-factor must be on or off, got '" + value + "'");
      c.trim_load_factor = value == "on";
    } else if (key == "--departure-hold") {
      if (value != "on" && value != "off")
        return usage_error("--departure-hold must be on or off, got '" + value + "'");
      c.departure_hold = value == "on";
    } else if (key == "--adapt-counted-channel") {
      static const char* const kSensors[] = {"vel", "aoa", "pit", "az", "rol", "yaw", "ay"};
      std::string lower = value;
      for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
      if (std::find(std::begin(kSensors), std::end(kSensors), lower) == std::end(kSensors))
        return usage_error("--adapt-counted-channel must name a measurement (vel, aoa, pit, az, rol, yaw, ay), got '" +
                           value + "'");
      c.adapt_counted_channel = lower;
    } else if (key == "--schedule-mode") {
      if (value != "interpolate" && value != "nearest")
        return usage_error("--schedule-mode must be interpolate or nearest, got '" + value + "'");
      c.schedule_nearest = value == "nearest";
    } else if (key == "--air-data-time-constant") {
      const std::optional<double> tau = finite_number(value);
      if (!tau || *tau < 0.0 || *tau > 60.0)
        return usage_error("--air-data-time-constant must be a time constant in seconds in [0, 60] (0: no "
                           "low-pass), got '" + value + "'");
      c.air_data_time_constant_s = *tau;
    } else if (key == "--maneuver-tempering") {
      const std::optional<double> g = finite_number(value);
      if (!g || *g <= 0.0 || *g > 100.0)
        return usage_error("--maneuver-tempering must be a load factor in g, > 0 and <= 100, got '" + value + "'");
      c.maneuver_tempering_g = *g;
    } else if (key == "--actuator-rate-limits" || key == "--actuator-position-limits") {
      std::vector<double> limits;
      std::size_t start = 0;
      while (true) {
        const std::size_t comma = value.find(',', start);
        const std::string item = value.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        // "inf": an input without actuator (the throttle; actuator_limits.h)
        const std::optional<double> x =
            item == "inf" ? std::optional<double>(std::numeric_limits<double>::infinity()) : finite_number(item);
        if (!x || *x <= 0.0)
          return usage_error(key + " must be positive numbers separated by commas (" +
                             (key == "--actuator-rate-limits" ? "rad/s" : "rad") +
                             ", one per input; inf for an input without actuator), got '" + value + "'");
        limits.push_back(*x);
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
      (key == "--actuator-rate-limits" ? c.actuator_rate_limits_rad_s : c.actuator_position_limits_rad) = limits;
    } else if (key == "--max-frames") {
      errno = 0;
      char* end = nullptr;
      const long long n = std::strtoll(value.c_str(), &end, 10);
      if (value.empty() || *end != '\0' || errno != 0 || n < 0)
        return usage_error("--max-frames must be a whole number >= 0, got '" + value + "'");
      c.max_frames = n;
    } else if (key == "--warm-lead-us" || key == "--rewarm-us") {
      const std::optional<double> us = finite_number(value);
      if (!us || *us < 0.0)
        return usage_error(key + " must be a number of microseconds >= 0 (0: " +
                           (key == "--rewarm-us" ? "one warm-up per frame" : "no warm-up") + "), got '" + value +
                           "'");
      (key == "--rewarm-us" ? c.rewarm_us : c.warm_lead_us) = *us;
    } else if (key == "--realtime") {
      errno = 0;
      char* end = nullptr;
      const long p = std::strtol(value.c_str(), &end, 10);
      if (value.empty() || *end != '\0' || errno != 0 || p < 1 || p > 99)
        return usage_error("--realtime must be a SCHED_FIFO priority from 1 to 99, got '" + value + "'");
      c.realtime_priority = static_cast<int>(p);
    }
  }
  if (!have_bank) return usage_error("--bank FILE is required (a model-bank file from 'f16mmae design')");
  if (c.trim_freeze_probability && c.trim_time_constant_s == 0.0)
    return usage_error("--trim-freeze-probability applies with --trim-tracking only");
  if (c.adapt_reference_climb && !c.adapt_turbulence)
    return usage_error("--adapt-reference-climb applies with --adapt-turbulence only");
  if (c.adapt_reference_climb_hold_s && !c.adapt_reference_climb)
    return usage_error("--adapt-reference-climb-hold applies with --adapt-reference-climb only");
  if (c.adapt_reference_climb_dwell_s && !c.adapt_reference_climb)
    return usage_error("--adapt-reference-climb-dwell applies with --adapt-reference-climb only");
  if ((c.maneuver_dwell_hold_s || c.maneuver_dwell_g || c.maneuver_dwell_time_constant_s) &&
      !(c.maneuver_dwell_s && *c.maneuver_dwell_s > 0.0))
    return usage_error(std::string(c.maneuver_dwell_hold_s ? "--maneuver-dwell-hold"
                                   : c.maneuver_dwell_g    ? "--maneuver-dwell-g"
                                                           : "--maneuver-dwell-time-constant") +
                       " applies with --maneuver-dwell S > 0 only");
  if (c.maneuver_trim_time_constant_s && !c.maneuver_trim)
    return usage_error("--maneuver-trim-time-constant applies with --maneuver-trim only");
  if (c.maneuver_trim_accel && !c.maneuver_trim)
    return usage_error("--maneuver-trim-accel applies with --maneuver-trim only");
  if (c.maneuver_trim_inertial && !c.maneuver_trim)
    return usage_error("--maneuver-trim-rates applies with --maneuver-trim only");
  if (c.maneuver_trim_blend_s && !c.maneuver_trim)
    return usage_error("--maneuver-trim-blend applies with --maneuver-trim only");
  if (c.maneuver_reference && !c.adapt_turbulence)
    return usage_error("--maneuver-reference applies with --adapt-turbulence only");
  if (c.maneuver_tempering_deadband_g && c.maneuver_tempering_g == 0.0)
    return usage_error("--maneuver-tempering-deadband applies with --maneuver-tempering only");
  if (c.trim_steady_g > 0.0 && c.trim_time_constant_s == 0.0)
    return usage_error("--trim-tracking-steady applies with --trim-tracking only");
  if (c.trim_load_factor && c.trim_steady_g == 0.0)
    return usage_error("--trim-tracking-load-factor applies with --trim-tracking-steady only");
  if (c.adapt_reference && !c.adapt_turbulence)
    return usage_error("--adapt-reference applies with --adapt-turbulence only");
  if (c.adapt_own_channels && !c.adapt_turbulence)
    return usage_error("--adapt-own-channels applies with --adapt-turbulence only");
  if (!c.adapt_counted_channel.empty() && !c.adapt_own_channels)
    return usage_error("--adapt-counted-channel applies with --adapt-own-channels only");
  if (c.set_tempering && !c.turbulence_banks)
    return usage_error("--set-tempering applies with --turbulence-banks only");
  if (!c.set_tempering &&
      (!c.set_tempering_full.empty() || c.set_tempering_rho || c.set_tempering_own_fit || c.set_tempering_burst))
    return usage_error("--set-tempering-full, --set-tempering-rho, --set-tempering-own-fit and --set-tempering-burst "
                       "apply with --set-tempering only");
  if (c.actuator_rate_limits_rad_s.size() != c.actuator_position_limits_rad.size())
    return usage_error("--actuator-rate-limits and --actuator-position-limits go together, one value per input each "
                       "(got " + std::to_string(c.actuator_rate_limits_rad_s.size()) + " and " +
                       std::to_string(c.actuator_position_limits_rad.size()) + ")");
  for (const auto& [name, us] : {std::pair<const char*, double>{"--warm-lead-us", c.warm_lead_us},
                                  std::pair<const char*, double>{"--rewarm-us", c.rewarm_us}}) {
    if (us * 1e-6 * c.rate_hz >= 1.0) {
      std::ostringstream s;
      s << name << " " << us << " must be shorter than a frame period (" << 1e6 / c.rate_hz << " us at --rate-hz "
        << c.rate_hz << ")";
      return usage_error(s.str());
    }
  }
  if (!have_url) c.lcm_url = (default_url && *default_url) ? default_url : kDefaultLcmUrl;
  ParseResult r;
  r.ok = true;
  r.config = c;
  return r;
}

}  // namespace f16mmae::daemon
