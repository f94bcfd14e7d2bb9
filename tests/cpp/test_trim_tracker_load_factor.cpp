// The trim tracker's load-factor scaling (trim_tracker.h, load_factor): against a hand
// computation of the two low-passes, the 1-g offset d1 tracked as (z - z_trim) / n and the
// offset in force n d1; frozen in a turn d1 stays and the offset follows n; a failure's
// freezing frame holds n; n below 0.5 g is not tracked; off, the tracker without it bit for
// bit; the refusals.
#include "f16mmae/air_data_rates.h"
#include "f16mmae/trim_tracker.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

using namespace f16mmae;

namespace {

constexpr double kRate = 10.0;   // frames a second
const AirDataRates kNoAirData(kRate);   // no sample observed: both rates 0
const std::vector<std::string> kNames{"VEL", "AOA", "AZ", "ROL"};
constexpr int kAoa = 1, kAz = 2;
using Tracker = TrimTracker<Eigen::Dynamic, Eigen::Dynamic>;
using Vec = Eigen::VectorXd;

TrimTrackingOptions options(bool load_factor) {
  TrimTrackingOptions o;
  o.time_constant_s = 1.0;   // a = 1 - exp(-0.1)
  o.steady_g = 0.1;
  o.hold_s = 0.0;
  o.load_factor = load_factor;
  o.load_factor_time_constant_s = 0.5;   // b = 1 - exp(-0.2)
  return o;
}

// One frame: z - z_trim with `aoa` rad on AOA and 0.3 on VEL (not tracked), the measured AZ
// `az_g`, the bank's estimated load factor off trim `dn` (its gate), `freezing` the freeze rule.
void frame(Tracker& t, double aoa, double az_g, double dn, bool freezing = false) {
  Vec z_pert = Vec::Zero(4), z_hat = Vec::Zero(4), z_abs = Vec::Zero(4);
  z_pert(0) = 0.3;
  z_pert(kAoa) = aoa;
  z_abs(kAz) = az_g;
  z_pert(kAz) = az_g - 1.0;
  z_hat(kAz) = dn;
  t.after_update(z_pert, freezing, z_hat, kNoAirData, z_abs);
  t.after_propagate(Vec::Zero(2));
}

}  // namespace

TEST(TrimTrackerLoadFactor, LevelTrackingThenATurnFollowTheHandComputation) {
  Tracker t(options(true), kRate, 2, 4, kNames);
  const double a = 1.0 - std::exp(-0.1), b = 1.0 - std::exp(-0.2);
  ASSERT_NEAR(t.gain(), a, 1e-15);
  const double c = -0.002;   // the lighter aircraft's 1-g AOA offset, rad
  // 20 level frames at AZ 1 g: n stays 1, d1 = c (1 - (1 - a)^k), the offset in force d1.
  for (int k = 1; k <= 20; ++k) {
    frame(t, c, 1.0, 0.0);
    const double d1 = c * (1.0 - std::pow(1.0 - a, k));
    EXPECT_NEAR(t.dz()(kAoa), d1, 1e-15) << k;
    EXPECT_NEAR(t.dz_1g()(kAoa), d1, 1e-15) << k;
    EXPECT_EQ(t.dz()(0), 0.0);     // VEL: not tracked
    EXPECT_EQ(t.dz()(kAz), 0.0);   // AZ: not tracked
  }
  const double d1 = c * (1.0 - std::pow(1.0 - a, 20));
  // A 30-deg turn: AZ 1/cos 30 deg, the bank's dn 0.155 g > steady_g: d1 frozen, n the AZ's
  // low-pass, n_m = 1 + (n_turn - 1)(1 - (1 - b)^m), the offset in force n_m d1.
  const double n_turn = 1.0 / std::cos(M_PI / 6.0);
  for (int m = 1; m <= 30; ++m) {
    frame(t, c * n_turn + 0.01, n_turn, n_turn - 1.0);   // the turn's own alpha is not tracked
    const double n = 1.0 + (n_turn - 1.0) * (1.0 - std::pow(1.0 - b, m));
    EXPECT_TRUE(t.frozen()) << m;
    EXPECT_NEAR(t.load_factor(), n, 1e-14) << m;
    EXPECT_NEAR(t.dz_1g()(kAoa), d1, 1e-15) << m;
    EXPECT_NEAR(t.dz()(kAoa), n * d1, 1e-15) << m;
  }
  // 30 frames of b: the offset in force is 1.155 times the 1-g offset to within 0.3 %.
  EXPECT_NEAR(t.dz()(kAoa) / d1, n_turn, 0.003);
}

TEST(TrimTrackerLoadFactor, TracksZOverNSoTheOneGOffsetComesOutInAClimb) {
  // A steady climb at gamma 18.2 deg: AZ = cos gamma = 0.95, within the gate (dn 0). The offset
  // measured there is n c: d1 converges to c, the offset in force to n c, the measured one.
  Tracker t(options(true), kRate, 2, 4, kNames);
  const double c = -0.002, n = 0.95;
  for (int k = 0; k < 3000; ++k) frame(t, n * c, n, 0.0);
  EXPECT_NEAR(t.load_factor(), n, 1e-12);
  EXPECT_NEAR(t.dz_1g()(kAoa), c, 1e-12);
  EXPECT_NEAR(t.dz()(kAoa), n * c, 1e-12);
  // Without the scaling the same frames give the measured offset as the 1-g one.
  Tracker plain(options(false), kRate, 2, 4, kNames);
  for (int k = 0; k < 3000; ++k) frame(plain, n * c, n, 0.0);
  EXPECT_NEAR(plain.dz()(kAoa), n * c, 1e-12);
  EXPECT_EQ(plain.load_factor(), 1.0);
}

TEST(TrimTrackerLoadFactor, AFailuresFreezingFrameHoldsNAndBelowHalfAGNothingIsTracked) {
  Tracker t(options(true), kRate, 2, 4, kNames);
  for (int k = 0; k < 50; ++k) frame(t, -0.002, 1.0, 0.0);
  const double d1 = t.dz_1g()(kAoa);
  // The freeze rule's frames (a failure rising): a failed AZ reading 3 g does not move n.
  for (int k = 0; k < 20; ++k) frame(t, -0.002, 3.0, 0.0, true);
  EXPECT_EQ(t.load_factor(), 1.0);
  EXPECT_EQ(t.dz()(kAoa), d1);
  // AZ 0.2 g (a push-over), inside the dn gate: n = 1 - 0.8 (1 - (1 - b)^k) falls below 0.5 g
  // at k = 5 (4.9); from there on d1 is held.
  for (int k = 1; k <= 5; ++k) {
    frame(t, -0.002, 0.2, 0.0);
    EXPECT_EQ(t.frozen(), k == 5) << k;
  }
  const double held = t.dz_1g()(kAoa);
  EXPECT_NE(held, d1);   // tracked (as z / n) while n >= 0.5
  for (int k = 0; k < 40; ++k) frame(t, -0.002, 0.2, 0.0);
  EXPECT_LT(t.load_factor(), TrimTrackingOptions::kLoadFactorTrackMin);
  EXPECT_TRUE(t.frozen());
  EXPECT_EQ(t.dz_1g()(kAoa), held);
  EXPECT_NEAR(t.dz()(kAoa), t.load_factor() * held, 1e-18);
  t.reset();
  EXPECT_EQ(t.load_factor(), 1.0);
  EXPECT_EQ(t.dz()(kAoa), 0.0);
  EXPECT_EQ(t.dz_1g()(kAoa), 0.0);
}

TEST(TrimTrackerLoadFactor, OffIsTheTrackerWithoutItBitForBit) {
  TrimTrackingOptions o = options(false);
  Tracker off(o, kRate, 2, 4, kNames), plain(options(false), kRate, 2, 4, kNames);
  for (int k = 0; k < 200; ++k) {
    const double az = k < 100 ? 1.0 : 1.2, dn = k < 100 ? 0.0 : 0.2;
    frame(off, -0.002 + 1e-4 * std::sin(k), az, dn);
    Vec z_pert = Vec::Zero(4), z_hat = Vec::Zero(4);
    z_pert(0) = 0.3;
    z_pert(kAoa) = -0.002 + 1e-4 * std::sin(k);
    z_pert(kAz) = az - 1.0;
    z_hat(kAz) = dn;
    // the four-argument form's rule: the steady gates, then the freeze rule
    const bool gate = !(std::abs(dn) <= o.steady_g);
    plain.after_update(z_pert, gate);
    plain.after_propagate(Vec::Zero(2));
    ASSERT_EQ(off.dz(), plain.dz()) << k;
    ASSERT_EQ(off.frozen(), plain.frozen()) << k;
  }
  EXPECT_NE(off.dz()(kAoa), 0.0);
}

TEST(TrimTrackerLoadFactor, RefusesWithoutSteadyTrackingAndANonPositiveTimeConstant) {
  TrimTrackingOptions o = options(true);
  o.steady_g = 0.0;
  try {
    Tracker t(o, kRate, 2, 4, kNames);
    FAIL() << "accepted load_factor without steady tracking";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("load_factor needs steady tracking"), std::string::npos) << e.what();
  }
  o = options(true);
  o.load_factor_time_constant_s = 0.0;
  EXPECT_THROW(Tracker(o, kRate, 2, 4, kNames), std::invalid_argument);
  o = options(true);
  EXPECT_THROW(Tracker(o, kRate, 2, 4, {"VEL", "AOA", "ROL"}), std::invalid_argument);   // no AZ
}
