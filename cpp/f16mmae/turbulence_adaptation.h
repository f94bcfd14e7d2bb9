// TurbulenceAdaptation — on-line adaptation of the MMAE's likelihoods to the turbulence
// intensity, which the estimator is never told (issue 14, option (b): residual covariance
// scaling common to all hypotheses). Eigen and std only.
//
// The bank's filters are designed for one gust intensity (the shipped bank: light). In
// stronger gusts every filter's residual is larger than its A_k says, the log-likelihood
// differences grow with the residual power, and gust-shaped residuals are read as failures;
// in calmer air the opposite. The adaptation models the residual covariance of every filter
// on line as s·A_k, with one scale s common to all hypotheses, estimated on line:
//
//   per accepted update, with q_k = r_kᵀ A_k⁻¹ r_k the bank's quadratic forms:
//     m_k ← m_k + α (min(q_k, q_clip) − m_k),   α = 1 − exp(−1 / (τ f))     (f: frame rate)
//     s   = clamp(min_k m_k / m,  s_min, s_max),                             (m: measurements)
//   and the bank's log-likelihood of that frame (eq. 2) uses the s of the frames BEFORE it:
//     l_k = −q_k / (2 s)            (leading term stripped, the default)
//     l_k = −q_k / (2 s) − (m/2) ln 2π − (1/2) ln|A_k|   (kept: ln|s A_k| adds −(m/2) ln s to
//                                    every l_k alike, which the normalisation of eq. 1 removes)
//
// Why these choices:
//   - E[q_k] = m when filter k's model is right and its residual covariance is A_k, so
//     m_k / m estimates the ratio of the actual residual power to the design's.
//   - The MINIMUM over the hypotheses on line, not the no-failure filter's own m_0: after a
//     failure the no-failure filter's residuals grow, but the matching hypothesis's do not, so
//     the failure does not raise s (the adaptation does not absorb the failure). Gusts, which
//     no hypothesis models, raise every m_k.
//   - s_min (default 1): the bank's own A_k are the floor, so in calmer air than the design
//     the bank is exactly the one designed (sharpening below the design is not done by default).
//   - q_clip = 10 m s_max keeps one wild frame (a sensor spike) from moving s by more than
//     α·q_clip / m.
//   - A filter loaded at a hierarchical switch (load_filter) restarts with m_k = s·m, so the
//     scale in force carries over the switch.
// Off (enabled = false, the default) the bank computes exactly what it did without it
// (l_k = −q_k/2): bit-identical results.
//
// Cost per frame: K multiply-adds, a minimum, a clamp, K multiplies; no allocation.
// Throws: configure() throws std::invalid_argument naming the option and its valid range.
#pragma once

#include "f16mmae/estimator_settings.h"

#include <Eigen/Dense>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace f16mmae {

struct TurbulenceAdaptationOptions {
  bool enabled = false;          // off: the bank as designed (bit-identical)
  double time_constant_s = 5.0;  // τ of the residual-power average
  double scale_min = 1.0;        // s_min: the design's A_k are the floor
  double scale_max = 100.0;      // s_max
  double frame_rate_hz = 64.0;   // f (the hierarchical bank sets its ModelBank's)
};

// Throws std::invalid_argument "<who>: <option> must be <range>, got <value>".
inline void check_adaptation(const TurbulenceAdaptationOptions& o, const std::string& who) {
  const auto refuse = [&](const char* what, const std::string& range, double v) {
    throw std::invalid_argument(who + ": " + what + " must be " + range + ", got " + format_value(v));
  };
  if (!(o.time_constant_s > 0.0 && o.time_constant_s <= 3600.0))
    refuse("adapt_time_constant_s", "in (0, 3600] s", o.time_constant_s);
  if (!(o.scale_min > 0.0 && std::isfinite(o.scale_min))) refuse("adapt_scale_min", "positive and finite", o.scale_min);
  if (!(o.scale_max >= o.scale_min && std::isfinite(o.scale_max)))
    refuse("adapt_scale_max", "finite and >= adapt_scale_min = " + format_value(o.scale_min), o.scale_max);
  check_frame_rate(o.frame_rate_hz, who);
}

// The scale estimator of the header's equations for a bank of K hypotheses (Eigen::Dynamic:
// sized by configure()).
template <int K>
class ResidualScale {
 public:
  using PVector = Eigen::Matrix<double, K, 1>;

  // Validates and sets the options; sizes for k hypotheses of nz measurements; resets.
  void configure(const TurbulenceAdaptationOptions& o, int k, int nz, const std::string& who) {
    check_adaptation(o, who);
    options_ = o;
    nz_ = static_cast<double>(nz);
    alpha_ = 1.0 - std::exp(-1.0 / (o.time_constant_s * o.frame_rate_hz));
    q_clip_ = 10.0 * nz_ * o.scale_max;
    m_.setZero(k);
    reset();
  }
  bool enabled() const noexcept { return options_.enabled; }
  const TurbulenceAdaptationOptions& options() const noexcept { return options_; }
  // s, the scale in force for the next frame's likelihoods (1 when disabled).
  double scale() const noexcept { return options_.enabled ? s_ : 1.0; }
  double inverse_scale() const noexcept { return options_.enabled ? inv_s_ : 1.0; }
  // m_k, the residual-power averages of the hypotheses on line.
  const PVector& averages() const noexcept { return m_; }

  // One accepted update's quadratic forms (non-finite ones leave their m_k as it was).
  void observe(const PVector& q) noexcept {
    if (!options_.enabled) return;
    double lo = std::numeric_limits<double>::infinity();
    for (int i = 0; i < m_.size(); ++i) {
      const double qi = q(i);
      if (qi == qi && qi < std::numeric_limits<double>::infinity()) m_(i) += alpha_ * ((qi < q_clip_ ? qi : q_clip_) - m_(i));
      if (m_(i) < lo) lo = m_(i);
    }
    double s = lo / nz_;
    s = s < options_.scale_min ? options_.scale_min : (s > options_.scale_max ? options_.scale_max : s);
    s_ = s;
    inv_s_ = 1.0 / s;
  }
  // Hypothesis k replaced (a hierarchical switch): it restarts at the scale in force.
  void restart(int k) noexcept { m_(k) = s_ * nz_; }
  // Back to the start: s = s_min, every m_k = s_min·m.
  void reset() noexcept {
    s_ = options_.scale_min;
    inv_s_ = 1.0 / s_;
    m_.setConstant(s_ * nz_);
  }

 private:
  TurbulenceAdaptationOptions options_{};
  PVector m_{};
  double nz_ = 1.0, alpha_ = 0.0, q_clip_ = 0.0, s_ = 1.0, inv_s_ = 1.0;
};

}  // namespace f16mmae
