// ManeuverDwell — a declaration dwell and a turbulence-adaptation reference of their own while
// the aircraft maneuvers, read from what the estimator sees: its estimated load factor (from u
// and z) and the measured air data. In steady level flight the declarer's own dwell and the
// adaptation's own reference stay in force. Nothing allocates.
//
// Why: in a climb, a descent, a speed change, a turn and its roll-out the filters (designed
// for wings-level flight at the scheduled trim; the maneuver model adds the kinematic terms)
// carry a model error that lifts a failure hypothesis above the threshold for a second or
// more and lets it go; a failure stays. A long dwell everywhere costs level flight its
// latency; a dwell gated on the air data alone (climb_reference.h) misses the turns and
// their roll-outs, which hold altitude and speed.
//
// Rule, per accepted update (HierarchicalBank::update, after the bank's update and before the
// declarer), with f the frame rate:
//   dn      = the AZ entry of z_hat's perturbation (g off the trim; the blended estimate, as
//             the load-factor tempering's, maneuver_kinematics.h)
//   n_lp   += c (dn - n_lp),   c = 1 - exp(-1 / (tau f)),   n_lp = 0 at the start
//             (a first-order low-pass, tau = time_constant_s, default 2 s: a turn's 0.155 g
//             passes, light turbulence's few hundredths of a g on single frames do not)
//   moving  = |n_lp| > c_g g  or  |h_dot| > c climb_ft_s  or  |M_dot| > c mach_per_s
//             (h_dot, M_dot: air_data_rates.h, the bank's rates handed to each update;
//             rate 0 until samples arrive, then only n_lp gates; c = c_g = 1, or the gusts'
//             scale with hierarchical_bank.h's gust-scaled gates: c = sqrt(s_b), c_g = 1, or
//             c = c_g = sqrt(s_c) calm-scaled)
//   maneuvering = moving on this frame or on one of the hold_frames = round(hold_s f) before.
// While maneuvering:
//   dwell      a level-0 declaration needs p > threshold on max(1, round(dwell_s f))
//              consecutive frames (dwell_s > 0; 0: the declarer's dwell);
//   reference  the adaptation's rho_0 is `reference` (turbulence_adaptation.h; NaN, the
//              default: the reference in force without this option). A climb reference
//              (climb_reference.h), while it is in force, takes precedence over it.
// Elsewhere the declarer's dwell and the reference in force without this option.
// Off (dwell_s 0 and reference NaN, the default): the bank as designed, bit for bit.
// Options are checked by validate() (std::invalid_argument naming the value and its range).
#pragma once

#include "f16mmae/air_data_rates.h"
#include "f16mmae/estimator_settings.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace f16mmae {

struct ManeuverDwellOptions {
  double dwell_s = 0.0;           // the level-0 dwell while maneuvering; 0: the declarer's
  double reference = std::numeric_limits<double>::quiet_NaN();   // rho_0 while maneuvering; NaN: off
  double hold_s = 0.0;            // maneuvering this long after the last moving frame
  double g = 0.1;                 // |low-passed dn| above this (g): moving
  double time_constant_s = 2.0;   // tau of the load factor's low-pass, s
  double climb_ft_s = AirDataRates::kClimbFtS;   // |h_dot| above this: moving (300 ft/min)
  double mach_per_s = AirDataRates::kMachPerS;   // |M_dot| above this: moving
  bool has_reference() const noexcept { return !std::isnan(reference); }
  bool enabled() const noexcept { return dwell_s > 0.0 || has_reference(); }
  void validate() const {
    if (!(dwell_s >= 0.0 && dwell_s <= kMaxDwellS))
      throw std::invalid_argument("maneuver dwell: dwell_s must be in [0, " + format_value(kMaxDwellS) +
                                  "] s (0: the declarer's dwell), got " + format_value(dwell_s));
    if (has_reference() && !(reference >= 0.0 && reference <= 100.0))
      throw std::invalid_argument("maneuver dwell: reference must be a power ratio in [0, 100], got " +
                                  format_value(reference));
    if (!(hold_s >= 0.0 && hold_s <= 3600.0))
      throw std::invalid_argument("maneuver dwell: hold_s must be in [0, 3600] s, got " + format_value(hold_s));
    if (!(g > 0.0 && g <= 10.0))
      throw std::invalid_argument("maneuver dwell: g must be a load factor in (0, 10] g, got " + format_value(g));
    if (!(time_constant_s >= 0.0 && time_constant_s <= 60.0))
      throw std::invalid_argument("maneuver dwell: time_constant_s must be in [0, 60] s (0: no low-pass), got " +
                                  format_value(time_constant_s));
    if (!(climb_ft_s > 0.0 && mach_per_s > 0.0))
      throw std::invalid_argument("maneuver dwell: climb_ft_s and mach_per_s must be > 0, got " +
                                  format_value(climb_ft_s) + " and " + format_value(mach_per_s));
  }
};

class ManeuverDwell {
 public:
  ManeuverDwell(const ManeuverDwellOptions& options, double frame_rate_hz)
      : options_(options) {
    options.validate();
    check_frame_rate(frame_rate_hz, "maneuver dwell");
    hold_frames_ = static_cast<std::int64_t>(std::llround(options.hold_s * frame_rate_hz));
    gain_ = options.time_constant_s > 0.0 ? 1.0 - std::exp(-1.0 / (options.time_constant_s * frame_rate_hz)) : 1.0;
    if (options.dwell_s > 0.0) dwell_frames_ = f16mmae::dwell_frames(options.dwell_s, frame_rate_hz, "maneuver dwell");
  }
  bool enabled() const noexcept { return options_.enabled(); }
  void reset() noexcept {
    n_lp_ = 0.0;
    held_for_ = 0;
  }
  // One accepted update: dn, the estimated load factor off the trim (g); rates, the air-data
  // rates with every usable sample so far observed; c scales the rate thresholds
  // (AirDataRates::changing; 1: as given), c_g the load factor's g.
  void observe_load_factor(double dn, const AirDataRates& rates, double c = 1.0, double c_g = 1.0) noexcept {
    if (std::isfinite(dn)) n_lp_ += gain_ * (dn - n_lp_);
    const bool moving =
        !(std::abs(n_lp_) <= options_.g * c_g) || rates.changing(options_.climb_ft_s, options_.mach_per_s, c);
    if (moving)
      held_for_ = hold_frames_ + 1;
    else if (held_for_ > 0)
      --held_for_;
  }
  bool maneuvering() const noexcept { return held_for_ > 0; }
  double load_factor_lp() const noexcept { return n_lp_; }
  // The dwell in force (frames): dwell_s's while maneuvering (dwell_s > 0), else `base`.
  int dwell_frames(int base) const noexcept { return dwell_frames_ > 0 && maneuvering() ? dwell_frames_ : base; }
  // The reference in force: `reference` while maneuvering (if set), else `base`.
  double reference(double base) const noexcept {
    return options_.has_reference() && maneuvering() ? options_.reference : base;
  }
  const ManeuverDwellOptions& options() const noexcept { return options_; }

 private:
  ManeuverDwellOptions options_;
  double gain_ = 1.0, n_lp_ = 0.0;
  std::int64_t hold_frames_ = 0, held_for_ = 0;
  int dwell_frames_ = 0;   // 0: off
};

}  // namespace f16mmae
