// TurbulenceBankSet — one estimator from calm air to severe turbulence: a set of hierarchical
// banks designed for rising turbulence intensities, one of them running at a time, chosen on
// line by the turbulence intensity the running bank measures (issue 14, the "moving bank").
// Eigen and std only.
//
// Members 0..n-1 (n >= 2) are banks of one type (same sizes, same hypotheses by name and
// order), designed for rising gust intensities (the F-16 set: calm air, light, moderate,
// severe turbulence; `f16mmae design --turbulence-banks`). Each member runs its turbulence
// adaptation (turbulence_adaptation.h), whose averaged residual power ratio ρ — the running
// filters' min_k q_k / nz, averaged over τ — is the intensity measure: ρ reads ≈ the same
// value when a member flies at its own design level, more in stronger gusts, less in calmer
// air. Only the running member a steps; per frame:
//
//   update(z)     member a's update; then the selector, on the member's ρ_a:
//                   frozen  (no switch, counters cleared) while the member is at level 1,
//                           a failure is declared, or a failure hypothesis on line has
//                           p > freeze_probability: the adaptation must not absorb a failure
//                           (a failure raises the residuals too; its own hypothesis keeps min_k q_k
//                           low, but a rising hypothesis is not yet matched);
//                   settle  no switch within settle_s of the last one (the new member's ρ
//                           restarts at its reference and averages over τ);
//                   up      ρ_a > up[a] for hold_s in a row (a < n-1)  -> member a+1;
//                   down    ρ_a < down[a-1] for hold_s in a row (a > 0) -> member a-1.
//                 hysteresis: a member's band (down[a-1], up[a]) is its own ρ's, and a switch
//                 needs the excursion to last hold_s; thresholds come from measured ρ of each
//                 member at each level (tools/turbulence_banks.py).
//   handover      (after that update, before its propagate; bumpless) the new member takes
//                 over the running one (HierarchicalBank::take_over): level, hypotheses on
//                 line, every filter's states (the members share the state vector), the
//                 probabilities, the declarer's state, the declarations, frame count, air
//                 data, trim offsets; its own filters and adaptation (ρ restarts at its ρ_0).
//   propagate(u)  member a's propagate.
//   schedule(a)   member a's schedule (the air data carries over at a handover).
//
// Start and reset(): member `start` (the design's light member) runs from the first frame.
// Outputs are the running member's (probabilities, z_hat, declarations, level).
// Members of different state vectors (13 against 19 gust states) are not supported here:
// their handover would need a state map.
//
// The set holds the members by pointer; the caller owns them and keeps them alive.
// Throws std::invalid_argument (constructor): fewer than two members, members whose
// hypotheses differ, a scheduled member, adaptation off in a member, thresholds out of order
// (up[i] must exceed down[i]; both finite and positive), hold/settle/freeze out of range.
// Per frame noexcept; no allocation for fixed sizes (the handover copies within reserved capacity).
// Cost: the running member's frame plus a comparison; a handover copies K filters' states.
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
  double hold_s = 1.0;                 // the threshold crossed for this long in a row
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
    select(b);
    return d;
  }
  bool propagate(const UVector& u_abs) noexcept { return members_[active_]->propagate(u_abs); }
  int step(const ZVector& z_abs, const UVector& u_abs) noexcept {
    const int d = update(z_abs);
    propagate(u_abs);
    return d;
  }
  void schedule(const AirData& a) noexcept { members_[active_]->schedule(a); }
  // Every member back to its start; member `start` runs.
  void reset() noexcept {
    for (Bank* m : members_) m->reset();
    active_ = options_.start;
    up_count_ = down_count_ = 0;
    since_switch_ = settle_frames_;   // the start is not a switch: the selector may act at once
    switches_ = 0;
    frozen_frames_ = 0;
  }

  // ---- outputs -----------------------------------------------------------------------------
  const Bank& running() const noexcept { return *members_[active_]; }
  int active() const noexcept { return active_; }
  int member_count() const noexcept { return static_cast<int>(members_.size()); }
  double power_ratio() const noexcept { return running().bank().adaptation().power_ratio(); }
  std::int64_t switches() const noexcept { return switches_; }
  std::int64_t frozen_frames() const noexcept { return frozen_frames_; }
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
    if (frozen(b)) {
      ++frozen_frames_;
      up_count_ = down_count_ = 0;
      return;
    }
    if (since_switch_ < settle_frames_) return;
    const double rho = b.bank().adaptation().power_ratio();
    const int n = member_count();
    up_count_ = active_ < n - 1 && rho > options_.up[active_] ? up_count_ + 1 : 0;
    down_count_ = active_ > 0 && rho < options_.down[active_ - 1] ? down_count_ + 1 : 0;
    if (up_count_ > hold_frames_) handover(active_ + 1);
    else if (down_count_ > hold_frames_) handover(active_ - 1);
  }

  void handover(int next) noexcept {
    members_[next]->take_over(*members_[active_]);
    active_ = next;
    up_count_ = down_count_ = 0;
    since_switch_ = 0;
    ++switches_;
  }

  std::vector<Bank*> members_;
  TurbulenceBankSetOptions options_;
  std::int64_t hold_frames_ = 0, settle_frames_ = 0;
  int active_ = 0;
  std::int64_t up_count_ = 0, down_count_ = 0, since_switch_ = 0, switches_ = 0, frozen_frames_ = 0;
};

}  // namespace f16mmae
