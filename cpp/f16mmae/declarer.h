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
// frame_rate_hz is not positive and finite, the dwell exceeds kMaxDwellFrames frames, or
// dwell_nats is not in [0, kMaxDwellNats].
// update() is noexcept and allocation-free; a NaN probability never counts as "above".
#pragma once

#include <cmath>
#include <string>

#include "f16mmae/estimator_settings.h"

namespace f16mmae {

struct DeclarerOptions {
  double threshold = kDefaultThreshold;  // p_k must exceed this ...
  double dwell_s = kDefaultDwellS;        // ... for this long (consecutive frames)
  double frame_rate_hz = 64.0;   // frames per second of the probabilities fed in
  double dwell_nats = 0.0;       // ... or this log-odds excess summed over those frames (0: off)
};

// The evidence dwell's upper bound: 16 frames at the ceiling of K = 13 and p_min 0 in double
// precision (ln(1/eps) = 36 nats a frame) is far below it.
inline constexpr double kMaxDwellNats = 1.0e6;

class Declarer {
 public:
  explicit Declarer(const DeclarerOptions& options = {}, int presumed = 0)
      : options_(options),
        dwell_frames_(checked_dwell_frames(options)),
        threshold_log_odds_(std::log(options.threshold / (1.0 - options.threshold))) {
    reset(presumed);
  }

  // Feed one frame's probabilities p[0..n). Returns the index declared on this frame, or -1.
  template <class Vector>
  int update(const Vector& p) noexcept {
    return update(p, dwell_frames_);
  }
  // The same with the dwell in force on this frame, `dwell_frames` (>= 1; a flight phase's own
  // dwell, climb_reference.h): the count carries on across a change of the dwell in force.
  template <class Vector>
  int update(const Vector& p, int dwell_frames) noexcept {
    const int n = static_cast<int>(p.size());
    int above = -1;
    for (int k = 0; k < n; ++k)
      if (p[k] > options_.threshold) {
        above = k;
        break;
      }
    if (!dwelt(above, above < 0 ? 0.0 : p[above], dwell_frames, current_)) return -1;
    current_ = candidate_;
    return current_;
  }

  // The same with components (header): group[k] the lowest slot of slot k's
  // component, for k in [0, p.size()); a null group is the rule without components.
  template <class Vector>
  int update(const Vector& p, int dwell_frames, const int* group) noexcept {
    if (group == nullptr) return update(p, dwell_frames);
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
    if (!dwelt(above, above_mass, dwell_frames, group[current_])) return -1;
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
  }

  // Carry over `from`'s state (current, candidate, dwell count), keeping this declarer's
  // threshold and dwell (turbulence_bank_set.h). noexcept.
  void carry_over(const Declarer& from) noexcept {
    current_ = from.current_;
    candidate_ = from.candidate_;
    count_ = from.count_;
    evidence_nats_ = from.evidence_nats_;
  }
  int current() const noexcept { return current_; }      // presumed or last declared
  int candidate() const noexcept { return candidate_; }  // hypothesis (component: its slot) above threshold, or -1
  int dwell_count() const noexcept { return count_; }    // consecutive frames above so far
  double dwell_evidence_nats() const noexcept { return evidence_nats_; }   // E_n so far (header)
  int dwell_frames() const noexcept { return dwell_frames_; }
  const DeclarerOptions& options() const noexcept { return options_; }

 private:
  // The dwell on `above` (the slot above the threshold, -1: none; `mass` its probability or
  // its component's): restarts when it changes; true once it has held dwell_frames
  // consecutive updates, or gathered the evidence dwell in force (header), and is not `current`.
  bool dwelt(int above, double mass, int dwell_frames, int current) noexcept {
    if (above < 0) {
      candidate_ = -1;
      count_ = 0;
      evidence_nats_ = 0.0;
      return false;
    }
    if (above != candidate_) {
      candidate_ = above;
      count_ = 0;
      evidence_nats_ = 0.0;
    }
    if (count_ < dwell_frames) ++count_;
    bool enough = count_ >= dwell_frames;
    if (options_.dwell_nats > 0.0) {
      // ln(P / (1 - P)) - ln(T / (1 - T)) > 0 since P > T; log1p keeps 1 - P exact near 1.
      evidence_nats_ += std::log(mass) - std::log1p(-mass) - threshold_log_odds_;
      enough = enough || evidence_nats_ >= options_.dwell_nats * dwell_frames / dwell_frames_;
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

  DeclarerOptions options_;
  int dwell_frames_ = 1;
  int current_ = 0;
  int candidate_ = -1;
  int count_ = 0;
  double threshold_log_odds_ = 0.0;   // ln(threshold / (1 - threshold))
  double evidence_nats_ = 0.0;        // E_n of the candidate (header)
};

}  // namespace f16mmae
