// Maneuver kinematics (maneuver_kinematics.h): the closed-form Jacobian against central
// differences of g, the remainder of a steady level turn against its hand-derived values,
// the remainder second order, the bank's propagation moved by exactly dt R of its blended
// state, off bit-identical, a bank without the airframe names refused by name, and no heap
// allocation in the F-16-sized step with it on (global operator new is counted here).
#include "f16mmae/hierarchical_bank.h"
#include "f16mmae/maneuver_kinematics.h"

#include "allocation_counter.h"
#include "synthetic_models.h"

#include <gtest/gtest.h>

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
  const test::Plant plant = test::random_plant(13, 5, 7, 7u, 1e-3, 1e-3);
  test::Truth truth(plant, test::kF16Actuators, test::kF16Sensors, 3u);
  for (int i = 0; i < 300; ++i) {
    const std::vector<std::string> failed = i >= 100 ? std::vector<std::string>{"LF"} : std::vector<std::string>{};
    const Eigen::Matrix<double, 7, 1> z = truth.measure(failed) + mb.z_trim;
    const Eigen::VectorXd du = test::dither(5, i, 64.0);
    const Eigen::Matrix<double, 5, 1> u = du + mb.u_trim;
    a.step(z, u), b.step(z, u);
    truth.advance(du, failed);
    ASSERT_EQ(a.probabilities(), b.probabilities()) << "frame " << i;
    ASSERT_EQ(a.blended_state(), b.blended_state()) << "frame " << i;
  }
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
    const Eigen::VectorXd du = test::dither(5, i, 64.0);
    z.push_back(truth.measure(failed) + mb.z_trim);
    u.push_back(du + mb.u_trim);
    truth.advance(du, failed);
  }
  const long long before = f16mmae::testing::allocation_count();
  for (std::size_t i = 0; i < z.size(); ++i) hb.step(z[i], u[i]);
  const long long after = f16mmae::testing::allocation_count();
  EXPECT_EQ(after - before, 0);
  EXPECT_FALSE(hb.declarations().empty());   // the switch to level 1 happened inside the count
}
