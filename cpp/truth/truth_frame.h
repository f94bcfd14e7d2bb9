// f16mmae truth model, per-step arithmetic: actuators, sensors, flight control law, dither.
//
// The C++ twin of python/harness/f16mmae/truth/{actuators,sensors,fcs,dither}.py, which stay
// the reference and the documentation of the model; every constant and derived coefficient
// (limits, lag decays, scaled gains, dither amplitudes) comes in from Python through the
// structs below, so this header holds the per-step arithmetic only, written in the Python
// code's order of operations so both give the same doubles.  Standard library only: JSBSim
// lives at the edge (bindings/bind_truth.cpp).  Nothing here allocates.
//
// Actuator i (rate dt_s = 1/128 s), commands c clipped to +-lim_i:
//   new = c + (delta - c) * decay_i,  decay_i = exp(-LAG_RAD_S_i dt_s)     (mode normal/loss)
//   delta += clip(new - delta, +-max_step_i),  delta = clip(delta, +-lim_i)
//   complete: new = trim_i; hardover: new = +-lim_i; stuck: delta held.
//   Effective position: delta, or trim_i + value_i (delta - trim_i) under loss.
// Sensor i at t: z_i = ideal_i + n_i sigma_i (n_i standard normal, drawn by the caller), or
//   complete: z_trim_i + v_i; null: 0; stuck: last z_i before the failure; hardover: full
//   scale (high if value >= 0); bias: ideal + (v_i + value); drift: ideal + (v_i + value (t - t_f)).
// Flight control law: truth/fcs.py's module docstring (pitch C*-like PI, roll-rate command,
// washed-out yaw damper with ARI), plus dither d_j = g_j (a_j sin(w_j t + phi_j)), and
// + h_j (b_j sin(v_j t + psi_j)) where h_j != 0 (the adaptive dither's turbulence line,
// truth/dither.py adaptive_gains; g_j = 1, h_j = 0 for the fixed dither), clipped to +-lim;
// its pilot commands nz_cmd, p_cmd are zero, or come from the outer loop.
// Throttle dither (truth/dither.py throttle_command): th = sat(base + a sin(w t), 0, 1), written
// before a frame's JSBSim steps; base = the trim throttle, or in maneuvers the outer loop's
// throttle command of the frame (the dither rides on the pilot's throttle); scheduled
// (truth/dither.py scheduled_throttle_amplitude):
// a = target / b_x(M, h), b_x bilinear in the table at the air data (M, h) measured with the
// frame's z, clamped to the grid; non-finite air data: (0.4, 20000).
// Adaptive dither for one adapted bank (AdaptedDither; the closed loop's rule, truth/dither.py):
// each frame h from the bank's measured residual power ratio and a reference bilinear in a
// (Mach, altitude) table at the measured air data; g_j = 1 - h, h_j = h on the flaperons; the
// rudder's g = max(1, min(sqrt(rho / rho_r), G)) above rho_r (truth/dither.py adaptive_rudder_gain).
// Outer loop (pilot side, maneuvers): truth/outer_loop.py's module docstring -- piecewise
// references (at most kMaxSegments per channel) and the altitude / bank / Mach PI laws; it reads
// the instruments (h, hdot, M, phi) and returns (nz_cmd, p_cmd, throttle).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

namespace f16mmae::truth {

inline constexpr int kSurfaces = 5;  // LS RS LF RF RUD
inline constexpr int kSensors = 7;   // VEL AOA PIT AZ ROL YAW AY

using Surfaces = std::array<double, kSurfaces>;
using Sensors = std::array<double, kSensors>;

/// Failure mode codes, shared with python/harness/f16mmae/truth/{actuators,sensors}.py.
enum class ActuatorMode : int { normal = 0, complete = 1, stuck = 2, hardover = 3, loss = 4 };
enum class SensorMode : int { normal = 0, complete = 1, null = 2, stuck = 3, hardover = 4, bias = 5, drift = 6 };

inline double clip(double x, double lim) { return x > lim ? lim : (x < -lim ? -lim : x); }

/// The five actuators, stepped at the JSBSim rate.
struct ActuatorBank {
  Surfaces trim_rad{}, limit_rad{}, decay{}, max_step_rad{};
  Surfaces position_rad{};
  std::array<ActuatorMode, kSurfaces> mode{};
  Surfaces value{};

  void reset() {
    position_rad = trim_rad;
    mode.fill(ActuatorMode::normal);
    value.fill(0.0);
  }
  void fail(int i, ActuatorMode m, double v) { mode[i] = m; value[i] = v; }

  /// One step with commands cmd_rad; returns the effective positions.
  Surfaces step(const Surfaces& cmd_rad) {
    Surfaces out{};
    for (int i = 0; i < kSurfaces; ++i) {
      const ActuatorMode m = mode[i];
      const double lim = limit_rad[i];
      double p = position_rad[i];
      if (m == ActuatorMode::stuck) {
        out[i] = p;
        continue;
      }
      double target;
      if (m == ActuatorMode::complete) {
        target = trim_rad[i];
      } else if (m == ActuatorMode::hardover) {
        target = value[i] >= 0.0 ? lim : -lim;
      } else {
        const double c = clip(cmd_rad[i], lim);
        target = c + (p - c) * decay[i];
      }
      const double d = clip(target - p, max_step_rad[i]);
      p += d;
      p = clip(p, lim);
      position_rad[i] = p;
      out[i] = m == ActuatorMode::loss ? trim_rad[i] + value[i] * (p - trim_rad[i]) : p;
    }
    return out;
  }
};

/// The seven sensors' noise and failures (the ideal values come from the aircraft).
struct SensorSet {
  Sensors z_trim{}, sigma{}, full_scale_low{}, full_scale_high{};
  std::array<SensorMode, kSensors> mode{};
  Sensors value{}, t_fail_s{}, held{}, last{};

  void reset() {
    mode.fill(SensorMode::normal);
    value.fill(0.0);
    t_fail_s.fill(0.0);
    held.fill(0.0);
    last = z_trim;
  }
  void fail(int i, SensorMode m, double v, double time_s) {
    mode[i] = m;
    value[i] = v;
    t_fail_s[i] = time_s;
    held[i] = last[i];
  }

  /// z at time_s from the ideal values and standard-normal draws normal (7,).
  Sensors measure(const Sensors& ideal, const double* normal, double time_s) {
    Sensors z = ideal;
    for (int i = 0; i < kSensors; ++i) {
      const double v = normal[i] * sigma[i];
      switch (mode[i]) {
        case SensorMode::normal: z[i] += v; break;
        case SensorMode::complete: z[i] = z_trim[i] + v; break;
        case SensorMode::null: z[i] = 0.0; break;
        case SensorMode::stuck: z[i] = held[i]; break;
        case SensorMode::hardover: z[i] = value[i] >= 0.0 ? full_scale_high[i] : full_scale_low[i]; break;
        case SensorMode::bias: z[i] += v + value[i]; break;
        case SensorMode::drift: z[i] += v + value[i] * (time_s - t_fail_s[i]); break;
      }
    }
    last = z;
    return z;
  }
};

/// Coefficients of the flight control law, already scheduled (truth/fcs.py computes them).
struct FcsCoefficients {
  Surfaces u_trim{}, limit_rad{};
  Sensors z_trim{};
  double kq = 0, kn = 0, ki = 0, kp = 0, kpff = 0, kr = 0, kay = 0, kari = 0;
  double k_c = 0, k_v = 0, k_d = 0, speed_filter_s = 1, washout_s = 1, g_dt = 0;
  double xi_max = 0, dt_s = 0;
  bool dither_enabled = false;
  Surfaces dither_amplitude_rad{}, dither_omega_rad_s{}, dither_phase_rad{};
  Surfaces dither_gain{1.0, 1.0, 1.0, 1.0, 1.0};  // the adaptive dither's g_j (1: the fixed dither)
  Surfaces dither2_gain{}, dither2_amplitude_rad{}, dither2_omega_rad_s{}, dither2_phase_rad{};  // h_j, b_j, v_j, psi_j
};

/// The flight control law with its three states; pilot commands nz_cmd (g), p_cmd (rad/s).
struct FlightControlLaw {
  FcsCoefficients c;
  double x_int = 0.0, x_wash = 0.0, x_vel = 0.0;

  void reset() { x_int = x_wash = x_vel = 0.0; }

  Surfaces command(const Sensors& zf, double time_s, double nz_cmd = 0.0, double p_cmd = 0.0) {
    const Sensors& zt = c.z_trim;
    const double dvel = zf[0] - zt[0], dq = zf[2] - zt[2], daz = zf[3] - zt[3];
    const double dp = zf[4] - zt[4], dr = zf[5] - zt[5], day = zf[6] - zt[6];
    const double spd = clip(c.k_v * dvel, 0.05);
    const double nd = clip(c.k_d * (dvel - x_vel) / c.speed_filter_s, 0.05);
    x_vel += (dvel - x_vel) * c.dt_s / c.speed_filter_s;
    const double de = c.kq * dq + c.kn * (daz - nz_cmd - nd) + c.ki * x_int;
    const double xi = x_int + (daz + c.k_c * dq - nz_cmd - nd - spd) * c.dt_s;
    x_int = clip(xi, c.xi_max);
    const double da = c.kpff * p_cmd - c.kp * (dp - p_cmd);
    const double dr_cmd = c.kr * (dr - x_wash) + c.kay * day + c.kari * da;
    x_wash += (dr - x_wash) * c.dt_s / c.washout_s;
    Surfaces d{};
    if (c.dither_enabled)
      for (int j = 0; j < kSurfaces; ++j)
      {
        d[j] = c.dither_gain[j] * (c.dither_amplitude_rad[j] * std::sin(c.dither_omega_rad_s[j] * time_s + c.dither_phase_rad[j]));
        if (c.dither2_gain[j] != 0.0)
          d[j] += c.dither2_gain[j] *
                  (c.dither2_amplitude_rad[j] * std::sin(c.dither2_omega_rad_s[j] * time_s + c.dither2_phase_rad[j]));
      }
    const Surfaces& ut = c.u_trim;
    Surfaces u{ut[0] + de + c.g_dt * da + d[0], ut[1] + de - c.g_dt * da + d[1], ut[2] + da + d[2],
                ut[3] - da + d[3], ut[4] + dr_cmd + d[4]};
    for (int j = 0; j < kSurfaces; ++j) u[j] = clip(u[j], c.limit_rad[j]);
    return u;
  }
};

/// A table on a (Mach, pressure altitude) grid, bilinear at the air data and clamped to the grid,
/// in truth/dither.py _bilinear's order of operations: the throttle dither's thrust per unit
/// command and the adaptive dither's reference.
struct AirDataTable {
  static constexpr int kMaxGrid = 16;
  int n_mach = 0, n_alt = 0;
  std::array<double, kMaxGrid> mach{}, alt_ft{};
  std::array<double, kMaxGrid * kMaxGrid> value{};  // row-major (mach, alt)

  /// (i, t): the grid cell of v clamped to the grid (truth/dither.py _cell).
  static void cell(const double* grid, int n, double v, int& i, double& t) {
    v = std::min(std::max(v, grid[0]), grid[n - 1]);
    i = 0;
    while (i + 2 < n && v >= grid[i + 1]) ++i;
    t = (v - grid[i]) / (grid[i + 1] - grid[i]);
  }
  double at(double m, double h) const {
    int i, j;
    double tm, ta;
    cell(mach.data(), n_mach, m, i, tm);
    cell(alt_ft.data(), n_alt, h, j, ta);
    const auto t = [&](int a, int b) { return value[a * n_alt + b]; };
    return (1.0 - tm) * ((1.0 - ta) * t(i, j) + ta * t(i, j + 1)) + tm * ((1.0 - ta) * t(i + 1, j) + ta * t(i + 1, j + 1));
  }
};

/// The truth's throttle dither: command (0..1) at time t, in truth/dither.py's order of operations;
/// scheduled: the amplitude from the measured air data (mach, alt_ft) through the thrust table.
struct ThrottleDither {
  double trim = 0.0, amplitude = 0.0, omega_rad_s = 0.0;
  bool scheduled = false;
  double target_fps2 = 0.0;  // CRITERION nx_g * g
  AirDataTable thrust_accel_fps2;

  double command(double time_s, double air_mach = 0.0, double air_alt_ft = 0.0) const {
    return command_about(trim, time_s, air_mach, air_alt_ft);
  }
  // The dither about `base` (the trim, or the outer loop's throttle of the frame), on the lever's 0..1.
  double command_about(double base, double time_s, double air_mach, double air_alt_ft) const {
    double a = amplitude;
    if (scheduled) {
      if (!(std::isfinite(air_mach) && std::isfinite(air_alt_ft))) air_mach = 0.4, air_alt_ft = 20000.0;
      a = target_fps2 / thrust_accel_fps2.at(air_mach, air_alt_ft);
    }
    const double th = base + a * std::sin(omega_rad_s * time_s);
    return th > 1.0 ? 1.0 : (th < 0.0 ? 0.0 : th);
  }
};

/// The adaptive dither's rule for one adapted bank (truth/dither.py adapted_dither_reference and
/// adaptive_mix, loop/flight.py), in their order of operations: rho_ref bilinear in the table at
/// the last finite air data (none yet: h = 0), h = min((sqrt(rho / rho_ref) - 1) / (full - 1), 1)
/// for rho > rho_ref, else 0 (and for a non-finite rho); the flaperons' calm line then takes the
/// gain 1 - h and their turbulence line h.  The rudder's calm line takes rudder_gain(rho) once a
/// reference is in force (1 before: truth/dither.py adaptive_rudder_gain with loop/flight.py's rho 0).
struct AdaptedDither {
  bool on = false;
  double full_ratio = 0.0;
  double rudder_reference = 0.0;   // rho_r (truth/dither.py ADAPTIVE_RUDDER_REFERENCE)
  double rudder_bound = 1.0;       // G, the rudder line's rate bound (truth/dither.py Dither.rudder_gain_bound)
  AirDataTable reference;
  bool has_reference = false;
  double reference_now = 0.0;

  double mix(double rho, double air_mach, double air_alt_ft) noexcept {
    if (std::isfinite(air_mach) && std::isfinite(air_alt_ft)) {
      reference_now = reference.at(air_mach, air_alt_ft);
      has_reference = true;
    }
    if (!has_reference || !(std::isfinite(rho) && rho > reference_now)) return 0.0;
    return std::min((std::sqrt(rho / reference_now) - 1.0) / (full_ratio - 1.0), 1.0);
  }

  double rudder_gain(double rho) const noexcept {
    if (!has_reference || !(std::isfinite(rho) && rho > rudder_reference)) return 1.0;
    return std::max(1.0, std::min(std::sqrt(rho / rudder_reference), rudder_bound));
  }
};

inline constexpr int kMaxSegments = 32;

/// One channel's piecewise reference (truth/outer_loop.py ``Reference``): segments
/// (t0, v0, v1, slope per s; slope = inf for a step) in time order, the value before the first.
struct Reference {
  double start = 0.0;
  int n = 0;
  std::array<double, kMaxSegments> t0{}, v0{}, v1{}, slope{};

  /// (value, slope) at time t.
  void at(double t, double& value, double& rate) const {
    int k = -1;
    for (int i = 0; i < n; ++i) {
      if (t0[i] <= t) k = i;
      else break;
    }
    if (k < 0) { value = start; rate = 0.0; return; }
    if (std::isinf(slope[k])) { value = v1[k]; rate = 0.0; return; }
    const double step = slope[k] * (t - t0[k]);
    if (step >= std::fabs(v1[k] - v0[k])) { value = v1[k]; rate = 0.0; return; }
    const double sign = v1[k] > v0[k] ? 1.0 : -1.0;
    value = v0[k] + sign * step;
    rate = sign * slope[k];
  }
};

inline double sat(double x, double lo, double hi) { return x > hi ? hi : (x < lo ? lo : x); }

/// The outer loop's gains (truth/outer_loop.py ``OuterLoopGains``) and its start values.
struct OuterLoopCoefficients {
  double k_h = 0, k_hd = 0, k_hi = 0, nz_min_g = 0, nz_max_g = 0, k_phi = 0, k_phi_i = 0, p_max_rad_s = 0;
  double k_m = 0, k_mi = 0, dt_s = 0, throttle_0 = 0;
  Reference h_ref, m_ref, phi_ref;
};

/// The outer loop with its three integrators, in truth/outer_loop.py's order of operations.
struct OuterLoopLaw {
  OuterLoopCoefficients c;
  double x_h = 0.0, x_m = 0.0, x_phi = 0.0;

  /// Instruments h (ft), hdot (ft/s), mach, phi (rad) at time_s -> nz_cmd, p_cmd, throttle.
  void command(double time_s, double h, double hdot, double mach, double phi, double& nz_cmd, double& p_cmd,
               double& throttle) {
    double h_ref, hdot_ff, m_ref, m_rate, phi_ref, phi_rate;
    c.h_ref.at(time_s, h_ref, hdot_ff);
    c.m_ref.at(time_s, m_ref, m_rate);
    c.phi_ref.at(time_s, phi_ref, phi_rate);
    const double e_hd = hdot_ff + c.k_h * (h_ref - h) - hdot;
    const double x_lim = c.k_hi > 0 ? std::max(-c.nz_min_g, c.nz_max_g) / c.k_hi : INFINITY;
    x_h = sat(x_h + e_hd * c.dt_s, -x_lim, x_lim);
    const double turn_ff = 1.0 / std::cos(sat(phi, -1.2, 1.2)) - 1.0;
    nz_cmd = sat(c.k_hd * e_hd + c.k_hi * x_h + turn_ff, c.nz_min_g, c.nz_max_g);
    const double e_phi = phi_ref - phi;
    const double phi_lim = c.k_phi_i > 0 ? c.p_max_rad_s / c.k_phi_i : INFINITY;
    x_phi = sat(x_phi + e_phi * c.dt_s, -phi_lim, phi_lim);
    p_cmd = sat(c.k_phi * e_phi + c.k_phi_i * x_phi, -c.p_max_rad_s, c.p_max_rad_s);
    const double e_m = m_ref - mach;
    const double raw = c.throttle_0 + c.k_m * e_m + c.k_mi * x_m;
    if (!((raw >= 1.0 && e_m > 0) || (raw <= 0.0 && e_m < 0))) x_m += e_m * c.dt_s;
    throttle = sat(c.throttle_0 + c.k_m * e_m + c.k_mi * x_m, 0.0, 1.0);
  }
};

}  // namespace f16mmae::truth
