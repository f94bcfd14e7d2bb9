// The maneuver trim's inertial rates (inertial_flight_path.h): a pull-up's gamma against the
// complementary filter's recursion solved by hand, a steady coordinated turn read as no climb,
// an airspeed ramp's acceleration against the two low-passes' discrete steady state, the freeze
// rule (a failed pitch gyro moves nothing while frozen, and drives gamma to its limit when not),
// the refusals; and in the bank the option reading z with no allocation per frame (a bank
// without PIT refused by name).
#include "f16mmae/hierarchical_bank.h"
#include "f16mmae/inertial_flight_path.h"

#include "allocation_counter.h"
#include "synthetic_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

using namespace f16mmae;

namespace {
constexpr double kRate = 64.0, kDt = 1.0 / kRate, kG = 32.174;
double gain(double t) { return 1.0 - std::exp(-1.0 / (t * kRate)); }
}  // namespace

TEST(InertialFlightPath, PullUpFollowsThePitchRateAndBlendsToTheAirData) {
  InertialFlightPathOptions o;   // T_c = 2 s
  InertialFlightPath f(o, kRate);
  const double alpha = 0.05, q = 0.02, v = 400.0;   // wings level, constant AOA, 0.02 rad/s of pitch rate
  f.observe(q, 0.0, 0.0, alpha, v, 0.0, 0.0, false);   // the first frame: theta = gamma_air + alpha
  EXPECT_DOUBLE_EQ(f.gamma(), 0.0);
  const int n = 64;   // 1 s
  for (int k = 0; k < n; ++k) f.observe(q, 0.0, 0.0, alpha, v, 0.0, 0.0, false);
  // e = theta - alpha: e_{k+1} = (1 - c) e_k + dt q, e_0 = 0  =>  e_n = dt q (1 - (1 - c)^n) / c
  const double c = gain(2.0);
  const double expected = kDt * q * (1.0 - std::pow(1.0 - c, n)) / c;
  EXPECT_NEAR(f.gamma(), expected, 1e-14);
  EXPECT_GT(f.gamma(), 0.75 * q * 1.0);   // three quarters of the 0.02 rad the pitch rate gave in 1 s
  // the pull-up ends (q = 0) and the air data show the climb's gamma: gamma -> gamma_air
  const double g_air = 0.03;
  for (int k = 0; k < 64 * 30; ++k) f.observe(0.0, 0.0, 0.0, alpha, v, g_air, 0.0, false);
  EXPECT_NEAR(f.gamma(), g_air, 1e-6);
}

TEST(InertialFlightPath, SteadyCoordinatedTurnIsNotAClimb) {
  InertialFlightPath f(InertialFlightPathOptions{}, kRate);
  const double v = 400.0, phi = 30.0 * M_PI / 180.0;
  const double psi_dot = kG * std::tan(phi) / v;   // level coordinated turn
  const double q = psi_dot * std::sin(phi), r = psi_dot * std::cos(phi);
  for (int k = 0; k < 640; ++k) f.observe(q, 0.0, r, 0.06, v, 0.0, 0.0, false);
  EXPECT_NEAR(f.phi(), phi, 1e-12);   // asin(V r / g) = asin(sin phi)
  EXPECT_NEAR(f.gamma(), 0.0, 1e-13);
}

TEST(InertialFlightPath, AirspeedRampGivesItsSlope) {
  InertialFlightPathOptions o;
  o.vel_time_constant_s = 0.25;
  InertialFlightPath f(o, kRate);
  const double s = 5.0;   // ft/s^2
  const int n = 64 * 20;
  for (int k = 0; k <= n; ++k) f.observe(0.0, 0.0, 0.0, 0.05, 400.0 + s * k * kDt, 0.0, 0.0, false);
  // a discrete first-order low-pass of a ramp of s dt per frame lags it by s dt (1 - c) / c
  const double cf = gain(0.25), cs = gain(1.25);
  const double expected = s * kDt * ((1.0 - cs) / cs - (1.0 - cf) / cf) / (4.0 * 0.25);
  EXPECT_NEAR(f.accel(), expected, 1e-6 * s);
  EXPECT_NEAR(f.accel(), s, 0.01 * s);
}

TEST(InertialFlightPath, FrozenReadsNoSensorAndGoesOverToTheAirData) {
  InertialFlightPathOptions o;
  const double alpha = 0.05, v = 400.0, g_air = 0.05, a_air = 2.0, hardover = 0.2;   // a failed PIT: 0.2 rad/s
  InertialFlightPath frozen(o, kRate), live(o, kRate);
  frozen.observe(0.0, 0.0, 0.0, alpha, v, 0.0, 0.0, false);
  live.observe(0.0, 0.0, 0.0, alpha, v, 0.0, 0.0, false);
  const int n = 128;
  for (int k = 0; k < n; ++k) {
    frozen.observe(hardover, 0.3, 0.1, alpha + 0.2, v + 50.0 * k, g_air, a_air, true);
    live.observe(hardover, 0.0, 0.0, alpha, v, g_air, a_air, false);
  }
  // frozen: theta - alpha_f relaxes from 0 to g_air, a from 0 to a_air, by the blend term only
  const double c = gain(o.blend_time_constant_s), decay = std::pow(1.0 - c, n);
  EXPECT_NEAR(frozen.gamma(), g_air * (1.0 - decay), 1e-14);
  EXPECT_NEAR(frozen.accel(), a_air * (1.0 - decay), 1e-13);
  EXPECT_DOUBLE_EQ(frozen.phi(), 0.0);
  // not frozen, the hardover drives gamma to the limit gamma_air + max_gap
  EXPECT_NEAR(live.gamma(), g_air + o.max_gap_rad, 1e-12);
}

TEST(InertialFlightPath, RefusesBadOptionsByName) {
  InertialFlightPathOptions o;
  o.blend_time_constant_s = 0.0;
  try {
    InertialFlightPath f(o, kRate);
    ADD_FAILURE() << "accepted blend_time_constant_s = 0";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("blend_time_constant_s"), std::string::npos) << e.what();
  }
  o = InertialFlightPathOptions{};
  o.vel_time_constant_s = -1.0;
  EXPECT_THROW(InertialFlightPath(o, kRate), std::invalid_argument);
  EXPECT_THROW(InertialFlightPath(InertialFlightPathOptions{}, 0.0), std::invalid_argument);
}

TEST(InertialFlightPath, BankReadsZAndRefusesABankWithoutPitchRate) {
  ModelBank mb = test::f16_model_bank(7u);
  mb.state_names = {"u_fps", "alpha_rad", "q_rad_s", "theta_rad", "beta_rad", "p_rad_s", "r_rad_s",
                    "phi_rad", "d_ls_rad", "d_rs_rad", "d_lf_rad", "d_rf_rad", "d_rud_rad"};
  mb.mach = 0.4;
  mb.alt_ft = 20000.0;
  HierarchicalOptions o;
  o.maneuver_trim.enabled = true;
  o.maneuver_trim.inertial = true;
  {
    F16HierarchicalBank b(mb, o);
    // level flight at the trim with a pitch rate reading of 0.01 rad/s over the trim: the bank's
    // gamma is the filter's own on the same readings
    InertialFlightPath f(o.maneuver_trim.inertial_path, mb.frame_rate_hz);
    Eigen::Matrix<double, 7, 1> z = mb.z_trim;
    const int pit = 2, rol = 4, yaw = 5, aoa = 1, vel = 0;
    z(pit) += 0.001;
    long long allocations = 0;
    for (int k = 0; k < 64; ++k) {
      const long long before = f16mmae::testing::allocation_count();
      b.schedule(AirData{0.4, 20000.0});
      b.update(z);
      b.propagate(mb.u_trim);
      allocations += f16mmae::testing::allocation_count() - before;
      f.observe(z(pit), z(rol), z(yaw), z(aoa), z(vel), b.maneuver_trim().air_gamma(), b.maneuver_trim().air_accel(),
                b.failure_suspected());
    }
    EXPECT_EQ(allocations, 0);   // the per-frame path with the inertial rates allocates nothing
    EXPECT_NEAR(b.maneuver_trim().gamma(), f.gamma(), 1e-15);
    EXPECT_GT(b.maneuver_trim().gamma(), 0.0005);   // the pitch rate read: not the air data's 0
  }
  mb.measurement_names[2] = "Q";
  try {
    F16HierarchicalBank b(mb, o);
    ADD_FAILURE() << "accepted a bank without PIT";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'PIT'"), std::string::npos) << e.what();
  }
}
