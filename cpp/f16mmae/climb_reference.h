// ClimbReference — the turbulence adaptation's reference rho_0 by flight phase, read from the
// measured air data: a climb, a descent or a change of speed takes its own reference
// (turbulence_adaptation.h: tempering starts above rho_0; a lower rho_0 tempers more).
// Nothing allocates.
//
// Why: flying a climb, a descent or a speed change, the filters (designed for level flight at
// the scheduled trim; the maneuver model adds the kinematic and gravity terms) carry a model
// error that the residual power ratio rho only just shows (rho 0.6-0.66 where level flight in
// light turbulence reads about 0.6-0.65), and a failure hypothesis (AOA's cover above all)
// takes it as evidence in under a second. Level turns hold their air data; there the
// bank's reference stays, and a failure keeps its evidence rate.
//
// Rule, per frame with a usable air-data sample (HierarchicalBank::schedule):
//   climbing  =  |h_dot| > c climb_ft_s  or  |M_dot| > c mach_per_s    (air_data_rates.h; c = 1,
//                or the gusts' sqrt(s_b) with hierarchical_bank.h's gust-scaled gates)
// and for hold_s after the last such frame (the level-off: the outer loop settles the altitude
// and speed it captured). While climbing, the adaptation's reference is `reference`; else the
// one in force without this option (--adapt-reference, or a scheduled bank's node reference).
// Off (reference NaN, the default): nothing changes, bit for bit. Needs the adaptation on.
// With dwell_s > 0 (0, the default: the declarer's own) a level-0 declaration in the same
// phase (climbing or its hold) needs p > threshold on max(1, round(dwell_s f)) consecutive
// frames instead of the declarer's dwell (HierarchicalBank::update; declarer.h): the model
// error of a climb or speed change lifts a hypothesis for a while and lets it go, a failure
// stays. Level flight and level turns keep the declarer's dwell, and so their latency.
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

struct ClimbReferenceOptions {
  double reference = std::numeric_limits<double>::quiet_NaN();   // rho_0 while climbing; NaN = off
  double hold_s = 0.0;            // kept this long after the last climbing frame
  double dwell_s = 0.0;           // the level-0 declaration dwell while climbing; 0: the declarer's
  double climb_ft_s = AirDataRates::kClimbFtS;   // |h_dot| above this: climbing (300 ft/min)
  double mach_per_s = AirDataRates::kMachPerS;   // |M_dot| above this: changing speed
  bool enabled() const noexcept { return !std::isnan(reference); }
  void validate() const {
    if (!enabled()) return;
    if (!(reference >= 0.0 && reference <= 100.0))
      throw std::invalid_argument("adapt_reference_climb must be a power ratio in [0, 100], got " +
                                  std::to_string(reference));
    if (!(hold_s >= 0.0 && hold_s <= 3600.0))
      throw std::invalid_argument("adapt_reference_climb_hold_s must be in [0, 3600] s, got " + std::to_string(hold_s));
    if (!(dwell_s >= 0.0 && dwell_s <= kMaxDwellS))
      throw std::invalid_argument("adapt_reference_climb_dwell_s must be in [0, " + std::to_string(kMaxDwellS) +
                                  "] s (0: the declarer's dwell), got " + std::to_string(dwell_s));
    if (!(climb_ft_s > 0.0 && mach_per_s > 0.0))
      throw std::invalid_argument("climb reference: climb_ft_s and mach_per_s must be > 0, got " +
                                  std::to_string(climb_ft_s) + " and " + std::to_string(mach_per_s));
  }
};

class ClimbReference {
 public:
  ClimbReference(const ClimbReferenceOptions& options, double frame_rate_hz)
      : options_(options),
        hold_frames_(static_cast<std::int64_t>(std::llround(options.hold_s * frame_rate_hz))) {
    options.validate();
    if (options.enabled() && options.dwell_s > 0.0)
      dwell_frames_ = f16mmae::dwell_frames(options.dwell_s, frame_rate_hz, "climb reference");
  }
  bool enabled() const noexcept { return options_.enabled(); }
  void reset() noexcept { held_for_ = 0; }
  // After each usable air-data sample: the rates with that sample observed; c scales both
  // thresholds (AirDataRates::changing; 1: as given).
  void observe(const AirDataRates& rates, double c = 1.0) noexcept {
    if (rates.changing(options_.climb_ft_s, options_.mach_per_s, c))
      held_for_ = hold_frames_ + 1;
    else if (held_for_ > 0)
      --held_for_;
  }
  bool climbing() const noexcept { return held_for_ > 0; }
  // The reference in force: `reference` while climbing, else `base`.
  double reference(double base) const noexcept { return climbing() ? options_.reference : base; }
  // The dwell in force (frames): the phase's own while climbing (dwell_s > 0), else `base`.
  int dwell_frames(int base) const noexcept { return dwell_frames_ > 0 && climbing() ? dwell_frames_ : base; }
  const ClimbReferenceOptions& options() const noexcept { return options_; }

 private:
  ClimbReferenceOptions options_;
  std::int64_t hold_frames_ = 0, held_for_ = 0;
  int dwell_frames_ = 0;   // 0: off
};

}  // namespace f16mmae
