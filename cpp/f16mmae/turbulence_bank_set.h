// TurbulenceBankSet — one estimator from calm air to severe turbulence: a set of hierarchical
// banks designed for rising turbulence intensities, one of them in force at a time, chosen on
// line by the turbulence intensity the bank in force measures (issue 14, the "moving bank").
// Eigen and std only.
//
// Members 0..n-1 (n >= 2) are banks of one type (same sizes, same hypotheses by name and
// order), designed for rising gust intensities (the F-16 set: calm air, light, moderate,
// severe turbulence; `f16mmae design --turbulence-banks`). Each member runs its turbulence
// adaptation (turbulence_adaptation.h), whose averaged residual power ratio ρ — the filters'
// min_k q_k / nz, averaged over τ — is the intensity measure: a member's ρ reads about the
// same value at its own design level, more in stronger gusts, less in calmer air. Per frame:
//
//   update(z)     the member in force a updates (and the standby c, if one runs); then the
//                 selector, on ρ_a:
//                   frozen  (no switch, standby dropped) while member a is at level 1, has a
//                           failure declared, or a failure hypothesis on line has p >
//                           freeze_probability: the adaptation must not absorb a failure (a
//                           failure raises the no-failure filter's residuals too);
//                   settle  no switch within settle_s of the last one;
//                   up      ρ_a > up[a]           (a < n-1): the standby is c = a+1;
//                   down    ρ_a < down[a-1]       (a > 0):   the standby is c = a-1;
//                   neither: the standby is dropped.
//                 A standby starts as a copy of member a (HierarchicalBank::take_over) and
//                 then runs on the frames itself, so its filters and its ρ converge to its own
//                 design's (a bank designed for calm air started from a light bank's states
//                 reads the mismatch as a VEL failure for seconds: measured on the F-16 set);
//                 once its condition has held for hold_s, it is handed over.
//   handover      (after that update, before its propagate; bumpless) the standby takes over
//                 member a's level, hypotheses on line, probabilities, declarer state,
//                 declarations, frame count, air data and trim offsets, keeping its own
//                 filter states and ρ (warm take_over); it is in force from this frame on.
//   propagate(u)  member a's propagate (and the standby's).
//   schedule(a)   member a's schedule (and the standby's).
//
// Start and reset(): member `start` (the design's light member) in force from the first frame.
// Outputs are the member in force's (probabilities, z_hat, declarations, level).
// Members of different state vectors (13 against 19 gust states) would need the standby's
// first copy to map the states; they are not supported here (one Bank type).
//
// The set holds the members by pointer; the caller owns them and keeps them alive.
// Throws std::invalid_argument (constructor): fewer than two members, members whose
// hypotheses differ, a scheduled member, adaptation off in a member, thresholds out of order
// (up[i] must exceed down[i]; both finite and positive), hold/settle/freeze out of range.
// Per frame noexcept; no allocation for fixed sizes (the copies stay within reserved capacity).
// Cost: one member's frame; two while a standby runs (only while a threshold is crossed).
#pragma once

#include "f16mmae/hierarchical_bank.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace f16mmae {

struct TurbulenceBankSetOptions {
  std::vector<double> up;              // up[i]: member i -> i+1 when ρ_i > up[i]   (n-1 values)
  std::vector<double> down;            // down[i]: member i+1 -> i when ρ_{i+1} < down[i] (n-1)
  double hold_s = 5.0;                 // the threshold crossed for this long in a row (the standby warms up)
  double settle_s = 10.0;              // no switch within this long of the last one
  double freeze_probability = 0.05;    // a failure hypothesis above this freezes the selector
  int start = 1;                       // the member running at the start (and after reset())
};

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
    const auto count = [&](const std::vector<double>& v, const char* what) {
      if (static_cast<int>(v.size()) != n - 1)
        refuse(std::string(what) + " must have " + std::to_string(n - 1) + " values (one per boundary), got " +
               std::to_string(v.size()));
    };
    count(options.up, "up");
    count(options.down, "down");
    for (int i = 0; i < n - 1; ++i) {
      const double u = options.up[i], d = options.down[i];
      if (!(std::isfinite(u) && std::isfinite(d) && d > 0.0 && u > d))
        refuse("boundary " + std::to_string(i) + ": up must exceed down and both be finite and positive, got up " +
               format_value(u) + ", down " + format_value(d));
    }
    if (!(options.hold_s >= 0.0 && options.hold_s <= 600.0)) refuse("hold_s must be in [0, 600], got " + format_value(options.hold_s));
    if (!(options.settle_s >= 0.0 && options.settle_s <= 3600.0))
      refuse("settle_s must be in [0, 3600], got " + format_value(options.settle_s));
    if (!(options.freeze_probability > 0.0 && options.freeze_probability <= 1.0))
      refuse("freeze_probability must be in (0, 1], got " + format_value(options.freeze_probability));
    if (options.start < 0 || options.start >= n)
      refuse("start must be a member index in [0, " + std::to_string(n - 1) + "], got " + std::to_string(options.start));
    const double rate = members_[0]->frame_rate_hz();
    hold_frames_ = static_cast<std::int64_t>(std::llround(options.hold_s * rate));
    settle_frames_ = static_cast<std::int64_t>(std::llround(options.settle_s * rate));
    reset();
  }

  // ---- per frame (noexcept; absolute signals, as HierarchicalBank) --------------------------
  int update(const ZVector& z_abs) noexcept {
    Bank& b = *members_[active_];
    const int d = b.update(z_abs);
    if (standby_ >= 0) members_[standby_]->update(z_abs);
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
  // Every member back to its start; member `start` in force.
  void reset() noexcept {
    for (Bank* m : members_) m->reset();
    active_ = options_.start;
    standby_ = -1;
    held_ = 0;
    since_switch_ = settle_frames_;   // the start is not a switch: the selector may act at once
    switches_ = 0;
    frozen_frames_ = 0;
    standby_frames_ = 0;
  }

  // ---- outputs -----------------------------------------------------------------------------
  const Bank& running() const noexcept { return *members_[active_]; }
  int active() const noexcept { return active_; }
  int standby() const noexcept { return standby_; }   // the member warming up, or -1
  int member_count() const noexcept { return static_cast<int>(members_.size()); }
  double power_ratio() const noexcept { return running().bank().adaptation().power_ratio(); }
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

  void select(const Bank& b) noexcept {
    ++since_switch_;
    int want = -1;
    if (frozen(b)) {
      ++frozen_frames_;
    } else if (since_switch_ >= settle_frames_) {
      const double rho = b.bank().adaptation().power_ratio();
      if (active_ < member_count() - 1 && rho > options_.up[active_]) want = active_ + 1;
      else if (active_ > 0 && rho < options_.down[active_ - 1]) want = active_ - 1;
    }
    if (want != standby_) {   // a new standby starts as a copy of the member in force
      standby_ = want;
      held_ = 0;
      if (want >= 0) members_[want]->take_over(b);
      return;
    }
    if (standby_ < 0) return;
    ++standby_frames_;
    if (++held_ >= hold_frames_) handover();
  }

  void handover() noexcept {
    members_[standby_]->take_over(*members_[active_], /*warm=*/true);
    active_ = standby_;
    standby_ = -1;
    held_ = 0;
    since_switch_ = 0;
    ++switches_;
  }

  std::vector<Bank*> members_;
  TurbulenceBankSetOptions options_;
  std::int64_t hold_frames_ = 0, settle_frames_ = 0;
  int active_ = 0, standby_ = -1;
  std::int64_t held_ = 0, since_switch_ = 0, switches_ = 0, frozen_frames_ = 0, standby_frames_ = 0;
};

}  // namespace f16mmae
