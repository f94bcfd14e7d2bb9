// The maneuver trim's acceleration from the airspeed of z (maneuver_trim.h, AirspeedAccel): the
// first frames against the recursion computed by hand, a ramp's slope, a step of acceleration
// against the continuous second-order step response, the freeze rule, the refusals; in the bank:
// the option reads VEL and AOA of z with no allocation per frame, gamma stays the air data's, and
// off is the bank without it.
#include "f16mmae/hierarchical_bank.h"
#include "f16mmae/maneuver_trim.h"

#include "allocation_counter.h"
#include "synthetic_models.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

using namespace f16mmae;

namespace {
constexpr double kRate = 64.0, kDt = 1.0 / kRate;
}  // namespace

TEST(AirspeedAccel, FirstFramesAgainstTheRecursionByHand) {
  const double w0 = 2.0;
  AirspeedAccel f(w0, kRate);
  // w0 = 2, zeta = 1/sqrt(2): k1 = 2 zeta w0 = 2 sqrt(2), k2 = w0^2 = 4; dt = 1/64.
  // frame 0: V^ = 400 / cos(0) = 400, a^ = a_air = 1.5.
  f.observe(400.0, 0.0, 1.5, false);
  EXPECT_EQ(f.airspeed(), 400.0);
  EXPECT_EQ(f.accel(), 1.5);
  // frame 1: V_m = 401, e = 1: V^ = 400 + (1.5 + 2 sqrt(2)) / 64 = 400.0676320..., a^ = 1.5 + 4/64 = 1.5625
  f.observe(401.0, 0.0, 1.5, false);
  EXPECT_NEAR(f.airspeed(), 400.0 + (1.5 + 2.0 * std::sqrt(2.0)) / 64.0, 1e-12);
  EXPECT_NEAR(f.accel(), 1.5625, 1e-15);
  // frame 2: V_m = 402 / cos(0.1) (AOA 0.1 rad: VEL is u = V cos(alpha))
  const double v1 = 400.0 + (1.5 + 2.0 * std::sqrt(2.0)) / 64.0;
  const double e = 402.0 / std::cos(0.1) - v1;
  f.observe(402.0, 0.1, 1.5, false);
  EXPECT_NEAR(f.airspeed(), v1 + (1.5625 + 2.0 * std::sqrt(2.0) * e) / 64.0, 1e-12);
  EXPECT_NEAR(f.accel(), 1.5625 + 4.0 * e / 64.0, 1e-12);
}

TEST(AirspeedAccel, RampSettlesAtItsSlope) {
  AirspeedAccel f(1.0, kRate);
  const double r = 5.0;   // ft/s^2, about 0.005 Mach/s at 20,000 ft
  for (int k = 0; k < 64 * 30; ++k) f.observe(900.0 + r * k * kDt, 0.0, 0.0, false);
  EXPECT_NEAR(f.accel(), r, 1e-6);
}

TEST(AirspeedAccel, AccelerationStepFollowsTheSecondOrderResponse) {
  // V_m = V0 for t < 0, V0 + r t for t >= 0 (a step of the acceleration at t = 0): a^ / r against
  // 1 - exp(-zeta w0 t) (cos(w_d t) + zeta w0 / w_d sin(w_d t)); the Euler recursion is within
  // O(dt) of it.
  const double w0 = 1.0, r = 5.0, zeta = AirspeedAccel::kZeta, wd = w0 * std::sqrt(1.0 - zeta * zeta);
  AirspeedAccel f(w0, kRate);
  f.observe(900.0, 0.0, 0.0, false);
  for (int k = 1; k <= 64 * 8; ++k) {
    const double t = k * kDt;
    f.observe(900.0 + r * t, 0.0, 0.0, false);
    if (k % 64 == 0) {
      const double closed = 1.0 - std::exp(-zeta * w0 * t) * (std::cos(wd * t) + zeta * w0 / wd * std::sin(wd * t));
      EXPECT_NEAR(f.accel() / r, closed, 0.02) << "t = " << t;
    }
  }
  // (the mean delay 2 zeta / w0 = 1.41 s: at t = 1.41 s the closed form is 0.49)
}

TEST(AirspeedAccel, FrozenReadsNoSensorAndGoesOverToTheAirData) {
  const double w0 = 1.0;
  AirspeedAccel f(w0, kRate);
  for (int k = 0; k < 64 * 20; ++k) f.observe(900.0 + 3.0 * k * kDt, 0.0, 0.0, false);
  const double a0 = f.accel();
  EXPECT_NEAR(a0, 3.0, 1e-4);
  // frozen: a failed VEL reading 0 moves nothing but the relaxation to the air data's a = 1
  const double c = 1.0 - std::exp(-w0 / (2.0 * AirspeedAccel::kZeta * kRate));
  double expect = a0;
  for (int k = 0; k < 64; ++k) {
    f.observe(0.0, 0.0, 1.0, true);
    expect += c * (1.0 - expect);
  }
  EXPECT_NEAR(f.accel(), expect, 1e-12);
  // a non-finite reading counts as frozen
  f.observe(std::nan(""), 0.0, 1.0, false);
  expect += c * (1.0 - expect);
  EXPECT_NEAR(f.accel(), expect, 1e-12);
  // the first frame read after the freeze restarts V^ at V_m and keeps a^
  f.observe(950.0, 0.0, 1.0, false);
  EXPECT_EQ(f.airspeed(), 950.0);
  EXPECT_NEAR(f.accel(), expect, 1e-12);
}

TEST(AirspeedAccel, RefusesBadOptionsByName) {
  EXPECT_THROW(AirspeedAccel(0.0, kRate), std::invalid_argument);
  EXPECT_THROW(AirspeedAccel(1.0, 0.0), std::invalid_argument);
  ManeuverTrimOptions o;
  o.enabled = true;
  o.accel_airspeed_rad_s = 0.01;
  try {
    o.validate();
    ADD_FAILURE() << "accepted w0 = 0.01";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("accel_airspeed_rad_s"), std::string::npos) << e.what();
  }
  o.accel_airspeed_rad_s = 1.0;
  o.inertial = true;
  try {
    o.validate();
    ADD_FAILURE() << "accepted both the inertial rates and the airspeed's acceleration";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("exclude each other"), std::string::npos) << e.what();
  }
}

TEST(AirspeedAccel, BankReadsVelAndAoaOfZ) {
  ModelBank mb = test::f16_model_bank(7u);
  mb.state_names = {"u_fps", "alpha_rad", "q_rad_s", "theta_rad", "beta_rad", "p_rad_s", "r_rad_s",
                    "phi_rad", "d_ls_rad", "d_rs_rad", "d_lf_rad", "d_rf_rad", "d_rud_rad"};
  mb.mach = 0.4;
  mb.alt_ft = 20000.0;
  HierarchicalOptions off;
  off.maneuver_trim.enabled = true;
  off.trim.freeze_probability = 1.0;   // no rising hypothesis freezes it (a declaration still would)
  HierarchicalOptions on = off;
  on.maneuver_trim.accel_airspeed_rad_s = 1.0;
  F16HierarchicalBank b_on(mb, on), b_off(mb, off);
  AirspeedAccel f(1.0, mb.frame_rate_hz);
  const int vel = 0, aoa = 1;
  long long allocations = 0;
  double peak = 0.0;
  int read = 0;
  for (int k = 0; k < 128; ++k) {
    Eigen::Matrix<double, 7, 1> z = mb.z_trim;
    z(vel) += 2.0 * k / mb.frame_rate_hz;   // VEL ramps at 2 ft/s^2; the air data stand still
    const long long before = f16mmae::testing::allocation_count();
    b_on.schedule(AirData{0.4, 20000.0});
    b_on.update(z);
    b_on.propagate(mb.u_trim);
    allocations += f16mmae::testing::allocation_count() - before;
    b_off.schedule(AirData{0.4, 20000.0});
    b_off.update(z);
    b_off.propagate(mb.u_trim);
    if (b_on.failure_suspected()) break;   // the ramp declared VEL: frozen from here (the freeze rule's test above)
    f.observe(z(vel), z(aoa), b_on.maneuver_trim().air_accel(), false);
    EXPECT_NEAR(b_on.maneuver_trim().accel(), f.accel(), 1e-15) << "frame " << k;
    peak = std::max(peak, b_on.maneuver_trim().accel());
    ++read;
  }
  EXPECT_GE(read, 16) << "frames read before a declaration";
  EXPECT_EQ(allocations, 0);
  EXPECT_GT(peak, 0.2 * read / 64.0);   // the VEL ramp read (2 ft/s^2; a^ / r is 0.1 at 0.5 s, 0.3 at 1 s)
  EXPECT_EQ(b_on.maneuver_trim().gamma(), b_off.maneuver_trim().gamma());   // gamma the air data's
  EXPECT_EQ(b_off.maneuver_trim().accel(), 0.0);     // off: the air data's (standing still)
}
