// ManeuverKinematics — the rigid-body kinematic and gravity terms that the filters' linear
// model drops, put back into their propagation, so that a steady turn or pull-up is not
// read as a failure. Eigen and std only; nothing allocates.
//
// Why: each hypothesis filter is the airframe linearized about wings-level, 1-g, level
// flight (p = q = r = phi = beta = 0). Its state x (perturbation from the trim x0) obeys
// x' = A x + B u. The true state obeys x' = f_aero(x, u) + g(x), where g holds the terms of
// the body-axis equations that are pure kinematics and gravity (no aerodynamic data):
//
//   state s = (u, alpha, q, theta, beta, p, r, phi)  (names.STATES[:8]), w = u tan alpha,
//   V = sqrt(u^2 + w^2) / cos beta, v = V sin beta,
//   k_u = r v - q w - g sin theta
//   k_v = p w - r u + g cos theta sin phi
//   k_w = q u - p v + g cos theta cos phi
//   g_u     = k_u
//   g_alpha = (u k_w - w k_u) / (u^2 + w^2)
//   g_beta  = (k_v - v V_k' / V) / (V cos beta),   V_k' = (u k_u + v k_v + w k_w) / V
//   g_theta = q cos phi - r sin phi
//   g_phi   = p + (q sin phi + r cos phi) tan theta
//   g_q = g_p = g_r = 0   (the inertial couplings (I_zz - I_xx) p r / I_yy etc. are left out:
//                          at a 30 deg level turn at Mach 0.4 they are below 1e-3 rad/s^2)
//
// The linear model holds g's first-order part J (x - x0) exactly (the design linearizes the
// whole derivative). What it lacks is the remainder
//
//   R(x) = g(x) - g(x0) - J (x - x0),      J = dg/dx at x0,
//
// which is second order in the perturbation and zero in wings-level unaccelerated flight.
// In a steady level turn at bank phi (turn rate omega = g tan phi / V, q = omega sin phi,
// r = omega cos phi) it is, to leading order,
//   R_theta = -q                                    (theta is constant: theta' = 0, not q)
//   R_alpha = u g cos theta0 (cos phi - 1) / (u^2 + w^2)   (the lift of 1/cos phi g)
//   R_beta  = g cos theta0 (sin phi - phi) / V      (and small terms in R_u, R_phi)
// At 30 deg and Mach 0.4, 20,000 ft: R_theta = -0.022 rad/s, R_alpha = -0.010 rad/s; the
// linear model would have theta ramp at 1.3 deg/s and the airspeed fall with it.
//
// What the bank does (HierarchicalBank, HierarchicalOptions::maneuver): after every filter's
// propagate, x⁻_k += dt R(x0 + x̂), x̂ the blended posterior (sum_k p_k x⁺_k) of the frame,
// dt = 1 / frame_rate_hz (Euler step of the forcing over the frame). One R per frame, shared
// by the filters: the blended estimate is the bank's best state, and R is second order, so
// the estimate's error enters it only multiplied by another perturbation.
//
// Why it cannot absorb a failure: R is a fixed function of the state (kinematics and
// gravity, no aerodynamic coefficient and nothing fitted or integrated on line); it has no
// memory and no free parameter, so it cannot learn an offset. It vanishes in wings-level
// flight about the trim (R = 0 at x = x0, and its first derivative is zero there), so a
// failure in level flight meets the filters exactly as without it. A failure during a turn
// changes R only through the state estimate, second order.
//
// Load-factor tempering (ManeuverOptions::tempering_g = n_ref > 0; HierarchicalBank applies
// it): beyond the kinematics, a hard pull-up takes the aircraft where the linear aerodynamics
// no longer hold (a 3,000-fpm climb entry at Mach 0.4, 20,000 ft pulls up to 1.7 g, the angle
// of attack from 8 to 15 deg; the pitch-rate residual then runs about 3 sigma for seconds, which
// the stabilator hypotheses explain). Every likelihood is tempered by
//   s_m = 1 + (dn / n_ref)^2,   dn = the AZ entry of z_hat (the blended estimate's load factor
//                                    off the trim, g), from the frame before,
// l_k = -q_k / (2 s s_m). With n_ref = 0.1 g (the value the maneuver
// campaign's tuning seeds chose, docs/results/maneuver.md) s_m is 1 in level and steadily climbing flight,
// 3.4 in a 30 deg level turn, 45 at 1.66 g. The price: detection slows while the load factor is
// off 1 g, and a failure that itself moves the load factor (a stabilator hard-over) tempers its
// own evidence while it does.
// With a dead band d > 0 (ManeuverOptions::tempering_deadband_g; 0, the default, is the rule
// above bit for bit) only the load factor beyond it counts:
//   s_m = 1 + (max(0, |dn| - d) / n_ref)^2,
// so the estimated load factor that light turbulence gives level flight (a few hundredths of a
// g) tempers nothing, while a pull-up (0.7 g at a 3,000-fpm climb entry) still does; a 30 deg
// turn's 0.155 g tempers by 1 + ((0.155 - d) / n_ref)^2.
//
// Angle-of-attack tempering (ManeuverOptions::tempering_alpha_deg = a_ref > 0, with a dead band
// a_d = tempering_alpha_deadband_deg >= 0): slow flight leaves the linear aerodynamics at a load
// factor too small for the term above. At Mach 0.3, 10,000 ft (trim alpha 9.5 deg) a pilot
// holding altitude and Mach in light turbulence pitches alpha to 12 deg at about 0.1 g; the
// airspeed residual then runs -3.7 sigma for half a second (more drag than the linear model
// has) and a stabilator or flaperon hypothesis explains it. With da = |the AOA entry of z_hat|
// (the blended estimate's angle of attack off the trim in force, deg, from the frame before) and
// s = max(1, the turbulence adaptation's scale, turbulence_adaptation.h; 1 without it)
//   y   = max(0, da - a_d sqrt(s)) / a_ref,
// every likelihood's total scale s s_m carries y^2 added to s, not multiplied (s_m below): the
// model error's variance adds to the gusts'. The dead band grows with the gusts the adaptation
// measures (their alpha's spread grows as sqrt(s)), so the angle of attack that the gusts
// themselves give, modelled by the filters, tempers nothing, while the pilot's excursion in
// light air (s about 1) does. The price is as the load factor's: a failure that itself moves the
// angle of attack (a stabilator hard-over) tempers its own evidence while it does.
// With a trim knee a_k > 0 (ManeuverOptions::tempering_alpha_trim_deg; 0, the default, is the
// rule above bit for bit) the reference shrinks in slow flight:
//   a_ref' = a_ref min(1, (a_k / alpha0)^3),   alpha0 = the trim in force's angle of attack (deg:
//                                              z_trim + dz of AOA: the scheduled node's, the trim
//                                              tracker's and the maneuver trim's; hierarchical_bank.h
//                                              passes it),
// so y = max(0, da - a_d sqrt(s)) / a_ref'. Why: the same excursion takes an aircraft trimmed
// near the lift curve's bend further from its linear model. In moderate air at Mach 0.31-0.35,
// 18,000-27,000 ft (trim alpha 11-16 deg) a downward gust of 2-2.5 deg in alpha reads as a
// failed flaperon within half a second, whatever the load factor. Why the cube: at the five
// points of trim alpha 9-16 deg in the envelope soak of the tuning seed, a_ref' with the power 1,
// 2 and 3 left 8, 5 and 1 false flaperons in 25 h of moderate air; a smaller a_ref everywhere
// (0.5) quiets them too but slows the nominal point (trim alpha 8 deg) by 0.15 s
// (docs/results/envelope_scheduled.md, round 49).
// The load factor has an added term of the same form (ManeuverOptions::tempering_added_g = n_a
// > 0, dead band d_a = tempering_added_deadband_g): x_a = max(0, |dn| - d_a sqrt(s)) / n_a joins
// y^2 added to s. With every term
//   s_m = (1 + (max(0, |dn| - d) / n_ref)^2) (1 + (y^2 + x_a^2) / s),
// a term that is off contributing nothing (the first factor 1 with n_ref = 0). So a pull-up's
// or a turn's load factor in light air (s about 1) tempers through x_a as the maneuver setting's
// n_ref = 0.1 g does, while severe air's gusts, whose load factor spreads as sqrt(s), stay inside
// its band and their tempering is the multiplied term's alone.
// With a spread factor k > 0 (ManeuverOptions::tempering_added_spread; 0, the default, is the rule
// above) the added term's band is at least k sigma_n, the load factor's own measured spread:
//   x_a = max(0, |dn| - max(d_a sqrt(s), k sigma_n)) / n_a
//   m   += c_m (dn - m),                 c_m = 1 - exp(-1 / (T_m f)),  T_m = 0.35 s
//   v   += a_i ((dn - m)^2 - v),         a_i = max(1 / i, c_v),  c_v from T_v = 30 s,  sigma_n = sqrt(v)
// (per update, dn the estimate the tempering reads; m starts at the first dn, v is a plain mean
// over its first T_v f updates: running_mean.h). Why: s is each node's residual power against its
// own light air, but the gusts' load factor grows with the dynamic pressure: in light air at Mach
// 0.77, 8,000 ft the estimated load factor swings +-0.3-0.4 g about the trim (at Mach 0.4, 20,000 ft
// a few hundredths), so a fixed band tempers every frame there, a failed flaperon's evidence with
// them. Those swings are the short period's, about a second long; m follows a maneuver's slower
// load factor, so a steady turn adds nothing to v, and a roll-in or a pull-up little, for the
// fraction of a second its onset outruns T_m. T_m was chosen on tuning seeds between the
// flaperons at high dynamic pressure (a longer T_m) and the maneuvers' onsets (a shorter one):
// docs/results/envelope_scheduled.md, round 32.
//
// The trim x0: (u0, alpha0) from the trim in force (z_trim + dz of the VEL and AOA
// channels: the body-axis airspeed and angle of attack), theta0 = alpha0 (the design trims
// are level, flight-path angle 0), every other state zero. J at that x0 in closed form
// (jacobian(); the test checks it against central differences of g).
//
// Options: enabled = false (the default) is the bank without it, bit for bit.
// Sizes: the bank's state vector must hold the eight airframe states under the names above
// and its measurements VEL and AOA; the constructor throws std::invalid_argument naming the
// one that is missing (only when enabled); the tempering needs AZ (n_ref > 0) and AOA (a_ref > 0).
#pragma once

#include "f16mmae/running_mean.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace f16mmae {

struct ManeuverOptions {
  bool kinematics = false;   // put the kinematic/gravity remainder into the propagation
  double tempering_g = 0.0;  // n_ref of the load-factor tempering (g); 0 = off
  double tempering_deadband_g = 0.0;  // d: the load factor that tempers nothing (g); 0 = none
  double tempering_alpha_deg = 0.0;   // alpha_ref of the angle-of-attack term (deg); 0 = off
  double tempering_alpha_deadband_deg = 0.0;  // a_d: the excursion that tempers nothing at s <= 1 (deg); 0 = none
  double tempering_alpha_trim_deg = 0.0;      // a_k: above this trim alpha a_ref shrinks as (a_k / alpha0)^3 (deg); 0 = off
  double tempering_added_g = 0.0;             // n_a of the load factor's added term (g); 0 = off
  double tempering_added_deadband_g = 0.0;    // d_a: the load factor that tempers nothing at s <= 1 (g); 0 = none
  double tempering_added_spread = 0.0;        // k: the added term's band at least k sigma_n (header); 0 = off
  bool enabled() const noexcept { return kinematics; }
  bool tempering() const noexcept { return tempering_g > 0.0 || tempering_alpha_deg > 0.0 || tempering_added_g > 0.0; }
  void validate() const {
    if (!(tempering_g >= 0.0 && std::isfinite(tempering_g)))
      throw std::invalid_argument("maneuver: tempering_g must be >= 0 g (0 = off), got " + std::to_string(tempering_g));
    // each term's reference and dead band: in range, and the band only with its term
    const auto num = [](double v) {
      std::ostringstream o;
      o << v;
      return o.str();
    };
    const auto term = [&num](const char* name, double ref, double ref_max, const char* band_name, double band,
                             double band_max, const char* unit) {
      if (!(ref >= 0.0 && ref <= ref_max))
        throw std::invalid_argument(std::string("maneuver: ") + name + " must be in [0, " + num(ref_max) + "] " + unit +
                                    " (0 = off), got " + num(ref));
      if (!(band >= 0.0 && band <= band_max))
        throw std::invalid_argument(std::string("maneuver: ") + band_name + " must be in [0, " + num(band_max) + "] " +
                                    unit + " (0 = none), got " + num(band));
      if (band > 0.0 && !(ref > 0.0))
        throw std::invalid_argument(std::string("maneuver: ") + band_name + " applies with " + name + " > 0 only");
    };
    term("tempering_g", tempering_g, HUGE_VAL, "tempering_deadband_g", tempering_deadband_g, 10.0, "g");
    term("tempering_alpha_deg", tempering_alpha_deg, 90.0, "tempering_alpha_deadband_deg", tempering_alpha_deadband_deg,
         90.0, "deg");
    term("tempering_alpha_deg", tempering_alpha_deg, 90.0, "tempering_alpha_trim_deg", tempering_alpha_trim_deg, 90.0,
         "deg");
    term("tempering_added_g", tempering_added_g, 100.0, "tempering_added_deadband_g", tempering_added_deadband_g, 10.0,
         "g");
    term("tempering_added_g", tempering_added_g, 100.0, "tempering_added_spread", tempering_added_spread, 100.0,
         "sigma_n");
  }
};

class ManeuverKinematics {
 public:
  static constexpr int kN = 8;            // airframe states: u alpha q theta beta p r phi
  static constexpr double kG = 32.174;    // ft/s^2, the gravity the truth model (JSBSim) uses near sea level
  using Vec = Eigen::Matrix<double, kN, 1>;
  using Mat = Eigen::Matrix<double, kN, kN>;
  enum : int { U = 0, ALPHA, Q, THETA, BETA, P, R, PHI };

  ManeuverKinematics() = default;
  // state_names / measurement_names: the bank's; frame_rate_hz: its frame rate.
  ManeuverKinematics(const ManeuverOptions& options, const std::vector<std::string>& state_names,
                     const std::vector<std::string>& measurement_names, double frame_rate_hz)
      : options_(options), dt_(1.0 / frame_rate_hz),
        spread_mean_gain_(1.0 - std::exp(-1.0 / (kSpreadMeanS * frame_rate_hz))),
        spread_power_gain_(1.0 - std::exp(-1.0 / (kSpreadPowerS * frame_rate_hz))),
        spread_length_(running_mean_length(spread_power_gain_)) {
    options.validate();
    if (options.tempering_g > 0.0 || options.tempering_added_g > 0.0) az_ = find(measurement_names, "AZ", "measurement");
    if (options.tempering_alpha_deg > 0.0) aoa_tempering_ = find(measurement_names, "AOA", "measurement");
    if (!options.enabled()) return;
    static const char* const kStates[kN] = {"u_fps", "alpha_rad", "q_rad_s", "theta_rad",
                                            "beta_rad", "p_rad_s", "r_rad_s", "phi_rad"};
    for (int i = 0; i < kN; ++i) state_index_[i] = find(state_names, kStates[i], "state");
    vel_ = find(measurement_names, "VEL", "measurement");
    aoa_ = find(measurement_names, "AOA", "measurement");
  }

  bool enabled() const noexcept { return options_.enabled(); }
  bool tempering() const noexcept { return options_.tempering(); }
  static constexpr double kDegPerRad = 180.0 / 3.14159265358979323846;
  static constexpr double kSpreadMeanS = 0.35, kSpreadPowerS = 30.0;   // T_m, T_v of the spread (header)
  // The load factor's spread (header: m, v) observes the estimate the tempering reads next (with
  // tempering_added_spread > 0; else nothing). Non-finite dn is skipped.
  template <class Z>
  void observe_spread(const Z& z_hat_perturbation) noexcept {
    if (!(options_.tempering_added_spread > 0.0)) return;
    const double dn = z_hat_perturbation(az_);
    if (!std::isfinite(dn)) return;
    if (spread_updates_ == 0) spread_mean_ = dn;
    spread_mean_ += spread_mean_gain_ * (dn - spread_mean_);
    const double e = dn - spread_mean_;
    const double a = spread_updates_ < spread_length_ ? 1.0 / static_cast<double>(++spread_updates_) : spread_power_gain_;
    spread_power_ += a * (e * e - spread_power_);
  }
  double load_factor_spread() const noexcept { return std::sqrt(spread_power_); }   // sigma_n (0 at the start)
  void reset_spread() noexcept {
    spread_mean_ = spread_power_ = 0.0;
    spread_updates_ = 0;
  }
  // A bank taking over (HierarchicalBank::take_over): the spread measured so far goes on.
  void carry_over_spread(const ManeuverKinematics& from) noexcept {
    spread_mean_ = from.spread_mean_;
    spread_power_ = from.spread_power_;
    spread_updates_ = from.spread_updates_;
  }
  // The tempering's likelihood scale s_m (header: the load factor's and the angle of attack's
  // terms) for the bank's estimated measurement perturbation z_hat (dn = its AZ entry, g; da its
  // AOA entry, rad), the turbulence adaptation's scale (1 without it) and the trim in force's
  // angle of attack alpha0 (rad; read with a trim knee only).
  template <class Z>
  double tempering_scale(const Z& z_hat_perturbation, double turbulence_scale = 1.0,
                         double trim_alpha_rad = 0.0) const noexcept {
    double scale = 1.0;
    if (options_.tempering_g > 0.0) {
      const double dn = z_hat_perturbation(az_);
      const double x = (options_.tempering_deadband_g > 0.0
                            ? std::max(0.0, std::abs(dn) - options_.tempering_deadband_g)
                            : dn) / options_.tempering_g;
      scale += x * x;
    }
    if (!(options_.tempering_alpha_deg > 0.0 || options_.tempering_added_g > 0.0)) return scale;
    const double s = std::max(turbulence_scale, 1.0), root_s = std::sqrt(s);
    // (max(0, |v| - band sqrt(s)) / ref)^2, 0 with the term off
    const auto excess2 = [root_s](double v, double band, double ref) {
      if (!(ref > 0.0)) return 0.0;
      const double e = std::max(0.0, std::abs(v) - band * root_s) / ref;
      return e * e;
    };
    // the added term's band in units of sqrt(s): max(d_a sqrt(s), k sigma_n) / sqrt(s)
    const double added_band = std::max(options_.tempering_added_deadband_g,
                                       options_.tempering_added_spread * load_factor_spread() / root_s);
    const double added =   // y^2 + x_a^2, added to s
        excess2(z_hat_perturbation(aoa_tempering_) * kDegPerRad, options_.tempering_alpha_deadband_deg,
                alpha_reference(trim_alpha_rad)) +
        excess2(z_hat_perturbation(az_), added_band, options_.tempering_added_g);
    return scale * (1.0 + added / s);
  }
  // a_ref' = a_ref min(1, (a_k / alpha0)^3) (header; a_ref without a knee or at a non-finite alpha0)
  double alpha_reference(double trim_alpha_rad) const noexcept {
    const double a_ref = options_.tempering_alpha_deg, a_k = options_.tempering_alpha_trim_deg;
    const double alpha0 = trim_alpha_rad * kDegPerRad;
    if (!(a_k > 0.0 && alpha0 > a_k)) return a_ref;
    const double r = a_k / alpha0;
    return a_ref * r * r * r;
  }
  const ManeuverOptions& options() const noexcept { return options_; }
  int vel_index() const noexcept { return vel_; }
  int aoa_index() const noexcept { return aoa_; }
  bool reads_trim_alpha() const noexcept { return options_.tempering_alpha_deg > 0.0 && options_.tempering_alpha_trim_deg > 0.0; }
  int aoa_tempering_index() const noexcept { return aoa_tempering_; }   // AOA's measurement (with the alpha term)
  double dt() const noexcept { return dt_; }

  // The level trim x0 of body airspeed u0 (ft/s) and angle of attack alpha0 (rad).
  static Vec level_trim(double u0, double alpha0) noexcept {
    Vec x0 = Vec::Zero();
    x0(U) = u0;
    x0(ALPHA) = alpha0;
    x0(THETA) = alpha0;
    return x0;
  }

  // g(s) of the header, s absolute.
  static Vec derivative(const Vec& s) noexcept {
    const double u = s(U), q = s(Q), p = s(P), r = s(R);
    const double ta = std::tan(s(ALPHA));
    const double sb = std::sin(s(BETA)), cb = std::cos(s(BETA));
    const double st = std::sin(s(THETA)), ct = std::cos(s(THETA));
    const double sp = std::sin(s(PHI)), cp = std::cos(s(PHI));
    const double w = u * ta;
    const double uw2 = u * u + w * w;
    const double vt = std::sqrt(uw2) / cb;
    const double v = vt * sb;
    const double ku = r * v - q * w - kG * st;
    const double kv = p * w - r * u + kG * ct * sp;
    const double kw = q * u - p * v + kG * ct * cp;
    const double vtd = (u * ku + v * kv + w * kw) / vt;
    Vec g;
    g(U) = ku;
    g(ALPHA) = (u * kw - w * ku) / uw2;
    g(Q) = 0.0;
    g(THETA) = q * cp - r * sp;
    g(BETA) = (kv - v * vtd / vt) / (vt * cb);
    g(P) = 0.0;
    g(R) = 0.0;
    g(PHI) = p + (q * sp + r * cp) * (st / ct);
    return g;
  }

  // J = dg/ds at a level trim x0 (p = q = r = beta = phi = 0), in closed form.
  static Mat jacobian(const Vec& x0) noexcept {
    const double u0 = x0(U), a0 = x0(ALPHA), th = x0(THETA);
    const double ta = std::tan(a0), ca = std::cos(a0);
    const double st = std::sin(th), ct = std::cos(th);
    const double w0 = u0 * ta, d0 = u0 * u0 + w0 * w0, v0 = std::sqrt(d0);
    const double ku0 = -kG * st, kw0 = kG * ct;
    const double n0 = u0 * kw0 - w0 * ku0;
    const double dn_du = kw0 - ta * ku0, dd_du = 2.0 * u0 / (ca * ca);
    const double dn_da = -(u0 / (ca * ca)) * ku0, dd_da = 2.0 * w0 * u0 / (ca * ca);
    const double vtd0 = (u0 * ku0 + w0 * kw0) / v0;
    Mat j = Mat::Zero();
    j(U, Q) = -w0;
    j(U, THETA) = -kG * ct;
    j(ALPHA, U) = (dn_du * d0 - n0 * dd_du) / (d0 * d0);
    j(ALPHA, ALPHA) = (dn_da * d0 - n0 * dd_da) / (d0 * d0);
    j(ALPHA, Q) = 1.0;
    j(ALPHA, THETA) = kG * (w0 * ct - u0 * st) / d0;
    j(THETA, Q) = 1.0;
    j(BETA, BETA) = -vtd0 / v0;
    j(BETA, P) = w0 / v0;
    j(BETA, R) = -u0 / v0;
    j(BETA, PHI) = kG * ct / v0;
    j(PHI, P) = 1.0;
    j(PHI, R) = st / ct;
    return j;
  }

  // R(x0 + dx) of the header (dx: airframe perturbation, this class's order).
  static Vec remainder(const Vec& x0, const Vec& dx) noexcept {
    return derivative(x0 + dx) - derivative(x0) - jacobian(x0) * dx;
  }

  // dt R for the bank's (u0, alpha0) and its blended perturbation state x (bank order);
  // written into `forcing` at the bank's state indices (the other entries are zero).
  template <class X, class F>
  void forcing(double u0, double alpha0, const X& x, F& forcing) noexcept {
    const Vec x0 = level_trim(u0, alpha0);
    if (x0 != x0_) {
      x0_ = x0;
      g0_ = derivative(x0);
      j0_ = jacobian(x0);
    }
    Vec dx;
    for (int i = 0; i < kN; ++i) dx(i) = x(state_index_[i]);
    const Vec r = derivative(x0 + dx) - g0_ - j0_ * dx;
    forcing.setZero();
    for (int i = 0; i < kN; ++i) forcing(state_index_[i]) = dt_ * r(i);
  }

 private:
  static int find(const std::vector<std::string>& names, const char* name, const char* what) {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return static_cast<int>(i);
    throw std::invalid_argument(std::string("maneuver kinematics: the model bank has no ") + what + " '" + name +
                                "' (it needs the airframe states u_fps alpha_rad q_rad_s theta_rad beta_rad "
                                "p_rad_s r_rad_s phi_rad and the measurements VEL and AOA)");
  }

  ManeuverOptions options_;
  double dt_ = 0.0;
  std::array<int, kN> state_index_{};
  int vel_ = 0, aoa_ = 1, az_ = 3, aoa_tempering_ = 1;
  double spread_mean_gain_ = 0.0, spread_power_gain_ = 0.0, spread_mean_ = 0.0, spread_power_ = 0.0;
  std::int64_t spread_length_ = 1, spread_updates_ = 0;   // T_v f, and the updates averaged (running_mean.h)
  Vec x0_ = Vec::Constant(std::nan("")), g0_ = Vec::Zero();   // g and J at the last x0
  Mat j0_ = Mat::Zero();
};

}  // namespace f16mmae
