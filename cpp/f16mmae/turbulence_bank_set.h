// TurbulenceBankSet — one estimator from calm air to severe turbulence: a set of hierarchical
// banks designed for rising turbulence intensities, one of them in force at a time, chosen on
// line by the turbulence intensity the bank in force measures (issue 14, the "moving bank").
// Eigen and std only.
//
// Members 0..n-1 (n >= 2) are banks of one type (same sizes, same hypotheses by name and
// order), designed for rising gust intensities (the F-16 set: calm air, light, moderate,
// severe turbulence; `f16mmae design --turbulence-banks`). Each member runs its turbulence
// adaptation (turbulence_adaptation.h). The intensity measure ρ of a member is its
// adaptation's measured ρ̄: per accepted update, x = min_k q_k / nz over its filters on line,
// averaged —
//   ρ ← ρ + a_i (x − ρ),  a_i = max(1 / i, 1 − exp(−1 / (τ f)))   (i: updates averaged so far)
// i.e. the adaptation's average over τ, but a plain mean over the first τ f updates so that
// ρ is right within a second of a start (the adaptation's tempering ρ starts at its reference).
// The set reads it and keeps no average of its own; it restarts with the member's adaptation
// (reset(), and a copied standby's take_over). A member's ρ reads about the same at its own
// design level, more in stronger gusts, less in calmer air. Per frame:
//
//   update(z)     the member in force a updates (and the standby c, if one runs); then the
//                 selector classifies the turbulence from ρ_a by member a's own boundaries:
//                   level L = the number of bounds[a][i] (i = 0..n-2, rising) below ρ_a
//                 (bounds[a][i]: between member a's typical ρ at level i and at level i+1,
//                 measured; the classification may jump levels), and wants member L:
//                   frozen  (standby dropped) while member a is at level 1, has a failure
//                           declared, or a failure hypothesis on line has p >
//                           freeze_probability: the adaptation must not absorb a failure (a
//                           failure raises the no-failure filter's residuals too);
//                   settle  within settle_s of the last switch (or of the start) nothing is
//                           decided: the standby runs on, its hold does not count;
//                 calmer_own_rho (the rule `calmer_own_rho`): while a calmer standby c < a
//                 runs, member c's own ρ decides whether it is wanted:
//                   wanted  if classify(c, ρ_c) <= c, i.e. ρ_c <= bounds[c][c] (c's own row:
//                           the air reads at c's level or calmer to c itself), whatever ρ_a
//                           says;
//                   else    member a's classification as above, except that a wish for c
//                           itself keeps c running without counting its hold;
//                 so the member in force is chosen by its own ρ and a calmer one by its own:
//                 a member read in air stronger than its design reads far above its bounds,
//                 a stronger member in calmer air only a little below (its wider gust model
//                 expects more), the better measure of "calm" being the calm member's;
//                 a wanted member other than a becomes the standby c (replacing another); a
//                 wish for a itself drops the standby. A standby started during the flight is
//                 a copy of member a (HierarchicalBank::take_over) with its adaptation's
//                 tempering ρ at its typical value (typical[c]) and its measured ρ restarted
//                 (the next update's x); it then runs on the frames itself, so its
//                 filters converge to its own design's (a bank designed for calm air started
//                 from a light bank's states reads the mismatch as a VEL failure for seconds;
//                 docs/results/turbulence_banks.md). At the start the member `start_standby` (if >= 0)
//                 runs as a standby from frame 0, from the same zero state as every member:
//                 no copy, nothing to converge.
//                 Handed over once wanted for hold_s in a row (after settle) and, a copied
//                 standby, once it has run warm_up_s (c > a) or warm_down_s (c < a) since its
//                 copy (a calmer design converges more slowly).
//                 floor by ρ (floor_rho > 0; off by default): after settle, while not frozen,
//                 member a's level-0 floor is
//                   p_min_a = floor_p_min[a]  if ρ_a <= floor_rho and floor_p_min[a] > 0,
//                             its own (its bank's p_min)  otherwise,
//                 and a member taking over sets its own the same way by its ρ; settling, the
//                 floor in force stays; frozen (a failure rising or declared), the member's
//                 own floor is in force, so a level-1 bank (NONE, f and its duals) and a
//                 back-out need the evidence the member's own floor asks. Why: a member that tempers by its ρ
//                 (s = 1 + κ (ρ − ρ_0)) flies light and moderate air near s = 1-4, where a
//                 higher floor (fewer nats to lift a hypothesis, ln 1/p_min) shortens the
//                 latency, and severe air at its bound, where the same floor let the gusts'
//                 excursions through; ρ separates the two by a factor of 4 or more.
//   handover      (after that update, before its propagate; bumpless) the standby takes over
//                 member a's level, hypotheses on line, probabilities, declarer state,
//                 declarations, frame count, air data and trim offsets, keeping its own
//                 filter states and ρ (warm take_over; a standby with other hypotheses on
//                 line than member a's takes member a's filters and restarts its adaptation,
//                 ρ with it); it is in force from this frame on.
//   propagate(u)  member a's propagate (and the standby's).
//   schedule(a)   member a's schedule (and the standby's).
//   warm_cache()  member a's (and the standby's) working set touched ahead of a frame.
//
// Start and reset(): member `start` in force from the first frame, `start_standby` beside it,
// every member at its own floor.
// Outputs are the member in force's (probabilities, z_hat, declarations, level).
// Members of different state vectors (13 against 19 gust states) would need the standby's
// first copy to map the states; they are not supported here (one Bank type).
//
// The set holds the members by pointer; the caller owns them and keeps them alive.
// Throws std::invalid_argument (constructor): fewer than two members, members whose
// hypotheses differ, a scheduled member, adaptation off in a member, bounds not n x (n-1)
// positive, finite and rising along each row, typical not n positive finite values,
// hold/warm-up/settle/freeze/start out of range, floor_rho or floor_p_min out of range.
// Per frame noexcept; no allocation for fixed sizes (the copies stay within reserved capacity).
// Cost: one member's frame; two while a standby runs (the start, and while a boundary is crossed).
#pragma once

#include "f16mmae/hierarchical_bank.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace f16mmae {

struct TurbulenceBankSetOptions {
  std::vector<double> bounds;          // n x (n-1), row-major: member a's ρ between levels i and i+1
  std::vector<double> typical;         // n: member c's typical ρ at its own level (a copied standby's)
  double hold_s = 1.0;                 // a member wanted this long in a row (after settle): handed over
  double warm_up_s = 1.0;              // a copied standby of a stronger member runs this long first
  double warm_down_s = 5.0;            // ... of a calmer member
  double settle_s = 1.0;               // nothing decided within this long of a switch or the start
  double freeze_probability = 0.05;    // a failure hypothesis above this freezes the selector
  int start = 1;                       // the member in force at the start (and after reset())
  int start_standby = 0;               // the member beside it from frame 0 (-1: none)
  bool calmer_own_rho = false;         // a calmer standby is wanted by its own ρ (header)
  double floor_rho = 0.0;              // the floor by ρ: a member's raised floor while its ρ <= this (0: off)
  std::vector<double> floor_p_min;     // empty or n: member m's level-0 floor while its ρ <= floor_rho (0: its own)
};

// The selector's settings for n members (the constructor's and the set file's check): bounds
// n x (n-1), positive, finite and rising along each row; typical n positive finite values;
// hold/warm-up/warm-down in [0, 600] s, settle in [0, 3600] s, freeze_probability in (0, 1];
// start a member index, start_standby -1 or another member index; floor_rho finite in [0, 1e6];
// floor_p_min empty or n values in [0, 1e-3]. Throws std::invalid_argument
// "turbulence bank set: <field> ...".
inline void check_turbulence_set_selector(const TurbulenceBankSetOptions& options, int n) {
  const auto refuse = [](const std::string& what) { throw std::invalid_argument("turbulence bank set: " + what); };
  const auto finite_positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (static_cast<int>(options.bounds.size()) != n * (n - 1))
    refuse("bounds must have n x (n-1) = " + std::to_string(n * (n - 1)) + " values (a row per member), got " +
           std::to_string(options.bounds.size()));
  for (int a = 0; a < n; ++a)
    for (int i = 0; i < n - 1; ++i) {
      const double v = options.bounds[a * (n - 1) + i];
      if (!finite_positive(v) || (i > 0 && !(v > options.bounds[a * (n - 1) + i - 1])))
        refuse("bounds row " + std::to_string(a) + " must be finite, positive and rising, got " + format_value(v) +
               " at " + std::to_string(i));
    }
  if (static_cast<int>(options.typical.size()) != n)
    refuse("typical must have " + std::to_string(n) + " values (one per member), got " +
           std::to_string(options.typical.size()));
  for (double v : options.typical)
    if (!finite_positive(v)) refuse("typical must be finite and positive, got " + format_value(v));
  for (const double h : {options.hold_s, options.warm_up_s, options.warm_down_s})
    if (!(h >= 0.0 && h <= 600.0))
      refuse("hold_s, warm_up_s and warm_down_s must be in [0, 600], got " + format_value(h));
  if (!(options.settle_s >= 0.0 && options.settle_s <= 3600.0))
    refuse("settle_s must be in [0, 3600], got " + format_value(options.settle_s));
  if (!(options.freeze_probability > 0.0 && options.freeze_probability <= 1.0))
    refuse("freeze_probability must be in (0, 1], got " + format_value(options.freeze_probability));
  if (options.start < 0 || options.start >= n)
    refuse("start must be a member index in [0, " + std::to_string(n - 1) + "], got " + std::to_string(options.start));
  if (!(options.floor_rho >= 0.0 && options.floor_rho <= 1e6))
    refuse("floor_rho must be in [0, 1e6] (0: off), got " + format_value(options.floor_rho));
  if (!options.floor_p_min.empty() && static_cast<int>(options.floor_p_min.size()) != n)
    refuse("floor_p_min must be empty or have " + std::to_string(n) + " values (one per member), got " +
           std::to_string(options.floor_p_min.size()));
  for (double v : options.floor_p_min)
    if (!(v >= 0.0 && v <= 1e-3)) refuse("floor_p_min must be in [0, 1e-3] (0: the member's own), got " + format_value(v));
  if (options.start_standby < -1 || options.start_standby >= n || options.start_standby == options.start)
    refuse("start_standby must be -1 or a member index in [0, " + std::to_string(n - 1) + "] other than start, got " +
           std::to_string(options.start_standby));
}

template <class Bank>
class TurbulenceBankSet {
 public:
  using ZVector = typename Bank::ZVector;
  using UVector = typename Bank::UVector;
  using PVector = typename Bank::PVector;

  TurbulenceBankSet(std::vector<Bank*> members, const TurbulenceBankSetOptions& options)
      : members_(std::move(members)), options_(options) {
    const int n = static_cast<int>(members_.size());
    const auto refuse = [](const std::string& what) { throw std::invalid_argument("turbulence bank set: " + what); };
    if (n < 2) refuse("needs at least 2 member banks, got " + std::to_string(n));
    for (int i = 0; i < n; ++i) {
      if (members_[i] == nullptr) refuse("member " + std::to_string(i) + " is missing");
      const Bank& b = *members_[i];
      if (b.scheduled().active()) refuse("member " + std::to_string(i) + " is a scheduled bank (not supported)");
      if (!b.options().bank.adaptation.enabled)
        refuse("member " + std::to_string(i) + " runs without the turbulence adaptation (its rho is the selector's measure)");
      if (b.hypothesis_count() != members_[0]->hypothesis_count())
        refuse("member " + std::to_string(i) + " has " + std::to_string(b.hypothesis_count()) +
               " hypotheses, member 0 " + std::to_string(members_[0]->hypothesis_count()));
      for (int h = 0; h < b.hypothesis_count(); ++h)
        if (b.name(h) != members_[0]->name(h))
          refuse("member " + std::to_string(i) + "'s hypothesis " + std::to_string(h) + " is '" + b.name(h) +
                 "', member 0's '" + members_[0]->name(h) + "'");
    }
    check_turbulence_set_selector(options, n);
    for (const Bank* m : members_) own_p_min_.push_back(m->options().bank.p_min);
    const double rate = members_[0]->frame_rate_hz();
    const auto frames = [rate](double s) { return static_cast<std::int64_t>(std::llround(s * rate)); };
    hold_frames_ = frames(options.hold_s);
    warm_up_frames_ = frames(options.warm_up_s);
    warm_down_frames_ = frames(options.warm_down_s);
    settle_frames_ = frames(options.settle_s);
    reset();
  }

  // ---- per frame (noexcept; absolute signals, as HierarchicalBank) --------------------------
  int update(const ZVector& z_abs) noexcept {
    Bank& b = *members_[active_];
    const int d = b.update(z_abs);
    if (standby_ >= 0) {
      members_[standby_]->update(z_abs);
      ++standby_age_;
    }
    select(b);
    return d;
  }
  bool propagate(const UVector& u_abs) noexcept {
    if (standby_ >= 0) members_[standby_]->propagate(u_abs);
    return members_[active_]->propagate(u_abs);
  }
  int step(const ZVector& z_abs, const UVector& u_abs) noexcept {
    const int d = update(z_abs);
    propagate(u_abs);
    return d;
  }
  void schedule(const AirData& a) noexcept {
    if (standby_ >= 0) members_[standby_]->schedule(a);
    members_[active_]->schedule(a);
  }
  // Touch the per-frame working set of the member in force and of the standby (cache_warm.h).
  void warm_cache() const noexcept {
    members_[active_]->warm_cache();
    if (standby_ >= 0) members_[standby_]->warm_cache();
  }
  // Every member back to its start; member `start` in force, `start_standby` beside it.
  void reset() noexcept {
    for (int m = 0; m < member_count(); ++m) {
      members_[m]->set_level0_p_min(own_p_min_[m]);
      members_[m]->reset();
    }
    active_ = options_.start;
    standby_ = options_.start_standby;
    standby_copied_ = false;
    standby_age_ = held_ = since_switch_ = 0;
    switches_ = frozen_frames_ = standby_frames_ = 0;
  }

  // ---- outputs -----------------------------------------------------------------------------
  const Bank& running() const noexcept { return *members_[active_]; }
  int active() const noexcept { return active_; }
  int standby() const noexcept { return standby_; }   // the member warming up, or -1
  int member_count() const noexcept { return static_cast<int>(members_.size()); }
  // The selector's ρ of member m (header: its adaptation's measured ρ̄); of the member in force
  // by default.
  double power_ratio(int m = -1) const noexcept {
    return members_[m < 0 ? active_ : m]->bank().adaptation().measured_power_ratio();
  }
  std::int64_t switches() const noexcept { return switches_; }
  std::int64_t frozen_frames() const noexcept { return frozen_frames_; }
  std::int64_t standby_frames() const noexcept { return standby_frames_; }
  const TurbulenceBankSetOptions& options() const noexcept { return options_; }

 private:
  bool frozen(const Bank& b) const noexcept {
    if (b.level() != 0 || b.current_hypothesis() != 0) return true;
    const PVector& p = b.probabilities();
    for (int k = 1; k < b.size(); ++k)
      if (p(k) > options_.freeze_probability) return true;
    return false;
  }

  // The member whose level member a's ρ falls in (header).
  int classify(int a, double rho) const noexcept {
    const int n = member_count();
    int level = 0;
    while (level < n - 1 && rho > options_.bounds[a * (n - 1) + level]) ++level;
    return level;
  }

  void select(const Bank& b) noexcept {
    if (frozen(b)) {
      ++frozen_frames_;
      ++since_switch_;
      drop_standby();
      own_floor(active_);
      return;
    }
    if (++since_switch_ < settle_frames_) return;   // settling: the standby runs on
    apply_floor(active_);
    int want = classify(active_, power_ratio(active_));
    if (want == active_) want = -1;
    if (options_.calmer_own_rho && standby_ >= 0 && standby_ < active_) {
      if (classify(standby_, power_ratio(standby_)) <= standby_) {
        want = standby_;
      } else if (want == standby_) {   // member a's ρ wants it, its own does not: it runs on, unheld
        ++standby_frames_;
        held_ = 0;
        return;
      }
    }
    if (want != standby_) {
      drop_standby();
      if (want >= 0) {   // a standby started in flight: a copy of the member in force
        standby_ = want;
        standby_copied_ = true;
        members_[want]->take_over(b);   // not warm: its adaptation restarts, ρ̄ with it
        members_[want]->set_turbulence_power_ratio(options_.typical[want]);
      }
      return;
    }
    if (standby_ < 0) return;
    ++standby_frames_;
    const std::int64_t warm = !standby_copied_ ? 0 : standby_ > active_ ? warm_up_frames_ : warm_down_frames_;
    if (++held_ >= hold_frames_ && standby_age_ >= warm) handover();
  }

  // The floor by ρ (header): member m's level-0 floor, floor_p_min[m] while its ρ <= floor_rho,
  // else its own.
  void apply_floor(int m) noexcept {
    if (options_.floor_rho <= 0.0 || options_.floor_p_min.empty() || options_.floor_p_min[m] <= 0.0) return;
    members_[m]->set_level0_p_min(power_ratio(m) <= options_.floor_rho ? options_.floor_p_min[m] : own_p_min_[m]);
  }

  // Member m's own level-0 floor again (the floor by ρ on): frozen, a failure rising or declared.
  void own_floor(int m) noexcept {
    if (options_.floor_rho > 0.0 && !options_.floor_p_min.empty() && options_.floor_p_min[m] > 0.0)
      members_[m]->set_level0_p_min(own_p_min_[m]);
  }

  void drop_standby() noexcept {
    standby_ = -1;
    standby_age_ = held_ = 0;
  }

  void handover() noexcept {
    members_[standby_]->take_over(*members_[active_], /*warm=*/true);
    active_ = standby_;
    apply_floor(active_);
    drop_standby();
    since_switch_ = 0;
    ++switches_;
  }

  std::vector<Bank*> members_;
  TurbulenceBankSetOptions options_;
  std::vector<double> own_p_min_;   // each member's level-0 floor as built
  std::int64_t hold_frames_ = 0, warm_up_frames_ = 0, warm_down_frames_ = 0, settle_frames_ = 0;
  int active_ = 0, standby_ = -1;
  bool standby_copied_ = false;
  std::int64_t standby_age_ = 0, held_ = 0, since_switch_ = 0, switches_ = 0, frozen_frames_ = 0,
               standby_frames_ = 0;
};

}  // namespace f16mmae
