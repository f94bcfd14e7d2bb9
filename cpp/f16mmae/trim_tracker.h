// TrimTracker — a slow on-line estimate of the trim the aircraft is really flying at, against
// the trim the bank was designed (or scheduled) for: the residual trim error that air data
// cannot explain (weight and fuel burn, centre of gravity, the real aircraft against the
// design model). Eigen only; nothing allocates.
//
// Model: in unaccelerated flight about its trim the aircraft's mean inputs and measurements
// are its trim (u*, z*); the perturbations about it that the filters model (turbulence,
// dither, noise) are zero-mean. A design trim (u_trim, z_trim) that differs from (u*, z*)
// therefore shows as a constant input and measurement offset, which the filters would call a
// failure. The tracker estimates the offsets (du, dz) = (u* - u_trim, z* - z_trim) by a
// first-order low-pass of the absolute signals about the design trim, per frame i:
//
//   dz_(i+1) = dz_i + a ((z_i - z_trim) - dz_i)      after the update of frame i
//   du_(i+1) = du_i + a ((u_i - u_trim) - du_i)      after the propagate of frame i
//   a = 1 - exp(-dt / tau),  dt = 1 / frame_rate_hz,  tau = time_constant_s
//
// and the bank uses the trim in force (u_trim + du, z_trim + dz) from the next frame on
// (HierarchicalBank::set_trim_offset). Both start at zero (the design trim). tau is slow
// against detection (a declaration takes a dwell of a fraction of a second; tau is tens of
// seconds) and fast against fuel burn (the trim drifts over minutes to hours): its lag error
// on a trim drifting at rate v is v tau.
//
// Freeze rule: the estimate is held (a frozen frame changes neither dz nor du) on every frame
// on which, after its update,
//   - the bank is at level 1, or a failure is declared (the current hypothesis is not NONE), or
//   - some failure hypothesis on line has probability > freeze_probability (it is rising
//     towards a declaration),
// and for hold_s seconds after the last such frame. So a failure that makes any hypothesis
// rise is not absorbed into the trim; a failure slow enough to stay below freeze_probability
// for many tau can still be (docs/results/trim_tracking.md shows one flight each way).
//
// Steady tracking (steady_g > 0; 0, the default: the tracker above, bit for bit; the bank's
// measurements must include AZ and ROL). Weight and
// fuel burn move the trim of level flight slowly; a maneuver moves u and z far more, and
// quickly, in ways the maneuver model (maneuver_kinematics.h) already explains. Tracked through
// a maneuver, the low-pass takes a share of the maneuver's own offsets (a roll-in's roll rate, a
// turn's load factor, yaw rate and angle of attack) into the trim and hands it to every filter
// when the maneuver ends. So with steady_g > 0:
//   - a frame on which the bank's estimated load factor is more than steady_g off the trim,
//     |dn| > steady_g (dn = the AZ entry of z_hat's perturbation, g, after the update, as
//     the load-factor tempering's), freezes the estimate like a freezing frame above (and
//     hold_s after it): a turn at 30 deg bank is 0.155 g off, a pull-up more;
//   - of the measurements only those named in steady_measurements are tracked (default AOA:
//     at a held speed and altitude a lighter aircraft flies a lower angle of attack, while its
//     speed, load factor and rates are those of the trim); the others keep dz = 0, so a failure
//     of their sensors can never be absorbed. Every input is tracked (stabilator and throttle
//     trims follow the weight).
//   - a frame on which the bank's estimated roll rate (z_hat's ROL entry, rad/s) exceeds
//     steady_roll_rate_rad_s freezes it too (and hold_s after): a roll-in moves the surfaces
//     most (a differential stabilator of degrees) before the load factor has risen;
//   - a frame on which the measured air data say the aircraft climbs, descends, speeds up or
//     slows down freezes it too (and hold_s after): |h_dot| > steady_climb_ft_s or
//     |M_dot| > steady_mach_per_s, the rates read from the air data (air_data_rates.h: two
//     first-order low-passes, 1 s and 5 s, the bank's, handed to after_update; rate 0 until
//     samples arrive, then only dn gates). A steady climb
//     flies another throttle and stabilator than level flight: tracked, they would be handed
//     to the filters as the trim at the level-off;
//
// Load-factor scaling (load_factor = true; steady tracking only; false, the default: the
// tracker above, bit for bit). What the tracked AOA offset estimates is the weight: a lighter
// (or heavier) aircraft than the design's flies a load factor at another angle of attack.
// From the lift equation, linear in alpha, at dynamic pressure q and wing area S,
//   n W = L = q S C_La (alpha - alpha_0)   =>   alpha(n) = alpha_0 + n W / (q S C_La),
// so at the same q and Mach (the same C_La) the weight's offset W' - W moves alpha by
//   delta alpha(n) = n (W' - W) / (q S C_La) = n delta alpha(1),
// n times the 1-g offset. The lift-curve slope cancels: it sets alpha per g, which the bank's
// own model and trim at the node carry (the filters explain a maneuver's alpha at the design
// weight); the weight's share is the n delta alpha(1) on top. So the tracker estimates the
// 1-g offset d1 and hands the bank, on the tracked measurements (steady_measurements), n d1:
//   n_(i+1)  = n_i + b (AZ_i - n_i),   b = 1 - exp(-dt / load_factor_time_constant_s)
//              (AZ_i the frame's measured AZ, g; n_0 = 1 g; n is held on a frame of the
//               freeze rule above -- level 1, a failure declared or rising -- so a failed AZ
//               sensor does not scale the offset; the steady gates do not hold it)
//   d1_(i+1) = d1_i + a ((z_i - z_trim) / n_(i+1) - d1_i)   tracked entries, when not frozen;
//              a frame with n < kLoadFactorTrackMin freezes like a freezing frame
//   dz_i     = n_(i+1) d1_(i+1)   tracked entries (the others 0), on every frame, frozen or not
// The steady gates still freeze d1 in turns and pull-ups (their own alpha is not the weight's),
// but the correction dz follows n there instead of staying the 1-g offset. Valid while q and
// Mach stay those of the frames d1 was tracked on (a 1/q term otherwise; a turn at a held
// speed keeps them). The input offsets du are not scaled (the throttle does not scale with n).
// AZ is the body-axis normal load factor (about 0.985 g in the F-16's level trim, not 1): only
// the ratio of the n an offset is applied at to the n it was tracked at enters n d1, so that
// factor cancels as long as alpha changes little between the two.
// The names are resolved into a fixed mask at construction (options().steady_measurements is
// then empty: a copied tracker allocates nothing).
//
// Options: time_constant_s > 0 enables it (0 = off: offsets stay zero, the bank behaves
// exactly as without a tracker); freeze_probability in (0, 1]; hold_s >= 0; freeze = false
// never freezes (for comparison only: such a tracker absorbs a failure into the trim);
// steady_g >= 0 (0 = off); steady_measurements: names of the bank's measurements;
// load_factor needs steady_g > 0; load_factor_time_constant_s > 0.
#pragma once

#include "f16mmae/air_data_rates.h"

#include <Eigen/Dense>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace f16mmae {

struct TrimTrackingOptions {
  double time_constant_s = 0.0;      // tau; 0 = off
  double freeze_probability = 0.05;  // a failure hypothesis above this freezes the estimate
  double hold_s = 2.0;               // held this long after the last freezing frame
  bool freeze = true;                // false: never frozen (comparison only)
  double steady_g = 0.0;             // > 0: track only while |dn| <= steady_g, only steady_measurements
  std::vector<std::string> steady_measurements{"AOA"};
  double steady_roll_rate_rad_s = 0.0872664626;   // steady tracking: |p_hat| above this freezes (5 deg/s)
  double steady_climb_ft_s = AirDataRates::kClimbFtS;   // steady tracking: |h_dot| above this freezes (300 ft/min)
  double steady_mach_per_s = AirDataRates::kMachPerS;   // steady tracking: |M_dot| above this freezes
  bool load_factor = false;                  // steady tracking: the tracked offsets applied as n times the 1-g offset
  double load_factor_time_constant_s = 0.5;  // the measured AZ's low-pass for n
  static constexpr double kLoadFactorTrackMin = 0.5;   // g: a frame below it is not tracked (z / n)

  bool enabled() const noexcept { return time_constant_s > 0.0; }
  void validate() const {
    if (!(time_constant_s >= 0.0 && std::isfinite(time_constant_s)))
      throw std::invalid_argument("trim tracking: time_constant_s must be >= 0 s (0 = off), got " +
                                  std::to_string(time_constant_s));
    if (!(freeze_probability > 0.0 && freeze_probability <= 1.0))
      throw std::invalid_argument("trim tracking: freeze_probability must lie in (0, 1], got " +
                                  std::to_string(freeze_probability));
    if (!(hold_s >= 0.0 && std::isfinite(hold_s)))
      throw std::invalid_argument("trim tracking: hold_s must be >= 0 s, got " + std::to_string(hold_s));
    if (!(steady_g >= 0.0 && std::isfinite(steady_g)))
      throw std::invalid_argument("trim tracking: steady_g must be >= 0 g (0 = off), got " + std::to_string(steady_g));
    if (!(steady_climb_ft_s > 0.0 && steady_mach_per_s > 0.0 && steady_roll_rate_rad_s > 0.0))
      throw std::invalid_argument("trim tracking: steady_roll_rate_rad_s, steady_climb_ft_s and steady_mach_per_s must be "
                                  "> 0, got " + std::to_string(steady_roll_rate_rad_s) + ", " +
                                  std::to_string(steady_climb_ft_s) + " and " + std::to_string(steady_mach_per_s));
    if (load_factor && !(steady_g > 0.0))
      throw std::invalid_argument("trim tracking: load_factor needs steady tracking (steady_g > 0), got steady_g " +
                                  std::to_string(steady_g));
    if (!(load_factor_time_constant_s > 0.0 && std::isfinite(load_factor_time_constant_s)))
      throw std::invalid_argument("trim tracking: load_factor_time_constant_s must be > 0 s, got " +
                                  std::to_string(load_factor_time_constant_s));
  }
  bool steady() const noexcept { return steady_g > 0.0; }
};

template <int NU, int NZ>
class TrimTracker {
 public:
  using UVector = Eigen::Matrix<double, NU, 1>;
  using ZVector = Eigen::Matrix<double, NZ, 1>;

  // measurement_names: the bank's (steady tracking resolves AZ and steady_measurements in
  // them; std::invalid_argument naming a missing one).
  TrimTracker(const TrimTrackingOptions& options, double frame_rate_hz, int nu, int nz,
              const std::vector<std::string>& measurement_names = {})
      : options_(options) {
    options.validate();
    gain_ = options.enabled() ? 1.0 - std::exp(-1.0 / (frame_rate_hz * options.time_constant_s)) : 0.0;
    hold_frames_ = static_cast<std::int64_t>(std::llround(options.hold_s * frame_rate_hz));
    du_ = UVector::Zero(nu);
    dz_ = ZVector::Zero(nz);
    mask_ = ZVector::Ones(nz);
    d1_ = ZVector::Zero(nz);
    load_factor_ = options.enabled() && options.load_factor;
    n_gain_ = load_factor_ ? 1.0 - std::exp(-1.0 / (frame_rate_hz * options.load_factor_time_constant_s)) : 0.0;
    if (options.enabled() && options.steady()) {
      az_ = find(measurement_names, "AZ");
      rol_ = find(measurement_names, "ROL");
      mask_.setZero();
      for (const auto& name : options.steady_measurements) mask_(find(measurement_names, name)) = 1.0;
    }
    options_.steady_measurements.clear();
    options_.steady_measurements.shrink_to_fit();
  }

  void reset() noexcept {
    du_.setZero();
    dz_.setZero();
    d1_.setZero();
    n_ = 1.0;
    held_for_ = 0;
    frozen_ = false;
    frozen_frames_ = 0;
  }

  // After frame i's update: `freezing` is the freeze condition on that frame (header);
  // z_pert = z_i - z_trim (the design/scheduled trim, without the offset).
  // Steady tracking: z_hat_pert = the bank's z_hat perturbation after the update (its AZ entry
  // is dn) and rates the air-data rates with every usable sample so far observed; a frame
  // beyond steady_g, steady_roll_rate_rad_s or the climb and Mach rates freezes as a freezing
  // frame does. z_abs: the frame's measurements (load-factor scaling reads its AZ, g; a
  // non-finite AZ leaves n as it was).
  template <class Z, class ZH, class ZA>
  void after_update(const Z& z_pert, bool freezing, const ZH& z_hat_pert, const AirDataRates& rates,
                    const ZA& z_abs) noexcept {
    if (load_factor_ && !freezing && std::isfinite(z_abs(az_))) n_ += n_gain_ * (z_abs(az_) - n_);
    if (load_factor_ && !(n_ >= TrimTrackingOptions::kLoadFactorTrackMin)) freezing = true;
    if (options_.steady() && !(std::abs(z_hat_pert(az_)) <= options_.steady_g &&
                               std::abs(z_hat_pert(rol_)) <= options_.steady_roll_rate_rad_s &&
                               !rates.changing(options_.steady_climb_ft_s, options_.steady_mach_per_s)))
      freezing = true;
    after_update(z_pert, freezing);
  }
  template <class Z>
  void after_update(const Z& z_pert, bool freezing) noexcept {
    if (!options_.enabled()) return;
    if (freezing && options_.freeze) held_for_ = hold_frames_ + 1;
    frozen_ = held_for_ > 0;
    if (held_for_ > 0) --held_for_;
    if (load_factor_) {
      if (frozen_)
        ++frozen_frames_;
      else
        d1_ += gain_ * (z_pert / n_ - d1_).cwiseProduct(mask_);
      dz_ = n_ * d1_;
      return;
    }
    if (frozen_) {
      ++frozen_frames_;
      return;
    }
    if (options_.steady())
      dz_ += gain_ * (z_pert - dz_).cwiseProduct(mask_);
    else
      dz_ += gain_ * (z_pert - dz_);
  }
  // After frame i's propagate: u_pert = u_i - u_trim.
  template <class U>
  void after_propagate(const U& u_pert) noexcept {
    if (!options_.enabled() || frozen_) return;
    du_ += gain_ * (u_pert - du_);
  }

  const UVector& du() const noexcept { return du_; }
  const ZVector& dz() const noexcept { return dz_; }                   // in force (load factor: n d1)
  const ZVector& dz_1g() const noexcept { return load_factor_ ? d1_ : dz_; }   // the tracked 1-g offset
  double load_factor() const noexcept { return n_; }                    // n (1 without load-factor scaling)
  bool frozen() const noexcept { return frozen_; }                      // on the last frame
  std::int64_t frozen_frames() const noexcept { return frozen_frames_; }  // since reset
  double gain() const noexcept { return gain_; }
  const TrimTrackingOptions& options() const noexcept { return options_; }
  const ZVector& mask() const noexcept { return mask_; }   // 1: a tracked measurement

 private:
  static int find(const std::vector<std::string>& names, const std::string& name) {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return static_cast<int>(i);
    std::string valid;
    for (const auto& n : names) valid += (valid.empty() ? "" : ", ") + n;
    throw std::invalid_argument("trim tracking: steady tracking needs the measurement '" + name +
                                "'; the bank's: " + valid);
  }

  TrimTrackingOptions options_;
  double gain_ = 0.0;
  std::int64_t hold_frames_ = 0, held_for_ = 0, frozen_frames_ = 0;
  bool frozen_ = false, load_factor_ = false;
  double n_gain_ = 0.0, n_ = 1.0;
  int az_ = 0, rol_ = 0;
  UVector du_;
  ZVector dz_, mask_, d1_;
};

}  // namespace f16mmae
