#include "daemon_config.h"

#include "f16mmae/calm_air_complete.h"
#include "f16mmae/declarer.h"
#include "f16mmae/estimator_settings.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <set>
#include <sstream>
#include <utility>

namespace f16mmae::daemon {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// The F-16 bank's hypotheses at level 0: the floors' ranges here are the harness's
// (loop/estimator_options.py); the core checks each floor against the bank it loads.
constexpr int kF16Hypotheses = 13;

// A flag's setter: applies the value to the config, or returns why the value is refused ("must be
// a probability in [0, 1]"); the parser prefixes the flag and appends ", got 'VALUE'".
using Setter = std::function<std::string(DaemonConfig&, const std::string&)>;

// A value flag's setter and, for a number, its range as the help says it ("a power ratio in [0, 100]").
struct Value {
  Setter set;
  std::string range;
};

// A value the row's own function parses (names, lists, whole numbers).
Value parsed_by(Setter set) { return {std::move(set), ""}; }

// The field at a member path from the config, e.g. at(&C::estimator, &HierarchicalOptions::trim,
// &TrimTrackingOptions::steady_g): a callable giving the field's reference.
template <class... Member>
auto at(Member... path) {
  return [path...](DaemonConfig& c) -> decltype(auto) { return (c .* ... .* path); };
}

// One row of the flag table. A row without a name is a heading of the help. A switch has no
// metavar and sets `on`; a value flag has a metavar and its value. `with` names what the flag
// needs ("--trim-tracking"), `with_ok` tells whether the parsed config has it.
struct Flag {
  const char* name;
  const char* metavar;
  const char* help;
  Value value;
  std::function<bool&(DaemonConfig&)> on;   // a switch's field: a member pointer or at(...)
  const char* with = nullptr;
  bool (*with_ok)(const DaemonConfig&) = nullptr;
};

// `text` as a finite number, or nothing (empty, trailing characters, out of range, inf, nan).
std::optional<double> finite_number(const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno != 0 || !std::isfinite(x)) return std::nullopt;
  return x;
}

// `text` as a whole number in [lo, hi], or nothing.
std::optional<long long> whole_number(const std::string& text, long long lo, long long hi) {
  errno = 0;
  char* end = nullptr;
  const long long n = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno != 0 || n < lo || n > hi) return std::nullopt;
  return n;
}

// A finite number in the interval from lo to hi, each end closed or open; `what` says it to the
// user ("a time in seconds in [0, 60]"). Field: double or std::optional<double>.
struct Interval {
  double lo, hi;
  bool lo_open = false, hi_open = false;
  bool holds(double x) const { return (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi); }
};

// A number in the range, handed to `apply` (a row that sets more than one field).
Value number_applied(Interval range, std::string what, std::function<void(DaemonConfig&, double)> apply) {
  return {Setter([range, what, apply](DaemonConfig& c, const std::string& v) -> std::string {
            const std::optional<double> x = finite_number(v);
            if (!x || !range.holds(*x)) return "must be " + what;
            apply(c, *x);
            return "";
          }),
          what};
}

// Field (here and below): a member pointer of the config, or at(...).
template <class Field>
Value number(Field field, Interval range, std::string what) {
  return number_applied(range, std::move(what), [field](DaemonConfig& c, double x) { std::invoke(field, c) = x; });
}

// One of the named choices, each setting the field to its value; the refusal lists them.
template <class Field, class V>
Value choice(Field field, std::vector<std::pair<std::string, V>> choices) {
  std::string what;
  for (std::size_t i = 0; i < choices.size(); ++i)
    what += (i == 0 ? "'" : i + 1 == choices.size() ? " or '" : ", '") + choices[i].first + "'";
  return parsed_by([field, choices, what](DaemonConfig& c, const std::string& v) -> std::string {
    for (const auto& [name, value] : choices) {
      if (v == name) {
        std::invoke(field, c) = value;
        return "";
      }
    }
    return "must be " + what;
  });
}

template <class Field>
Value on_off(Field field) {
  return choice(field, std::vector<std::pair<std::string, bool>>{{"on", true}, {"off", false}});
}

// A non-empty text (a file name, a URL); `need` says what is missing ("needs a file name").
Value text(std::string DaemonConfig::*field, std::string need) {
  return parsed_by([field, need](DaemonConfig& c, const std::string& v) -> std::string {
    if (v.empty()) return need;
    c.*field = v;
    return "";
  });
}

// Positive numbers separated by commas, "inf" for an input without actuator (actuator_limits.h).
template <class Field>
Value limits(Field field, const char* unit) {
  return parsed_by([field, unit](DaemonConfig& c, const std::string& v) -> std::string {
    std::vector<double> values;
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = v.find(',', start);
      const std::string item = v.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      const std::optional<double> x = item == "inf" ? std::optional<double>(kInf) : finite_number(item);
      if (!x || *x <= 0.0)
        return std::string("must be positive numbers separated by commas (") + unit +
               ", one per input; inf for an input without actuator)";
      values.push_back(*x);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    std::invoke(field, c) = values;
    return "";
  });
}

// The F-16 bank's measurements, lower case (names.SENSORS).
constexpr const char* kSensors[] = {"vel", "aoa", "pit", "az", "rol", "yaw", "ay"};
bool is_sensor(const std::string& lower) {
  return std::find(std::begin(kSensors), std::end(kSensors), lower) != std::end(kSensors);
}

// `text` split at commas, each name upper-cased, or nothing (an empty name).
std::optional<std::vector<std::string>> upper_case_names(const std::string& text) {
  std::vector<std::string> names;
  std::string name;
  for (std::size_t k = 0; k <= text.size(); ++k) {
    if (k < text.size() && text[k] != ',') {
      name += static_cast<char>(std::toupper(static_cast<unsigned char>(text[k])));
      continue;
    }
    if (name.empty()) return std::nullopt;
    names.push_back(name);
    name.clear();
  }
  return names;
}

// A measurement's name, stored lower case, or the sentence refusing it.
Value sensor(std::string DaemonConfig::*field, bool none = false) {
  return parsed_by([field, none](DaemonConfig& c, const std::string& v) {
    std::string lower = v;
    for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (none && lower == "none") {   // no channel: the field stays empty
      c.*field = std::string();
      return std::string();
    }
    if (!is_sensor(lower))
      return std::string(none ? "must name a measurement (vel, aoa, pit, az, rol, yaw, ay) or none"
                              : "must name a measurement (vel, aoa, pit, az, rol, yaw, ay)");
    c.*field = lower;
    return std::string();
  });
}

// Hypothesis names separated by commas, upper-cased (the bank's level-0 hypotheses; main.cpp
// finds them in the bank).
Value hypothesis_names(std::vector<std::string> DaemonConfig::*field) {
  return parsed_by([field](DaemonConfig& c, const std::string& v) -> std::string {
    const std::optional<std::vector<std::string>> names = upper_case_names(v);
    if (!names) return "must be hypothesis names separated by commas";
    c.*field = *names;
    return "";
  });
}

bool adapting(const DaemonConfig& c) { return c.estimator.bank.adaptation.enabled; }
bool rough_floor(const DaemonConfig& c) { return c.estimator.rough_floor.enabled(); }
bool tracking_trim(const DaemonConfig& c) { return c.estimator.trim.time_constant_s > 0.0; }
bool climb_reference(const DaemonConfig& c) { return c.estimator.climb_reference.enabled(); }
bool maneuver_dwell(const DaemonConfig& c) { return c.estimator.maneuver_dwell.dwell_s > 0.0; }
bool rough_dwell(const DaemonConfig& c) { return !c.estimator.declarer.rough_dwell_s_per_hypothesis.empty(); }
bool maneuver_trim(const DaemonConfig& c) { return c.estimator.maneuver_trim.enabled; }
bool set_tempering(const DaemonConfig& c) { return c.set_tempering.has_value(); }
bool set_tempering_margin(const DaemonConfig& c) { return c.set_tempering_margin; }
bool set_tempering_rough(const DaemonConfig& c) { return c.set_tempering_rough.has_value(); }
bool turbulence_set(const DaemonConfig& c) { return c.turbulence_banks; }

// A least-dwell table "NAME=S,..." (declarer.h) into the declarer's `table`; the parser's
// "<table>: why" without its prefix.
Value least_dwell_table(std::map<std::string, double> DeclarerOptions::*table) {
  return parsed_by([table](DaemonConfig& c, const std::string& v) -> std::string {
    try {
      c.estimator.declarer.*table = parse_dwell_s_per_hypothesis(v);
    } catch (const std::invalid_argument& e) {
      const std::string why = e.what();
      return why.substr(why.find(": ") + 2);
    }
    return "";
  });
}

const std::string kDwellRange = "[0, " + format_value(kMaxDwellS) + "]";

// The flags, in the order the help gives them. Each flag's parsing, range, requirement and help
// live in its row and nowhere else.
const std::vector<Flag>& flags() {
  using C = DaemonConfig;
  using H = HierarchicalOptions;
  constexpr auto E = &C::estimator;
  const auto adaptation = [E](auto member) { return at(E, &H::bank, &FilterBankOptions::adaptation, member); };
  static const std::vector<Flag> table = {
      {nullptr, nullptr, "The bank and the transport"},
      {"--bank", "FILE",
       "model-bank file (f16mmae design --out FILE), validated on load; or a turbulence bank set file "
       "(f16mmae design --turbulence-banks --out FILE), whose start member runs alone without "
       "--turbulence-banks (required)",
       text(&C::bank_path, "needs a file name")},
      {"--turbulence-banks", "",
       "fly the turbulence bank set of --bank FILE: one member in force, chosen on line by its measured "
       "turbulence intensity (the status carries the set's hash)",
       {}, &C::turbulence_banks},
      {"--lcm-url", "URL", "LCM provider (default $LCM_DEFAULT_URL, else udpm://239.255.76.67:7667?ttl=0)",
       text(&C::lcm_url, "needs a URL such as memq:// or udpm://239.255.76.67:7667?ttl=0")},
      {"--channel-prefix", "P", "prepended to F16_SENSORS, F16_COMMANDS, MMAE_STATUS, MMAE_RESET",
       parsed_by([](C& c, const std::string& v) {
         c.channel_prefix = v;
         return std::string();
       })},
      {"--rate-hz", "HZ", "frame rate; must equal the bank's design rate (default 64)",
       number(&C::rate_hz, {0.0, kInf, true}, "a positive number of frames per second")},
      {"--bank-public-key", "FILE",
       "load the bank only if FILE.sig beside it is an Ed25519 signature of its bytes by this public key "
       "(32 bytes; see docs/INTERFACES.md: f16mmae.core.sign_bank_file)",
       text(&C::bank_public_key_path, "needs a key file name")},
      {"--auth-key", "FILE",
       "accept only frames, commands and resets signed with the key in FILE (16-64 bytes, e.g. head -c 32 "
       "/dev/urandom > FILE), each with a sequence above the last; sign every status with it. Without it "
       "the daemon obeys any sender that reaches the URL",
       text(&C::auth_key_path, "needs a key file name")},

      {nullptr, nullptr,
       "The declaration (default: the bank's recommended p_min, threshold and dwell_s, as 'f16mmae run')"},
      {"--p-min", "P", "probability floor (the core checks 1/K for the bank it loads)",
       number(&C::p_min, {0.0, 1.0 / kF16Hypotheses, false, true}, "a probability in [0, 1/13)")},
      {"--threshold", "T", "declaration threshold",
       number(&C::threshold, {0.5, 1.0, true, true}, "a probability in (0.5, 1)")},
      {"--dwell-s", "S", "declaration dwell, s",
       number(&C::dwell_s, {0.0, kMaxDwellS}, "a time in seconds in " + kDwellRange)},
      {"--dwell-nats", "N",
       "... or until the candidate's log-odds above the threshold's, summed over those frames, reach N nats "
       "(declarer.h), given, for every hypothesis (0: the dwell alone; default: the bank's N_k, its hypotheses' "
       "dwell_nats; off with a climb or maneuver dwell unless --evidence-dwell-in-phases, hierarchical_bank.h)",
       number(&C::dwell_nats, {0.0, kMaxDwellNats},
              "a number of nats in [0, " + format_value(kMaxDwellNats) + "] (0: the dwell alone)")},
      {"--dwell-nats-per-hypothesis", "FILE|NAME=N,...",
       "... per hypothesis: a file of 'NAME N' lines, or the table inline (an argument with '='), N nats for "
       "NAME (0: the dwell alone); others take --dwell-nats (declarer.h; default: the bank's own N_k, its "
       "hypotheses' dwell_nats; 'f16mmae hil' gives a scheduled bank's with --adapt-turbulence, its default in "
       "process)",
       text(&C::dwell_nats_table_path, "needs a table file name or NAME=N entries")},
      {"--evidence-dwell-in-phases", "",
       "keep the evidence dwell through a climb's and a maneuver's dwell, asking N times the phase's dwell over "
       "--dwell-s (hierarchical_bank.h; default: off in those phases; 'f16mmae hil' gives it with a scheduled "
       "bank's table)",
       {}, at(E, &H::evidence_dwell_in_phases)},
      {"--dwell-s-per-hypothesis", "NAME=S,...",
       "the least dwell of these hypotheses, s: NAME is declared after the longer of the dwell in force and S, "
       "a dual A+B not named after the longer of A's and B's (declarer.h; default: none; 'f16mmae hil' gives a "
       "scheduled bank's with --adapt-turbulence, its default in process)",
       least_dwell_table(&DeclarerOptions::dwell_s_per_hypothesis)},
      {"--rough-dwell-s-per-hypothesis", "NAME=S,...",
       "... in rough air: while the turbulence adaptation's scale is at least --rough-scale, NAME is declared "
       "after the longer of its --dwell-s-per-hypothesis entry and S (declarer.h; default: none; 'f16mmae hil' "
       "gives a scheduled bank's with --adapt-turbulence, its default in process)",
       least_dwell_table(&DeclarerOptions::rough_dwell_s_per_hypothesis), nullptr, "--adapt-turbulence", adapting},
      {"--rough-scale", "S",
       "rough air for --rough-dwell-s-per-hypothesis: the adaptation's scale at least S (> 1; default 4, "
       "declarer.h)",
       number(at(E, &H::declarer, &DeclarerOptions::rough_scale), {1.0, kMaxRoughScale, true},
              "a scale in (1, " + format_value(kMaxRoughScale) + "]"),
       nullptr, "--rough-dwell-s-per-hypothesis", rough_dwell},
      {"--start-up-s", "S",
       "the first S seconds of frames after a start or reset update the filters but weigh no hypothesis "
       "(default: the bank's recommendation, a scheduled-bank file's start_up_s, else 0)",
       number(&C::start_up_s, {0.0, kMaxStartUpS}, "a time in seconds in [0, 3600]")},
      {"--fresh-floor-levels", "",
       "a hypothesis on its probability floor restarts its failed sensors' tracked levels at each reading "
       "(the floor is a failure beginning now; filter_bank.h; default: they follow the healthy reading)",
       {}, at(E, &H::bank, &FilterBankOptions::fresh_floor_levels)},
      {"--declare-components", "",
       "a bank with partial-loss hypotheses: declare a surface's forms (complete and partial) as one "
       "component, naming the heavier form (declarer.h; default: each hypothesis alone)",
       {}, at(E, &H::declare_components)},
      {"--partial-p-min", "P",
       "such a bank: its partial hypotheses' floor at level 0, the others keeping theirs (the core refuses a "
       "floor that leaves no room for a declaration; default 0: the level-0 floor)",
       number(at(E, &H::partial_p_min), {0.0, 0.1}, "a probability in [0, 0.1]")},
      {"--rough-p-min", "P",
       "the level-0 floor in rough air: it moves from the bank's (a scheduled bank's node floor) to P as the "
       "air's measured power ratio, in the schedule's calm-air units, crosses --rough-p-min-from .. -to "
       "(rough_air_floor.h; default 0: off; 'f16mmae hil' gives a scheduled bank's with --adapt-turbulence)",
       number(at(E, &H::rough_floor, &RoughAirFloorOptions::p_min), {0.0, 1.0 / kF16Hypotheses, false, true},
              "a probability in [0, 1/13) (0: off)"),
       nullptr, "--adapt-turbulence", adapting},
      {"--rough-p-min-from", "X",
       "the band's lower end: the bank's floor below it (calm-air units; default 1.3)",
       number(at(E, &H::rough_floor, &RoughAirFloorOptions::from), {0.0, RoughAirFloor::kMaxRatio, false, true},
              "a power ratio in [0, 1000)"),
       nullptr, "--rough-p-min", rough_floor},
      {"--rough-p-min-to", "X",
       "the band's upper end: the rough-air floor above it (> --rough-p-min-from; default 1.5)",
       number(at(E, &H::rough_floor, &RoughAirFloorOptions::to), {0.0, RoughAirFloor::kMaxRatio, true},
              "a power ratio in (0, 1000]"),
       nullptr, "--rough-p-min", rough_floor},

      {nullptr, nullptr, "The turbulence adaptation (turbulence_adaptation.h; default off: the bank as designed)"},
      {"--adapt-turbulence", "", "scale the likelihoods on line to the turbulence intensity", {},
       adaptation(&TurbulenceAdaptationOptions::enabled)},
      {"--adapt-reference", "RHO",
       "the residual power ratio above which the likelihoods are tempered (default: a scheduled bank's "
       "per-node references where it carries them, else 0.6)",
       number_applied({0.0, 100.0}, "a power ratio in [0, 100]",
                      [](C& c, double x) {   // one reference everywhere: not the nodes' own
                        c.estimator.bank.adaptation.reference = x;
                        c.estimator.schedule.node_adapt_reference = false;
                      }),
       nullptr, "--adapt-turbulence",
       adapting},
      {"--adapt-own-channels", "",
       "each filter's residual power counts per channel it reads, so a hypothesis whose failed sensor's "
       "channel is uninformative does not read the air calmer than it is (a turbulence bank set's members "
       "always run with it)",
       {}, adaptation(&TurbulenceAdaptationOptions::own_channels), "--adapt-turbulence", adapting},
      {"--adapt-running-start", "",
       "the residual power ratio is the plain mean of its samples from the start until the average's length, "
       "so the tempering is the air's within a second of the start instead of rising over the time constant "
       "('f16mmae hil' gives it with a scheduled bank that recommends it, its default in process)",
       {}, adaptation(&TurbulenceAdaptationOptions::running_start), "--adapt-turbulence", adapting},
      {"--adapt-level-scale", "on|off",
       "on: while a failure read as a sensor level is declared, every hypothesis reading that level gains "
       "(1/2) ln s a frame: the others' tempered densities carry s on its channel, the level's does not "
       "(filter_bank.h; default off; 'f16mmae hil' gives on with a scheduled bank's --adapt-turbulence, its "
       "default in process)",
       on_off(adaptation(&TurbulenceAdaptationOptions::level_scale)), {},
       "--adapt-turbulence", adapting},
      {"--adapt-counted-channel", "NAME",
       "the failed NAME's uninformative channel still counts in each filter's channel count ('f16mmae hil' "
       "gives vel with a scheduled bank's --adapt-turbulence, its default in process)",
       sensor(&C::adapt_counted_channel), nullptr, "--adapt-own-channels",
       [](const C& c) { return c.estimator.bank.adaptation.own_channels; }},
      {"--adapt-excluded-channel", "NAME",
       "the hypotheses that read NAME's channel as a free level (a constant or cover level for it) leave the "
       "adaptation's minimum over the hypotheses; they still get its scale",
       sensor(&C::adapt_excluded_channel), nullptr, "--adapt-turbulence", adapting},
      {"--adapt-level-scale-channel", "NAME|none",
       "every hypothesis reading NAME's channel as a level gains (1/2) ln max(s / S0, 1) a frame at every "
       "level, not only while that failure is declared (filter_bank.h; default none; 'f16mmae hil' gives vel "
       "with a scheduled bank's --adapt-turbulence, its default in process)",
       sensor(&C::adapt_level_scale_channel, true), nullptr, "--adapt-turbulence", adapting},
      {"--adapt-level-scale-from", "S0",
       "the scale s_0 of --adapt-level-scale-channel's gain (default 1: (1/2) ln s; 'f16mmae hil' gives 8 with "
       "a scheduled bank's --adapt-turbulence, its default in process)",
       number(adaptation(&TurbulenceAdaptationOptions::level_scale_from), {1.0, 1000.0}, "a scale in [1, 1000]"),
       nullptr, "--adapt-turbulence", adapting},
      {"--adapt-floor", "TAU_S",
       "a lull floor on the adaptation's scale: s reads the larger of its residual power ratio and that ratio "
       "averaged over TAU_S seconds (in force from TAU_S / 2 on, held while climbing or maneuvering), so a burst "
       "after a lull in the gusts does not meet the untempered design "
       "(turbulence_adaptation.h; default 0: off; 'f16mmae hil' gives a scheduled bank's with --adapt-turbulence, "
       "its default in process)",
       parsed_by([](DaemonConfig& c, const std::string& v) -> std::string {
         // 0 (off) or at least the averaging time τ, the core's default (the daemon sets no other),
         // refused here as the core would refuse it, before the bank is read
         const double tau = TurbulenceAdaptationOptions{}.time_constant_s;
         const std::optional<double> x = finite_number(v);
         if (!x || !(*x == 0.0 || (*x >= tau && *x <= 3600.0)))
           return "must be 0 (off) or a time in [" + format_value(tau) +
                  ", 3600] s (at least the adaptation's averaging time)";
         c.estimator.bank.adaptation.floor_time_constant_s = *x;
         return "";
       }),
       nullptr, "--adapt-turbulence", adapting},
      {"--adapt-scale-max-from", "RHO",
       "the bound's knee: from the power ratio RHO on, the adaptation's bound on s rises with the air at its "
       "gain, so the roughest air is tempered as the line reads (turbulence_adaptation.h; default 0: off, s "
       "held at the bound; 'f16mmae hil' gives a scheduled bank's with --adapt-turbulence, its default in "
       "process)",
       number(adaptation(&TurbulenceAdaptationOptions::scale_max_from), {0.0, 100.0}, "a power ratio in [0, 100]"),
       nullptr, "--adapt-turbulence", adapting},
      {"--calm-complete", "NAME=RHO,...",
       "while the adaptation's measured power ratio is below RHO (decided while no failure is presumed or rising), "
       "the hypotheses that read measurement NAME as a tracked level read it as the paper's complete failure, the "
       "trim plus its noise (calm_air_complete.h; default: none; 'f16mmae hil' gives a scheduled bank's with "
       "--adapt-turbulence, its default in process)",
       parsed_by([](DaemonConfig& c, const std::string& v) -> std::string {
         try {
           c.estimator.calm_complete.rho = f16mmae::parse_calm_complete(v);
         } catch (const std::invalid_argument& e) {   // "calm_complete: why"
           const std::string why = e.what();
           return why.substr(why.find(": ") + 2);
         }
         return "";
       }),
       nullptr, "--adapt-turbulence", adapting},
      {"--calm-measure", "power|whiteness|either",
       "with --calm-complete, how the air is read: the measured power ratio against RHO times the reference "
       "(power, the default), how white the presumed filter's residuals are on VEL, AOA, AZ, AY and ROL against "
       "--calm-whiteness-bound (whiteness; residual_whiteness.h), or calm by either",
       choice(at(E, &H::calm_complete, &CalmAirCompleteOptions::measure),
              std::vector<std::pair<std::string, CalmMeasure>>{{"power", CalmMeasure::kPowerRatio},
                                                               {"whiteness", CalmMeasure::kWhiteness},
                                                               {"either", CalmMeasure::kEither}}),
       nullptr, "--calm-complete", [](const C& c) { return !c.estimator.calm_complete.rho.empty(); }},
      {"--calm-whiteness-bound", "W", "the air is calm while the residual whiteness is below W (default 0.78)",
       number(at(E, &H::calm_complete, &CalmAirCompleteOptions::whiteness_bound), {0.0, 100.0, true},
              "a bound in (0, 100]"),
       nullptr, "--calm-measure",
       [](const C& c) { return c.estimator.calm_complete.measure != CalmMeasure::kPowerRatio; }},
      {"--adapt-reference-climb", "RHO",
       "the reference while the air data climb or descend faster than 300 ft/min or change Mach faster than "
       "the Mach-rate gate (default: off, the reference above everywhere)",
       number(at(E, &H::climb_reference, &ClimbReferenceOptions::reference), {0.0, 100.0}, "a power ratio in [0, 100]"), nullptr,
       "--adapt-turbulence", adapting},
      {"--adapt-reference-climb-hold", "S", "keep it S s after the climb or speed change ends (default 0)",
       number(at(E, &H::climb_reference, &ClimbReferenceOptions::hold_s), {0.0, 3600.0}, "a time in seconds in [0, 3600]"), nullptr,
       "--adapt-reference-climb", climb_reference},
      {"--adapt-reference-climb-dwell", "S",
       "a level-0 declaration while that reference is in force (the climb, descent or speed change and its "
       "hold) needs S s above the threshold instead of the dwell (default 0: the dwell everywhere)",
       number(at(E, &H::climb_reference, &ClimbReferenceOptions::dwell_s), {0.0, kMaxDwellS},
              "a time in seconds in " + kDwellRange + " (0: the dwell)"),
       nullptr, "--adapt-reference-climb", climb_reference},
      {"--adapt-channel-weight", "G",
       "with --adapt-turbulence or --turbulence-banks: temper each channel by s^(1-G) s_j^G, s_j its own "
       "scale (default 0: one scale common to all)",
       number(adaptation(&TurbulenceAdaptationOptions::channel_weight), {0.0, 1.0}, "a weight in [0, 1]")},
      {"--maneuver-reference", "RHO",
       "the adaptation's reference while the aircraft maneuvers (the gate of --maneuver-dwell), unless the "
       "climb reference is in force (default: off)",
       number(at(E, &H::maneuver_dwell, &ManeuverDwellOptions::reference), {0.0, 100.0}, "a power ratio in [0, 100]"), nullptr,
       "--adapt-turbulence", adapting},

      {nullptr, nullptr, "The per-hypothesis tempering (with --adapt-turbulence or --turbulence-banks)"},
      {"--set-tempering", "W",
       "each frame the best-fitting failure hypothesis at level 0 has its evidence against NONE tempered by "
       "1 + W (s - 1) in place of the adaptation's s (default 1: off)",
       number(&C::set_tempering, {0.0, 1.0, true}, "a weight in (0, 1]"), nullptr,
       "--adapt-turbulence or --turbulence-banks", [](const C& c) { return turbulence_set(c) || adapting(c); }},
      {"--set-tempering-full", "NAME,...",
       "the hypotheses kept at the full s (names of the bank's level-0 hypotheses; 'f16mmae hil' gives "
       "LS,RS,LF,RF with --turbulence-banks, LS,RS,LF,RF,AZ,AOA,VEL with --adapt-turbulence)",
       hypothesis_names(&C::set_tempering_full),
       nullptr, "--set-tempering", set_tempering},
      {"--set-tempering-rho", "RHO", "only while the member's measured rho is at least RHO (default 0: at any rho)",
       number(&C::set_tempering_rho, {0.0, 100.0}, "a power ratio in [0, 100]"), nullptr, "--set-tempering",
       set_tempering},
      {"--set-tempering-rough", "RHO",
       "while the air's measured rho is at least RHO the --set-tempering-rough-full hypotheses take "
       "--set-tempering-rough-weight's share of the tempering ('f16mmae hil' gives the scheduled default: "
       "9, RUD,AY, 0.5; default: none)",
       number(&C::set_tempering_rough, {0.0, 100.0}, "a power ratio in [0, 100]"), nullptr, "--set-tempering",
       set_tempering},
      {"--set-tempering-rough-full", "NAME,...",
       "the hypotheses --set-tempering-rough keeps at the full s in rough air (names of the bank's level-0 "
       "hypotheses)",
       hypothesis_names(&C::set_tempering_rough_full), nullptr, "--set-tempering-rough", set_tempering_rough},
      {"--set-tempering-rough-weight", "W",
       "in rough air the --set-tempering-rough-full hypotheses' evidence is tempered by 1 + W (s - 1) when one "
       "fits best (default 1: the full s)",
       number(&C::set_tempering_rough_weight, {0.0, 1.0, true}, "a weight in (0, 1]"), nullptr,
       "--set-tempering-rough", set_tempering_rough},
      {"--set-tempering-margin", "",
       "the spared evidence is the hypothesis's margin over the best-fitting of NONE and the "
       "--set-tempering-full hypotheses (default: over NONE)",
       {}, &C::set_tempering_margin, "--set-tempering", set_tempering},
      {"--set-tempering-margin-over", "NAME,...",
       "the margin's reference: NONE and these hypotheses in place of the --set-tempering-full ones "
       "('f16mmae hil' gives LS,RS with --set-tempering-margin-stabilators)",
       hypothesis_names(&C::set_tempering_margin_over), nullptr, "--set-tempering-margin", set_tempering_margin},
      {"--set-tempering-dwell", "S",
       "a level-0 declaration needs S s above the threshold on the frames where the tempering spares "
       "(with --set-tempering-rho: severe air) instead of the dwell (default 0: the dwell everywhere)",
       number(at(E, &H::spare_dwell_s), {0.0, kMaxDwellS}, "a time in seconds in " + kDwellRange + " (0: the dwell)"),
       nullptr, "--set-tempering", set_tempering},

      {nullptr, nullptr, "Maneuvering flight"},
      {"--maneuver-dwell", "S",
       "a level-0 declaration needs S s above the threshold while the aircraft maneuvers (the estimated load "
       "factor, low-passed, off the trim by more than --maneuver-dwell-g, or the air data climb or change "
       "Mach) and for --maneuver-dwell-hold after; elsewhere the dwell (default 0: the dwell everywhere)",
       number(at(E, &H::maneuver_dwell, &ManeuverDwellOptions::dwell_s), {0.0, kMaxDwellS}, "a time in seconds in " + kDwellRange + " (0: the dwell)")},
      {"--maneuver-dwell-hold", "S", "its hold after a maneuver (default 0)",
       number(at(E, &H::maneuver_dwell, &ManeuverDwellOptions::hold_s), {0.0, 3600.0}, "a time in seconds in [0, 3600]"), nullptr,
       "--maneuver-dwell S > 0", maneuver_dwell},
      {"--maneuver-dwell-g", "G", "the load-factor gate, g (default 0.1)",
       number(at(E, &H::maneuver_dwell, &ManeuverDwellOptions::g), {0.0, 10.0, true}, "a load factor in g, > 0 and <= 10"), nullptr,
       "--maneuver-dwell S > 0", maneuver_dwell},
      {"--maneuver-dwell-time-constant", "TAU_S", "the load factor's low-pass, s (0: none; default 2)",
       number(at(E, &H::maneuver_dwell, &ManeuverDwellOptions::time_constant_s), {0.0, 60.0},
              "a time constant in seconds in [0, 60] (0: no low-pass)"),
       nullptr, "--maneuver-dwell S > 0", maneuver_dwell},
      {"--maneuver-mach-rate", "MACH_PER_S",
       "the air data's Mach changing faster than this, per s, opens the gates of --maneuver-dwell and "
       "--adapt-reference-climb (air_data_rates.h; default 0.001)",
       number_applied({0.0, 1.0, true}, "a Mach rate per second, > 0 and <= 1",
                      [](C& c, double x) {   // one gate for both (estimator_init.h)
                        c.estimator.maneuver_dwell.mach_per_s = c.estimator.climb_reference.mach_per_s = x;
                      })},
      {"--maneuver-climb-rate", "FT_S",
       "the air data's altitude changing faster than this, ft/s, opens the gates of --maneuver-dwell and "
       "--adapt-reference-climb (air_data_rates.h; default 5, 300 ft/min)",
       number_applied({0.0, 1000.0, true}, "a climb rate in ft/s, > 0 and <= 1000",
                      [](C& c, double x) {   // one gate for both (estimator_init.h)
                        c.estimator.maneuver_dwell.climb_ft_s = c.estimator.climb_reference.climb_ft_s = x;
                      })},
      {"--maneuver-rate-gust-scaled", "",
       "multiply the climb-rate and Mach-rate thresholds of --maneuver-dwell's and --adapt-reference-climb's "
       "gates by sqrt(s_b), s_b the adaptation's scale at the node's reference: the gusts' own air-data rates "
       "(hierarchical_bank.h; needs --adapt-turbulence; default off)",
       {}, at(E, &H::rate_gates_gust_scaled), "--adapt-turbulence", adapting},
      {"--maneuver-gates-calm-scaled", "",
       "multiply all three thresholds of the gates (the climb rate, the Mach rate and --maneuver-dwell's load "
       "factor) by sqrt(s_c), s_c the adaptation's scale at the node's calm-air reference: light air's gusts "
       "count too (hierarchical_bank.h; needs --adapt-turbulence; over --maneuver-rate-gust-scaled; default off)",
       {}, at(E, &H::gates_calm_scaled), "--adapt-turbulence", adapting},
      {"--maneuver-kinematics", "",
       "add the turn kinematics and gravity terms the wings-level linearization drops to every filter's "
       "propagation",
       {}, at(E, &H::maneuver, &ManeuverOptions::kinematics)},
      {"--maneuver-tempering", "G",
       "divide every likelihood by 1 + (dn/G)^2, dn the estimated load factor off trim, g (0: off; default: "
       "off; with --turbulence-banks the set file's recommended tempering)",
       number(at(E, &H::maneuver, &ManeuverOptions::tempering_g), {0.0, 100.0}, "a load factor in g in [0, 100] (0: off)")},
      {"--maneuver-tempering-deadband", "D", "only the load factor beyond D g tempers (default 0: no dead band)",
       number(at(E, &H::maneuver, &ManeuverOptions::tempering_deadband_g), {0.0, 10.0}, "a load factor in g in [0, 10]"), nullptr,
       "--maneuver-tempering", [](const C& c) { return c.estimator.maneuver.tempering_g > 0.0; }},
      {"--maneuver-tempering-alpha", "DEG",
       "temper every likelihood by a further (da/DEG)^2 added to the turbulence scale s, da the estimated angle "
       "of attack off trim beyond the dead band, deg (0: off; default: off; 'f16mmae hil' gives a scheduled "
       "bank's with --adapt-turbulence, its default in process)",
       number(at(E, &H::maneuver, &ManeuverOptions::tempering_alpha_deg), {0.0, 90.0}, "an angle in deg in [0, 90] (0: off)")},
      {"--maneuver-tempering-alpha-deadband", "DEG", "only the angle of attack beyond DEG sqrt(s) tempers (default 0: no dead band)",
       number(at(E, &H::maneuver, &ManeuverOptions::tempering_alpha_deadband_deg), {0.0, 90.0}, "an angle in deg in [0, 90]"), nullptr,
       "--maneuver-tempering-alpha", [](const C& c) { return c.estimator.maneuver.tempering_alpha_deg > 0.0; }},
      {"--maneuver-tempering-alpha-trim", "DEG",
       "above a trim angle of attack of DEG the alpha tempering's reference shrinks as (DEG / the trim in "
       "force's)^3 (default 0: off)",
       number(at(E, &H::maneuver, &ManeuverOptions::tempering_alpha_trim_deg), {0.0, 90.0}, "an angle in deg in [0, 90]"), nullptr,
       "--maneuver-tempering-alpha", [](const C& c) { return c.estimator.maneuver.tempering_alpha_deg > 0.0; }},
      {"--maneuver-tempering-added", "G",
       "temper every likelihood by a further (dn/G)^2 added to the turbulence scale s, dn the estimated load "
       "factor off trim beyond the dead band, g (0: off; default: off)",
       number(at(E, &H::maneuver, &ManeuverOptions::tempering_added_g), {0.0, 100.0}, "a load factor in g in [0, 100] (0: off)")},
      {"--maneuver-tempering-added-deadband", "D", "only the load factor beyond D sqrt(s) g tempers (default 0: no dead band)",
       number(at(E, &H::maneuver, &ManeuverOptions::tempering_added_deadband_g), {0.0, 10.0}, "a load factor in g in [0, 10]"), nullptr,
       "--maneuver-tempering-added", [](const C& c) { return c.estimator.maneuver.tempering_added_g > 0.0; }},
      {"--maneuver-tempering-added-spread", "K",
       "the added term's band at least K times the estimated load factor's own spread about its 0.35-s mean "
       "(over 30 s; default 0: off)",
       number(at(E, &H::maneuver, &ManeuverOptions::tempering_added_spread), {0.0, 100.0}, "a factor in [0, 100]"),
       nullptr, "--maneuver-tempering-added", [](const C& c) { return c.estimator.maneuver.tempering_added_g > 0.0; }},
      {"--maneuver-trim", "",
       "the filters' trim follows the climb and acceleration the air data show (each node's climb and "
       "acceleration trim offsets)",
       {}, at(E, &H::maneuver_trim, &ManeuverTrimOptions::enabled)},
      {"--maneuver-trim-time-constant", "T_S", "the rates' low-passes, T_S and 5 T_S s (default 0.5)",
       number(at(E, &H::maneuver_trim, &ManeuverTrimOptions::time_constant_s), {0.05, 60.0}, "a time constant in seconds in [0.05, 60]"),
       nullptr, "--maneuver-trim", maneuver_trim},
      {"--maneuver-trim-accel", "on|off", "off keeps the climb's trim only (default on)",
       on_off(at(E, &H::maneuver_trim, &ManeuverTrimOptions::accel)), nullptr, "--maneuver-trim", maneuver_trim},
      {"--maneuver-trim-rates", "air|inertial",
       "the climb angle and acceleration from the air data (default) or from the rate gyros, AOA and VEL "
       "against the air data (inertial_flight_path.h)",
       choice(at(E, &H::maneuver_trim, &ManeuverTrimOptions::inertial), std::vector<std::pair<std::string, bool>>{{"air", false}, {"inertial", true}}),
       nullptr, "--maneuver-trim", maneuver_trim},
      {"--maneuver-trim-blend", "T_S", "the inertial rates' blend time constant (default 2)",
       number(at(E, &H::maneuver_trim, &ManeuverTrimOptions::inertial_path, &InertialFlightPathOptions::blend_time_constant_s), {0.05, 600.0}, "a time constant in seconds in [0.05, 600]"), nullptr,
       "--maneuver-trim", maneuver_trim},
      {"--maneuver-trim-accel-airspeed", "W0",
       "the acceleration from VEL / cos(AOA) through a second-order differentiator of natural frequency W0 "
       "rad/s, delay 1.41/W0 s (maneuver_trim.h, AirspeedAccel; default: the air data's)",
       number(at(E, &H::maneuver_trim, &ManeuverTrimOptions::accel_airspeed_rad_s), {0.05, 20.0}, "a natural frequency in rad/s in [0.05, 20]"),
       {}, "--maneuver-trim and the air data's rates",
       [](const C& c) { return c.estimator.maneuver_trim.enabled && !c.estimator.maneuver_trim.inertial; }},
      {"--maneuver-trim-gamma-load-factor", "on|off",
       "on: the climb angle is the air data's plus what their low-passes hold back of the path's turn, from "
       "AZ, ROL and YAW (maneuver_trim.h, ClimbAngleComplement; default off)",
       on_off(at(E, &H::maneuver_trim, &ManeuverTrimOptions::gamma_load_factor)), {},
       "--maneuver-trim and the air data's rates",
       [](const C& c) { return c.estimator.maneuver_trim.enabled && !c.estimator.maneuver_trim.inertial; }},

      {nullptr, nullptr, "Level 1: a failure's dual bank on line"},
      {"--level1-p-min", "P",
       "the floor while a failure's level-1 (dual) bank is on line (below (1 - threshold)/12; default 0: "
       "the level-0 floor)",
       number(at(E, &H::level1_p_min), {0.0, (1.0 - kDefaultThreshold) / (kF16Hypotheses - 1), false, true},
              "a probability in [0, (1 - 0.9)/12) (the core checks (1 - threshold)/(K - 1) for the bank)")},
      {"--level1-dwell-s", "S", "the dwell while it is on line (default 0: the dwell)",
       number(at(E, &H::level1_dwell_s), {0.0, kMaxDwellS}, "a time in seconds in " + kDwellRange + " (0: the dwell)")},
      {"--level1-allowance", "K",
       "the duals' drift allowance while it is on line: each dual's log-odds against the failure drift down "
       "K nats a frame unless its evidence outgrows it (default 0: none)",
       number(at(E, &H::level1_allowance), {0.0, 5.0}, "a number of nats a frame in [0, 5]")},
      {"--departure-hold", "on|off",
       "declare nothing while the measurements leave the linearization, nor 1 s after (default on)",
       on_off(at(E, &H::departure, &DepartureOptions::enabled))},

      {nullptr, nullptr, "Trim tracking (trim_tracker.h)"},
      {"--trim-tracking", "TAU_S",
       "track the trim on line with time constant TAU_S s (e.g. 30), frozen while a failure hypothesis "
       "rises or is declared; 0: off ('f16mmae hil' gives 30 with a scheduled bank's --adapt-turbulence, its "
       "default in process)",
       number(at(E, &H::trim, &TrimTrackingOptions::time_constant_s), {0.0, 1e6}, "a time constant in seconds in [0, 1e6] (0: off)")},
      {"--trim-freeze-probability", "P", "a failure hypothesis above P freezes the trim estimate (default 0.05)",
       number(at(E, &H::trim, &TrimTrackingOptions::freeze_probability), {0.0, 1.0, true}, "a probability in (0, 1]"), nullptr,
       "--trim-tracking", tracking_trim},
      {"--trim-tracking-steady", "G",
       "track only in steady level flight, frozen while the estimated load factor is more than G g off the "
       "trim, the roll rate above 5 deg/s or the air data climb or change Mach; of the measurements AOA "
       "unless --trim-tracking-steady-measurements names others (default: off)",
       number(at(E, &H::trim, &TrimTrackingOptions::steady_g), {0.0, 10.0, true}, "a load factor in g, > 0 and <= 10"), nullptr,
       "--trim-tracking", tracking_trim},
      {"--trim-tracking-load-factor", "on|off",
       "on applies the tracked AOA offset as n times the 1-g offset, n the measured AZ low-passed (a lighter "
       "aircraft's alpha offset grows with the load factor; default off)",
       on_off(at(E, &H::trim, &TrimTrackingOptions::load_factor)), nullptr, "--trim-tracking-steady",
       [](const C& c) { return c.estimator.trim.steady_g > 0.0; }},
      {"--trim-tracking-steady-air-data", "on|off",
       "off lets the air data's climb and Mach rates no longer freeze the steady tracking (the load factor and "
       "roll rate still do; default on)",
       parsed_by([](C& c, const std::string& v) -> std::string {
         TrimTrackingOptions& t = c.estimator.trim;
         if (v != "on" && v != "off") return "must be 'on' or 'off'";
         t.steady_climb_ft_s = v == "on" ? TrimTrackingOptions{}.steady_climb_ft_s : kInf;
         t.steady_mach_per_s = v == "on" ? TrimTrackingOptions{}.steady_mach_per_s : kInf;
         return "";
       }),
       nullptr, "--trim-tracking-steady", [](const C& c) { return c.estimator.trim.steady_g > 0.0; }},
      {"--trim-tracking-steady-measurements", "NAME,...",
       "the measurements whose trim offsets the steady tracking tracks, each once (VEL, AOA, PIT, AZ, ROL, "
       "YAW, AY; the others keep the scheduled trim; default AOA)",
       parsed_by([](C& c, const std::string& v) -> std::string {
         const std::optional<std::vector<std::string>> names = upper_case_names(v);
         const auto measurement = [](std::string n) {
           for (char& ch : n) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
           return is_sensor(n);
         };
         if (!names || std::set<std::string>(names->begin(), names->end()).size() != names->size() ||
             !std::all_of(names->begin(), names->end(), measurement))
           return "must name measurements (VEL, AOA, PIT, AZ, ROL, YAW, AY), each once, separated by commas";
         c.estimator.trim.steady_measurements = *names;
         return "";
       }),
       nullptr, "--trim-tracking-steady", [](const C& c) { return c.estimator.trim.steady_g > 0.0; }},
      {"--complete-trim-hold", "off|suspected|declared",
       "a complete sensor failure's hypothesis reads the failed sensor against the trim held while a failure "
       "is suspected (declared, or a failure hypothesis above --trim-freeze-probability) or only while one "
       "is declared, not against the trim the schedule and the tracker move (complete_trim_hold.h; default off)",
       choice(at(E, &H::complete_trim_hold, &CompleteTrimHoldOptions::hold),
              std::vector<std::pair<std::string, TrimHold>>{{"off", TrimHold::kOff},
                                                            {"suspected", TrimHold::kSuspected},
                                                            {"declared", TrimHold::kDeclared}})},
      {"--complete-trim-time-constant", "S",
       "a complete sensor failure's hypothesis reads the failed sensor against the trim in force averaged "
       "over S seconds while nothing is held: the flight condition's trim, not the gusts' wander "
       "(complete_trim_hold.h; default 0, the trim in force)",
       number(at(E, &H::complete_trim_hold, &CompleteTrimHoldOptions::time_constant_s), {0.0, 3600.0},
              "a time in seconds in [0, 3600]")},

      {nullptr, nullptr, "A scheduled bank (*.f16sched)"},
      {"--schedule-mode", "interpolate|nearest",
       "interpolate between grid points on the frames' air data (default), or the nearest point, switched "
       "with hysteresis",
       choice(at(E, &H::schedule, &ScheduleOptions::mode),
              std::vector<std::pair<std::string, ScheduleMode>>{{"interpolate", ScheduleMode::kInterpolate},
                                                                {"nearest", ScheduleMode::kNearest}})},
      {"--air-data-time-constant", "TAU_S",
       "the time constant of the air data's low-pass the schedule follows (a running mean for its first "
       "TAU_S; 0: none; default: the core's, 2)",
       number(at(E, &H::schedule, &ScheduleOptions::air_data_time_constant_s), {0.0, 60.0}, "a time constant in seconds in [0, 60] (0: no low-pass)")},

      {nullptr, nullptr, "The actuators (actuator_limits.h; both or none)"},
      {"--actuator-rate-limits", "R1,...,R5[,inf]",
       "the actuators' rate limits, rad/s, one per input, applied to the commands the filters see (inf: an "
       "input without actuator, e.g. the throttle)",
       limits(at(E, &H::actuators, &ActuatorLimitOptions::rate_limit_rad_s), "rad/s")},
      {"--actuator-position-limits", "L1,...,L5[,inf]", "their position limits, rad, one per input",
       limits(at(E, &H::actuators, &ActuatorLimitOptions::position_limit_rad), "rad")},

      {nullptr, nullptr, "The process"},
      {"--max-frames", "N", "exit after publishing N status frames (default: until signalled)",
       parsed_by([](C& c, const std::string& v) {
         const std::optional<long long> n = whole_number(v, 0, std::numeric_limits<long long>::max());
         if (!n) return std::string("must be a whole number >= 0");
         c.max_frames = *n;
         return std::string();
       })},
      {"--realtime", "PRIORITY",
       "run SCHED_FIFO at PRIORITY with memory locked (needs CAP_SYS_NICE / root; a warning, not an error, "
       "without it)",
       parsed_by([](C& c, const std::string& v) {
         const std::optional<long long> p = whole_number(v, 1, 99);
         if (!p) return std::string("must be a SCHED_FIFO priority from 1 to 99");
         c.realtime_priority = static_cast<int>(*p);
         return std::string();
       })},
      {"--warm-lead-us", "US",
       "wake US microseconds before the next sensor frame is due (one period after the last) and touch the "
       "estimator's working set, so the step runs from cache after the idle time (default 500; 0: off)",
       number(&C::warm_lead_us, {0.0, kInf}, "a number of microseconds >= 0 (0: no warm-up)")},
      {"--rewarm-us", "US",
       "after that warm-up, warm up again every US microseconds until the frame arrives (at most "
       "--warm-lead-us past its due time), so the caches stay warm however the frame jitters (default 100; "
       "0: one warm-up per frame)",
       number(&C::rewarm_us, {0.0, kInf}, "a number of microseconds >= 0 (0: one warm-up per frame)")},
      {"--quiet", "", "do not print the ready line", {}, &C::quiet},
      {"--help", "", "this text"},
  };
  return table;
}

const Flag* find_flag(const std::string& name) {
  for (const Flag& f : flags())
    if (f.name && name == f.name) return &f;
  return nullptr;
}

// `text` wrapped to lines of at most `width` characters, every line after the first indented.
std::string wrap(const std::string& text, std::size_t first_column, std::size_t indent, std::size_t width) {
  std::string out;
  std::size_t column = first_column;
  std::istringstream words(text);
  std::string word;
  bool first = true;
  while (words >> word) {
    if (!first && column + 1 + word.size() > width) {
      out += "\n" + std::string(indent, ' ');
      column = indent;
    } else if (!first) {
      out += ' ';
      ++column;
    }
    out += word;
    column += word.size();
    first = false;
  }
  return out;
}

ParseResult usage_error(const std::string& what) {
  ParseResult r;
  r.exit_code = 2;
  r.message = "mmae-daemon: error: " + what + "\n(run 'mmae-daemon --help' for the options)";
  return r;
}

}  // namespace

std::vector<std::string> daemon_flag_names() {
  std::vector<std::string> names;
  for (const Flag& f : flags())
    if (f.name) names.emplace_back(f.name);
  return names;
}

std::string daemon_usage() {
  constexpr std::size_t kWidth = 100, kColumn = 23;
  std::string synopsis = "mmae-daemon --bank FILE";
  for (const Flag& f : flags()) {
    if (!f.name || std::string(f.name) == "--bank") continue;
    // '\x01' holds a flag and its metavar together through the wrap
    synopsis += std::string(" [") + f.name + (*f.metavar ? std::string("\x01") + f.metavar : "") + "]";
  }
  synopsis = wrap(synopsis, 7, 19, kWidth);
  std::replace(synopsis.begin(), synopsis.end(), '\x01', ' ');
  std::string s = "usage: " + synopsis + "\n\n" +
                  "The MMAE executive of f16mmae: steps the hierarchical bank of FILE once per sensor frame received\n"
                  "over LCM and publishes the hypothesis probabilities and z_hat. An option whose text begins 'with X'\n"
                  "applies with X only.\n";
  for (const Flag& f : flags()) {
    if (!f.name) {
      s += std::string("\n") + f.help + ":\n";
      continue;
    }
    std::string head = std::string("  ") + f.name + (*f.metavar ? std::string(" ") + f.metavar : "");
    std::string help = f.help;
    if (f.with) help = std::string("with ") + f.with + ": " + help;
    if (!f.value.range.empty()) help += "; " + std::string(f.metavar) + ": " + f.value.range;
    if (head.size() + 2 <= kColumn) {
      head += std::string(kColumn - head.size(), ' ');
    } else {
      head += "  ";
    }
    s += head + wrap(help, head.size(), kColumn, kWidth) + "\n";
  }
  s += "\nSIGINT or SIGTERM ends it with a summary line (messages by fate, step time p50/p99/max) and the same\n"
       "as one JSON line, 'mmae-daemon: statistics {...}'. Exit status 0 on a clean end, 1 if the bank or the\n"
       "LCM URL cannot be used, 2 on a usage error.\n";
  return s;
}

ParseResult parse_daemon_args(const std::vector<std::string>& args, const char* default_url) {
  DaemonConfig c;
  std::set<const Flag*> given;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "-h" || a == "--help") {
      ParseResult r;
      r.message = daemon_usage();
      return r;
    }
    std::string key = a, value;
    bool inline_value = false;
    const auto eq = a.find('=');
    if (a.rfind("--", 0) == 0 && eq != std::string::npos) {
      key = a.substr(0, eq);
      value = a.substr(eq + 1);
      inline_value = true;
    }
    const Flag* f = find_flag(key);
    if (!f) {
      std::string valid;
      for (const std::string& name : daemon_flag_names()) valid += (valid.empty() ? "" : ", ") + name;
      return usage_error("unknown argument '" + a + "'; valid options: " + valid);
    }
    given.insert(f);
    if (!*f->metavar) {  // a switch
      if (inline_value) return usage_error(key + " takes no value, got '" + value + "'");
      f->on(c) = true;
      continue;
    }
    if (!inline_value) {
      if (i + 1 >= args.size()) return usage_error(key + " needs a value");
      value = args[++i];
    }
    const std::string refused = f->value.set(c, value);
    if (!refused.empty()) return usage_error(key + " " + refused + ", got '" + value + "'");
  }
  if (c.bank_path.empty()) return usage_error("--bank FILE is required (a model-bank file from 'f16mmae design')");
  for (const Flag& f : flags()) {
    if (f.with && given.count(&f) && !f.with_ok(c))
      return usage_error(std::string(f.name) + " applies with " + f.with + " only");
  }
  const RoughAirFloorOptions& rough = c.estimator.rough_floor;
  if (!(rough.from < rough.to))
    return usage_error("--rough-p-min-from " + format_value(rough.from) + " must lie below --rough-p-min-to " +
                       format_value(rough.to) + " (the band the floor moves across)");
  const ActuatorLimitOptions& actuators = c.estimator.actuators;
  if (actuators.rate_limit_rad_s.size() != actuators.position_limit_rad.size())
    return usage_error("--actuator-rate-limits and --actuator-position-limits go together, one value per input each "
                       "(got " + std::to_string(actuators.rate_limit_rad_s.size()) + " and " +
                       std::to_string(actuators.position_limit_rad.size()) + ")");
  for (const auto& [name, us] : {std::pair<const char*, double>{"--warm-lead-us", c.warm_lead_us},
                                  std::pair<const char*, double>{"--rewarm-us", c.rewarm_us}}) {
    if (us * 1e-6 * c.rate_hz >= 1.0) {
      std::ostringstream s;
      s << name << " " << us << " must be shorter than a frame period (" << 1e6 / c.rate_hz << " us at --rate-hz "
        << c.rate_hz << ")";
      return usage_error(s.str());
    }
  }
  if (c.lcm_url.empty()) c.lcm_url = (default_url && *default_url) ? default_url : kDefaultLcmUrl;
  ParseResult r;
  r.ok = true;
  r.config = c;
  return r;
}

}  // namespace f16mmae::daemon
