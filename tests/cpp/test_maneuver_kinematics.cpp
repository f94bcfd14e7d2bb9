// Maneuver kinematics (maneuver_kinematics.h): the closed-form Jacobian against central
// differences of g, the remainder of a steady level turn against its hand-derived values,
// the remainder second order, the bank's propagation moved by exactly dt R of its blended
// state, off bit-identical, a bank without the airframe names refused by name, and no heap
// allocation in the F-16-sized step with it on (global operator new is counted here); the
// actuator limits by hand (actuator_limits.h) and the load-factor and angle-of-attack tempering of
// the likelihoods.
#include "f16mmae/hierarchical_bank.h"
#include "f16mmae/actuator_limits.h"
#include "f16mmae/maneuver_kinematics.h"

#include "allocation_counter.h"
#include "synthetic_models.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

using namespace f16mmae;
using MK = ManeuverKinematics;

namespace {

constexpr double kPi = 3.14159265358979323846;
// The nominal trim (Mach 0.4, 20,000 ft): body airspeed and angle of attack.
constexpr double kU0 = 410.9, kAlpha0 = 0.1417;

const std::vector<std::string> kStates{"u_fps",   "alpha_rad", "q_rad_s", "theta_rad", "beta_rad",
                                       "p_rad_s", "r_rad_s",   "phi_rad", "d_ls_rad",  "d_rs_rad",
                                       "d_lf_rad", "d_rf_rad", "d_rud_rad"};
const std::vector<std::string> kZNames{"VEL", "AOA", "PIT", "AZ", "ROL", "YAW", "AY"};   // the bank's measurements

// The synthetic F-16-sized bank with the airframe's state names, trimmed at (kU0, kAlpha0).
ModelBank named_bank(unsigned seed) {
  ModelBank mb = test::f16_model_bank(seed);
  mb.state_names = kStates;
  mb.z_trim(0) = kU0;
  mb.z_trim(1) = kAlpha0;
  return mb;
}

// A steady level turn at bank phi about x0: q = omega sin phi, r = omega cos phi.
MK::Vec turn(double phi_rad) {
  const double v0 = kU0 / std::cos(kAlpha0);
  const double omega = MK::kG * std::tan(phi_rad) / v0;
  MK::Vec dx = MK::Vec::Zero();
  dx(MK::Q) = omega * std::sin(phi_rad);
  dx(MK::R) = omega * std::cos(phi_rad);
  dx(MK::PHI) = phi_rad;
  return dx;
}

// 80 frames of the synthetic plant dithered (scaled by dither_scale) through `bank`: before each
// update check receives the blended estimate's measurement perturbation of the frame before (what
// the tempering reads), after it the bank.
template <class Bank, class Check>
void fly_dithered(Bank& bank, const ModelBank& mb, double dither_scale, Check&& check) {
  const test::Plant plant = test::random_plant(13, 5, 7, 5u, 1e-3, 1e-3);
  test::Truth truth(plant, test::kF16Actuators, test::kF16Sensors, 6u);
  for (int i = 0; i < 80; ++i) {
    const Eigen::VectorXd du = dither_scale * test::dither(5, i, 64.0);
    Eigen::Matrix<double, 7, 1> z = truth.measure({}) + mb.z_trim;
    const Eigen::Matrix<double, 7, 1> z_hat_before = bank.z_hat_perturbation();
    bank.update(z);
    check(z_hat_before, bank);
    bank.propagate(du + mb.u_trim);
    truth.advance(du, {});
  }
}

// Every likelihood of the bank's last update is -q_k / (2 s).
template <class Bank>
void expect_tempered_by(const Bank& b, double s) {
  for (int k = 0; k < b.size(); ++k) {
    const double expected = -0.5 * b.bank().quadratic_forms()(k) / s;
    ASSERT_NEAR(b.bank().log_likelihoods()(k), expected, 1e-12 * (1.0 + std::abs(expected)));
  }
}

}  // namespace

TEST(ManeuverKinematics, JacobianEqualsCentralDifferences) {
  for (const double alpha0 : {0.02, kAlpha0, 0.3}) {
    const MK::Vec x0 = MK::level_trim(kU0, alpha0);
    const MK::Mat j = MK::jacobian(x0);
    for (int c = 0; c < MK::kN; ++c) {
      const double h = c == MK::U ? 1e-3 : 1e-6;
      MK::Vec a = x0, b = x0;
      a(c) += h;
      b(c) -= h;
      const MK::Vec fd = (MK::derivative(a) - MK::derivative(b)) / (2.0 * h);
      for (int r = 0; r < MK::kN; ++r)
        EXPECT_NEAR(j(r, c), fd(r), 1e-7 * (1.0 + std::abs(fd(r)))) << "alpha0 " << alpha0 << " d" << r << "/d" << c;
    }
  }
}

TEST(ManeuverKinematics, SteadyLevelTurnRemainderByHand) {
  const MK::Vec x0 = MK::level_trim(kU0, kAlpha0);
  const double phi = 30.0 * kPi / 180.0;
  const MK::Vec dx = turn(phi);
  const MK::Vec r = MK::remainder(x0, dx);
  const double w0 = kU0 * std::tan(kAlpha0), d0 = kU0 * kU0 + w0 * w0, v0 = std::sqrt(d0);
  const double ct = std::cos(kAlpha0), tt = std::tan(kAlpha0);
  // theta' = q cos phi - r sin phi = 0 in a level turn; the linear model has q.
  EXPECT_NEAR(r(MK::THETA), -dx(MK::Q), 1e-15);
  EXPECT_NEAR(r(MK::ALPHA), kU0 * MK::kG * ct * (std::cos(phi) - 1.0) / d0, 1e-14);
  EXPECT_NEAR(r(MK::BETA), MK::kG * ct * (std::sin(phi) - phi) / v0, 1e-14);
  EXPECT_NEAR(r(MK::PHI), tt * (dx(MK::Q) * std::sin(phi) + dx(MK::R) * (std::cos(phi) - 1.0)), 1e-15);
  EXPECT_NEAR(r(MK::U), 0.0, 1e-12);
  EXPECT_EQ(r(MK::Q), 0.0);
  EXPECT_EQ(r(MK::P), 0.0);
  EXPECT_EQ(r(MK::R), 0.0);
  // The figures the header quotes: -0.022 and -0.010 rad/s at 30 deg.
  EXPECT_NEAR(r(MK::THETA), -0.022, 0.001);
  EXPECT_NEAR(r(MK::ALPHA), -0.010, 0.001);
}

TEST(ManeuverKinematics, RemainderIsSecondOrderAndZeroAtTrim) {
  const MK::Vec x0 = MK::level_trim(kU0, kAlpha0);
  EXPECT_EQ(MK::remainder(x0, MK::Vec::Zero()), MK::Vec::Zero());
  MK::Vec dx;
  dx << 3.0, 0.02, 0.01, 0.05, 0.01, 0.04, 0.02, 0.3;
  // R(eps dx) = eps^2 C + O(eps^3): halving eps quarters it.
  const MK::Vec r1 = MK::remainder(x0, 0.02 * dx), r2 = MK::remainder(x0, 0.01 * dx);
  for (int i = 0; i < MK::kN; ++i) {
    if (r1(i) == 0.0) continue;
    EXPECT_NEAR(r1(i) / r2(i), 4.0, 0.05) << "state " << i;
  }
}

TEST(ManeuverKinematics, BankPriorMovesByDtTimesTheRemainderOfItsBlendedState) {
  const ModelBank mb = named_bank(11u);
  HierarchicalOptions off, on;
  on.maneuver.kinematics = true;
  F16HierarchicalBank a(mb, off), b(mb, on);
  const test::Plant plant = test::random_plant(13, 5, 7, 11u, 1e-3, 1e-3);
  test::Truth truth(plant, test::kF16Actuators, test::kF16Sensors, 4u);
  // One frame: the same update in both (identical priors so far), then the propagates differ
  // by dt R of the blended posterior about the level trim (kU0, kAlpha0).
  Eigen::Matrix<double, 7, 1> z = truth.measure({}) + mb.z_trim;
  z(2) += 0.02;   // a pitch rate and yaw rate, as in a turn
  z(5) += 0.04;
  const Eigen::Matrix<double, 5, 1> u = test::dither(5, 0, 64.0) + mb.u_trim;
  a.update(z), b.update(z);
  ASSERT_EQ(a.blended_state(), b.blended_state());
  const Eigen::Matrix<double, 13, 1> x = b.blended_state();
  a.propagate(u), b.propagate(u);
  MK::Vec dx;
  for (int i = 0; i < MK::kN; ++i) dx(i) = x(i);
  const MK::Vec r = MK::remainder(MK::level_trim(kU0, kAlpha0), dx);
  for (int k = 0; k < a.size(); ++k) {
    const Eigen::Matrix<double, 13, 1> diff = b.bank().prior(k) - a.bank().prior(k);
    for (int i = 0; i < 13; ++i)
      EXPECT_NEAR(diff(i), i < MK::kN ? r(i) / 64.0 : 0.0, 1e-15) << "filter " << k << " state " << i;
  }
  EXPECT_NE(r(MK::THETA), 0.0);
}

TEST(ManeuverKinematics, OffIsBitIdenticalToTheBankWithoutIt) {
  const ModelBank mb = named_bank(7u);
  HierarchicalOptions plain, off;
  off.maneuver.kinematics = false;
  F16HierarchicalBank a(mb, plain), b(mb, off);
  test::fly_alike(mb, 7u, 3u, 300, [&](int i) {
    EXPECT_EQ(a.probabilities(), b.probabilities()) << "frame " << i;
    EXPECT_EQ(a.blended_state(), b.blended_state()) << "frame " << i;
    return a.probabilities() == b.probabilities() && a.blended_state() == b.blended_state();
  }, a, b);
}

TEST(ManeuverKinematics, BankWithoutTheAirframeNamesIsRefusedByName) {
  HierarchicalOptions on;
  on.maneuver.kinematics = true;
  const ModelBank unnamed = test::f16_model_bank(3u);   // states x0..x12
  try {
    F16HierarchicalBank hb(unnamed, on);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("state 'u_fps'"), std::string::npos) << e.what();
  }
  ModelBank no_aoa = named_bank(3u);
  no_aoa.measurement_names[1] = "ALPHA";
  try {
    F16HierarchicalBank hb(no_aoa, on);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("measurement 'AOA'"), std::string::npos) << e.what();
  }
  F16HierarchicalBank fine(unnamed, HierarchicalOptions{});   // off: the names are not needed
  EXPECT_EQ(fine.level(), 0);
}

TEST(ManeuverKinematics, F16SizedStepWithKinematicsAllocatesNothing) {
  const ModelBank mb = named_bank(31u);
  HierarchicalOptions o;
  o.maneuver.kinematics = true;
  F16HierarchicalBank hb(mb, o);
  const test::Plant plant = test::random_plant(13, 5, 7, 31u, 1e-3, 1e-3);
  test::Truth truth(plant, test::kF16Actuators, test::kF16Sensors, 5u);
  std::vector<Eigen::Matrix<double, 7, 1>> z;
  std::vector<Eigen::Matrix<double, 5, 1>> u;
  for (int i = 0; i < 640; ++i) {
    const std::vector<std::string> failed = i >= 64 ? std::vector<std::string>{"PIT"} : std::vector<std::string>{};
    // The synthetic plant is no airframe: its states fed through the kinematic terms grow
    // without bound at the usual dither, so the dither is small here.
    const Eigen::VectorXd du = 0.01 * test::dither(5, i, 64.0);
    Eigen::Matrix<double, 7, 1> zi = truth.measure(failed) + mb.z_trim;
    if (i >= 64) zi(2) += 0.02;   // the failed pitch-rate gyro reads off: a sure declaration
    z.push_back(zi);
    u.push_back(du + mb.u_trim);
    truth.advance(du, failed);
  }
  const long long before = f16mmae::testing::allocation_count();
  for (std::size_t i = 0; i < z.size(); ++i) hb.step(z[i], u[i]);
  const long long after = f16mmae::testing::allocation_count();
  EXPECT_EQ(after - before, 0);
  EXPECT_EQ(hb.rejected_frames(), 0);
  EXPECT_FALSE(hb.declarations().empty());   // the switch to level 1 happened inside the count
}

// ---- actuator limits (actuator_limits.h) ----------------------------------------------------

namespace {

// One input driving a lag state (state 1) and, within the frame, another state (state 0).
struct LagModel {
  Eigen::MatrixXd phi = Eigen::MatrixXd::Zero(2, 2), bd = Eigen::MatrixXd::Zero(2, 1);
  explicit LagModel(double a) {
    phi << 0.9, 0.05, 0.0, a;
    bd << 0.01, 1.0 - a;
  }
};

}  // namespace

TEST(ActuatorLimits, InsideTheLimitsTheCommandIsUnchanged) {
  const LagModel m(0.7293);
  ActuatorLimitOptions o{{1.0}, {0.4}, 2};
  ActuatorLimits<1> lim(o, m.phi, m.bd, 64.0);
  Eigen::Matrix<double, 1, 1> u, e;
  for (int i = 0; i < 200; ++i) {
    u << 0.01 * std::sin(0.3 * i);   // at most 0.003 rad per frame: far inside 1 rad/s
    lim.effective(u, e);
    EXPECT_NEAR(e(0), u(0), 1e-14) << "frame " << i;
  }
}

TEST(ActuatorLimits, RateAndPositionLimitedStepByHand) {
  const double a = 0.7293, rate = 1.0, limit = 0.3;
  const LagModel m(a);
  ActuatorLimitOptions o{{rate}, {limit}, 2};
  ActuatorLimits<1> lim(o, m.phi, m.bd, 64.0);
  Eigen::Matrix<double, 1, 1> u, e;
  u << 0.0;
  lim.effective(u, e);   // starts at 0
  // A step to 0.5 rad: clipped to 0.3, and each half-frame step at most 1/128 rad.
  u << 0.5;
  double delta = 0.0, model = 0.0;
  const double s = std::sqrt(a), step = rate / 128.0;
  for (int i = 0; i < 80; ++i) {
    lim.effective(u, e);
    const double start = delta;
    for (int k = 0; k < 2; ++k) {
      const double target = limit + (delta - limit) * s;
      delta += std::clamp(target - delta, -step, step);
    }
    EXPECT_NEAR(lim.position()(0), delta, 1e-15);
    EXPECT_NEAR(e(0), (delta - a * start) / (1.0 - a), 1e-12);
    model = a * model + (1.0 - a) * e(0);   // the filter's lag fed the effective command
    EXPECT_NEAR(model, delta, 1e-12) << "frame " << i;
    EXPECT_LE(delta, limit + 1e-15);
  }
  EXPECT_NEAR(delta, limit, 1e-6);   // reached the position limit
  EXPECT_NEAR(e(0), limit, 1e-6);
  lim.reset();
  u << 0.1;
  lim.effective(u, e);   // after a reset it starts again at the first command
  EXPECT_DOUBLE_EQ(lim.position()(0), 0.1);
}

TEST(ActuatorLimits, OptionsAndModelsThatDoNotFitAreNamed) {
  const LagModel m(0.7293);
  auto refused = [&](const ActuatorLimitOptions& o, const Eigen::MatrixXd& phi, const Eigen::MatrixXd& bd,
                     const std::string& what) {
    try {
      ActuatorLimits<1> lim(o, phi, bd, 64.0);
      FAIL() << "no exception for " << what;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  refused({{1.0, 2.0}, {0.3}, 2}, m.phi, m.bd, "need 1 values each");
  refused({{0.0}, {0.3}, 2}, m.phi, m.bd, "rate_limit_rad_s[0]");
  refused({{1.0}, {std::nan("")}, 2}, m.phi, m.bd, "position_limit_rad[0]");
  refused({{1.0}, {0.3}, 0}, m.phi, m.bd, "substeps");
  Eigen::MatrixXd coupled = m.phi;
  coupled(1, 0) = 0.1;   // the lag state depends on another state
  refused({{1.0}, {0.3}, 2}, coupled, m.bd, "drives no first-order lag state");
  Eigen::MatrixXd gain = m.bd;
  gain(1, 0) = 0.5;   // not 1 - a
  refused({{1.0}, {0.3}, 2}, m.phi, gain, "not a stable lag of unit gain");
  ActuatorLimits<1> off(ActuatorLimitOptions{}, m.phi, m.bd, 64.0);
  Eigen::Matrix<double, 1, 1> u, e;
  u << 5.0;
  off.effective(u, e);
  EXPECT_EQ(e(0), 5.0);
}

// ---- load-factor tempering (FilterBank::set_extra_scale) ------------------------------------

TEST(ManeuverTempering, LikelihoodsAreDividedByTheScale) {
  const ModelBank mb = named_bank(5u);
  HierarchicalOptions o;
  F16HierarchicalBank plain(mb, o);
  o.maneuver.tempering_g = 0.1;
  F16HierarchicalBank tempered(mb, o);
  const test::Plant plant = test::random_plant(13, 5, 7, 5u, 1e-3, 1e-3);
  test::Truth truth(plant, test::kF16Actuators, test::kF16Sensors, 6u);
  for (int i = 0; i < 50; ++i) {
    const Eigen::VectorXd du = test::dither(5, i, 64.0);
    Eigen::Matrix<double, 7, 1> z = truth.measure({}) + mb.z_trim;
    const Eigen::Matrix<double, 5, 1> u = du + mb.u_trim;
    const double dn = tempered.z_hat_perturbation()(3);   // the estimated load factor off trim
    const double s = 1.0 + (dn / 0.1) * (dn / 0.1);
    tempered.update(z);
    plain.update(z);
    for (int k = 0; k < plain.size(); ++k) {
      const double expected = -0.5 * tempered.bank().quadratic_forms()(k) / s;
      ASSERT_NEAR(tempered.bank().log_likelihoods()(k), expected, 1e-13 * (1.0 + std::abs(expected)));
    }
    tempered.propagate(u);
    plain.propagate(u);
    truth.advance(du, {});
  }
  // the un-tempered bank's likelihoods are -q/2 exactly
  for (int k = 0; k < plain.size(); ++k)
    EXPECT_DOUBLE_EQ(plain.bank().log_likelihoods()(k), -0.5 * plain.bank().quadratic_forms()(k));
}

// The dead band: only |dn| beyond d tempers, s_m = 1 + (max(0, |dn| - d) / n_ref)^2. d is set
// at the median |dn| of the same flight so that frames inside and beyond it are both checked.
TEST(ManeuverTempering, DeadBandTempersOnlyTheLoadFactorBeyondIt) {
  const ModelBank mb = named_bank(5u);
  auto fly = [&](F16HierarchicalBank& bank, auto&& check) {
    fly_dithered(bank, mb, 1.0, [&](const auto& z_hat, const F16HierarchicalBank& b) { check(z_hat(3), b); });
  };
  HierarchicalOptions o;
  o.maneuver.tempering_g = 1e-3;
  std::vector<double> dns;
  F16HierarchicalBank probe(mb, o);
  fly(probe, [&](double dn, const F16HierarchicalBank&) { dns.push_back(std::abs(dn)); });
  std::vector<double> sorted = dns;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double d = sorted[sorted.size() / 2];
  ASSERT_GT(d, 0.0);
  o.maneuver.tempering_deadband_g = d;
  F16HierarchicalBank banded(mb, o);
  int inside = 0, beyond = 0;
  fly(banded, [&](double dn, const F16HierarchicalBank& b) {
    const double excess = std::abs(dn) > d ? std::abs(dn) - d : 0.0;
    (excess > 0.0 ? beyond : inside)++;
    const double s = 1.0 + (excess / 1e-3) * (excess / 1e-3);
    expect_tempered_by(b, s);
  });
  EXPECT_GT(inside, 10);
  EXPECT_GT(beyond, 10);
  HierarchicalOptions bad;
  bad.maneuver.tempering_deadband_g = 0.1;   // without the tempering
  EXPECT_THROW(F16HierarchicalBank(mb, bad), std::invalid_argument);
  bad.maneuver.tempering_g = 0.1;
  bad.maneuver.tempering_deadband_g = -0.1;
  EXPECT_THROW(F16HierarchicalBank(mb, bad), std::invalid_argument);
}

// ---- angle-of-attack tempering ---------------------------------------------------------------

// s_m = (1 + (dn / n_ref)^2) (1 + (y^2 + x_a^2) / s), y = max(0, |da| - a_d sqrt(s)) / a_ref, da the
// AOA entry of z_hat in degrees, x_a = max(0, |dn| - d_a sqrt(s)) / n_a: by hand for s = 1 and s = 4,
// with and without the load factor's multiplied and added terms.
TEST(ManeuverTempering, AddedTermsAddTheirSquaresToTheTurbulenceScaleByHand) {
  ManeuverOptions o;
  o.tempering_alpha_deg = 2.0;
  o.tempering_alpha_deadband_deg = 0.5;
  const MK alpha_only(o, kStates, kZNames, 64.0);
  Eigen::Matrix<double, 7, 1> z = Eigen::Matrix<double, 7, 1>::Zero();
  z(1) = -3.0 * kPi / 180.0;   // 3 deg below the trim
  z(3) = 0.2;                  // 0.2 g
  EXPECT_NEAR(alpha_only.tempering_scale(z, 1.0), 1.0 + (2.5 / 2.0) * (2.5 / 2.0), 1e-12);
  // s = 4: the dead band 0.5 * 2 = 1 deg, y = 2 / 2 = 1, s_m = 1 + 1 / 4 (s s_m = s + y^2 = 5)
  EXPECT_NEAR(alpha_only.tempering_scale(z, 4.0), 1.25, 1e-12);
  // s below 1 counts as 1
  EXPECT_NEAR(alpha_only.tempering_scale(z, 0.3), alpha_only.tempering_scale(z, 1.0), 1e-15);
  // inside the dead band: nothing
  z(1) = 0.9 * kPi / 180.0;
  EXPECT_EQ(alpha_only.tempering_scale(z, 4.0), 1.0);
  // with the load factor's term (n_ref 0.1 g, no dead band): the product of the two factors
  o.tempering_g = 0.1;
  const MK both(o, kStates, kZNames, 64.0);
  z(1) = 4.0 * kPi / 180.0;
  // dn / n_ref = 2; y = (4 - 1) / 2 = 1.5
  EXPECT_NEAR(both.tempering_scale(z, 4.0), (1.0 + 4.0) * (1.0 + 1.5 * 1.5 / 4.0), 1e-12);
  // the load factor's added term (n_a 0.1 g, dead band 0.05 sqrt(s) g) joins y^2 in what is added to s:
  // s = 4, dn = 0.2: x_a = (0.2 - 0.1) / 0.1 = 1; y = 1.5 as above
  o.tempering_added_g = 0.1;
  o.tempering_added_deadband_g = 0.05;
  const MK added(o, kStates, kZNames, 64.0);
  EXPECT_NEAR(added.tempering_scale(z, 4.0), (1.0 + 4.0) * (1.0 + (1.5 * 1.5 + 1.0) / 4.0), 1e-12);
  z(3) = 0.09;   // inside the added term's band at s = 4 (0.1 g): only the multiplied term and y
  EXPECT_NEAR(added.tempering_scale(z, 4.0), (1.0 + 0.81) * (1.0 + 1.5 * 1.5 / 4.0), 1e-12);
  o.tempering_added_g = 0.0;
  o.tempering_added_deadband_g = 0.0;
  {  // the added term alone reads AZ: at s = 1, dn = 0.3 g, n_a = 0.1 g, s_m = 1 + 9
    ManeuverOptions only_added;
    only_added.tempering_added_g = 0.1;
    const MK m(only_added, kStates, kZNames, 64.0);
    Eigen::Matrix<double, 7, 1> z3 = Eigen::Matrix<double, 7, 1>::Zero();
    z3(3) = -0.3;
    EXPECT_NEAR(m.tempering_scale(z3, 1.0), 10.0, 1e-12);
    const std::vector<std::string> no_az{"VEL", "AOA", "PIT", "AZZ", "ROL", "YAW", "AY"};
    EXPECT_THROW(MK(only_added, kStates, no_az, 64.0), std::invalid_argument);
  }
  // the load factor's term alone does not read AOA, and without AOA the alpha term is refused by name
  const std::vector<std::string> no_aoa{"VEL", "AOX", "PIT", "AZ", "ROL", "YAW", "AY"};
  try {
    MK(o, kStates, no_aoa, 64.0);
    FAIL() << "a bank without AOA was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("AOA"), std::string::npos) << e.what();
  }
  o.tempering_alpha_deg = 0.0;
  o.tempering_alpha_deadband_deg = 0.0;
  EXPECT_NO_THROW(MK(o, kStates, no_aoa, 64.0));
}

// With a trim knee a_k the reference is a_ref min(1, (a_k / alpha0)^3), alpha0 the trim in force's angle
// of attack: by hand below, at and above the knee; without a knee alpha0 is not read.
TEST(ManeuverTempering, AlphaReferenceShrinksAboveTheTrimKneeByHand) {
  ManeuverOptions o;
  o.tempering_alpha_deg = 1.0;
  o.tempering_alpha_deadband_deg = 0.25;
  const MK plain(o, kStates, kZNames, 64.0);
  o.tempering_alpha_trim_deg = 8.0;
  const MK knee(o, kStates, kZNames, 64.0);
  EXPECT_TRUE(knee.reads_trim_alpha());
  EXPECT_FALSE(plain.reads_trim_alpha());
  Eigen::Matrix<double, 7, 1> z = Eigen::Matrix<double, 7, 1>::Zero();
  z(1) = 1.25 * kPi / 180.0;   // 1.25 deg off the trim: y = (1.25 - 0.25 sqrt(s)) / a_ref'
  const double deg = kPi / 180.0;
  // below and at the knee: the plain rule, y = 1 at s = 1
  EXPECT_NEAR(knee.tempering_scale(z, 1.0, 5.0 * deg), 2.0, 1e-12);
  EXPECT_NEAR(knee.tempering_scale(z, 1.0, 8.0 * deg), 2.0, 1e-12);
  EXPECT_NEAR(plain.tempering_scale(z, 1.0, 16.0 * deg), 2.0, 1e-12);
  // trimmed at 16 deg: a_ref' = (8 / 16)^3 = 0.125, y = 1 / 0.125 = 8, s_m = 1 + 64
  EXPECT_NEAR(knee.alpha_reference(16.0 * deg), 0.125, 1e-12);
  EXPECT_NEAR(knee.tempering_scale(z, 1.0, 16.0 * deg), 65.0, 1e-12);
  // s = 4: band 0.5 deg, y = 0.75 / 0.125 = 6, s_m = 1 + 36 / 4
  EXPECT_NEAR(knee.tempering_scale(z, 4.0, 16.0 * deg), 10.0, 1e-12);
  // at 10 deg: (8 / 10)^3 = 0.512
  EXPECT_NEAR(knee.alpha_reference(10.0 * deg), 0.512, 1e-12);
  // a negative or non-finite trim alpha: the plain reference
  EXPECT_EQ(knee.alpha_reference(-10.0 * deg), 1.0);
  EXPECT_EQ(knee.alpha_reference(std::nan("")), 1.0);
  // the knee applies with the alpha term only, and in [0, 90] deg
  ManeuverOptions bad;
  bad.tempering_alpha_trim_deg = 8.0;
  EXPECT_THROW(MK(bad, kStates, kZNames, 64.0), std::invalid_argument);
  bad.tempering_alpha_deg = 1.0;
  bad.tempering_alpha_trim_deg = 91.0;
  EXPECT_THROW(MK(bad, kStates, kZNames, 64.0), std::invalid_argument);
  bad.tempering_alpha_trim_deg = -1.0;
  EXPECT_THROW(MK(bad, kStates, kZNames, 64.0), std::invalid_argument);
}

// The added term's band is at least k sigma_n, sigma_n the load factor's spread about its 0.35-s
// mean (a plain mean of the squares over the first 30 s): recomputed here from the header's
// recursions, frame by frame, with the scale it gives; reset() starts it again; off observes nothing.
TEST(ManeuverTempering, AddedTermsBandFollowsTheLoadFactorsMeasuredSpread) {
  ManeuverOptions o;
  o.tempering_added_g = 0.03;
  o.tempering_added_deadband_g = 0.08;
  o.tempering_added_spread = 3.0;
  MK m(o, kStates, kZNames, 64.0);
  const MK fixed_band([&] { ManeuverOptions f = o; f.tempering_added_spread = 0.0; return f; }(), kStates, kZNames,
                      64.0);
  const double cm = 1.0 - std::exp(-1.0 / (0.35 * 64.0));
  double mean = 0.0, power = 0.0;
  Eigen::Matrix<double, 7, 1> z = Eigen::Matrix<double, 7, 1>::Zero();
  int wider = 0;
  for (int i = 0; i < 640; ++i) {
    const double dn = 0.3 * std::sin(2.0 * kPi * 0.7 * i / 64.0) + (i % 7 == 0 ? 0.05 : 0.0);   // gusts at high q
    z(3) = dn;
    m.observe_spread(z);
    if (i == 0) mean = dn;
    mean += cm * (dn - mean);
    power += (1.0 / (i + 1)) * ((dn - mean) * (dn - mean) - power);   // i + 1 <= 30 s f: the plain mean
    ASSERT_NEAR(m.load_factor_spread(), std::sqrt(power), 1e-12) << i;
    for (double s : {1.0, 4.0}) {
      const double band = std::max(0.08 * std::sqrt(s), 3.0 * std::sqrt(power));
      const double x = std::max(0.0, std::abs(dn) - band) / 0.03;
      ASSERT_NEAR(m.tempering_scale(z, s), 1.0 + x * x / s, 1e-9) << i;
    }
    if (m.tempering_scale(z, 1.0) < fixed_band.tempering_scale(z, 1.0)) ++wider;
  }
  EXPECT_GT(wider, 300);   // the swings' own spread holds them inside the band
  m.reset_spread();
  EXPECT_EQ(m.load_factor_spread(), 0.0);
  MK off = fixed_band;
  z(3) = 0.5;
  off.observe_spread(z);
  EXPECT_EQ(off.load_factor_spread(), 0.0);
  o.tempering_added_spread = -1.0;
  EXPECT_THROW(MK(o, kStates, kZNames, 64.0), std::invalid_argument);
  o.tempering_added_spread = 2.0;
  o.tempering_added_g = 0.0;
  o.tempering_added_deadband_g = 0.0;
  EXPECT_THROW(MK(o, kStates, kZNames, 64.0), std::invalid_argument);   // the band without its term
}

// In the bank: every likelihood is -q / (2 s_m), s_m = 1 + x_a^2 (no adaptation: s = 1) with the
// band max(d_a, k sigma_n) of the spread recomputed from the blended estimates the bank read, frame
// by frame; reset() starts the spread again (the fresh bank's flight, bit for bit); a bank that
// takes over carries it on (the same model's bank flies on as the first, bit for bit).
TEST(ManeuverTempering, AddedTermsSpreadBandInTheBankResetAndTakeOver) {
  const ModelBank mb = named_bank(5u);
  HierarchicalOptions o;
  o.maneuver.tempering_added_g = 1e-4;
  o.maneuver.tempering_added_deadband_g = 1e-5;
  o.maneuver.tempering_added_spread = 1.0;
  F16HierarchicalBank bank(mb, o);
  const double cm = 1.0 - std::exp(-1.0 / (MK::kSpreadMeanS * 64.0));
  double mean = 0.0, power = 0.0;
  int i = 0, spread_band = 0, beyond = 0;
  std::vector<double> first;
  fly_dithered(bank, mb, 1e-3, [&](const auto& z_hat, const F16HierarchicalBank& b) {
    const double dn = z_hat(3);
    if (i == 0) mean = dn;
    mean += cm * (dn - mean);
    power += (1.0 / ++i) * ((dn - mean) * (dn - mean) - power);   // 80 frames: the plain mean
    const double band = std::max(1e-5, std::sqrt(power));
    const double x = std::max(0.0, std::abs(dn) - band) / 1e-4;
    spread_band += std::sqrt(power) > 1e-5;
    beyond += x > 0.0;
    expect_tempered_by(b, 1.0 + x * x);
    first.push_back(b.bank().log_likelihoods()(0));
  });
  EXPECT_GT(spread_band, 40);
  EXPECT_GT(beyond, 10);
  bank.reset();
  std::size_t j = 0;
  fly_dithered(bank, mb, 1e-3, [&](const auto&, const F16HierarchicalBank& b) {
    ASSERT_EQ(b.bank().log_likelihoods()(0), first[j++]);
  });
  // take over half way: the same model's bank flies on as the first did
  F16HierarchicalBank a(mb, o), b(mb, o);
  const test::Plant plant = test::random_plant(13, 5, 7, 5u, 1e-3, 1e-3);
  test::Truth truth(plant, test::kF16Actuators, test::kF16Sensors, 6u);
  for (int f = 0; f < 80; ++f) {
    const Eigen::VectorXd du = 1e-3 * test::dither(5, f, 64.0);
    const Eigen::Matrix<double, 7, 1> z = truth.measure({}) + mb.z_trim;
    a.update(z);
    if (f >= 40) {
      b.update(z);
      ASSERT_EQ(b.bank().log_likelihoods(), a.bank().log_likelihoods()) << f;
    }
    if (f == 39) b.take_over(a);
    a.propagate(du + mb.u_trim);
    if (f >= 39) b.propagate(du + mb.u_trim);
    truth.advance(du, {});
  }
}

// In the bank: every likelihood is -q / (2 s_m) with s_m from the blended estimate's AOA of the
// frame before (no adaptation: s = 1), the dead band at the flight's median |da| so that frames
// inside and beyond it are both checked; the options' ranges are refused.
TEST(ManeuverTempering, AlphaTermTempersTheBanksLikelihoodsBeyondItsDeadBand) {
  const ModelBank mb = named_bank(5u);
  auto fly = [&](F16HierarchicalBank& bank, auto&& check) {   // the dither scaled: the synthetic alpha in degrees' range
    fly_dithered(bank, mb, 1e-3, [&](const auto& z_hat, const F16HierarchicalBank& b) {
      check(std::abs(z_hat(1)) * 180.0 / kPi, b);
    });
  };
  HierarchicalOptions o;
  o.maneuver.tempering_alpha_deg = 1e-3;
  std::vector<double> das;
  F16HierarchicalBank probe(mb, o);
  fly(probe, [&](double da, const F16HierarchicalBank&) { das.push_back(da); });
  std::nth_element(das.begin(), das.begin() + das.size() / 2, das.end());
  const double d = das[das.size() / 2];
  ASSERT_GT(d, 0.0);
  ASSERT_LT(d, 45.0);
  const double a_ref = d;
  o.maneuver.tempering_alpha_deg = a_ref;
  o.maneuver.tempering_alpha_deadband_deg = d;
  F16HierarchicalBank banded(mb, o);
  int inside = 0, beyond = 0;
  fly(banded, [&](double da, const F16HierarchicalBank& b) {
    const double y = std::max(0.0, da - d) / a_ref;
    (y > 0.0 ? beyond : inside)++;
    const double s = 1.0 + y * y;
    expect_tempered_by(b, s);
  });
  EXPECT_GT(inside, 10);
  EXPECT_GT(beyond, 10);
  HierarchicalOptions bad;
  bad.maneuver.tempering_alpha_deadband_deg = 0.5;   // without the alpha term
  EXPECT_THROW(F16HierarchicalBank(mb, bad), std::invalid_argument);
  bad.maneuver.tempering_alpha_deg = 91.0;
  EXPECT_THROW(F16HierarchicalBank(mb, bad), std::invalid_argument);
  bad.maneuver.tempering_alpha_deg = 1.0;
  bad.maneuver.tempering_alpha_deadband_deg = -0.1;
  EXPECT_THROW(F16HierarchicalBank(mb, bad), std::invalid_argument);
  bad.maneuver.tempering_alpha_deadband_deg = 0.0;
  bad.maneuver.tempering_deadband_g = 0.05;   // the load factor's dead band without its term
  EXPECT_THROW(F16HierarchicalBank(mb, bad), std::invalid_argument);
  bad.maneuver.tempering_deadband_g = 0.0;
  bad.maneuver.tempering_added_deadband_g = 0.05;   // the added term's dead band without it
  EXPECT_THROW(F16HierarchicalBank(mb, bad), std::invalid_argument);
  bad.maneuver.tempering_added_g = 101.0;
  EXPECT_THROW(F16HierarchicalBank(mb, bad), std::invalid_argument);
  bad.maneuver.tempering_added_g = 0.1;
  bad.maneuver.tempering_added_deadband_g = 11.0;
  EXPECT_THROW(F16HierarchicalBank(mb, bad), std::invalid_argument);
}
