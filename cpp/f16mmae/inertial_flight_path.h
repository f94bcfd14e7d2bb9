// InertialFlightPath — the flight-path angle gamma and the acceleration a = dV/dt the maneuver
// trim (maneuver_trim.h) needs, fast from the rate gyros, the angle of attack and the airspeed of
// the measurements z, slow from the air data's rates: a complementary filter. The air data's
// rates alone (pressure altitude and Mach, low-passed against their noise) lag a pull-up, a
// push-over, a roll-in or an acceleration's start by seconds; the pitch rate does not.
// Nothing allocates; every quantity is a scalar.
//
// Inputs per frame (dt = 1 / f): from z (absolute) the pitch, roll and yaw rates q, p, r (rad/s),
// the angle of attack alpha (rad) and the airspeed V (ft/s); from the air data gamma_air (rad)
// and a_air (ft/s^2) (maneuver_trim.h's rates); and `frozen` (a failure is suspected: below).
// With c_T = 1 - exp(-1 / (T f)) the gain of a first-order low-pass of time constant T:
//   bank angle, complementary (the roll rate fast, the coordinated turn's bank slow):
//     phi_ref = asin(clamp(V r / g, -0.9, 0.9))     (a coordinated turn at small theta:
//                                                     r = psi_dot cos phi, tan phi = V psi_dot / g)
//     phi    += dt p + c_{T_phi} (phi_ref - phi)
//   the pitch attitude's rate (Euler kinematics)  theta_dot = q cos phi - r sin phi
//   angle of attack, low-passed                   alpha_f += c_{T_alpha} (alpha - alpha_f)
//   pitch attitude, complementary (the pitch rate fast, the air data's gamma slow):
//     theta  += dt theta_dot + c_{T_c} (gamma_air + alpha_f - theta)
//   gamma   = theta - alpha_f, kept within gamma_air +- max_gap_rad
//   airspeed rate from the airspeed: two low-passes of V with T_v and 5 T_v,
//     a_v = (lp_{T_v}(V) - lp_{5 T_v}(V)) / (4 T_v)  (a ramp of slope s settles at s)
//   a       = a_v, kept within a_air +- max_gap_fps2
// A steady climb: theta_dot = 0, theta -> gamma_air + alpha_f, gamma -> gamma_air. A pull-up:
// gamma follows the integrated pitch rate at once and the air data take over over T_c. In a
// steady coordinated turn theta_dot = q cos phi - r sin phi = 0 (q = psi_dot sin phi,
// r = psi_dot cos phi), so the turn's pitch rate is not read as a climb.
//
// The freeze rule (as the trim tracker's, trim_tracker.h): while `frozen` (the bank's: level 1,
// a failure declared, or a failure hypothesis on line above the freeze probability) none of the
// sensors of z is read: phi and alpha_f hold, theta moves only by the slow term
//   theta += c_{T_c} (gamma_air + alpha_f - theta),  a += c_{T_c} (a_air - a)
// so gamma and a go over to the air data's own (which no failure hypothesis concerns) and a failed
// gyro, AOA or VEL sensor cannot drive the trim to absorb its failure. The airspeed's low-passes
// restart at the first frame after a freeze, continuing its a: lp_{T_v} = V,
// lp_{5 T_v} = V - 4 T_v a. The first frame starts everything at its readings (phi = phi_ref,
// alpha_f = alpha, theta = gamma_air + alpha, a = a_air).
// Options are checked by validate() (std::invalid_argument naming the value and its range).
#pragma once

#include "f16mmae/estimator_settings.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace f16mmae {

struct InertialFlightPathOptions {
  double blend_time_constant_s = 2.0;   // T_c: the air data take over the attitude after this
  double alpha_time_constant_s = 0.5;   // T_alpha
  double roll_time_constant_s = 2.0;    // T_phi
  double vel_time_constant_s = 0.25;    // T_v (the airspeed's rate: T_v and 5 T_v)
  double max_gap_rad = 0.15;            // |gamma - gamma_air| at most this
  double max_gap_fps2 = 10.0;           // |a - a_air| at most this
  void validate() const {
    auto check = [](double v, double lo, double hi, const char* what) {
      if (!(v >= lo && v <= hi))
        throw std::invalid_argument(std::string("inertial flight path: ") + what + " must be in [" +
                                    format_value(lo) + ", " + format_value(hi) + "], got " + format_value(v));
    };
    check(blend_time_constant_s, 0.05, 600.0, "blend_time_constant_s");
    check(alpha_time_constant_s, 0.0, 60.0, "alpha_time_constant_s");
    check(roll_time_constant_s, 0.05, 600.0, "roll_time_constant_s");
    check(vel_time_constant_s, 0.02, 60.0, "vel_time_constant_s");
    check(max_gap_rad, 0.0, 1.5, "max_gap_rad");
    check(max_gap_fps2, 0.0, 1000.0, "max_gap_fps2");
  }
};

class InertialFlightPath {
 public:
  static constexpr double kG = 32.174;   // ft/s^2
  InertialFlightPath() = default;
  InertialFlightPath(const InertialFlightPathOptions& o, double frame_rate_hz) : o_(o) {
    o.validate();
    if (!(frame_rate_hz > 0.0))
      throw std::invalid_argument("inertial flight path: the frame rate must be > 0, got " + format_value(frame_rate_hz));
    dt_ = 1.0 / frame_rate_hz;
    auto gain = [frame_rate_hz](double t) { return t > 0.0 ? 1.0 - std::exp(-1.0 / (t * frame_rate_hz)) : 1.0; };
    c_blend_ = gain(o.blend_time_constant_s);
    c_alpha_ = gain(o.alpha_time_constant_s);
    c_roll_ = gain(o.roll_time_constant_s);
    c_vf_ = gain(o.vel_time_constant_s);
    c_vs_ = gain(5.0 * o.vel_time_constant_s);
  }
  const InertialFlightPathOptions& options() const noexcept { return o_; }

  void reset() noexcept {
    seen_ = started_ = false;
    vel_seen_ = false;
    phi_ = alpha_f_ = theta_ = gamma_ = accel_ = vf_ = vs_ = 0.0;
  }
  // One frame (header). Non-finite readings count as frozen.
  void observe(double q, double p, double r, double alpha, double vel, double gamma_air, double a_air,
               bool frozen) noexcept {
    if (!std::isfinite(gamma_air) || !std::isfinite(a_air)) return;
    started_ = true;
    if (!(std::isfinite(q) && std::isfinite(p) && std::isfinite(r) && std::isfinite(alpha) && std::isfinite(vel)))
      frozen = true;
    if (!seen_) {
      if (frozen) {   // nothing read yet: the air data's own
        gamma_ = gamma_air;
        accel_ = a_air;
        return;
      }
      phi_ = phi_ref(vel, r);
      alpha_f_ = alpha;
      theta_ = gamma_air + alpha;
      gamma_ = gamma_air;
      accel_ = a_air;
      restart_vel(vel, a_air);
      seen_ = true;
      return;
    }
    if (frozen) {
      theta_ += c_blend_ * (gamma_air + alpha_f_ - theta_);
      accel_ += c_blend_ * (a_air - accel_);
      vel_seen_ = false;
    } else {
      phi_ = phi_step(phi_, p, vel, r, dt_, c_roll_);
      const double theta_dot = q * std::cos(phi_) - r * std::sin(phi_);
      alpha_f_ += c_alpha_ * (alpha - alpha_f_);
      theta_ += dt_ * theta_dot + c_blend_ * (gamma_air + alpha_f_ - theta_);
      if (!vel_seen_) {
        restart_vel(vel, accel_);
      } else {
        vf_ += c_vf_ * (vel - vf_);
        vs_ += c_vs_ * (vel - vs_);
        accel_ = (vf_ - vs_) / (4.0 * o_.vel_time_constant_s);
      }
    }
    theta_ = std::clamp(theta_, gamma_air + alpha_f_ - o_.max_gap_rad, gamma_air + alpha_f_ + o_.max_gap_rad);
    gamma_ = theta_ - alpha_f_;
    accel_ = std::clamp(accel_, a_air - o_.max_gap_fps2, a_air + o_.max_gap_fps2);
  }
  bool seen() const noexcept { return started_; }   // a frame with finite air-data rates has come
  // The coordinated turn's bank angle, asin(clamp(V r / g, -0.9, 0.9)) (header; V ft/s, r rad/s).
  static double phi_ref(double vel, double r) noexcept {
    return std::asin(std::clamp(vel * r / kG, -0.9, 0.9));
  }
  // One frame of the bank angle's complementary filter (header): phi + dt p + c (phi_ref - phi).
  static double phi_step(double phi, double p, double vel, double r, double dt, double c) noexcept {
    return phi + dt * p + c * (phi_ref(vel, r) - phi);
  }
  double gamma() const noexcept { return gamma_; }   // rad
  double accel() const noexcept { return accel_; }   // ft/s^2
  double phi() const noexcept { return phi_; }       // rad, the bank angle estimate
  double theta() const noexcept { return theta_; }   // rad, the pitch attitude estimate

 private:
  void restart_vel(double vel, double a) noexcept {
    vf_ = vel;
    vs_ = vel - 4.0 * o_.vel_time_constant_s * a;
    vel_seen_ = true;
  }
  InertialFlightPathOptions o_;
  double dt_ = 1.0 / 64.0;
  double c_blend_ = 0.0, c_alpha_ = 0.0, c_roll_ = 0.0, c_vf_ = 0.0, c_vs_ = 0.0;
  bool seen_ = false, vel_seen_ = false, started_ = false;
  double phi_ = 0.0, alpha_f_ = 0.0, theta_ = 0.0, gamma_ = 0.0, accel_ = 0.0, vf_ = 0.0, vs_ = 0.0;
};

}  // namespace f16mmae
