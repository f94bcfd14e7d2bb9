// CalmAirComplete — the paper's complete-failure model for a failed sensor while the air is
// calm (issues 13-14). Std only.
//
// A hypothesis that reads a failed sensor j as an unknown level (a `constant` or `cover` level,
// steady_state_filter.h) explains a reading that stays constant better than the no-failure
// filter predicts it whenever that filter's density on channel j is wider than the reading's
// noise: per frame it gains about (1/2) ln(A^0_jj|G / A^k_jj) less the level's misfit. A filter
// designed for gusts (light turbulence) is that wide in calm air, where a healthy airspeed
// sensor reads a constant, so the level's hypothesis gathers evidence in every calm flight (the
// scheduled default: a false VEL about 3.7 s into every calm flight; docs/results/
// envelope_scheduled.md, rounds 22-23). In calm level flight a failed airspeed sensor and a
// healthy one read the same constant (nothing moves the speed), so there the level cannot be
// told from the aircraft in any case; the paper's complete model (the failed sensor reads the
// trim plus its noise) does not fit a healthy reading that differs from the trim in force.
//
// The rule, per channel j with a bound ρ_j > 0 (options.rho, by measurement name; 0: off):
//   calm_j   decided after each update from the turbulence adaptation's measured power ratio ρ̄
//            (turbulence_adaptation.h: min_k q_k / m averaged over τ, the turbulence bank set's
//            measure of the air; 0 before the first update):
//              calm_j = ρ̄ < ρ_j c,
//            c the calm-air reference in force: a scheduled bank whose nodes carry one
//            (bank_schedule.h: each node's ρ̄ midway between its calm air and light turbulence,
//            blended with the filters, scheduled_filters.h), else 1 (ρ_j is then the bound),
//            on frames where the bank presumes no failure (level 0, hypothesis 0 current) and no
//            failure hypothesis on line has p > freeze_probability; on every other frame the
//            decision is held, so a failure that rises, or is declared, keeps the model it rose
//            under (a failure raises the no-failure filter's residuals, and with them ρ̄);
//   while calm_j, every hypothesis that tracks channel j's level while the presumed hypothesis
//   does not reads channel j with the complete density N(r_j; 0, A_jj) in place of its level's
//   predictive density (FilterBank::set_complete_channels); its level goes on tracking, so the
//   frame the air reads rougher the level's density is back with a level that has followed the
//   reading.
// The measure (options.measure):
//   power      ρ̄ against ρ_j c, above;
//   whiteness  how white the presumed filter's residuals are on the channels
//              options.whiteness_channels (residual_whiteness.h: W̄, about 1 in the gusts a bank
//              is designed for, below it in calm air, whatever the node), against one bound w for
//              the air (options.whiteness_bound), every bounded channel alike:
//                calm_j = W̄ < w   (ρ_j > 0),
//              from the first complete block of residuals on (the start's calm held until then);
//   either     calm_j = W̄ < w or ρ̄ < ρ_j c: where light gusts move the aircraft no more than
//              calm air does (above 30,000 ft) W̄ reads the two airs alike, near 1, and ρ̄ still
//              tells some calm flights.
// Each decided and held as above. Why w = 0.78 by default: in 10-s no-failure flights of the
// scheduled default at eight points up to 30,000 ft (ten seeds), a flight's W̄ averaged over a
// second, from the third second on, is at most 0.31-0.80 in calm air and at least 0.74-1.16 in
// light turbulence, the point's means 0.24-0.58 and 0.95-1.39; at 33,900 ft the means are 1.02
// and 1.22 (tools/schedule/calm_rho.py --per-second --measure whiteness;
// docs/results/envelope_scheduled.md, round 25).
// At the start and reset() every bounded channel is calm (ρ̄ reads 0 until the first update).
// Why a reference per node: in the design's own light turbulence ρ̄ is much the same wherever
// the scheduled default flies (0.56-0.67), while in calm air it rises with altitude, where the
// light gusts move the aircraft less (0.32 at Mach 0.65, 9,000 ft; 0.56 at 0.7, 30,000 ft;
// 0.66 at 0.45, 33,900 ft), so no one bound lies between the two airs everywhere
// (tools/schedule/calm_rho.py; docs/results/envelope_scheduled.md, round 24).
// Off (no bound, the default): every l_k bit for bit as without it.
// Throws std::invalid_argument (the constructor) naming a measurement the bank does not have (a
// bound's or a whiteness channel's), a bound outside [0, 100], freeze_probability not in (0, 1],
// or, with the whiteness, no channel or a whiteness bound not in (0, 100]. Per frame noexcept,
// no allocation.
#pragma once

#include "f16mmae/estimator_settings.h"
#include "f16mmae/residual_whiteness.h"

#include <cmath>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace f16mmae {

enum class CalmMeasure { kPowerRatio, kWhiteness, kEither };

// The measure's name, as the flag --calm-measure gives it.
inline const char* calm_measure_name(CalmMeasure m) noexcept {
  return m == CalmMeasure::kPowerRatio ? "power" : m == CalmMeasure::kWhiteness ? "whiteness" : "either";
}
// The measure named `text`; throws std::invalid_argument "calm_measure: ..." listing the names.
inline CalmMeasure parse_calm_measure(const std::string& text) {
  for (const CalmMeasure m : {CalmMeasure::kPowerRatio, CalmMeasure::kWhiteness, CalmMeasure::kEither})
    if (text == calm_measure_name(m)) return m;
  throw std::invalid_argument("calm_measure: must be 'power', 'whiteness' or 'either', got '" + text + "'");
}

struct CalmAirCompleteOptions {
  std::map<std::string, double> rho;   // measurement -> ρ_j: complete while ρ̄ < ρ_j c (empty: off)
  double freeze_probability = 0.05;    // a failure hypothesis above this holds the decision
  CalmMeasure measure = CalmMeasure::kPowerRatio;   // ρ̄, W̄ or either (header)
  double whiteness_bound = 0.78;                     // w: calm while W̄ < w (header)
  std::vector<std::string> whiteness_channels = {"VEL", "AOA", "AZ", "AY", "ROL"};   // J of W̄
};

// Why measurement `name`'s bound ρ is refused ("" if it lies in [0, 100]; 0: off).
inline std::string calm_bound_refusal(const std::string& name, double rho) {
  if (rho >= 0.0 && rho <= 100.0) return "";
  return name + "'s bound must lie in [0, 100] (0: off), got " + format_value(rho);
}

// The bounds' text form "NAME=RHO[,NAME=RHO...]" (the flag --calm-complete) as {name: ρ}. Throws
// std::invalid_argument "calm_complete: ..." naming the entry (parse_name_values); the names are
// checked against the bank where the bounds are used.
inline std::map<std::string, double> parse_calm_complete(const std::string& text) {
  return parse_name_values(text, "calm_complete", "NAME=RHO (a measurement and its calm-air bound)", "measurement",
                           calm_bound_refusal);
}

class CalmAirComplete {
 public:
  CalmAirComplete() = default;
  // `time_constant_s` and `frame_rate_hz`: the whiteness' average (the turbulence adaptation's τ
  // and the bank's rate).
  CalmAirComplete(const CalmAirCompleteOptions& options, const std::vector<std::string>& measurements,
                  double time_constant_s = 5.0, double frame_rate_hz = 64.0)
      : options_(options), bound_(measurements.size(), 0.0) {
    const auto refuse = [](const std::string& what) { throw std::invalid_argument("calm-air complete: " + what); };
    if (measurements.size() > 32) refuse("at most 32 measurements, the bank has " + std::to_string(measurements.size()));
    const auto index = [&](const std::string& name) {
      std::size_t j = 0;
      while (j < measurements.size() && measurements[j] != name) ++j;
      if (j == measurements.size()) {
        std::string valid;
        for (const auto& m : measurements) valid += (valid.empty() ? "" : ", ") + m;
        refuse("'" + name + "' is not a measurement of the bank; it has " + valid);
      }
      return j;
    };
    for (const auto& [name, rho] : options.rho) {
      const std::size_t j = index(name);
      if (const std::string why = calm_bound_refusal(name, rho); !why.empty()) refuse(why);
      bound_[j] = rho;
      if (rho > 0.0) bounded_ |= 1u << j;
    }
    if (!(options.freeze_probability > 0.0 && options.freeze_probability <= 1.0))
      refuse("freeze_probability must be in (0, 1], got " + format_value(options.freeze_probability));
    if (options.measure != CalmMeasure::kPowerRatio && bounded_ != 0) {
      if (options.whiteness_channels.empty()) refuse("the whiteness needs at least one channel");
      if (!(options.whiteness_bound > 0.0 && options.whiteness_bound <= 100.0))
        refuse("whiteness_bound must be in (0, 100], got " + format_value(options.whiteness_bound));
      std::uint32_t channels = 0;
      for (const auto& name : options.whiteness_channels) channels |= 1u << index(name);
      whiteness_.configure(channels, static_cast<int>(measurements.size()), time_constant_s, frame_rate_hz);
    }
    reset();
  }

  bool enabled() const noexcept { return bounded_ != 0; }
  // Every bounded channel calm (header: the start).
  void reset() noexcept {
    calm_ = bounded_;
    whiteness_.reset();
  }
  // Before observe(), with the measure whiteness or either: the update's residual of the
  // presumed filter (filter 0 of the bank on line; an Eigen vector).
  template <class R>
  void observe_residual(const R& r) noexcept { whiteness_.observe(r); }
  // W̄ (NaN without the whiteness or before its first block).
  double whiteness() const noexcept {
    return whiteness_.value();   // NaN when not configured
  }
  // After an update: `rho_bar` the adaptation's measured ρ̄, `decide` false while a failure is
  // presumed or rising, `reference` the calm-air reference c in force (header). Returns the
  // channels calm from the next update on; with the whiteness, W̄ is read too (header).
  std::uint32_t observe(double rho_bar, bool decide, double reference = 1.0) noexcept {
    if (!decide) return calm_;
    const CalmMeasure m = options_.measure;
    const double w = whiteness();
    const bool by_power = m != CalmMeasure::kWhiteness && std::isfinite(rho_bar) && std::isfinite(reference);
    const bool by_whiteness = m != CalmMeasure::kPowerRatio && std::isfinite(w);
    if (!by_power && !by_whiteness) return calm_;   // no measure yet: held
    calm_ = 0;
    const bool calm_by_whiteness = by_whiteness && w < options_.whiteness_bound;
    for (std::size_t j = 0; j < bound_.size(); ++j)
      if (bound_[j] > 0.0 && (calm_by_whiteness || (by_power && rho_bar < bound_[j] * reference))) calm_ |= 1u << j;
    return calm_;
  }
  std::uint32_t calm() const noexcept { return calm_; }
  // A bank taking over from another (turbulence_bank_set.h): its decision, on this one's channels.
  void carry_over(const CalmAirComplete& from) noexcept {
    calm_ = from.calm_ & bounded_;
    whiteness_.carry_over(from.whiteness_);
  }
  const CalmAirCompleteOptions& options() const noexcept { return options_; }

 private:
  CalmAirCompleteOptions options_;
  std::vector<double> bound_;   // per channel: ρ_j, 0 where unbounded
  std::uint32_t bounded_ = 0;
  std::uint32_t calm_ = 0;
  ResidualWhiteness whiteness_;   // enabled with the measure whiteness or either
};

}  // namespace f16mmae
