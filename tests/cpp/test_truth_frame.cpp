// Truth model per-step arithmetic (cpp/truth/truth_frame.h) against hand-computed values:
// actuator lag, rate and position limits and each failure mode; sensor noise and each failure
// mode; the control law's trim hold, gains, integrator limit, washout and dither; a frame of
// all three allocates nothing.
#include <gtest/gtest.h>

#include <cmath>

#include "allocation_counter.h"
#include "truth/truth_frame.h"

namespace f16mmae::truth {
namespace {

ActuatorBank one_surface_bank() {
  ActuatorBank b;
  b.trim_rad = {0.05, 0, 0, 0, 0};
  b.limit_rad = {0.4, 0.4, 0.4, 0.4, 0.4};
  b.decay = {0.5, 0.5, 0.5, 0.5, 0.5};
  b.max_step_rad = {0.1, 0.1, 0.1, 0.1, 0.1};
  b.reset();
  return b;
}

TEST(TruthActuators, LagThenRateLimitThenPositionLimit) {
  ActuatorBank b = one_surface_bank();
  // c = 0.3: target 0.3 + (0.05 - 0.3) * 0.5 = 0.175, change 0.125 clipped to 0.1 -> 0.15.
  EXPECT_DOUBLE_EQ(b.step({0.3, 0, 0, 0, 0})[0], 0.15);
  // target 0.3 + (0.15 - 0.3) * 0.5 = 0.225, change 0.075 -> 0.225.
  EXPECT_DOUBLE_EQ(b.step({0.3, 0, 0, 0, 0})[0], 0.225);
  // a command beyond the limit is clipped to 0.4 first: target 0.4 + (0.225 - 0.4) / 2 = 0.3125.
  EXPECT_DOUBLE_EQ(b.step({9.0, 0, 0, 0, 0})[0], 0.3125);
}

TEST(TruthActuators, FailureModes) {
  ActuatorBank b = one_surface_bank();
  b.step({0.3, 0, 0, 0, 0});  // LS at 0.15
  ActuatorBank stuck = b, complete = b, hard = b, loss = b;
  stuck.fail(0, ActuatorMode::stuck, 0.0);
  EXPECT_DOUBLE_EQ(stuck.step({-0.3, 0, 0, 0, 0})[0], 0.15);
  complete.fail(0, ActuatorMode::complete, 0.0);  // back to trim 0.05 at the rate limit
  EXPECT_DOUBLE_EQ(complete.step({0.3, 0, 0, 0, 0})[0], 0.05);
  hard.fail(0, ActuatorMode::hardover, -1.0);  // towards -0.4 at 0.1 per step
  EXPECT_DOUBLE_EQ(hard.step({0.3, 0, 0, 0, 0})[0], 0.05);
  EXPECT_NEAR(hard.step({0.3, 0, 0, 0, 0})[0], -0.05, 1e-15);
  loss.fail(0, ActuatorMode::loss, 0.25);  // moves to 0.225; the airframe sees 0.05 + 0.25 * 0.175
  EXPECT_DOUBLE_EQ(loss.step({0.3, 0, 0, 0, 0})[0], 0.05 + 0.25 * (0.225 - 0.05));
  EXPECT_DOUBLE_EQ(loss.position_rad[0], 0.225);
}

TEST(TruthSensors, NoiseAndFailureModes) {
  SensorSet s;
  s.z_trim = {100, 0.1, 0, 1, 0, 0, 0};
  s.sigma = {0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5};
  s.full_scale_low = {-1, -2, -3, -4, -5, -6, -7};
  s.full_scale_high = {1, 2, 3, 4, 5, 6, 7};
  s.reset();
  const Sensors ideal{110, 0.2, 0.01, 1.5, 0.02, 0.03, 0.04};
  const double normal[7] = {2, -2, 1, 0, 4, -4, 2};
  Sensors z = s.measure(ideal, normal, 0.0);
  EXPECT_DOUBLE_EQ(z[0], 111.0);
  EXPECT_DOUBLE_EQ(z[1], 0.2 - 1.0);
  s.fail(0, SensorMode::complete, 0.0, 1.0);
  s.fail(1, SensorMode::null, 0.0, 1.0);
  s.fail(2, SensorMode::stuck, 0.0, 1.0);  // holds the last reading, 0.01 + 0.5
  s.fail(3, SensorMode::hardover, -1.0, 1.0);
  s.fail(4, SensorMode::bias, 0.25, 1.0);
  s.fail(5, SensorMode::drift, 0.1, 1.0);
  z = s.measure(ideal, normal, 3.0);
  EXPECT_DOUBLE_EQ(z[0], 100.0 + 1.0);
  EXPECT_DOUBLE_EQ(z[1], 0.0);
  EXPECT_DOUBLE_EQ(z[2], 0.51);
  EXPECT_DOUBLE_EQ(z[3], -4.0);
  EXPECT_DOUBLE_EQ(z[4], 0.02 + (2.0 + 0.25));
  EXPECT_DOUBLE_EQ(z[5], 0.03 + (-2.0 + 0.1 * 2.0));
  EXPECT_DOUBLE_EQ(z[6], 0.04 + 1.0);
}

FcsCoefficients law() {
  FcsCoefficients c;
  c.u_trim = {-0.02, -0.02, 0.01, -0.01, 0.0};
  c.limit_rad = {0.4, 0.4, 0.4, 0.4, 0.5};
  c.z_trim = {600, 0.05, 0, 1, 0, 0, 0};
  c.kq = 1.0, c.kn = 0.2, c.ki = 0.2, c.kp = 0.4, c.kpff = 0.6, c.kr = 3.0, c.kay = -1.0, c.kari = -0.3;
  c.k_c = 0.5, c.k_v = 0.003, c.k_d = 0.05, c.speed_filter_s = 4.0, c.washout_s = 1.0, c.g_dt = 0.5;
  c.xi_max = 0.01, c.dt_s = 0.25;
  return c;
}

TEST(TruthControlLaw, HoldsTrimAndAppliesGains) {
  FlightControlLaw f{law()};
  const Surfaces u0 = f.command(f.c.z_trim, 0.0);
  for (int j = 0; j < kSurfaces; ++j) EXPECT_DOUBLE_EQ(u0[j], f.c.u_trim[j]);
  // pitch rate 0.01: de = kq dq = 0.01 on both stabilators; x_I += (k_c dq) dt = 0.00125.
  Sensors z = f.c.z_trim;
  z[2] = 0.01;
  const Surfaces u = f.command(z, 0.0);
  EXPECT_DOUBLE_EQ(u[0], -0.02 + 0.01);
  EXPECT_DOUBLE_EQ(u[1], -0.02 + 0.01);
  EXPECT_DOUBLE_EQ(f.x_int, 0.5 * 0.01 * 0.25);
  // roll rate 0.1: da = -kp dp = -0.04; flaperons +-da, stabilators +-g_dt da, rudder kari da.
  FlightControlLaw g{law()};
  z = g.c.z_trim;
  z[4] = 0.1;
  const Surfaces v = g.command(z, 0.0);
  EXPECT_DOUBLE_EQ(v[2], 0.01 - 0.04);
  EXPECT_DOUBLE_EQ(v[3], -0.01 + 0.04);
  EXPECT_DOUBLE_EQ(v[0], -0.02 - 0.5 * 0.04);
  EXPECT_NEAR(v[4], -0.3 * -0.04, 1e-17);
}

TEST(TruthControlLaw, IntegratorLimitWashoutAndDither) {
  FlightControlLaw f{law()};
  Sensors z = f.c.z_trim;
  z[3] = 2.0;  // 1 g above trim: x_I would grow by 0.25 per frame, held at xi_max 0.01
  f.command(z, 0.0);
  EXPECT_DOUBLE_EQ(f.x_int, 0.01);
  z = f.c.z_trim;
  z[5] = 0.2;  // yaw rate: washout state moves by (0.2 - 0) * 0.25 / 1
  f.command(z, 0.0);
  EXPECT_DOUBLE_EQ(f.x_wash, 0.05);
  FcsCoefficients c = law();
  c.dither_enabled = true;
  c.dither_amplitude_rad = {0.01, 0, 0, 0, 0.02};
  c.dither_omega_rad_s = {2.0, 0, 0, 0, 1.0};
  c.dither_phase_rad = {0.0, 0, 0, 0, 0.5};
  FlightControlLaw d{c};
  const Surfaces u = d.command(c.z_trim, 0.75);
  EXPECT_DOUBLE_EQ(u[0], -0.02 + 0.01 * std::sin(1.5));
  EXPECT_DOUBLE_EQ(u[4], 0.0 + 0.02 * std::sin(1.25));
  // the adaptive dither: g_j on the line, h_j on the second line (truth/dither.py adaptive_gains)
  c.dither_gain = {0.25, 1, 1, 1, 1};
  c.dither2_gain = {0.75, 0, 0, 0, 0};
  c.dither2_amplitude_rad = {0.1, 0, 0, 0, 0.5};   // the rudder's is not added: its h is 0
  c.dither2_omega_rad_s = {1.0, 0, 0, 0, 3.0};
  c.dither2_phase_rad = {0.2, 0, 0, 0, 0.0};
  FlightControlLaw a{c};
  const Surfaces v = a.command(c.z_trim, 0.75);
  EXPECT_NEAR(v[0], -0.02 + 0.25 * 0.01 * std::sin(1.5) + 0.75 * 0.1 * std::sin(0.95), 1e-15);
  EXPECT_DOUBLE_EQ(v[4], u[4]);
}

TEST(TruthControlLaw, AdaptedDitherRudderGain) {
  // truth/dither.py adaptive_rudder_gain: 1 until a reference is in force and up to rho_r, then
  // sqrt(rho / rho_r) up to the bound; 1 for a non-finite rho
  AdaptedDither a;
  a.on = true, a.full_ratio = 1.35, a.rudder_reference = 0.8, a.rudder_bound = 1.5;
  a.reference.n_mach = a.reference.n_alt = 2;
  a.reference.mach = {0.3, 0.8}, a.reference.alt_ft = {5000.0, 35000.0};
  a.reference.value = {2.0, 2.0, 2.0, 2.0};
  EXPECT_EQ(a.rudder_gain(4.0), 1.0);   // no air data yet
  EXPECT_EQ(a.mix(1.0, 0.4, 20000.0), 0.0);
  EXPECT_EQ(a.rudder_gain(0.8), 1.0);
  EXPECT_EQ(a.rudder_gain(std::nan("")), 1.0);
  EXPECT_DOUBLE_EQ(a.rudder_gain(0.8 * 1.44), std::sqrt(1.44));
  EXPECT_EQ(a.rudder_gain(100.0), 1.5);
  a.rudder_bound = 1.0;
  EXPECT_EQ(a.rudder_gain(100.0), 1.0);
}

TEST(TruthFrame, AFrameAllocatesNothing) {
  ActuatorBank act = one_surface_bank();
  SensorSet sen;
  sen.sigma.fill(0.1);
  sen.reset();
  FcsCoefficients c = law();
  c.dither_enabled = true;
  c.dither_amplitude_rad.fill(0.01);
  FlightControlLaw fcs{c};
  const double normal[7] = {0.1, -0.2, 0.3, -0.4, 0.5, -0.6, 0.7};
  sen.fail(2, SensorMode::drift, 0.01, 0.0);
  act.fail(1, ActuatorMode::loss, 0.5);
  const long long before = f16mmae::testing::allocation_count();
  double sum = 0.0;
  for (int i = 0; i < 100; ++i) {
    const Sensors z = sen.measure(c.z_trim, normal, i / 64.0);
    const Surfaces u = fcs.command(z, i / 64.0);
    sum += act.step(u)[0] + act.step(u)[1];
  }
  EXPECT_EQ(f16mmae::testing::allocation_count(), before);
  EXPECT_TRUE(std::isfinite(sum));
}

TEST(TruthOuterLoop, ReferenceRampsAndSteps) {
  Reference r;  // a climb 20,000 -> 21,000 ft at 50 ft/s from 10 s, then a step back at 60 s
  r.start = 20000.0;
  r.n = 2;
  r.t0 = {10.0, 60.0}, r.v0 = {20000.0, 21000.0}, r.v1 = {21000.0, 20500.0}, r.slope = {50.0, INFINITY};
  double v, rate;
  r.at(5.0, v, rate);
  EXPECT_EQ(v, 20000.0);
  EXPECT_EQ(rate, 0.0);
  r.at(14.0, v, rate);  // 4 s at 50 ft/s
  EXPECT_DOUBLE_EQ(v, 20200.0);
  EXPECT_EQ(rate, 50.0);
  r.at(40.0, v, rate);  // reached at 30 s
  EXPECT_EQ(v, 21000.0);
  EXPECT_EQ(rate, 0.0);
  r.at(61.0, v, rate);
  EXPECT_EQ(v, 20500.0);
}

TEST(TruthOuterLoop, HandComputedCommands) {
  OuterLoopCoefficients c;
  c.k_h = 0.1, c.k_hd = 0.015, c.k_hi = 0.0003, c.nz_min_g = -1.0, c.nz_max_g = 2.0;
  c.k_phi = 1.0, c.k_phi_i = 0.1, c.p_max_rad_s = 0.35, c.k_m = 8.0, c.k_mi = 1.0, c.dt_s = 0.5;
  c.throttle_0 = 0.25;
  c.h_ref.start = 20000.0, c.m_ref.start = 0.4, c.phi_ref.start = 0.0;
  OuterLoopLaw law{c};
  double nz, p, th;
  // 100 ft low, sinking at 2 ft/s, Mach 0.01 slow, banked 0.1 rad right, nothing commanded
  law.command(0.0, 19900.0, -2.0, 0.39, 0.1, nz, p, th);
  const double e_hd = 0.1 * 100.0 + 2.0;  // 12 ft/s
  EXPECT_DOUBLE_EQ(law.x_h, e_hd * 0.5);
  EXPECT_DOUBLE_EQ(nz, 0.015 * e_hd + 0.0003 * 6.0 + (1.0 / std::cos(0.1) - 1.0));
  EXPECT_DOUBLE_EQ(law.x_phi, -0.05);
  EXPECT_DOUBLE_EQ(p, -0.1 + 0.1 * -0.05);
  const double e_m = 0.4 - 0.39;
  EXPECT_DOUBLE_EQ(law.x_m, e_m * 0.5);
  EXPECT_DOUBLE_EQ(th, 0.25 + 8.0 * e_m + 1.0 * e_m * 0.5);
  // far too slow: the throttle saturates at 1 and its integrator holds
  law.command(0.5, 20000.0, 0.0, 0.2, 0.0, nz, p, th);
  EXPECT_EQ(th, 1.0);
  EXPECT_DOUBLE_EQ(law.x_m, e_m * 0.5);
}

}  // namespace
}  // namespace f16mmae::truth
