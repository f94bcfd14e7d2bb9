// CompleteTrimHold — the trim a complete sensor failure reads, held while a failure is
// suspected or declared (issues 13-14). Eigen and std only.
//
// The paper's complete failure of sensor j: the sensor reads its trim plus noise. Its
// hypothesis filter k has H_k's row j zero, so channel j's residual is the reading against the
// trim in force,
//   r_kj = z_j - z_trim_j - dz_j,
// with A_k's row and column j zero off the diagonal and K_k's column j zero (a complete channel
// informs no state). A scheduled bank's z_trim follows the measured air data, and the trim
// tracker's dz the slow offsets (trim_tracker.h). A healthy sensor moves with them; a failed one
// does not: in light air the airspeed wanders by a few ft/s over seconds, the scheduled AOA trim
// with it by up to 0.003-0.005 rad (two to three AOA noise sigmas) while a failed AOA sensor
// reads one value. The no-failure filter, which reads the stuck value as the aircraft's angle of
// attack, then fits better than the complete hypothesis, which expects the moving trim: a failed
// AOA declared at 3.3 s is backed out to NONE at 7.5 s as the trim drifts away
// (docs/results/envelope_scheduled.md, round 26).
//
// The rule (options.hold, options.time_constant_s = T): the reference
//   z_ref = z_trim + dz    on every update with no failure held for (T = 0), or
//   z_ref <- z_ref + a_i (z_trim + dz - z_ref),  a_i = max(1 / i, 1 - exp(-1 / (T f)))
//                          (T > 0, f the frame rate, i the updates since the start: a plain mean
//                          over the first T f updates, as the adaptation's ρ̄): the flight
//                          condition's trim over the last T seconds, which the gusts' wander of
//                          the measured airspeed moves far less than the trim in force,
//   z_ref held             while one is: `suspected`, a failure declared (level 1, or a declared
//                          failure current) or a failure hypothesis on line above the trim
//                          tracker's freeze probability (hierarchical_bank.h trim_freezing);
//                          `declared`, a failure declared only,
// and every complete channel j of every filter reads against it:
//   r_kj = z_j - z_ref_j = r_kj(trim in force) + d_j,   d = (z_trim + dz) - z_ref,
//   q_k += (2 r_kj + d_j) d_j (A_k⁻¹)_jj                 (exact: A_k is diagonal on j),
// applied by the filter bank after each update (FilterBank::set_held_offset). The states, the
// gains and every informative channel are untouched; with nothing held and T = 0, d = 0 and the
// bank is bit for bit as without the rule. So the complete failure reads the trim the aircraft
// flew (over the last T seconds) when the failure began to show (`suspected`) or was declared
// (`declared`). Why `declared`
// too: held from a false rise, the trim a healthy sensor is compared with stays where the rise
// began while the trim in force moves on, and the rise can last (Mach 0.35, 25,000 ft: a false AOA
// rising while a gust speeds the aircraft up; docs/results/envelope_scheduled.md, round 26).
// Why the average (T > 0): before a failure is declared, a failed AOA is compared with the trim
// in force, which light air moves by 0.003 rad (1.7 noise sigmas) within seconds after the
// failure, so the no-failure filter and the VEL hypothesis (free of the airspeed reading, it
// explains the stuck angle's lift changes by an airspeed gust) fit the stuck reading better than
// the AOA hypothesis does; the average over T moves with the flight condition, not with the
// gusts. Its price: where the scheduled trim swings more than the aircraft's own angle of attack
// (Mach 0.35, 25,000 ft) the average also fits a healthy AOA better, so false AOA rises there are
// more frequent (docs/results/envelope_scheduled.md, round 27).
// A failed sensor whose level the hypothesis tracks (a `constant` or `cover` level,
// steady_state_filter.h) is not a complete channel: its level is already absolute
// (hierarchical_bank.h shifts it with the scheduled trim).
//
// Complete channels (channels_of): channel j of hypothesis k when H_k's row j is zero, A_k's
// row j zero off the diagonal and the channel not uninformative (width 0 or no widths). Per
// frame noexcept, no allocation for fixed sizes (the offset vector is sized at construction).
#pragma once

#include <Eigen/Dense>

#include "f16mmae/estimator_settings.h"
#include "f16mmae/model_bank.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace f16mmae {

// When the reference is held (options.hold).
enum class TrimHold {
  kOff,         // never: every r_kj against the trim in force (the paper's model as designed)
  kSuspected,   // while a failure is suspected: declared, or a failure hypothesis rising
  kDeclared,    // while a failure is declared only
};
// "off", "suspected", "declared" (the option's words); std::invalid_argument naming the word else.
inline TrimHold parse_trim_hold(const std::string& word) {
  if (word == "off") return TrimHold::kOff;
  if (word == "suspected") return TrimHold::kSuspected;
  if (word == "declared") return TrimHold::kDeclared;
  throw std::invalid_argument("complete_trim_hold must be 'off', 'suspected' or 'declared', got '" + word + "'");
}
inline const char* trim_hold_name(TrimHold h) noexcept {
  return h == TrimHold::kSuspected ? "suspected" : h == TrimHold::kDeclared ? "declared" : "off";
}

struct CompleteTrimHoldOptions {
  TrimHold hold = TrimHold::kOff;
  double time_constant_s = 0.0;   // T: the reference the trim in force averaged over T s (0: the trim in force)
  bool enabled() const noexcept { return hold != TrimHold::kOff || time_constant_s > 0.0; }
};

template <int NZ>
class CompleteTrimHold {
 public:
  using ZVector = Eigen::Matrix<double, NZ, 1>;

  CompleteTrimHold() = default;
  // Throws std::invalid_argument "complete_trim_time_constant_s ..." for T outside [0, 3600] s or
  // a frame rate that is not positive and finite.
  CompleteTrimHold(const CompleteTrimHoldOptions& options, int nz, double frame_rate_hz = 64.0) : options_(options) {
    const double t = options.time_constant_s;
    if (!(t >= 0.0 && t <= 3600.0))
      throw std::invalid_argument("complete_trim_time_constant_s must be in [0, 3600] s (0: the trim in force), got " +
                                  format_value(t));
    if (!(std::isfinite(frame_rate_hz) && frame_rate_hz > 0.0))
      throw std::invalid_argument("complete trim hold: the frame rate must be positive, got " +
                                  format_value(frame_rate_hz));
    gain_ = t > 0.0 ? 1.0 - std::exp(-1.0 / (t * frame_rate_hz)) : 1.0;
    z_ref_ = ZVector::Zero(nz);
    offset_ = ZVector::Zero(nz);
  }

  // Bit j set: channel j is a complete channel of hypothesis `h` (header; channels j < 32).
  static std::uint32_t channels_of(const HypothesisModel& h) noexcept {
    std::uint32_t bits = 0;
    const Eigen::Index nz = h.h.rows();
    for (Eigen::Index j = 0; j < nz && j < 32; ++j) {
      if (!h.h.row(j).isZero(0.0)) continue;
      if (h.uninformative_width.size() == nz && h.uninformative_width(j) > 0.0) continue;
      bool coupled = false;
      for (Eigen::Index i = 0; i < nz; ++i) coupled = coupled || (i != j && h.a(j, i) != 0.0);
      if (!coupled) bits |= 1u << j;
    }
    return bits;
  }

  bool enabled() const noexcept { return options_.enabled(); }
  const CompleteTrimHoldOptions& options() const noexcept { return options_; }

  // The reference for this update from the trim in force (z_trim + dz): followed (or averaged,
  // T > 0) while no failure is held for, else held. Returns d = (z_trim + dz) - z_ref (zero while
  // following with T = 0).
  template <class Z>
  const ZVector& observe(const Eigen::MatrixBase<Z>& trim_in_force, bool held) noexcept {
    if (!started_ || (!held && gain_ == 1.0)) {
      z_ref_ = trim_in_force;
      started_ = true;
      averaged_ = 1;
    } else if (!held) {
      ++averaged_;
      const double a = std::max(1.0 / static_cast<double>(averaged_), gain_);
      z_ref_ += a * (trim_in_force - z_ref_);
    }
    if (!held && gain_ == 1.0) {
      offset_.setZero();
    } else {
      offset_ = trim_in_force;
      offset_ -= z_ref_;
    }
    return offset_;
  }
  const ZVector& reference() const noexcept { return z_ref_; }
  const ZVector& offset() const noexcept { return offset_; }
  bool holding() const noexcept { return started_ && !offset_.isZero(0.0); }
  void reset() noexcept {
    started_ = false;
    offset_.setZero();
  }
  // The hold of `from` (a bank of the same measurements taking over; turbulence_bank_set.h).
  void carry_over(const CompleteTrimHold& from) noexcept {
    z_ref_ = from.z_ref_;
    offset_ = from.offset_;
    started_ = from.started_;
    averaged_ = from.averaged_;
  }

 private:
  CompleteTrimHoldOptions options_{};
  double gain_ = 1.0;            // 1 - exp(-1 / (T f)); 1 with T = 0 (the trim in force)
  std::int64_t averaged_ = 0;    // i: the updates averaged since the start
  ZVector z_ref_, offset_;
  bool started_ = false;
};

}  // namespace f16mmae
