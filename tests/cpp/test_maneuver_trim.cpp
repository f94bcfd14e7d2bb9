// The maneuver trim (maneuver_trim.h): the climb and acceleration sensitivities of a small
// longitudinal model against their elimination by hand, the refusals; the air-data rates, gamma
// and dV/dt of a climb and a speed ramp against their values; and in the hierarchical bank:
// level flight bit for bit the bank without it, in a climb the trim offsets S (gamma, a) and the
// filters' states moved bumplessly.
#include "f16mmae/hierarchical_bank.h"
#include "f16mmae/maneuver_trim.h"

#include "synthetic_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

using namespace f16mmae;

namespace {

constexpr double kRate = 64.0;
constexpr double kG = 32.174;

// x = (u, alpha, q, theta); u = (LS, RS, LF, RF, RUD). Continuous
//   u'     = Xa alpha - g theta
//   alpha' = Za alpha + q + Zd (LS + RS) / 2
//   q'     = Ma alpha + Mq q + Md (LS + RS) / 2
//   theta' = q
// (LF, RF, RUD drive u and q; the constraints hold them at zero) and its Euler discretization
// phi = I + dt A, bd = dt B, so that (phi - I) x + bd u + dt b_T t = dt a e_u is A x + B u + b_T t = a e_u.
struct Small {
  double xa = 10.0, za = -1.0, zd = -0.1, ma = -4.0, mq = -1.5, md = -8.0;
  double v0 = 400.0, alpha0 = 0.1;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(4, 4), b = Eigen::MatrixXd::Zero(4, 5), h = Eigen::MatrixXd::Zero(2, 4);
  Small() {
    a(0, 1) = xa;
    a(0, 3) = -kG;
    a(1, 1) = za;
    a(1, 2) = 1.0;
    a(2, 1) = ma;
    a(2, 2) = mq;
    a(3, 2) = 1.0;
    b(1, 0) = b(1, 1) = zd / 2.0;
    b(2, 0) = b(2, 1) = md / 2.0;
    b(0, 2) = 0.3;
    b(2, 3) = 0.7;
    b(2, 4) = -0.2;
    h(0, 0) = 1.0;   // VEL ~ u
    h(1, 1) = 1.0;   // AOA ~ alpha
    h(1, 3) = 0.25;  // (a made-up output mixing, to check z = H x)
  }
  Eigen::MatrixXd phi() const { return Eigen::MatrixXd::Identity(4, 4) + a / kRate; }
  Eigen::MatrixXd bd() const { return b / kRate; }
};

const std::vector<std::string> kStates4{"u_fps", "alpha_rad", "q_rad_s", "theta_rad"};
const std::vector<std::string> kInputs{"LS", "RS", "LF", "RF", "RUD"};

}  // namespace

TEST(ManeuverTrim, SensitivitiesOfASmallModelMatchTheEliminationByHand) {
  const Small m;
  const TrimSensitivity s = trim_sensitivity(m.phi(), m.bd(), m.h, kStates4, kInputs, kRate, m.v0, m.alpha0);
  // By hand: q = 0 (theta' = q), u = 0, theta = alpha + gamma, LS = RS = delta, LF = RF = RUD = 0;
  // q' = 0: delta = -Ma alpha / Md; u' = a: t = a + g theta - Xa alpha;
  // alpha' = 0: Za alpha + Zd delta - s t = 0, s = sin(alpha0) / V0. So with
  // D = Za - Zd Ma / Md - s (g - Xa):
  //   per gamma: alpha = s g / D,   t = g (alpha + 1) - Xa alpha
  //   per a:     alpha = s / D,     t = 1 + (g - Xa) alpha
  const double sn = std::sin(m.alpha0) / m.v0;
  const double d = m.za - m.zd * m.ma / m.md - sn * (kG - m.xa);
  const double alpha_g = sn * kG / d, alpha_a = sn / d;
  const double expect_x[2][4] = {{0.0, alpha_g, 0.0, alpha_g + 1.0}, {0.0, alpha_a, 0.0, alpha_a}};
  const double expect_t[2] = {kG * (alpha_g + 1.0) - m.xa * alpha_g, 1.0 + (kG - m.xa) * alpha_a};
  for (int c = 0; c < 2; ++c) {
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(s.x(i, c), expect_x[c][i], 1e-12) << c << " " << i;
    const double delta = -m.ma * expect_x[c][1] / m.md;
    EXPECT_NEAR(s.u(0, c), delta, 1e-12);
    EXPECT_NEAR(s.u(1, c), delta, 1e-12);
    for (int j = 2; j < 5; ++j) EXPECT_NEAR(s.u(j, c), 0.0, 1e-12);
    EXPECT_NEAR(s.thrust(c), expect_t[c], 1e-9);
    EXPECT_NEAR(s.z(0, c), 0.0, 1e-12);
    EXPECT_NEAR(s.z(1, c), expect_x[c][1] + 0.25 * expect_x[c][3], 1e-12);
  }
  // a climb of 0.1 rad needs about g sin(0.1) ft/s^2 of thrust and the attitude up 0.1 rad
  EXPECT_NEAR(s.thrust(0) * 0.1, kG * 0.1, 0.05 * kG * 0.1);
}

TEST(ManeuverTrim, RefusesMissingNamesBadSizesAndBadOptions) {
  const Small m;
  std::vector<std::string> states = kStates4;
  states[3] = "th";
  try {
    trim_sensitivity(m.phi(), m.bd(), m.h, states, kInputs, kRate, m.v0, m.alpha0);
    ADD_FAILURE() << "accepted a model without theta_rad";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("state 'theta_rad'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(trim_sensitivity(m.phi(), m.bd(), m.h, kStates4, {"LS", "RS", "LF", "RF"}, kRate, m.v0, m.alpha0),
               std::invalid_argument);
  EXPECT_THROW(trim_sensitivity(m.phi(), m.bd(), m.h, kStates4, kInputs, kRate, 0.0, m.alpha0), std::invalid_argument);
  ManeuverTrimOptions o;
  o.enabled = true;
  o.time_constant_s = 0.0;
  try {
    ManeuverTrim t(o, kRate);
    ADD_FAILURE() << "accepted time_constant_s 0";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("time_constant_s"), std::string::npos) << e.what();
  }
}

TEST(ManeuverTrim, ClimbAndSpeedRampGiveGammaAndAcceleration) {
  ManeuverTrimOptions o;
  o.enabled = true;
  o.time_constant_s = 0.5;
  ManeuverTrim t(o, kRate);
  // 50 ft/s climb at Mach 0.4, c = 1000 ft/s: V = 400 ft/s, gamma = asin(0.125); after 30 s the
  // low-passes (0.5 and 2.5 s) have settled on the ramp; their discrete lags, (1/c_T - 1)/f,
  // differ by 4 T to a relative 1e-4 (1/c_T - 1 = T f - 1/2 + 1/(12 T f) - ...)
  for (int i = 0; i < 30 * 64; ++i) t.observe(0.4, 20000.0 + 50.0 * i / kRate, 1000.0);
  EXPECT_NEAR(t.gamma(), std::asin(0.125), 1e-4 * 0.125);
  EXPECT_NEAR(t.accel(), 0.0, 1e-12);
  t.reset();
  EXPECT_EQ(t.gamma(), 0.0);
  // Mach ramp 0.002/s at c = 1000 ft/s: 2 ft/s^2; level
  for (int i = 0; i < 30 * 64; ++i) t.observe(0.4 + 0.002 * i / kRate, 20000.0, 1000.0);
  EXPECT_NEAR(t.accel(), 2.0, 1e-4 * 2.0);
  EXPECT_NEAR(t.gamma(), 0.0, 1e-12);
  // without the acceleration part: the same ramp gives a = 0
  ManeuverTrimOptions climb_only = o;
  climb_only.accel = false;
  ManeuverTrim c(climb_only, kRate);
  for (int i = 0; i < 30 * 64; ++i) c.observe(0.4 + 0.002 * i / kRate, 20000.0 + 50.0 * i / kRate, 1000.0);
  EXPECT_EQ(c.accel(), 0.0);
  EXPECT_NEAR(c.gamma(), std::asin(50.0 / (1000.0 * (0.4 + 0.06))), 2e-3);   // V = c M: the Mach ramps too
  // clamped at gamma_max
  t.reset();
  for (int i = 0; i < 30 * 64; ++i) t.observe(0.4, 20000.0 + 4000.0 * i / kRate, 1000.0);
  EXPECT_NEAR(t.gamma(), o.gamma_max_rad, 1e-12);
}

namespace {

ModelBank named_bank() {
  ModelBank mb = test::f16_model_bank(7u);
  mb.state_names = {"u_fps", "alpha_rad", "q_rad_s", "theta_rad", "beta_rad", "p_rad_s", "r_rad_s",
                    "phi_rad", "d_ls_rad", "d_rs_rad", "d_lf_rad", "d_rf_rad", "d_rud_rad"};
  mb.mach = 0.4;
  mb.alt_ft = 20000.0;
  return mb;
}

}  // namespace

TEST(ManeuverTrim, BankInLevelFlightIsTheBankWithoutItBitForBit) {
  const ModelBank mb = named_bank();
  HierarchicalOptions oa, ob;
  ob.maneuver_trim.enabled = true;
  F16HierarchicalBank a(mb, oa), b(mb, ob);
  int frames = 0;
  bool equal = true;
  test::fly_alike(mb, 7u, 11u, 600, [&](int) {
    ++frames;
    equal = equal && a.probabilities() == b.probabilities() && a.blended_state() == b.blended_state();
    const AirData air{0.4, 20000.0};
    a.schedule(air);
    b.schedule(air);
    return true;
  }, a, b);
  EXPECT_EQ(frames, 600);
  EXPECT_TRUE(equal);
  EXPECT_EQ(a.declarations().size(), b.declarations().size());
  EXPECT_EQ(b.maneuver_trim().gamma(), 0.0);
}

TEST(ManeuverTrim, BankInAClimbOffsetsItsTrimAndMovesItsStatesBumplessly) {
  const ModelBank mb = named_bank();
  HierarchicalOptions o;
  o.maneuver_trim.enabled = true;
  F16HierarchicalBank b(mb, o);
  const HypothesisModel& none = mb.hypotheses[0];
  const TrimSensitivity s =
      trim_sensitivity(none.phi, none.bd, none.h, mb.state_names, mb.input_names, kRate, mb.z_trim(0), mb.z_trim(1));
  double max_jump = 0.0;
  int frames = 0;
  test::fly_alike(mb, 7u, 11u, 1600, [&](int i) {
    ++frames;
    // bumpless: every filter's state about the level trim (x⁻_k + dx_m; schedule() comes between a
    // propagate and the next update) is the same across schedule()
    Eigen::Matrix<double, 13, 13> x_before;
    for (int k = 0; k < 13; ++k) x_before.col(k) = b.bank().prior(k) + b.maneuver_trim_dx();
    b.schedule(AirData{0.4, 20000.0 + 30.0 * (i + 1) / kRate});   // 30 ft/s
    for (int k = 0; k < 13; ++k)
      max_jump = std::max(max_jump, (b.bank().prior(k) + b.maneuver_trim_dx() - x_before.col(k)).cwiseAbs().maxCoeff());
    return true;
  }, b);
  EXPECT_EQ(frames, 1600);
  EXPECT_LT(max_jump, 1e-12);
  // 25 s in: gamma = asin(30 / (c M)), c = VEL trim / design Mach = 1000 ft/s
  const double g = b.maneuver_trim().gamma();
  EXPECT_NEAR(g, std::asin(30.0 / 400.0), 1e-4 * 0.075);
  const Eigen::Vector2d ga(g, b.maneuver_trim().accel());
  for (int i = 0; i < 7; ++i) EXPECT_NEAR(b.z_trim()(i) - mb.z_trim(i), (s.z * ga)(i), 1e-12) << i;
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(b.u_trim()(i) - mb.u_trim(i), (s.u * ga)(i), 1e-12) << i;
  for (int i = 0; i < 13; ++i) EXPECT_NEAR(b.maneuver_trim_dx()(i), (s.x * ga)(i), 1e-12) << i;
  EXPECT_NEAR(b.maneuver_trim_dx()(3) - b.maneuver_trim_dx()(1), g, 1e-9);   // theta - alpha = gamma
  // reset: back to the level trim
  b.reset();
  EXPECT_EQ(b.z_trim(), mb.z_trim);
  EXPECT_EQ(b.u_trim(), mb.u_trim);
}

TEST(ManeuverTrim, BankWithoutTheNamedStatesIsRefusedByName) {
  ModelBank mb = named_bank();
  mb.state_names[3] = "pitch";
  HierarchicalOptions o;
  o.maneuver_trim.enabled = true;
  try {
    F16HierarchicalBank b(mb, o);
    ADD_FAILURE() << "accepted a bank without theta_rad";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'theta_rad'"), std::string::npos) << e.what();
  }
}
