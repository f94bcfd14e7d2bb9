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
// Options: time_constant_s > 0 enables it (0 = off: offsets stay zero, the bank behaves
// exactly as without a tracker); freeze_probability in (0, 1]; hold_s >= 0; freeze = false
// never freezes (for comparison only: such a tracker absorbs a failure into the trim).
#pragma once

#include <Eigen/Dense>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace f16mmae {

struct TrimTrackingOptions {
  double time_constant_s = 0.0;      // tau; 0 = off
  double freeze_probability = 0.05;  // a failure hypothesis above this freezes the estimate
  double hold_s = 2.0;               // held this long after the last freezing frame
  bool freeze = true;                // false: never frozen (comparison only)

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
  }
};

template <int NU, int NZ>
class TrimTracker {
 public:
  using UVector = Eigen::Matrix<double, NU, 1>;
  using ZVector = Eigen::Matrix<double, NZ, 1>;

  TrimTracker(const TrimTrackingOptions& options, double frame_rate_hz, int nu, int nz)
      : options_(options) {
    options.validate();
    gain_ = options.enabled() ? 1.0 - std::exp(-1.0 / (frame_rate_hz * options.time_constant_s)) : 0.0;
    hold_frames_ = static_cast<std::int64_t>(std::llround(options.hold_s * frame_rate_hz));
    du_ = UVector::Zero(nu);
    dz_ = ZVector::Zero(nz);
  }

  void reset() noexcept {
    du_.setZero();
    dz_.setZero();
    held_for_ = 0;
    frozen_ = false;
    frozen_frames_ = 0;
  }

  // After frame i's update: `freezing` is the freeze condition on that frame (header);
  // z_pert = z_i - z_trim (the design/scheduled trim, without the offset).
  template <class Z>
  void after_update(const Z& z_pert, bool freezing) noexcept {
    if (!options_.enabled()) return;
    if (freezing && options_.freeze) held_for_ = hold_frames_ + 1;
    frozen_ = held_for_ > 0;
    if (held_for_ > 0) --held_for_;
    if (frozen_) {
      ++frozen_frames_;
      return;
    }
    dz_ += gain_ * (z_pert - dz_);
  }
  // After frame i's propagate: u_pert = u_i - u_trim.
  template <class U>
  void after_propagate(const U& u_pert) noexcept {
    if (!options_.enabled() || frozen_) return;
    du_ += gain_ * (u_pert - du_);
  }

  const UVector& du() const noexcept { return du_; }
  const ZVector& dz() const noexcept { return dz_; }
  bool frozen() const noexcept { return frozen_; }                      // on the last frame
  std::int64_t frozen_frames() const noexcept { return frozen_frames_; }  // since reset
  double gain() const noexcept { return gain_; }
  const TrimTrackingOptions& options() const noexcept { return options_; }

 private:
  TrimTrackingOptions options_;
  double gain_ = 0.0;
  std::int64_t hold_frames_ = 0, held_for_ = 0, frozen_frames_ = 0;
  bool frozen_ = false;
  UVector du_;
  ZVector dz_;
};

}  // namespace f16mmae
