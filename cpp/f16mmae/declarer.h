// Declarer — turns the hypothesis probabilities of the MMAE bank (eq. 1) into failure
// declarations. Eigen-free, std only.
//
// Rule: hypothesis k is declared when p_k > threshold on `dwell_frames` consecutive frames,
//   dwell_frames = max(1, round(dwell_s * frame_rate_hz)),
// and k is not already the current (presumed or last declared) hypothesis. A declaration is
// an event: update() returns k on the frame the dwell completes, -1 otherwise. Since
// threshold > 0.5 and the probabilities sum to 1, at most one hypothesis can be above it,
// so one candidate and one counter suffice.
//
// Components (update(p, dwell_frames, group); off when group is null): hypotheses that fail the
// same component in different forms (a surface's complete/cover and partial-loss hypotheses,
// hierarchical_bank.h) are one component for the declaration. group[k] is the lowest slot of
// slot k's component (k itself for a hypothesis alone; so group[k] <= k, group[group[k]] ==
// group[k]); the caller keeps it so.
// With the component masses
//   P_g = sum_{k : group[k] = g} p_k,
// component g is declared when P_g > threshold on `dwell_frames` consecutive frames (the dwell
// runs on the sum, whichever of its forms holds the mass frame by frame) and g is not the
// current hypothesis' component group[current]. The declaration names the form that holds the
// most mass on the frame the dwell completes,
//   declared = argmax_{k : group[k] = g} p_k   (the lowest slot on a tie),
// which becomes current. Since the P_g also sum to 1, at most one component is above the
// threshold: one candidate (its representative slot g) and one counter still suffice. With
// every hypothesis alone (group[k] = k) P_k = p_k and the rule is the one above, bit for bit.
// Why: two forms of one component's failure share its mass (each explains the data about as
// well), so neither may hold the threshold for a dwell although their sum does; what the
// declaration hands on -- stop trusting that component -- is the same for both forms.
//
// Evidence dwell (dwell_nats > 0; 0, the default: off). Beside the dwell in frames, the
// candidate (hypothesis or component, mass P_t on frame t) is also declared once the log-odds it
// holds above the threshold's, summed over the consecutive frames it has been above,
//   E_n = sum_{t = 1..n} [ ln(P_t / (1 - P_t)) - ln(threshold / (1 - threshold)) ]   (each term > 0),
// reaches the dwell in nats in force,
//   E_n >= dwell_nats * dwell_frames_in_force / dwell_frames,
// so a dwell in force longer than the declarer's own (a maneuver's, climb_reference.h) asks for
// as many more nats. A candidate the data hold at the ceiling (K = 13, p_min 1e-9:
// ln((1 - 12e-9) / 12e-9) = 18.24 nats, 16.04 above the threshold's 2.197) gathers a dwell of
// 48 nats in 3 frames; one hovering just above the threshold (0.95: 0.75 nats a frame) would
// need 65 and is declared by the frame dwell as before. The rule is a CUSUM of the log-odds
// excess restarted whenever the candidate changes or falls below the threshold: a spike must
// be both high and long to count. P_t = 1 (no floor) makes the term infinite: the dwell
// completes on that frame. Either dwell declares; without dwell_nats the rule is the frame
// dwell alone, bit for bit. Off by default: excursions of gusts beyond the models also hold
// the ceiling for a few frames, so a short evidence dwell trades false declarations for
// latency (docs/results/detection_latency.md).
//
// Evidence dwell per hypothesis (dwell_nats_per_hypothesis: name -> N_k; empty, the default:
// off). Hypothesis k's candidate is declared once E_n >= N_k * dwell_frames_in_force /
// dwell_frames, N_k from the table; a hypothesis the table does not name takes dwell_nats, and
// N_k = 0 leaves k to the frame dwell alone. The candidate's hypothesis is
//   k = hypothesis_of_slot[s]   (s its slot, a component's representative; slot s itself when
//                                hypothesis_of_slot is null),
// so a bank whose slots hold different hypotheses at each level (hierarchical_bank.h) passes its
// slot-to-hypothesis map with the probabilities. The names are resolved once, at construction,
// against the bank's hypothesis names (index k = position in `names`) into a table of N_k by
// index; update() reads it (no allocation). Why per hypothesis: a hypothesis whose no-failure
// excursions above the threshold gather many nats (a sensor hypothesis that drops a channel
// explains a gust beyond the models at the ceiling for a few frames) needs a long evidence dwell
// or none, while one whose excursions gather few can be declared after a few frames at the
// ceiling (tools/latency/dwell_per_hypothesis.py derives N_k from the tuning flights' excursions).
// Table file (read_dwell_nats_table): one "NAME N" a line, '#' to the end of a line a comment;
// inline (parse_dwell_nats_per_hypothesis): "NAME=N[,NAME=N...]".
//
// Least dwell per hypothesis (dwell_s_per_hypothesis: name -> D_k seconds; empty, the default:
// off). Hypothesis k's candidate needs its dwell in force to be at least its own,
//   dwell_frames_k = max(dwell_frames_in_force, round(D_k frame_rate_hz)),
// in place of dwell_frames_in_force in both rules above (the frame dwell, and the evidence
// dwell's N_k dwell_frames_k / dwell_frames); a hypothesis the table does not name, or names
// with 0, keeps the dwell in force. A dual "A+B" the table does not name takes the longest of
// its components' least dwells, D_A+B = max(D_A, D_B) (a component not named: 0), so the
// dual that adds a failed VEL to a declared failure waits as VEL alone does; named, its own
// entry. k as for the evidence dwell (hypothesis_of_slot); the names
// are resolved at construction into frames by index. Why per hypothesis: a hypothesis whose
// no-failure excursions above the threshold are short but frequent while its failures hold the
// threshold for good (the scheduled bank's failed VEL: its filter, free of the airspeed reading,
// explains a gust's angle-of-attack and normal-acceleration excursion better than the no-failure
// filter for a fraction of a second; docs/results/envelope_scheduled.md, round 22) is held to
// a longer dwell at the cost of its own latency alone.
//
// Least dwell per hypothesis in rough air (rough_dwell_s_per_hypothesis: name -> R_k seconds;
// empty, the default: off). The caller hands the declarer the turbulence adaptation's scale s of
// the frame (observe_scale; turbulence_adaptation.h; hierarchical_bank.h hands s_b, the scale at
// the node's own reference, which a climb's or a maneuver's reference does not move), and while
//   s >= rough_scale
// hypothesis k's least dwell is the longer of its two tables' entries, max(D_k, R_k) (a dual
// "A+B" the rough table does not name: max(R_A, R_B), as above); below it, or before any scale,
// D_k alone. The rule is read on every frame of the dwell, so a candidate whose air turns rough
// during its dwell waits for the longer one. Why: a hypothesis whose no-failure excursions come
// in rough air only (the scheduled bank's failed rudder at the trimmable edge, Mach 0.365 at
// 34,500 ft, in moderate air: s 24-35 at those declarations, 8-11 in a flight's first seconds
// while s rises) needs a long dwell there, while its failures in light air (s <= 2.8 at every rudder
// declaration of 60 random points) and in moderate air at the nominal point (s <= 4.8) need
// none: one table for all air would cost the light air its latency (the rudder's median 0.70 ->
// 1.45 s over 40 random points for a 1-s least dwell; docs/results/envelope_scheduled.md,
// rounds 40-41). rough_scale (default 4) must exceed 1, the adaptation's floor: s >= 1 always,
// so a threshold at or below it would be the plain table.
//
// Defaults, and why: threshold 0.9, dwell 0.25 s at 64 Hz (16 frames).
//  - 0.9: with K = 13 and the floor p_min = 0.001 a hypothesis can reach 1 - 12 * 0.001 =
//    0.988; a correct, well-matched hypothesis sits near that, while an ambiguous pair
//    (the paper's LS/yaw "bouncing") shares the mass and stays below 0.9, so 0.9 asks for
//    a clear winner without requiring the ceiling.
//  - 0.25 s: eq. 1 moves a probability from the floor to the top within a few frames after
//    a hard failure, but single-frame spikes (turbulence gusts, model mismatch) also do;
//    16 consecutive frames above 0.9 reject such spikes (a spike lasting a quarter second
//    is evidence, not noise) and spend only a quarter of the 1.0-s median-latency budget
//    of the closed-loop goals, leaving the rest for the probability to converge.
//
// Throws: the constructor throws std::invalid_argument naming the value and the valid range
// (estimator_settings.h) if threshold is not in (0.5, 1), dwell_s is not in [0, 60] s,
// frame_rate_hz is not positive and finite, the dwell exceeds kMaxDwellFrames frames,
// dwell_nats or an N_k is not in [0, kMaxDwellNats], a D_k or R_k is not in [0, 60] s, a table
// names a hypothesis not in `names` (or is given without names), rough_scale is not in (1, 1e6]
// with a rough-air table.
// update() and observe_scale() are noexcept and allocation-free; a NaN probability never counts
// as "above".
#pragma once

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "f16mmae/estimator_settings.h"

namespace f16mmae {

struct DeclarerOptions {
  double threshold = kDefaultThreshold;  // p_k must exceed this ...
  double dwell_s = kDefaultDwellS;        // ... for this long (consecutive frames)
  double frame_rate_hz = 64.0;   // frames per second of the probabilities fed in
  double dwell_nats = 0.0;       // ... or this log-odds excess summed over those frames (0: off)
  // ... per hypothesis: name -> N_k nats (0: that hypothesis' frame dwell alone); a hypothesis
  // it does not name takes dwell_nats. Empty: dwell_nats for every hypothesis.
  std::map<std::string, double> dwell_nats_per_hypothesis;
  // name -> D_k: the least dwell (s) of that hypothesis (header); empty: the dwell in force for all.
  std::map<std::string, double> dwell_s_per_hypothesis;
  // name -> R_k: the least dwell (s) while the adaptation's scale is at least rough_scale (header);
  // empty: none.
  std::map<std::string, double> rough_dwell_s_per_hypothesis;
  double rough_scale = kDefaultRoughScale;   // s at or above this: rough air (header); > 1
};

// The evidence dwell's upper bound, kMaxDwellNats (estimator_settings.h): 16 frames at the
// ceiling of K = 13 and p_min 0 in double precision (ln(1/eps) = 36 nats a frame) is far below it.

// The refusal of a per-hypothesis table's value v of hypothesis `name` outside [0, max] (the
// tables' parsers below): "" to accept, else "<name>'s <quantity> must lie in [0, <max>] <unit>,
// got <v>".
inline std::string refuse_outside(const std::string& name, double v, const char* quantity, double max,
                                  const char* unit) {
  if (v >= 0.0 && v <= max) return "";
  return name + "'s " + quantity + " must lie in [0, " + format_value(max) + "] " + unit + ", got " + format_value(v);
}

// The per-hypothesis table of a file (header): one "NAME N" a line, '#' starts a comment.
// Throws std::invalid_argument naming `source` and the line for a line that is not a name and
// a number in [0, kMaxDwellNats], or a name given twice; the names are checked against the
// bank where the table is used (Declarer).
inline std::map<std::string, double> parse_dwell_nats_table(const std::string& text, const std::string& source) {
  std::map<std::string, double> out;
  std::istringstream lines(text);
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream fields(line);
    std::string name, value, extra;
    if (!(fields >> name)) continue;   // blank or comment only
    double n = 0.0;
    const bool ok = static_cast<bool>(fields >> value) && !(fields >> extra) && parse_whole_number(value, n);
    if (!ok)
      throw std::invalid_argument(source + " line " + std::to_string(number) +
                                  ": expected 'NAME N' (a hypothesis and its evidence dwell in nats), got '" + line + "'");
    if (const std::string why = refuse_outside(name, n, "N", kMaxDwellNats, "nats"); !why.empty())
      throw std::invalid_argument(source + " line " + std::to_string(number) + ": " + why);
    if (!out.emplace(name, n).second)
      throw std::invalid_argument(source + " line " + std::to_string(number) + ": hypothesis '" + name +
                                  "' given twice");
  }
  if (out.empty()) throw std::invalid_argument(source + ": no 'NAME N' line (an empty table)");
  return out;
}

// The table of file `path` (parse_dwell_nats_table); throws std::invalid_argument naming the
// path when it cannot be read.
inline std::map<std::string, double> read_dwell_nats_table(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("dwell-nats table '" + path + "': cannot be read");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_dwell_nats_table(text.str(), "dwell-nats table '" + path + "'");
}

// The per-hypothesis table inline, "NAME=N[,NAME=N...]", as {name: N}. Throws
// std::invalid_argument naming the entry for one that is not a name, '=' and a number in
// [0, kMaxDwellNats], or a name given twice; the names are checked where the table is used.
inline std::map<std::string, double> parse_dwell_nats_per_hypothesis(const std::string& text) {
  return parse_name_values(text, "dwell_nats_per_hypothesis", "NAME=N (a hypothesis and its evidence dwell in nats)",
                           "hypothesis", [](const std::string& name, double n) {
                             return refuse_outside(name, n, "N", kMaxDwellNats, "nats");
                           });
}

// The per-hypothesis table an argument names: inline (parse_dwell_nats_per_hypothesis) when it
// holds an '=', else the file of that path (read_dwell_nats_table). So "LS=32,RS=32" is a table
// and "tables/scheduled.txt" a file; a file whose path holds an '=' is read as "./" + its path
// would not be: name such a file without one.
inline std::map<std::string, double> dwell_nats_table_argument(const std::string& argument) {
  return argument.find('=') != std::string::npos ? parse_dwell_nats_per_hypothesis(argument)
                                                 : read_dwell_nats_table(argument);
}

// The least dwell per hypothesis of its text form (header), "NAME=S[,NAME=S...]", as
// {name: S}. Throws std::invalid_argument naming the entry for one that is not a name, '=' and a
// number in [0, kMaxDwellS] s, or a name given twice; the names are checked against the bank
// where the table is used (Declarer).
inline std::map<std::string, double> parse_dwell_s_per_hypothesis(const std::string& text) {
  return parse_name_values(text, "dwell_s_per_hypothesis", "NAME=S (a hypothesis and its least dwell in seconds)",
                           "hypothesis", [](const std::string& name, double d) {
                             return refuse_outside(name, d, "dwell", kMaxDwellS, "s");
                           });
}

class Declarer {
 public:
  // `names`: the hypotheses' names by index (the bank's), needed when the options name
  // hypotheses in dwell_nats_per_hypothesis (header).
  explicit Declarer(const DeclarerOptions& options = {}, int presumed = 0,
                    const std::vector<std::string>& names = {})
      : options_(options),
        dwell_frames_(checked_dwell_frames(options)),
        threshold_log_odds_(std::log(options.threshold / (1.0 - options.threshold))),
        nats_by_hypothesis_(resolve_per_hypothesis(options, names)),
        frames_by_hypothesis_(resolve_least_dwell(options.dwell_s_per_hypothesis, options.frame_rate_hz, names,
                                                  "dwell_s_per_hypothesis")),
        rough_frames_by_hypothesis_(resolve_rough_dwell(options, names)) {
    reset(presumed);
  }

  // The turbulence adaptation's scale s of the coming frame (header: the rough-air least dwell);
  // a NaN reads as calm. noexcept, allocation-free.
  void observe_scale(double s) noexcept { rough_ = s >= options_.rough_scale; }
  bool rough() const noexcept { return rough_; }   // the rough-air table in force (header)
  bool reads_scale() const noexcept { return !rough_frames_by_hypothesis_.empty(); }   // a rough-air table

  // Feed one frame's probabilities p[0..n). Returns the index declared on this frame, or -1.
  template <class Vector>
  int update(const Vector& p) noexcept {
    return update(p, dwell_frames_);
  }
  // The same with the dwell in force on this frame, `dwell_frames` (>= 1; a flight phase's own
  // dwell, climb_reference.h): the count carries on across a change of the dwell in force.
  template <class Vector>
  int update(const Vector& p, int dwell_frames) noexcept {
    return update_slots(p, dwell_frames, nullptr);
  }

  // The same with components (header): group[k] the lowest slot of slot k's
  // component, for k in [0, p.size()); a null group is the rule without components.
  // hypothesis_of_slot[s]: the hypothesis index (into `names`) slot s holds, for the
  // per-hypothesis evidence dwell (header); null: slot s is hypothesis s.
  template <class Vector>
  int update(const Vector& p, int dwell_frames, const int* group, const int* hypothesis_of_slot = nullptr) noexcept {
    if (group == nullptr) return update_slots(p, dwell_frames, hypothesis_of_slot);
    const int n = static_cast<int>(p.size());
    int above = -1;
    double above_mass = 0.0;
    for (int k = 0; k < n && above < 0; ++k) {
      if (group[k] != k) continue;   // each component once, at its representative
      double mass = 0.0;
      for (int j = k; j < n; ++j)
        if (group[j] == k) mass += p[j];
      if (mass > options_.threshold) {   // a NaN member makes the sum NaN: not above
        above = k;
        above_mass = mass;
      }
    }
    if (!dwelt(above, above_mass, dwell_frames, group[current_], hypothesis_of_slot)) return -1;
    int form = candidate_;
    for (int j = candidate_ + 1; j < n; ++j)
      if (group[j] == candidate_ && p[j] > p[form]) form = j;
    current_ = form;
    return current_;
  }

  // Start again with hypothesis `presumed` current (not declared) and no dwell under way.
  void reset(int presumed = 0) noexcept {
    current_ = presumed;
    candidate_ = -1;
    count_ = 0;
    evidence_nats_ = 0.0;
    frames_in_force_ = 0;
    rough_ = false;
  }

  // Carry over `from`'s state (current, candidate, dwell count), keeping this declarer's
  // threshold and dwell (turbulence_bank_set.h). noexcept.
  void carry_over(const Declarer& from) noexcept {
    current_ = from.current_;
    candidate_ = from.candidate_;
    count_ = from.count_;
    evidence_nats_ = from.evidence_nats_;
    frames_in_force_ = from.frames_in_force_;
    rough_ = from.rough_;
  }
  int current() const noexcept { return current_; }      // presumed or last declared
  int candidate() const noexcept { return candidate_; }  // hypothesis (component: its slot) above threshold, or -1
  int dwell_count() const noexcept { return count_; }    // consecutive frames above so far
  double dwell_evidence_nats() const noexcept { return evidence_nats_; }   // E_n so far (header)
  // The dwell in frames in force for the candidate on the last update (0: none above): the
  // phase's dwell or the candidate's least dwell (rough air's in rough air), the longer; its
  // evidence dwell asks N_k times this over dwell_frames() (header).
  int dwell_frames_in_force() const noexcept { return frames_in_force_; }
  int dwell_frames() const noexcept { return dwell_frames_; }
  const DeclarerOptions& options() const noexcept { return options_; }
  // The least dwell of hypothesis k in frames in force (header): D_k, or max(D_k, R_k) in rough
  // air; 0 when it has none.
  int least_dwell_frames_of(int hypothesis) const noexcept {
    const int own = entry(frames_by_hypothesis_, hypothesis);
    return rough_ ? std::max(own, entry(rough_frames_by_hypothesis_, hypothesis)) : own;
  }
  // The evidence dwell N_k of hypothesis k (header): its table entry, else dwell_nats.
  double dwell_nats_of(int hypothesis) const noexcept {
    if (hypothesis < 0 || hypothesis >= static_cast<int>(nats_by_hypothesis_.size())) return options_.dwell_nats;
    return nats_by_hypothesis_[static_cast<std::size_t>(hypothesis)];
  }

 private:
  template <class Vector>
  int update_slots(const Vector& p, int dwell_frames, const int* hypothesis_of_slot) noexcept {
    const int n = static_cast<int>(p.size());
    int above = -1;
    for (int k = 0; k < n; ++k)
      if (p[k] > options_.threshold) {
        above = k;
        break;
      }
    if (!dwelt(above, above < 0 ? 0.0 : p[above], dwell_frames, current_, hypothesis_of_slot)) return -1;
    current_ = candidate_;
    return current_;
  }

  // The dwell on `above` (the slot above the threshold, -1: none; `mass` its probability or
  // its component's): restarts when it changes; true once it has held dwell_frames
  // consecutive updates, or gathered the evidence dwell in force (header), and is not `current`.
  bool dwelt(int above, double mass, int dwell_frames, int current, const int* hypothesis_of_slot) noexcept {
    if (above < 0) {
      candidate_ = -1;
      count_ = 0;
      evidence_nats_ = 0.0;
      frames_in_force_ = 0;
      return false;
    }
    if (above != candidate_) {
      candidate_ = above;
      count_ = 0;
      evidence_nats_ = 0.0;
    }
    const int hypothesis = hypothesis_of_slot == nullptr ? above : hypothesis_of_slot[above];
    const int frames = std::max(dwell_frames, least_dwell_frames_of(hypothesis));
    frames_in_force_ = frames;
    if (count_ < frames) ++count_;
    bool enough = count_ >= frames;
    const double nats = dwell_nats_of(hypothesis);
    if (nats > 0.0) {
      // ln(P / (1 - P)) - ln(T / (1 - T)) > 0 since P > T; log1p keeps 1 - P exact near 1.
      evidence_nats_ += std::log(mass) - std::log1p(-mass) - threshold_log_odds_;
      enough = enough || evidence_nats_ >= nats * frames / dwell_frames_;
    }
    return enough && candidate_ != current;
  }
  static int checked_dwell_frames(const DeclarerOptions& o) {
    check_threshold(o.threshold, "declarer");
    if (!(o.dwell_nats >= 0.0 && o.dwell_nats <= kMaxDwellNats))
      throw std::invalid_argument("declarer: dwell_nats must be in [0, " + format_value(kMaxDwellNats) +
                                  "] nats, got " + format_value(o.dwell_nats));
    return f16mmae::dwell_frames(o.dwell_s, o.frame_rate_hz, "declarer");
  }
  static int entry(const std::vector<int>& frames, int hypothesis) noexcept {
    if (hypothesis < 0 || hypothesis >= static_cast<int>(frames.size())) return 0;
    return frames[static_cast<std::size_t>(hypothesis)];
  }
  // A least-dwell table (`setting` names it) in frames by hypothesis index (header); empty
  // without a table. Throws naming a name not in `names`, or an entry outside [0, kMaxDwellS] s.
  static std::vector<int> resolve_least_dwell(const std::map<std::string, double>& table, double rate_hz,
                                              const std::vector<std::string>& names, const std::string& setting) {
    std::vector<int> out;
    if (table.empty()) return out;
    check_names(table, names, setting);
    for (const auto& [name, d] : table)
      if (!(d >= 0.0 && d <= kMaxDwellS))
        throw std::invalid_argument("declarer: " + setting + " '" + name + "' must be in [0, " +
                                    format_value(kMaxDwellS) + "] s, got " + format_value(d));
    for (const auto& h : names) {
      const double d = least_dwell_s(table, h);
      out.push_back(d == 0.0 ? 0 : f16mmae::dwell_frames(d, rate_hz, "declarer"));
    }
    return out;
  }
  // The rough-air table (header), after checking rough_scale when there is one.
  static std::vector<int> resolve_rough_dwell(const DeclarerOptions& o, const std::vector<std::string>& names) {
    if (!o.rough_dwell_s_per_hypothesis.empty() && !(o.rough_scale > 1.0 && o.rough_scale <= kMaxRoughScale))
      throw std::invalid_argument("declarer: rough_scale must be in (1, " + format_value(kMaxRoughScale) +
                                  "] (the adaptation's scale is never below 1), got " + format_value(o.rough_scale));
    return resolve_least_dwell(o.rough_dwell_s_per_hypothesis, o.frame_rate_hz, names,
                               "rough_dwell_s_per_hypothesis");
  }
  // D of hypothesis `name` (header): its entry, else for a dual "A+B" the longest of its
  // components' entries, else 0.
  static double least_dwell_s(const std::map<std::string, double>& table, const std::string& name) {
    const auto it = table.find(name);
    if (it != table.end()) return it->second;
    if (name.find('+') == std::string::npos) return 0.0;
    double longest = 0.0;
    for (std::size_t start = 0;;) {
      const std::size_t plus = name.find('+', start);
      const auto part = table.find(name.substr(start, plus == std::string::npos ? plus : plus - start));
      if (part != table.end()) longest = std::max(longest, part->second);
      if (plus == std::string::npos) return longest;
      start = plus + 1;
    }
  }
  // Every name of `table` is one of `names`; throws std::invalid_argument naming `setting` and
  // the bank's hypotheses otherwise.
  static void check_names(const std::map<std::string, double>& table, const std::vector<std::string>& names,
                          const std::string& setting) {
    if (names.empty()) throw std::invalid_argument("declarer: " + setting + " needs the bank's hypothesis names");
    for (const auto& entry : table) {
      bool known = false;
      for (const auto& h : names) known = known || h == entry.first;
      if (!known) {
        std::string valid;
        for (const auto& h : names) valid += (valid.empty() ? "" : " ") + h;
        throw std::invalid_argument("declarer: " + setting + " names '" + entry.first +
                                    "', not a hypothesis of the bank (" + valid + ")");
      }
    }
  }
  // N_k by hypothesis index (header); empty without a table (dwell_nats for every hypothesis).
  static std::vector<double> resolve_per_hypothesis(const DeclarerOptions& o, const std::vector<std::string>& names) {
    std::vector<double> out;
    if (o.dwell_nats_per_hypothesis.empty()) return out;
    check_names(o.dwell_nats_per_hypothesis, names, "dwell_nats_per_hypothesis");
    for (const auto& [name, n] : o.dwell_nats_per_hypothesis) {
      if (!(n >= 0.0 && n <= kMaxDwellNats))
        throw std::invalid_argument("declarer: dwell_nats_per_hypothesis '" + name + "' must be in [0, " +
                                    format_value(kMaxDwellNats) + "] nats, got " + format_value(n));
    }
    for (const auto& h : names) {
      const auto it = o.dwell_nats_per_hypothesis.find(h);
      out.push_back(it == o.dwell_nats_per_hypothesis.end() ? o.dwell_nats : it->second);
    }
    return out;
  }

  DeclarerOptions options_;
  int dwell_frames_ = 1;
  int current_ = 0;
  int candidate_ = -1;
  int count_ = 0;
  double threshold_log_odds_ = 0.0;   // ln(threshold / (1 - threshold))
  double evidence_nats_ = 0.0;        // E_n of the candidate (header)
  int frames_in_force_ = 0;           // the candidate's dwell in force on the last update (0: none)
  std::vector<double> nats_by_hypothesis_;   // N_k by hypothesis index; empty: dwell_nats for all
  std::vector<int> frames_by_hypothesis_;    // D_k in frames by hypothesis index (0: none); empty: none
  std::vector<int> rough_frames_by_hypothesis_;   // R_k likewise (header)
  bool rough_ = false;                       // the last scale observed was at least rough_scale
};

}  // namespace f16mmae
