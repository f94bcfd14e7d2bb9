// ManeuverTrim — the trim of a steady climb (flight-path angle gamma) and of a steady
// acceleration (dV/dt), as offsets of the level trim the filters are linearized about, read from
// the measured air data only (pressure altitude and Mach rates). Nothing allocates per frame.
//
// Why: every filter is linear about wings-level, unaccelerated, level flight at the scheduled
// (Mach, altitude). In a steady climb at gamma the aircraft's pitch attitude is higher by
// about gamma, its elevator and angle of attack differ slightly, and its engine gives the thrust
// that holds the speed against g sin(gamma); a bank without the throttle as an input models
// neither that thrust nor the attitude. Its filters integrate the measured pitch rate of the
// pull-up into theta, then predict the deceleration of a climb without thrust, and the VEL and
// AOA residuals run off until the filters' gains walk theta back: what a failed (constant)
// air-data sensor explains. Likewise in a steady acceleration the scheduled trim's airspeed
// moves and the thrust that moves it is missing.
//
// The offsets. Let the filter model (the NONE hypothesis of a node, discrete, frame dt) be
//   x_{k+1} = Phi x_k + Bd u_k,   z_k = H x_k,
// x the perturbation from the level trim (states named u_fps, alpha_rad, theta_rad, ...),
// u the commands (LS RS LF RF RUD, and THR if the bank has the throttle as an input).
// The quasi-steady flight at (gamma, a = dV/dt) is the state x_s, commands u_s and unmodelled
// thrust acceleration t (ft/s^2 along the body x axis; a bank with the throttle input has its
// throttle in u_s and no t) with
//   (Phi - I) x_s + Bd u_s + dt b_T t = dt a e_u            (to first order in dt: A x_s + B u_s +
//                                                             b_T t = a e_u, the airspeed's ramp)
//   x_s(u_fps) = 0                                           (the airspeed is the schedule's)
//   x_s(theta_rad) - x_s(alpha_rad) = gamma                  (the flight-path angle)
//   u_s(LS) = u_s(RS),  u_s(LF) = u_s(RF) = u_s(RUD) = 0     (symmetric pitch control only)
// with b_T = e_u - e_alpha sin(alpha_0) / V_0 (thrust along the body x axis: u' = t and
// alpha' = -w t / (u^2 + w^2)), (V_0, alpha_0) the trim's VEL and AOA. nx + nu (+ 1) unknowns,
// as many equations; solved per node (column-pivoting QR; a rank-deficient system is refused).
// Linear in (gamma, a): x_s = S_x (gamma, a)', u_s = S_u (gamma, a)', and z_s = H x_s = S_z
// (gamma, a)'. S_x, S_u, S_z are the node's sensitivities (trim_sensitivity() below). They are
// a function of the node's own filter model, which the bank file carries; they are computed
// when the bank is built, so every bank file has them and none needs a field for them.
//
// What the bank does (HierarchicalOptions::maneuver_trim; HierarchicalBank::schedule): per
// usable air-data sample (Mach M, pressure altitude h)
//   two first-order low-passes of h and of M each, time constants T and 5 T (T = time_constant_s)
//     lp_T' += c_T (v - lp_T'),  c_T = 1 - exp(-1 / (T' f))
//   h_dot = (lp_T(h) - lp_5T(h)) / (4 T),  M_dot likewise      (air_data_rates.h's estimator;
//                                                               a ramp of slope r settles at r)
//   c    = V_trim / M_trim   (the speed of sound of the scheduled trim in force: its VEL over
//                             the Mach it is scheduled at; a bank of one node: its design's)
//   V    = c lp_T(M),   gamma = asin(clamp(h_dot / V, -sin gamma_max, sin gamma_max)),
//   a    = clamp(c M_dot, -a_max, a_max)   (0 with accel = false: the climb's trim only)
//   S    = sum_c w_c S_c over the nodes and weights of the filters in force
//   (du, dz, dx) = (S_u, S_z, S_x) (gamma, a)'
// and the trim in force becomes u_trim + du, z_trim + dz, x_trim + dx: the bank subtracts them
// from u and z, and, as for a change of the scheduled trim, every on-line filter's states move
// by dx_old - dx_new (bumpless: the absolute state estimate is continuous; the filters' theta is
// then measured from the climb's attitude) and the failed sensors' levels by dz_old - dz_new.
// Nothing here reads the truth: the air data are the scheduling input, the sensitivities the
// bank's own model. It cannot absorb a failure: (gamma, a) come from the air data alone, which
// no failure hypothesis concerns (air-data failures are out of scope).
// With options.accel_airspeed_rad_s = w0 > 0 the acceleration a comes instead from the airspeed of
// z (AirspeedAccel below: V = VEL / cos(AOA), a second-order tracking differentiator of natural
// frequency w0, damping 1/sqrt(2)), gamma staying the air data's. Why: the rate of the air data's
// Mach, (lp_T - lp_5T) / (4 T), is the derivative seen through two cascaded first-order lags,
//   a_air(s) = s V(s) / ((1 + T s)(1 + 5 T s)),
// whose step response in a lags by its mean delay T + 5 T = 6 T (3 s at T = 0.5 s); T is set by
// the Mach noise (sigma 0.002, about 2 ft/s of airspeed per frame), which a differentiator
// amplifies. The VEL sensor's white noise is about a quarter of that (0.5 ft/s), and a
// differentiator's white-noise variance grows as w0^3 (below), so at the same noise the airspeed's
// rate may be about 4^(2/3) = 2.5 times faster. The gusts are in both (both are air-relative).
// With options.inertial (gamma, a) come instead from inertial_flight_path.h: the pitch rate,
// roll and yaw rates, AOA and VEL of z, complementary to the air data's (gamma, a) above, fed by
// HierarchicalBank::update after each measurement update with the bank's freeze condition (the
// trim tracker's: a failure hypothesis rising, declared or level 1), under which it reads none of
// z and goes over to the air data's, so a failed sensor cannot drive the trim to absorb it. The
// (gamma, a) of frame k are applied at the schedule() of frame k + 1.
// With options.gamma_load_factor gamma is instead the air data's plus what their low-passes hold
// back of the path's turn, from the normal load factor AZ of z (ClimbAngleComplement below):
// the air data's climb rate is the truth's through L(s) = 1 / ((1 + T s)(1 + 5 T s)), so
//   gamma = gamma_air + (1 - L(s)) / s  gamma_dot_n,
//   gamma_dot_n = (g / V) (n_w cos phi - cos gamma)    (the flight path's pitch-up rate, wind axes;
//                 n_w the lift axis' load factor from the body axis' AZ and AOA)
// is gamma_air + (1 - L) gamma = gamma where gamma_dot_n is right: without the lag (mean delay
// 6 T) at a pull-out or level-off, and, as (1 - L(s)) / s has the finite gain 6 T at s = 0, a
// steady error e of gamma_dot_n only moves gamma by 6 T e (no integration drift); in a steady
// climb or turn gamma_dot_n = 0 and gamma is the air data's. The acceleration is unchanged (the
// air data's, or AirspeedAccel's with accel_airspeed_rad_s > 0).
// Off (enabled = false, the default): the bank as designed, bit for bit.
// Options are checked by validate() (std::invalid_argument naming the value and its range).
#pragma once

#include "f16mmae/estimator_settings.h"
#include "f16mmae/inertial_flight_path.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace f16mmae {

struct ManeuverTrimOptions {
  bool enabled = false;
  double time_constant_s = 0.5;       // T: the rates' low-passes are T and 5 T
  double gamma_max_rad = 0.5;         // |gamma| at most this
  double accel_max_fps2 = 32.174;     // |dV/dt| at most this (1 g)
  bool accel = true;                  // false: a = 0 (the climb's trim only)
  bool inertial = false;              // (gamma, a) from inertial_flight_path.h (header); false: the air data's
  InertialFlightPathOptions inertial_path;
  double accel_airspeed_rad_s = 0.0;  // w0 > 0: a from the airspeed of z (AirspeedAccel); 0: the air data's
  bool gamma_load_factor = false;     // gamma: the air data's plus ClimbAngleComplement's (AZ, ROL, YAW of z)
  void validate() const {
    if (!enabled) return;
    if (inertial && gamma_load_factor)
      throw std::invalid_argument("maneuver trim: the inertial rates and the load factor's climb angle exclude each "
                                  "other (the inertial rates have their own climb angle), got both");
    if (inertial) inertial_path.validate();
    if (!(accel_airspeed_rad_s == 0.0 || (accel_airspeed_rad_s >= 0.05 && accel_airspeed_rad_s <= 20.0)))
      throw std::invalid_argument("maneuver trim: accel_airspeed_rad_s must be 0 (the air data's acceleration) or "
                                  "in [0.05, 20] rad/s, got " + format_value(accel_airspeed_rad_s));
    if (inertial && accel_airspeed_rad_s > 0.0)
      throw std::invalid_argument("maneuver trim: the inertial rates and the airspeed's acceleration exclude each "
                                  "other (the inertial rates have their own airspeed rate), got both");
    if (!(time_constant_s >= 0.05 && time_constant_s <= 60.0))
      throw std::invalid_argument("maneuver trim: time_constant_s must be in [0.05, 60] s, got " +
                                  format_value(time_constant_s));
    if (!(gamma_max_rad > 0.0 && gamma_max_rad <= 1.5))
      throw std::invalid_argument("maneuver trim: gamma_max_rad must be in (0, 1.5] rad, got " +
                                  format_value(gamma_max_rad));
    if (!(accel_max_fps2 > 0.0 && accel_max_fps2 <= 1000.0))
      throw std::invalid_argument("maneuver trim: accel_max_fps2 must be in (0, 1000] ft/s^2, got " +
                                  format_value(accel_max_fps2));
  }
};

// d(x_trim, u_trim, z_trim) / d(gamma [rad], dV/dt [ft/s^2]) of one filter model (header).
struct TrimSensitivity {
  Eigen::MatrixXd x;        // (nx, 2)
  Eigen::MatrixXd u;        // (nu, 2)
  Eigen::MatrixXd z;        // (nz, 2)
  Eigen::Vector2d thrust{0.0, 0.0};   // t per unit gamma and per unit a (ft/s^2); 0 with a throttle input
};

namespace maneuver_trim_detail {
inline int find(const std::vector<std::string>& names, const char* name) {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);
  return -1;
}
inline int need(const std::vector<std::string>& names, const char* name, const char* what) {
  const int i = find(names, name);
  if (i < 0)
    throw std::invalid_argument(std::string("maneuver trim: the model bank has no ") + what + " '" + name +
                                "' (it needs the states u_fps alpha_rad theta_rad and the inputs LS RS LF RF RUD)");
  return i;
}
}  // namespace maneuver_trim_detail

// The sensitivities of the header for the model (phi, bd, h) with its state and input names,
// frame rate f (dt = 1/f) and trim airspeed v0_fps, angle of attack alpha0_rad.
// Throws std::invalid_argument for a missing name, mismatched sizes or a singular system.
inline TrimSensitivity trim_sensitivity(const Eigen::MatrixXd& phi, const Eigen::MatrixXd& bd,
                                        const Eigen::MatrixXd& h, const std::vector<std::string>& state_names,
                                        const std::vector<std::string>& input_names, double frame_rate_hz,
                                        double v0_fps, double alpha0_rad) {
  using maneuver_trim_detail::need;
  const int nx = static_cast<int>(phi.rows()), nu = static_cast<int>(bd.cols()), nz = static_cast<int>(h.rows());
  if (phi.cols() != nx || bd.rows() != nx || h.cols() != nx || static_cast<int>(state_names.size()) != nx ||
      static_cast<int>(input_names.size()) != nu)
    throw std::invalid_argument("maneuver trim: the model's sizes do not match its names");
  if (!(frame_rate_hz > 0.0) || !(v0_fps > 0.0) || !std::isfinite(alpha0_rad))
    throw std::invalid_argument("maneuver trim: needs a frame rate > 0, a trim airspeed > 0 and a finite trim "
                                "angle of attack, got " + format_value(frame_rate_hz) + ", " + format_value(v0_fps) +
                                ", " + format_value(alpha0_rad));
  const int iu = need(state_names, "u_fps", "state"), ia = need(state_names, "alpha_rad", "state"),
            it = need(state_names, "theta_rad", "state");
  const int ls = need(input_names, "LS", "input"), rs = need(input_names, "RS", "input"),
            lf = need(input_names, "LF", "input"), rf = need(input_names, "RF", "input"),
            rud = need(input_names, "RUD", "input");
  const bool throttle = maneuver_trim_detail::find(input_names, "THR") >= 0;
  const double dt = 1.0 / frame_rate_hz;
  const int nt = throttle ? 0 : 1;          // the thrust unknown
  const int n = nx + nu + nt;               // unknowns: x_s, u_s, t
  const int m = nx + 6;                     // equations: the model, then the six constraints
  if (n != m)
    throw std::invalid_argument("maneuver trim: " + std::to_string(n) + " unknowns for " + std::to_string(m) +
                                " equations (the inputs must be LS RS LF RF RUD, and THR optionally)");
  Eigen::MatrixXd lhs = Eigen::MatrixXd::Zero(m, n);
  lhs.block(0, 0, nx, nx) = phi - Eigen::MatrixXd::Identity(nx, nx);
  lhs.block(0, nx, nx, nu) = bd;
  if (!throttle) {
    lhs(iu, nx + nu) = dt;
    lhs(ia, nx + nu) = -dt * std::sin(alpha0_rad) / v0_fps;
  }
  lhs(nx + 0, iu) = 1.0;
  lhs(nx + 1, it) = 1.0;
  lhs(nx + 1, ia) = -1.0;
  lhs(nx + 2, nx + ls) = 1.0;
  lhs(nx + 2, nx + rs) = -1.0;
  lhs(nx + 3, nx + lf) = 1.0;
  lhs(nx + 4, nx + rf) = 1.0;
  lhs(nx + 5, nx + rud) = 1.0;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(m, 2);
  rhs(nx + 1, 0) = 1.0;   // gamma
  rhs(iu, 1) = dt;        // a
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(lhs);
  if (qr.rank() < n)
    throw std::invalid_argument("maneuver trim: the model's climb and acceleration trims are not unique "
                                "(rank " + std::to_string(qr.rank()) + " of " + std::to_string(n) + ")");
  const Eigen::MatrixXd v = qr.solve(rhs);
  if (!v.allFinite()) throw std::invalid_argument("maneuver trim: the model's climb trim is not finite");
  TrimSensitivity s;
  s.x = v.topRows(nx);
  s.u = v.middleRows(nx, nu);
  s.z = h * s.x;
  if (!throttle) s.thrust = v.row(nx + nu).transpose();
  return s;
}

// AirspeedAccel — the acceleration a = dV/dt from the airspeed of z (header of the file: why).
// Per frame (dt = 1 / f) the measured airspeed V_m = VEL / cos(AOA) (VEL is the body-axis forward
// airspeed u_a = V cos(alpha) cos(beta), beta ~ 0) drives the tracking differentiator
//   e  = V_m - V^
//   V^ += dt (a^ + 2 zeta w0 e)
//   a^ += dt w0^2 e,                                 zeta = 1 / sqrt(2)
// the Euler form of a^(s) = w0^2 s V_m(s) / (s^2 + 2 zeta w0 s + w0^2): a ramp of slope r settles
// at a^ = r (V^ then follows V_m without error), and a step of the acceleration is followed as
//   a^(t) / r = 1 - exp(-zeta w0 t) (cos(w_d t) + zeta w0 / w_d sin(w_d t)),  w_d = w0 sqrt(1 - zeta^2)
// (mean delay 2 zeta / w0: 1.41 s at w0 = 1 rad/s, against the air data's 6 T). White noise of
// spectral density N on V_m gives a^ the variance N w0^3 / (4 zeta).
// The freeze rule (the bank's, as inertial_flight_path.h's): while `frozen` (level 1, a failure
// declared, or a failure hypothesis on line above the freeze probability) neither VEL nor AOA is
// read: a^ goes over to the air data's a with the differentiator's delay as time constant,
//   a^ += c (a_air - a^),  c = 1 - exp(-dt w0 / (2 zeta)),
// so a failed VEL or AOA sensor cannot drive the trim to absorb its failure; at the first frame
// read after a freeze V^ restarts at V_m, a^ continuing. The first frame read starts V^ = V_m,
// a^ = a_air. Non-finite readings count as frozen.
class AirspeedAccel {
 public:
  static constexpr double kZeta = 0.70710678118654752;   // 1 / sqrt(2)
  AirspeedAccel() = default;
  AirspeedAccel(double w0_rad_s, double frame_rate_hz)
      : dt_(1.0 / frame_rate_hz), k1_(2.0 * kZeta * w0_rad_s), k2_(w0_rad_s * w0_rad_s),
        c_freeze_(1.0 - std::exp(-w0_rad_s / (2.0 * kZeta * frame_rate_hz))) {
    if (!(w0_rad_s > 0.0 && std::isfinite(w0_rad_s)) || !(frame_rate_hz > 0.0))
      throw std::invalid_argument("airspeed acceleration: needs w0 > 0 and a frame rate > 0, got " +
                                  format_value(w0_rad_s) + ", " + format_value(frame_rate_hz));
  }
  void reset() noexcept {
    seen_ = reading_ = false;
    v_ = a_ = 0.0;
  }
  // One frame: the measured VEL (ft/s) and AOA (rad) of z, the air data's a (ft/s^2), frozen.
  void observe(double vel, double alpha, double a_air, bool frozen) noexcept {
    if (!std::isfinite(a_air)) return;
    if (!(std::isfinite(vel) && std::isfinite(alpha)) || !(std::cos(alpha) > 0.0)) frozen = true;
    if (!seen_) {
      a_ = a_air;
      seen_ = true;
    }
    if (frozen) {
      a_ += c_freeze_ * (a_air - a_);
      reading_ = false;
      return;
    }
    const double vm = vel / std::cos(alpha);
    if (!reading_) {
      v_ = vm;
      reading_ = true;
      return;
    }
    const double e = vm - v_;
    v_ += dt_ * (a_ + k1_ * e);
    a_ += dt_ * k2_ * e;
  }
  bool seen() const noexcept { return seen_; }
  double accel() const noexcept { return a_; }   // ft/s^2
  double airspeed() const noexcept { return v_; }   // ft/s, V^

 private:
  double dt_ = 1.0 / 64.0, k1_ = 0.0, k2_ = 0.0, c_freeze_ = 0.0;
  bool seen_ = false, reading_ = false;
  double v_ = 0.0, a_ = 0.0;
};

// ClimbAngleComplement — the part of the climb angle the air data's low-passes hold back, from the
// normal load factor (header of the file: why). Per frame (dt = 1 / f), from z the normal load
// factor n (AZ, g, up +), the angle of attack alpha (rad) and the roll and yaw rates p, r (rad/s);
// the air data's airspeed V = c lp_T(M) (ft/s) and gamma_air (rad); the trim's acceleration a
// (ft/s^2); T the air data's time constant, c_x = 1 - exp(-1 / (x f)):
//   phi     = bank angle as inertial_flight_path.h's: phi += dt p + c_{T_phi} (phi_ref(V, r) - phi),
//             phi_ref = asin(clamp(V r / g, -0.9, 0.9)), but T_phi = 10 s: in a roll-in the yaw
//             rate overshoots the steady turn's and phi_ref with it, so phi leans on the roll
//             rate's integral longer (tools/maneuver/gamma_lag.py compares the two constants)
//   n_w     = n cos alpha + (sin(gamma + alpha) + a / g) sin alpha
//             (the lift axis' load factor: body z and x specific forces, the x one
//             n_x = sin(theta) + a / g taken from the path; level and steady n_w = 1)
//   w       = (g / V) (n_w cos phi - cos gamma)        (gamma: this filter's previous output)
//   f_1    += c_T (w - f_1),   f_5 += c_{5T} (w - f_5)
//   d       = T (25 f_5 - f_1) / 4                     (= (1 - L(s)) / s w: partial fractions of
//             (6 T + 5 T^2 s) / ((1 + T s)(1 + 5 T s)) = (25 T / 4) / (1 + 5 T s) - (T / 4) / (1 + T s))
//   gamma   = clamp(gamma_air + d, -gamma_max, gamma_max)
// A steady rate w0 settles at d = 6 T w0, the lag of the air data's gamma behind a ramp of slope
// w0 (their mean delay 6 T). An error e (g) of n_w moves gamma by 6 T g e / V in the steady state
// (0.05 deg per 0.005 g at 600 ft/s and T = 0.5 s).
// The freeze rule (the bank's, as AirspeedAccel's): while `frozen` none of z is read, phi holds
// and w = 0, so d decays (time constants T and 5 T) and gamma goes over to the air data's: a
// failed AZ, AOA, ROL or YAW sensor cannot drive the trim to absorb its failure. The first frame read
// starts phi = phi_ref, f_1 = f_5 = 0. Non-finite readings count as frozen.
class ClimbAngleComplement {
 public:
  static constexpr double kG = InertialFlightPath::kG;
  ClimbAngleComplement() = default;
  ClimbAngleComplement(double time_constant_s, double gamma_max_rad, double frame_rate_hz)
      : dt_(1.0 / frame_rate_hz), t_(time_constant_s), gamma_max_(gamma_max_rad),
        c1_(1.0 - std::exp(-1.0 / (time_constant_s * frame_rate_hz))),
        c5_(1.0 - std::exp(-1.0 / (5.0 * time_constant_s * frame_rate_hz))),
        c_roll_(1.0 - std::exp(-1.0 / (kRollTimeConstantS * frame_rate_hz))) {
    if (!(time_constant_s > 0.0) || !(frame_rate_hz > 0.0) || !(gamma_max_rad > 0.0))
      throw std::invalid_argument("climb angle complement: needs T > 0, gamma_max > 0 and a frame rate > 0, got " +
                                  format_value(time_constant_s) + ", " + format_value(gamma_max_rad) + ", " +
                                  format_value(frame_rate_hz));
  }
  static constexpr double kRollTimeConstantS = 10.0;   // T_phi
  void reset() noexcept {
    seen_ = phi_seen_ = false;
    phi_ = f1_ = f5_ = gamma_ = 0.0;
  }
  // One frame: n (g), alpha (rad), p, r (rad/s) of z; the air data's V (ft/s) and gamma_air (rad);
  // the trim's acceleration a (ft/s^2); frozen.
  void observe(double n, double alpha, double p, double r, double v_air, double gamma_air, double a,
               bool frozen) noexcept {
    if (!std::isfinite(gamma_air) || !std::isfinite(v_air) || !(v_air > 0.0)) return;
    if (!(std::isfinite(n) && std::isfinite(alpha) && std::isfinite(p) && std::isfinite(r) && std::isfinite(a)))
      frozen = true;
    if (!seen_) gamma_ = gamma_air;
    seen_ = true;
    double w = 0.0;
    if (!frozen) {
      if (!phi_seen_) {
        phi_ = InertialFlightPath::phi_ref(v_air, r);
        phi_seen_ = true;
      } else {
        phi_ = InertialFlightPath::phi_step(phi_, p, v_air, r, dt_, c_roll_);
      }
      const double n_w = n * std::cos(alpha) + (std::sin(gamma_ + alpha) + a / kG) * std::sin(alpha);
      w = kG / v_air * (n_w * std::cos(phi_) - std::cos(gamma_));
    }
    f1_ += c1_ * (w - f1_);
    f5_ += c5_ * (w - f5_);
    gamma_ = std::clamp(gamma_air + correction(), -gamma_max_, gamma_max_);
  }
  bool seen() const noexcept { return seen_; }
  double gamma() const noexcept { return gamma_; }   // rad
  double correction() const noexcept { return t_ * (25.0 * f5_ - f1_) / 4.0; }   // d, rad
  double phi() const noexcept { return phi_; }       // rad

 private:
  double dt_ = 1.0 / 64.0, t_ = 0.5, gamma_max_ = 0.5, c1_ = 0.0, c5_ = 0.0, c_roll_ = 0.0;
  bool seen_ = false, phi_seen_ = false;
  double phi_ = 0.0, f1_ = 0.0, f5_ = 0.0, gamma_ = 0.0;
};

// The per-frame part (header): the rates from the air data, (gamma, a), the blended offsets.
class ManeuverTrim {
 public:
  ManeuverTrim() = default;
  ManeuverTrim(const ManeuverTrimOptions& options, double frame_rate_hz) : options_(options) {
    options.validate();
    if (!options.enabled) return;
    gain_fast_ = 1.0 - std::exp(-1.0 / (frame_rate_hz * options.time_constant_s));
    gain_slow_ = 1.0 - std::exp(-1.0 / (frame_rate_hz * 5.0 * options.time_constant_s));
    if (options.inertial) path_ = InertialFlightPath(options.inertial_path, frame_rate_hz);
    if (options.accel_airspeed_rad_s > 0.0) airspeed_ = AirspeedAccel(options.accel_airspeed_rad_s, frame_rate_hz);
    if (options.gamma_load_factor)
      complement_ = ClimbAngleComplement(options.time_constant_s, options.gamma_max_rad, frame_rate_hz);
  }
  // observe_inertial() reads z: the inertial rates, the airspeed's acceleration or the load factor's climb angle.
  bool reads_z() const noexcept {
    return options_.enabled && (options_.inertial || options_.accel_airspeed_rad_s > 0.0 || options_.gamma_load_factor);
  }
  bool enabled() const noexcept { return options_.enabled; }
  const ManeuverTrimOptions& options() const noexcept { return options_; }

  void reset() noexcept {
    seen_ = false;
    h_fast_ = h_slow_ = m_fast_ = m_slow_ = 0.0;
    gamma_ = accel_ = 0.0;
    v_air_ = 0.0;
    path_.reset();
    airspeed_.reset();
    complement_.reset();
  }
  // One usable air-data sample (Mach, pressure altitude ft) and the speed of sound c (ft/s) of
  // the trim in force: updates gamma() and accel().
  void observe(double mach, double alt_ft, double sound_fps) noexcept {
    if (!seen_) {
      h_fast_ = h_slow_ = alt_ft;
      m_fast_ = m_slow_ = mach;
      seen_ = true;
    } else {
      h_fast_ += gain_fast_ * (alt_ft - h_fast_);
      h_slow_ += gain_slow_ * (alt_ft - h_slow_);
      m_fast_ += gain_fast_ * (mach - m_fast_);
      m_slow_ += gain_slow_ * (mach - m_slow_);
    }
    const double span = 4.0 * options_.time_constant_s;
    const double climb = (h_fast_ - h_slow_) / span, mach_rate = (m_fast_ - m_slow_) / span;
    const double v = sound_fps * m_fast_;
    v_air_ = v;
    const double sg = std::sin(options_.gamma_max_rad);
    gamma_ = v > 0.0 ? std::asin(std::clamp(climb / v, -sg, sg)) : 0.0;
    accel_ = options_.accel ? std::clamp(sound_fps * mach_rate, -options_.accel_max_fps2, options_.accel_max_fps2)
                            : 0.0;
    if (!std::isfinite(gamma_) || !std::isfinite(accel_)) gamma_ = accel_ = 0.0;
  }
  // With options.inertial: one frame's measurements (absolute: q, p, r rad/s, alpha rad, V ft/s)
  // and the bank's freeze condition, into the complementary filter (inertial_flight_path.h)
  // against the air data's (gamma, a) of the last observe(); with options.accel_airspeed_rad_s
  // > 0: alpha and V into AirspeedAccel against the air data's a; with options.gamma_load_factor:
  // n (AZ, g), alpha, p, r into ClimbAngleComplement against the air data's V and gamma. No-op otherwise.
  void observe_inertial(double q, double p, double r, double alpha, double vel, double n, bool frozen) noexcept {
    if (options_.inertial) path_.observe(q, p, r, alpha, vel, gamma_, accel_, frozen);
    if (options_.accel_airspeed_rad_s > 0.0 && seen_) airspeed_.observe(vel, alpha, accel_, frozen);
    if (options_.gamma_load_factor && seen_) complement_.observe(n, alpha, p, r, v_air_, gamma_, accel(), frozen);
  }
  // The (gamma, a) in force: the air data's, or with options.inertial the complementary
  // filter's once it has a frame, or with options.gamma_load_factor ClimbAngleComplement's once it
  // has one (a = 0 with accel = false).
  double gamma() const noexcept {   // rad
    if (options_.gamma_load_factor && complement_.seen()) return complement_.gamma();
    return options_.inertial && path_seen() ? path_.gamma() : gamma_;
  }
  double accel() const noexcept {                                                                     // ft/s^2
    if (!options_.accel) return 0.0;
    if (options_.accel_airspeed_rad_s > 0.0 && airspeed_.seen())
      return std::clamp(airspeed_.accel(), -options_.accel_max_fps2, options_.accel_max_fps2);
    return options_.inertial && path_seen() ? path_.accel() : accel_;
  }
  double air_gamma() const noexcept { return gamma_; }   // the air data's own
  double air_accel() const noexcept { return accel_; }
  double air_airspeed() const noexcept { return v_air_; }   // c lp_T(M), ft/s
  const InertialFlightPath& inertial_path() const noexcept { return path_; }
  const AirspeedAccel& airspeed_accel() const noexcept { return airspeed_; }
  const ClimbAngleComplement& climb_angle_complement() const noexcept { return complement_; }

 private:
  ManeuverTrimOptions options_;
  double gain_fast_ = 0.0, gain_slow_ = 0.0;
  bool seen_ = false;
  double h_fast_ = 0.0, h_slow_ = 0.0, m_fast_ = 0.0, m_slow_ = 0.0;
  double gamma_ = 0.0, accel_ = 0.0, v_air_ = 0.0;
  InertialFlightPath path_;
  AirspeedAccel airspeed_;
  ClimbAngleComplement complement_;
  bool path_seen() const noexcept { return path_.seen(); }
};

}  // namespace f16mmae
