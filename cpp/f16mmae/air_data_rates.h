// AirDataRates — the climb rate and the rate of change of Mach read from the measured air data
// (the estimator's scheduling input; never the truth), for the estimator's flight-phase gates
// (steady trim tracking, trim_tracker.h; the climb reference of the turbulence adaptation,
// climb_reference.h; the maneuver dwell, maneuver_dwell.h). HierarchicalBank owns the one
// instance, observes every usable air-data sample (schedule()) and hands it to each gate, so
// the gates read the same rates. Nothing allocates.
//
// Two first-order low-passes of each air-data signal x (pressure altitude ft, Mach), one
// usable sample per frame, with time constants T1 = 1 s and T2 = 5 s:
//   lp_T += g_T (x - lp_T),   g_T = 1 - exp(-1 / (T f))   (f: frame rate)
// For a ramp of slope v their difference settles at v (T2 - T1), so
//   rate = (lp_T1 - lp_T2) / (T2 - T1)        (ft/s, Mach/s)
// Both start at the first sample (rate 0) and stay where they are while no sample arrives.
// A gate asks changing(climb, mach, c): |rate| above its threshold times c (c = 1, or the
// gusts' scale sqrt(s_b) of hierarchical_bank.h's gust-scaled gates).
#pragma once

#include <cmath>

namespace f16mmae {

class AirDataRates {
 public:
  static constexpr double kFastS = 1.0, kSlowS = 5.0;   // T1, T2
  // The phase gates' default thresholds: 300 ft/min of climb or descent, 0.001 Mach/s.
  static constexpr double kClimbFtS = 5.0, kMachPerS = 0.001;

  explicit AirDataRates(double frame_rate_hz = 64.0)
      : gain_fast_(1.0 - std::exp(-1.0 / (frame_rate_hz * kFastS))),
        gain_slow_(1.0 - std::exp(-1.0 / (frame_rate_hz * kSlowS))) {}

  void reset() noexcept {
    seen_ = false;
    h_fast_ = h_slow_ = m_fast_ = m_slow_ = 0.0;
  }
  // One usable sample (Mach, pressure altitude ft).
  void observe(double mach, double alt_ft) noexcept {
    if (!seen_) {
      h_fast_ = h_slow_ = alt_ft;
      m_fast_ = m_slow_ = mach;
      seen_ = true;
      return;
    }
    h_fast_ += gain_fast_ * (alt_ft - h_fast_);
    h_slow_ += gain_slow_ * (alt_ft - h_slow_);
    m_fast_ += gain_fast_ * (mach - m_fast_);
    m_slow_ += gain_slow_ * (mach - m_slow_);
  }
  double climb_rate_ft_s() const noexcept { return (h_fast_ - h_slow_) / (kSlowS - kFastS); }
  double mach_rate_per_s() const noexcept { return (m_fast_ - m_slow_) / (kSlowS - kFastS); }
  // |climb rate| > c climb_ft_s or |Mach rate| > c mach_per_s.
  bool changing(double climb_ft_s, double mach_per_s, double c = 1.0) const noexcept {
    return !(std::abs(climb_rate_ft_s()) <= c * climb_ft_s && std::abs(mach_rate_per_s()) <= c * mach_per_s);
  }

 private:
  double gain_fast_, gain_slow_;
  bool seen_ = false;
  double h_fast_ = 0.0, h_slow_ = 0.0, m_fast_ = 0.0, m_slow_ = 0.0;
};

}  // namespace f16mmae
