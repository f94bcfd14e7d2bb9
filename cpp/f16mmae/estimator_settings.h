// EstimatorSettings — the settings of the MMAE estimator that a model bank recommends
// (p_min, threshold, dwell_s: typed fields of the bank file since format version 2; start_up_s:
// a scheduled-bank file's since schedule format 3, 0 from a bank file) and the range checks
// applied wherever they enter the core: FilterBank (p_min, start_up_s), Declarer (threshold,
// dwell_s), ModelBank::validate (all). std only.
//
// Valid ranges, and why:
//   p_min      0 <= p_min < 1/K, K = hypotheses on line: the K - 1 floored hypotheses must
//              leave the winner more than p_min (paper: 0.001; eq. 1's floor).
//   threshold  0.5 < threshold < 1: above 0.5 at most one hypothesis (probabilities sum to 1)
//              can exceed it; below 1 a hypothesis can reach it despite the floor.
//   dwell_s    0 <= dwell_s <= kMaxDwellS (60 s), and frame_rate_hz positive and finite. The
//              dwell in frames, dwell_frames = max(1, round(dwell_s * frame_rate_hz)), must be
//              at most kMaxDwellFrames, so it is an int: no huge dwell wraps to "no dwell".
//   start_up_s 0 <= start_up_s <= kMaxStartUpS (an hour).
//   dwell_nats 0 <= N <= kMaxDwellNats: an evidence dwell (declarer.h), the bank-wide option or
//              one hypothesis' N_k (a bank file's per-hypothesis field since format version 4).
// Each check throws std::invalid_argument "<who>: <setting> must be <range>, got <value>".
#pragma once

#include <charconv>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

namespace f16mmae {

inline constexpr double kDefaultPMin = 0.001;      // the paper's floor
inline constexpr double kDefaultThreshold = 0.9;   // declarer.h says why
inline constexpr double kDefaultDwellS = 0.25;     // declarer.h says why
inline constexpr double kMaxDwellS = 60.0;         // a minute: longer is no detection at all
inline constexpr int kMaxDwellFrames = 1 << 24;    // ~73 h at 64 Hz: far inside int
inline constexpr double kMaxStartUpS = 3600.0;     // filter_bank.h's start_up_s range: [0, 1 h]
inline constexpr double kMaxDwellNats = 1.0e6;     // an evidence dwell's range (declarer.h): [0, 1e6] nats
inline constexpr double kDefaultRoughScale = 4.0;  // the rough-air least dwell's scale (declarer.h says why)
inline constexpr double kMaxRoughScale = 1.0e6;     // ... its range (1, 1e6]

struct EstimatorSettings {
  double p_min = kDefaultPMin;
  double threshold = kDefaultThreshold;
  double dwell_s = kDefaultDwellS;
  // The start-up (filter_bank.h), s: a scheduled-bank file's (schedule format 3,
  // bank_schedule.h); a model-bank file carries none, 0.
  double start_up_s = 0.0;
};

// The shortest text that reads back as v ("0.4", "3.4e+07", "nan"), for error messages.
inline std::string format_value(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

namespace settings_detail {
[[noreturn]] inline void refuse(const std::string& who, const char* setting, const std::string& range, double value) {
  throw std::invalid_argument(who + ": " + setting + " must be " + range + ", got " + format_value(value));
}
}  // namespace settings_detail

// `text` as a number if the whole of it is one (std::stod's form; "nan" and "inf" parse, the
// callers' ranges refuse them): true and `out` set, else false.
inline bool parse_whole_number(const std::string& text, double& out) {
  std::size_t used = 0;
  try {
    out = std::stod(text, &used);
  } catch (const std::exception&) {
    return false;
  }
  return used == text.size();
}

// A table's text form "NAME=V[,NAME=V...]" as {name: V} (the least dwells per hypothesis,
// declarer.h; the calm-air bounds per measurement, calm_air_complete.h). Throws
// std::invalid_argument "<table>: ..." naming the entry for one that is not a name without blanks,
// '=' and a number (`expected` says what an entry is), for a value `refusal(name, v)` refuses (it
// returns the reason, "" to accept) and for a name given twice (`noun` says what a name is).
template <class Refusal>
std::map<std::string, double> parse_name_values(const std::string& text, const std::string& table,
                                                const std::string& expected, const std::string& noun,
                                                Refusal refusal) {
  std::map<std::string, double> out;
  for (std::size_t start = 0;;) {   // every entry, the empty ones too (",,", a trailing comma, "")
    const auto comma = text.find(',', start);
    const std::string entry = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const auto eq = entry.find('=');
    const std::string name = eq == std::string::npos ? entry : entry.substr(0, eq);
    const std::string value = eq == std::string::npos ? "" : entry.substr(eq + 1);
    double v = 0.0;
    if (name.empty() || name.find_first_of(" \t") != std::string::npos || !parse_whole_number(value, v))
      throw std::invalid_argument(table + ": expected " + expected + ", got '" + entry + "'");
    if (const std::string why = refusal(name, v); !why.empty()) throw std::invalid_argument(table + ": " + why);
    if (!out.emplace(name, v).second) throw std::invalid_argument(table + ": " + noun + " '" + name + "' given twice");
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

inline void check_p_min(double p_min, int k, const std::string& who) {
  if (!(p_min >= 0.0) || !(p_min * k < 1.0)) {
    settings_detail::refuse(who, "p_min", "in [0, 1/K) with K = " + std::to_string(k) + " hypotheses", p_min);
  }
}

inline void check_threshold(double threshold, const std::string& who) {
  if (!(threshold > 0.5 && threshold < 1.0)) settings_detail::refuse(who, "threshold", "in (0.5, 1)", threshold);
}

inline void check_frame_rate(double frame_rate_hz, const std::string& who) {
  if (!(frame_rate_hz > 0.0) || !std::isfinite(frame_rate_hz))
    settings_detail::refuse(who, "frame_rate_hz", "positive and finite", frame_rate_hz);
}

// max(1, round(dwell_s * frame_rate_hz)) after checking both (see the header).
inline int dwell_frames(double dwell_s, double frame_rate_hz, const std::string& who) {
  if (!(dwell_s >= 0.0 && dwell_s <= kMaxDwellS))
    settings_detail::refuse(who, "dwell_s", "in [0, " + format_value(kMaxDwellS) + "] s", dwell_s);
  check_frame_rate(frame_rate_hz, who);
  const double n = std::round(dwell_s * frame_rate_hz);
  if (!(n <= kMaxDwellFrames))
    throw std::invalid_argument(who + ": dwell_s * frame_rate_hz = " + format_value(dwell_s) + " s * " +
                                format_value(frame_rate_hz) + " Hz = " + format_value(n) +
                                " frames exceeds the limit of " + std::to_string(kMaxDwellFrames) + " frames");
  return n < 1.0 ? 1 : static_cast<int>(n);
}

// An evidence dwell in nats (the header's range); `setting` names it in the message.
inline void check_dwell_nats(double n, const std::string& who, const char* setting = "dwell_nats") {
  if (!(n >= 0.0 && n <= kMaxDwellNats))
    settings_detail::refuse(who, setting, "in [0, " + format_value(kMaxDwellNats) + "] nats", n);
}

// All four, for a bank of k hypotheses at frame_rate_hz.
inline void check_settings(const EstimatorSettings& s, int k, double frame_rate_hz, const std::string& who) {
  check_p_min(s.p_min, k, who);
  check_threshold(s.threshold, who);
  dwell_frames(s.dwell_s, frame_rate_hz, who);
  if (!(s.start_up_s >= 0.0 && s.start_up_s <= kMaxStartUpS))
    settings_detail::refuse(who, "start_up_s", "in [0, " + format_value(kMaxStartUpS) + "] s", s.start_up_s);
}

}  // namespace f16mmae
