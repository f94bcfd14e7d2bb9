// The maneuver trim's climb angle with the load factor's complement (maneuver_trim.h,
// ClimbAngleComplement): the first frame against the recursion by hand; a pull-up and a level-off
// flown with consistent air data and AZ, where the air data's gamma lags and the complement's does
// not, going over to the air data's in the steady climb; a steady coordinated turn read as no
// climb; the freeze rule; the refusals; in the bank: its gamma is the filter's on the same z with
// no allocation per frame, a bank without AZ is refused by name.
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
constexpr double kRate = 64.0, kDt = 1.0 / kRate, kG = InertialFlightPath::kG;
constexpr double kDeg = 3.14159265358979323846 / 180.0;
}  // namespace

TEST(ClimbAngleComplement, FirstFrameAgainstTheRecursionByHand) {
  const double t = 0.5;
  ClimbAngleComplement f(t, 0.5, kRate);
  // V = 600 ft/s, r = 0.02 rad/s: phi = asin(600 * 0.02 / g); n = 1.2 g; gamma_air = 0.05 rad.
  const double v = 600.0, r = 0.02, n = 1.2, ga = 0.05;
  f.observe(n, 0.0, 0.0, r, v, ga, 0.0, false);
  const double phi = std::asin(v * r / kG);
  const double w = kG / v * (n * std::cos(phi) - std::cos(ga));
  const double c1 = 1.0 - std::exp(-1.0 / (t * kRate)), c5 = 1.0 - std::exp(-1.0 / (5.0 * t * kRate));
  const double d = t * (25.0 * c5 * w - c1 * w) / 4.0;
  EXPECT_NEAR(f.phi(), phi, 1e-15);
  EXPECT_NEAR(f.correction(), d, 1e-15);
  EXPECT_NEAR(f.gamma(), ga + d, 1e-15);
  // frame 1: p = 0.1 rad/s rolls phi by dt p plus the blend towards phi_ref
  f.observe(n, 0.0, 0.1, r, v, ga, 0.0, false);
  const double c_roll = 1.0 - std::exp(-1.0 / (10.0 * kRate));   // T_phi = 10 s
  const double phi1 = phi + kDt * 0.1 + c_roll * (phi - phi);
  const double w1 = kG / v * (n * std::cos(phi1) - std::cos(ga + d));
  const double f1 = c1 * w + c1 * (w1 - c1 * w), f5 = c5 * w + c5 * (w1 - c5 * w);
  EXPECT_NEAR(f.phi(), phi1, 1e-15);
  EXPECT_NEAR(f.gamma(), ga + t * (25.0 * f5 - f1) / 4.0, 1e-15);
}

// A pull-up to a 6-deg climb (2 deg/s for 3 s), 20 s of steady climb, a level-off (2 deg/s), at
// 600 ft/s wings level, 29 s level, the air data exact (Mach = V / c, h = integral of V sin gamma) and
// n = cos gamma + V gamma_dot / g. The air data's gamma lags by its 6 T; the complement's follows.
TEST(ClimbAngleComplement, PullUpAndLevelOffWithoutTheAirDataLag) {
  ManeuverTrimOptions o;
  o.enabled = true;
  o.gamma_load_factor = true;
  ManeuverTrim trim(o, kRate);
  const double v = 600.0, c = 1000.0, rate = 2.0 * kDeg;
  double h = 20000.0, gamma = 0.0, err_air = 0.0, err_on = 0.0;
  const int frames = static_cast<int>(60.0 * kRate);
  for (int k = 0; k < frames; ++k) {
    const double t = k * kDt;
    const double gdot = (t >= 5.0 && t < 8.0) ? rate : (t >= 28.0 && t < 31.0) ? -rate : 0.0;
    trim.observe(v / c, h, c);
    trim.observe_inertial(0.0, 0.0, 0.0, 0.0, v, std::cos(gamma) + v * gdot / kG, false);
    err_air = std::max(err_air, std::abs(trim.air_gamma() - gamma));
    err_on = std::max(err_on, std::abs(trim.gamma() - gamma));
    h += kDt * v * std::sin(gamma + 0.5 * kDt * gdot);
    gamma += kDt * gdot;
  }
  // the air data's: at 2 deg/s the lag 6 T = 3 s would be 6 deg, the climb's 6 deg reached before
  EXPECT_GT(err_air, 3.0 * kDeg);
  EXPECT_LT(err_on, 0.1 * err_air) << "complement " << err_on / kDeg << " deg, air data " << err_air / kDeg << " deg";
  EXPECT_LT(err_on, 0.2 * kDeg);
  // level again for 29 s: the correction has decayed, gamma is the air data's
  EXPECT_NEAR(trim.gamma(), trim.air_gamma(), 0.02 * kDeg);
  EXPECT_NEAR(trim.gamma(), 0.0, 0.05 * kDeg);
}

TEST(ClimbAngleComplement, SteadyCoordinatedTurnIsNoClimb) {
  ClimbAngleComplement f(0.5, 0.5, kRate);
  const double v = 600.0, phi = 30.0 * kDeg, r = kG * std::sin(phi) / v;   // asin(V r / g) = phi
  for (int k = 0; k < 64 * 10; ++k) f.observe(1.0 / std::cos(phi), 0.0, 0.0, r, v, 0.0, 0.0, false);
  EXPECT_NEAR(f.phi(), phi, 1e-12);
  EXPECT_NEAR(f.gamma(), 0.0, 1e-12);
}

TEST(ClimbAngleComplement, FrozenReadsNoSensorAndGoesOverToTheAirData) {
  const double t = 0.5;
  ClimbAngleComplement f(t, 0.5, kRate);
  for (int k = 0; k < 64; ++k) f.observe(1.1, 0.0, 0.0, 0.0, 600.0, 0.02, 0.0, false);   // a pull: a correction builds up
  const double correction = f.correction(), phi = f.phi();
  ASSERT_GT(correction, 0.003);
  // the internal low-passes at the freeze: recover them from two frames of pure decay
  ClimbAngleComplement g = f;
  const double c1 = 1.0 - std::exp(-1.0 / (t * kRate)), c5 = 1.0 - std::exp(-1.0 / (5.0 * t * kRate));
  g.observe(1.1, 0.0, 0.0, 0.0, 600.0, 0.02, 0.0, true);
  const double l1 = g.correction();
  // correction = T (25 f5 - f1) / 4; frozen: f1 *= 1 - c1, f5 *= 1 - c5. Two equations, two unknowns.
  const double a = (1.0 - c1), b = (1.0 - c5);
  const double f5 = (l1 - a * correction) * 4.0 / t / (25.0 * (b - a));
  const double f1 = 25.0 * f5 - 4.0 * correction / t;
  // a failed AZ reading 5 g, AOA, ROL, YAW and the acceleration far off: nothing read, phi holds, the correction decays as stated
  for (int k = 1; k <= 128; ++k) {
    f.observe(5.0, 0.3, 1.0, 1.0, 600.0, 0.03, 9.0, true);
    const double expect = t * (25.0 * f5 * std::pow(b, k) - f1 * std::pow(a, k)) / 4.0;
    ASSERT_NEAR(f.correction(), expect, 1e-12) << "frame " << k;
    ASSERT_NEAR(f.gamma(), 0.03 + expect, 1e-12);
  }
  EXPECT_EQ(f.phi(), phi);
  EXPECT_LT(std::abs(f.correction()), 0.5 * correction);
  // a NaN counts as frozen
  const double before = f.correction();
  f.observe(std::nan(""), 0.0, 0.0, 0.0, 600.0, 0.03, 0.0, false);
  EXPECT_NEAR(f.correction(), t * (25.0 * f5 * std::pow(b, 129) - f1 * std::pow(a, 129)) / 4.0, 1e-12);
  EXPECT_NE(f.correction(), before);
}

TEST(ClimbAngleComplement, RefusesBadOptionsByName) {
  EXPECT_THROW(ClimbAngleComplement(0.0, 0.5, kRate), std::invalid_argument);
  EXPECT_THROW(ClimbAngleComplement(0.5, 0.5, 0.0), std::invalid_argument);
  ManeuverTrimOptions o;
  o.enabled = true;
  o.gamma_load_factor = true;
  o.inertial = true;
  try {
    o.validate();
    ADD_FAILURE() << "accepted both the inertial rates and the load factor's climb angle";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("exclude each other"), std::string::npos) << e.what();
  }
}

TEST(ClimbAngleComplement, BankReadsAzOfZAndRefusesABankWithoutIt) {
  ModelBank mb = test::f16_model_bank(7u);
  mb.state_names = {"u_fps", "alpha_rad", "q_rad_s", "theta_rad", "beta_rad", "p_rad_s", "r_rad_s",
                    "phi_rad", "d_ls_rad", "d_rs_rad", "d_lf_rad", "d_rf_rad", "d_rud_rad"};
  mb.mach = 0.4;
  mb.alt_ft = 20000.0;
  HierarchicalOptions off;
  off.maneuver_trim.enabled = true;
  off.trim.freeze_probability = 1.0;   // no rising hypothesis freezes it (a declaration still would)
  HierarchicalOptions on = off;
  on.maneuver_trim.gamma_load_factor = true;
  {
    F16HierarchicalBank b_on(mb, on), b_off(mb, off);
    ClimbAngleComplement f(on.maneuver_trim.time_constant_s, on.maneuver_trim.gamma_max_rad, mb.frame_rate_hz);
    const int aoa = 1, az = 3, rol = 4, yaw = 5;
    long long allocations = 0;
    int read = 0;
    for (int k = 0; k < 64; ++k) {
      Eigen::Matrix<double, 7, 1> z = mb.z_trim;
      z(az) += 0.01;   // a slight pull: 0.01 g over the trim; the air data stand still
      const long long before = f16mmae::testing::allocation_count();
      b_on.schedule(AirData{0.4, 20000.0});
      b_on.update(z);
      b_on.propagate(mb.u_trim);
      allocations += f16mmae::testing::allocation_count() - before;
      b_off.schedule(AirData{0.4, 20000.0});
      b_off.update(z);
      b_off.propagate(mb.u_trim);
      if (b_on.failure_suspected()) break;
      f.observe(z(az), z(aoa), z(rol), z(yaw), b_on.maneuver_trim().air_airspeed(), b_on.maneuver_trim().air_gamma(),
                b_on.maneuver_trim().accel(), false);
      EXPECT_NEAR(b_on.maneuver_trim().gamma(), f.gamma(), 1e-15) << "frame " << k;
      ++read;
    }
    EXPECT_GE(read, 16);
    EXPECT_EQ(allocations, 0);
    EXPECT_NE(b_on.maneuver_trim().gamma(), b_off.maneuver_trim().gamma());   // the load factor read
    EXPECT_EQ(b_off.maneuver_trim().gamma(), b_off.maneuver_trim().air_gamma());
    EXPECT_EQ(b_on.maneuver_trim().accel(), b_off.maneuver_trim().accel());   // the acceleration the air data's
  }
  mb.measurement_names[3] = "NZ";
  try {
    F16HierarchicalBank b(mb, on);
    ADD_FAILURE() << "accepted a bank without AZ";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'AZ'"), std::string::npos) << e.what();
  }
}
