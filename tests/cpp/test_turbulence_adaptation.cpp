// Turbulence adaptation (turbulence_adaptation.h): the scale's recursion by hand, the bank's
// tempered Bayes update by hand, the power ratio per channel each filter reads (own_channels), "off" bit-identical to the bank without it, the scale
// recovering a known noise-power ratio, a failure not absorbed, the per-hypothesis tempering by
// hand (its choice per channel read, its gate on the measured rho and its margin over the fully tempered
// hypotheses too), the bound's knee by hand, the running start by hand, the lull floor (the larger of two averages) by
// hand, option checks, and no heap
// allocation in the F-16-sized step with it on (global operator new is counted here).
#include "f16mmae/hierarchical_bank.h"
#include "f16mmae/turbulence_adaptation.h"

#include "allocation_counter.h"
#include "synthetic_models.h"
#include "scalar_models.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

using namespace f16mmae;

namespace {

using test::Scalar;
using test::ScalarBank;
using test::scalar_model;
using test::z1;

// Matched scale (κ = 1) unless a gain is given.
TurbulenceAdaptationOptions on(double tau_s, double s_min = 1.0, double s_max = 100.0, double gain = 1.0) {
  TurbulenceAdaptationOptions o;
  o.enabled = true;
  o.gain = gain;
  o.reference = 1.0;   // s = 1 + κ (ρ − 1): κ = 1 is s = ρ
  o.time_constant_s = tau_s;
  o.scale_min = s_min;
  o.scale_max = s_max;
  o.frame_rate_hz = 64.0;
  return o;
}

}  // namespace

TEST(TurbulenceAdaptation, ScaleFollowsTheHandComputedRecursion) {
  ResidualScale<Eigen::Dynamic> r;
  r.configure(on(0.5, 0.5, 20.0, 3.0), 2, "test");
  const double alpha = 1.0 - std::exp(-1.0 / (0.5 * 64.0));
  EXPECT_DOUBLE_EQ(r.scale(), 1.0);   // starts at the design's power: rho = 1
  double rho = 1.0;
  for (int n = 0; n < 50; ++n) {
    const Eigen::Vector3d q(8.0 + n, 6.0 + (n % 3), 30.0);   // the minimum moves between hypotheses
    r.observe(q);
    rho += alpha * (q.minCoeff() / 2.0 - rho);
    EXPECT_NEAR(r.power_ratio(), rho, 1e-12);
    const double s = std::min(20.0, std::max(0.5, 1.0 + 3.0 * (rho - 1.0)));
    EXPECT_NEAR(r.scale(), s, 1e-12) << "frame " << n;
  }
  // non-finite q are skipped; a huge minimum is clipped at 10 s_max = 200
  r.observe(Eigen::Vector3d(std::nan(""), 1e300, std::numeric_limits<double>::infinity()));
  rho += alpha * (200.0 - rho);
  EXPECT_NEAR(r.power_ratio(), rho, 1e-9);
  r.observe(Eigen::Vector3d(std::nan(""), std::nan(""), std::nan("")));   // nothing to learn
  EXPECT_NEAR(r.power_ratio(), rho, 1e-9);
  // below the design's power the scale stays at s_min
  for (int n = 0; n < 2000; ++n) r.observe(Eigen::Vector3d(0.2, 0.4, 0.6));
  EXPECT_NEAR(r.power_ratio(), 0.1, 1e-9);
  EXPECT_DOUBLE_EQ(r.scale(), 0.5);
  r.reset();
  EXPECT_DOUBLE_EQ(r.scale(), 1.0);
  EXPECT_DOUBLE_EQ(r.power_ratio(), 1.0);
}

TEST(TurbulenceAdaptation, LullFloorReadsTheLargerOfTheTwoAveragesByHand) {
  TurbulenceAdaptationOptions o = on(0.5, 1.0, 20.0, 3.0);
  o.floor_time_constant_s = 4.0;   // in force from 2 s = 128 updates on
  ResidualScale<Eigen::Dynamic> r, plain;
  r.configure(o, 2, "test");
  plain.configure(on(0.5, 1.0, 20.0, 3.0), 2, "test");
  const double alpha = 1.0 - std::exp(-1.0 / (0.5 * 64.0)), alpha_l = 1.0 - std::exp(-1.0 / (4.0 * 64.0));
  const auto clamped = [](double rho) { return std::min(20.0, std::max(1.0, 1.0 + 3.0 * (rho - 1.0))); };
  double rho = 1.0, rho_long = 1.0;
  int floored = 0, air_floored = 0;
  for (int n = 0; n < 600; ++n) {
    // bursts and lulls: x = min q / 2 above and below the averages in turn
    const double x = (n / 60) % 2 == 0 ? 4.0 + 0.1 * (n % 7) : 0.4 + 0.05 * (n % 5);
    const Eigen::Vector3d q(2.0 * x, 2.0 * x + 1.0, 30.0);
    r.observe(q);
    plain.observe(q);
    rho += alpha * (x - rho);
    rho_long += std::max(1.0 / (n + 1), alpha_l) * (x - rho_long);   // a plain mean first (running_mean.h)
    const bool in_force = n + 1 >= 128;
    floored += in_force && clamped(rho_long) > clamped(rho);
    // rho and rho-bar are those without the floor, bit for bit; s reads the larger average once in force
    ASSERT_EQ(r.power_ratio(), plain.power_ratio());
    ASSERT_EQ(r.measured_power_ratio(), plain.measured_power_ratio());
    ASSERT_NEAR(r.power_ratio(), rho, 1e-12);
    ASSERT_NEAR(r.scale(), clamped(in_force ? std::max(rho, rho_long) : rho), 1e-12) << "frame " << n;
    ASSERT_NEAR(r.inverse_scale(), 1.0 / r.scale(), 1e-15);
    if (!in_force || rho >= rho_long) ASSERT_EQ(r.scale(), plain.scale()) << "frame " << n;
    // the air's power ratio (the rough-air floor's measure): rho-bar, or rho_L where larger once in force
    const double measured = r.measured_power_ratio();
    ASSERT_NEAR(r.air_power_ratio(), in_force ? std::max(measured, rho_long) : measured, 1e-12) << "frame " << n;
    ASSERT_EQ(plain.air_power_ratio(), plain.measured_power_ratio());
    air_floored += in_force && rho_long > measured + 1e-9;
  }
  EXPECT_GT(air_floored, 60);
  EXPECT_GT(floored, 60);    // the lulls are floored ...
  EXPECT_LT(floored, 400);   // ... the bursts are not
  // reset: rho_L starts again, out of force until it has averaged 128 updates
  r.reset();
  EXPECT_DOUBLE_EQ(r.scale(), 1.0);
  for (int n = 0; n < 127; ++n) r.observe(Eigen::Vector3d(6.0, 7.0, 8.0));   // x = 3: the plain mean is 3
  for (int n = 0; n < 60; ++n) r.observe(Eigen::Vector3d(0.2, 0.4, 0.6));   // 60 more of x = 0.1
  double rho_r = 1.0, mean = 0.0;
  for (int n = 0; n < 187; ++n) {
    const double x = n < 127 ? 3.0 : 0.1;
    rho_r += alpha * (x - rho_r);
    mean += std::max(1.0 / (n + 1), alpha_l) * (x - mean);
  }
  EXPECT_NEAR(r.power_ratio(), rho_r, 1e-12);
  EXPECT_NEAR(r.scale(), clamped(std::max(rho_r, mean)), 1e-12);
  EXPECT_GT(clamped(mean), clamped(rho_r) + 1.0);   // floored by the mean since the reset
  // a power ratio set (a bank taking over in known air) sets rho_L too and puts the floor in force
  ResidualScale<Eigen::Dynamic> known;
  known.configure(o, 2, "test");
  known.set_power_ratio(3.0);
  EXPECT_DOUBLE_EQ(known.scale(), clamped(3.0));
  known.observe(Eigen::Vector3d(0.2, 0.4, 0.6));
  EXPECT_NEAR(known.scale(), clamped(3.0 + alpha_l * (0.1 - 3.0)), 1e-12);   // falling: rho_L is the larger
  // held (a flight phase): rho_L keeps its value and s reads rho alone, at once; released, the floor again
  const double long_before = 3.0 + alpha_l * (0.1 - 3.0);
  known.hold_floor(true);
  EXPECT_TRUE(known.floor_held());
  double rho_held = 3.0 + alpha * (0.1 - 3.0);
  EXPECT_NEAR(known.scale(), clamped(rho_held), 1e-12);
  for (int n = 0; n < 20; ++n) {
    known.observe(Eigen::Vector3d(0.2, 0.4, 0.6));
    rho_held += alpha * (0.1 - rho_held);
    EXPECT_NEAR(known.scale(), clamped(rho_held), 1e-12);
  }
  known.hold_floor(false);
  EXPECT_NEAR(known.scale(), clamped(long_before), 1e-12);   // rho_L as the hold found it
  known.hold_floor(true);
  known.reset();   // reset releases it
  EXPECT_FALSE(known.floor_held());
}

TEST(TurbulenceAdaptation, MeasuredRatioIsAPlainMeanFirstThenTheAverageOverTau) {
  // tau = 0.25 s at 64 Hz: alpha = 1 - e^-(1/16); a plain mean for the first 16 updates
  ResidualScale<Eigen::Dynamic> r;
  r.configure(on(0.25, 1.0, 2.0, 3.0), 2, "test");   // s_max 2: rho is clipped at 20, rho-bar not
  const double alpha = 1.0 - std::exp(-1.0 / 16.0);
  EXPECT_DOUBLE_EQ(r.measured_power_ratio(), 0.0);   // nothing averaged yet
  double sum = 0.0, mean = 0.0;
  for (int n = 1; n <= 40; ++n) {
    const double x = 3.0 + 0.5 * (n % 5) + (n == 7 ? 100.0 : 0.0);   // one wild frame, x = 104
    r.observe(Eigen::Vector3d(2.0 * x, 2.0 * x + 1.0, 50.0 * x));     // min q / nz = x
    if (n <= 16) {
      sum += x;
      mean = sum / n;   // the plain mean (1/n >= alpha while n <= 16)
    } else {
      mean += alpha * (x - mean);
    }
    EXPECT_NEAR(r.measured_power_ratio(), mean, 1e-12) << "update " << n;
  }
  // the tempering rho is a different average (from rho_0, clipped): its own recursion
  EXPECT_GT(std::abs(r.power_ratio() - r.measured_power_ratio()), 1e-3);
  r.set_power_ratio(0.5);   // sets the tempering rho only
  EXPECT_NEAR(r.measured_power_ratio(), mean, 1e-12);
  r.reset();                // restarts both
  EXPECT_DOUBLE_EQ(r.measured_power_ratio(), 0.0);
  r.observe(Eigen::Vector3d(9.0, 8.0, 7.0));
  EXPECT_DOUBLE_EQ(r.measured_power_ratio(), 3.5);   // the first update's x
  ResidualScale<Eigen::Dynamic> off;
  TurbulenceAdaptationOptions o = on(0.25);
  o.enabled = false;
  off.configure(o, 2, "test");
  off.observe(Eigen::Vector3d(9.0, 8.0, 7.0));
  EXPECT_DOUBLE_EQ(off.measured_power_ratio(), 0.0);   // disabled: nothing measured
}

TEST(TurbulenceAdaptation, MeasuredRatioEqualsTheMaxOfOneOverIAndAlphaBitForBit) {
  // a_i = max(1.0 / i, alpha) divided every update (the header's formula) against the scale's
  // count to a precomputed threshold: equal to the last bit, through and past the switch from
  // the plain mean to the average, for time constants and rates whose 1 / alpha is near an
  // integer and far from one.
  for (const double tau : {0.25, 1.0, 5.0, 7.3, 60.0})
    for (const double rate : {50.0, 64.0, 100.0}) {
      TurbulenceAdaptationOptions o = on(tau);
      o.frame_rate_hz = rate;
      ResidualScale<Eigen::Dynamic> r;
      r.configure(o, 2, "test");
      const double alpha = 1.0 - std::exp(-1.0 / (tau * rate));
      const int updates = static_cast<int>(1.0 / alpha) + 200;
      double mean = 0.0;
      for (int i = 1; i <= updates; ++i) {
        const double x = 0.7 + 0.3 * std::sin(0.37 * i) + (i % 97 == 0 ? 5.0 : 0.0);
        r.observe(Eigen::Vector3d(2.0 * x, 2.0 * x + 1.0, 9.0 * x));
        const double a = 1.0 / static_cast<double>(i);
        mean += (a > alpha ? a : alpha) * (x - mean);
        ASSERT_EQ(r.measured_power_ratio(), mean) << "tau " << tau << " s, " << rate << " Hz, update " << i;
      }
      r.reset();   // the count restarts with the average
      r.observe(Eigen::Vector3d(9.0, 8.0, 7.0));
      EXPECT_EQ(r.measured_power_ratio(), 3.5);
      r.observe(Eigen::Vector3d(3.0, 8.0, 7.0));
      EXPECT_EQ(r.measured_power_ratio(), 3.5 + 0.5 * (1.5 - 3.5));
    }
}

TEST(TurbulenceAdaptation, RunningStartIsAPlainMeanFromTheStartThenTheAverageByHand) {
  // running_start: rho (clipped x) and each rho_j follow a_i = max(1 / i, alpha) from the start
  // and every reset(), i counted per channel; s follows rho; set_power_ratio ends the running
  // start (the average goes on from the rho given); off, rho starts at rho_0 as before.
  TurbulenceAdaptationOptions o = on(0.25, 1.0, 2.0, 3.0);   // 16 plain-mean updates; clip 20
  o.running_start = true;
  ResidualScale<Eigen::Dynamic> r;
  r.configure(o, 2, "test");
  EXPECT_DOUBLE_EQ(r.power_ratio(), 1.0);   // rho_0 until the first update
  const double alpha = 1.0 - std::exp(-1.0 / 16.0);
  double rho = 0.0;
  for (int i = 1; i <= 40; ++i) {
    const double x = 0.6 + 0.4 * (i % 3) + (i == 5 ? 100.0 : 0.0);   // one wild frame: clipped at 20
    r.observe(Eigen::Vector3d(2.0 * x, 2.0 * x + 1.0, 9.0 * x));
    const double a = 1.0 / static_cast<double>(i);
    rho += (a > alpha ? a : alpha) * (std::min(x, 20.0) - rho);
    ASSERT_NEAR(r.power_ratio(), rho, 1e-12) << "update " << i;
    EXPECT_NEAR(r.scale(), std::min(2.0, std::max(1.0, 1.0 + 3.0 * (rho - 1.0))), 1e-12) << "update " << i;
  }
  r.reset();   // restarts the plain mean
  r.observe(Eigen::Vector3d(9.0, 8.0, 7.0));
  EXPECT_DOUBLE_EQ(r.power_ratio(), 3.5);
  r.set_power_ratio(0.5);   // a known rho: the average over tau from it
  r.observe(Eigen::Vector3d(3.0, 8.0, 7.0));
  EXPECT_NEAR(r.power_ratio(), 0.5 + alpha * (1.5 - 0.5), 1e-15);
  TurbulenceAdaptationOptions plain = o;   // off: from rho_0 with alpha, the first update included
  plain.running_start = false;
  ResidualScale<Eigen::Dynamic> p;
  p.configure(plain, 2, "test");
  p.observe(Eigen::Vector3d(9.0, 8.0, 7.0));
  EXPECT_NEAR(p.power_ratio(), 1.0 + alpha * (3.5 - 1.0), 1e-15);
  // per channel: the channels' own counts (a channel k* leaves out is not observed)
  o.channel_weight = 1.0;
  ResidualScale<Eigen::Dynamic> c;
  c.configure(o, 2, "test");
  Eigen::MatrixXd both = Eigen::MatrixXd::Identity(2, 2), first = both;
  first(1, 1) = 0.0;
  c.observe(Eigen::Vector3d(4.0, 5.0, 6.0));
  c.observe_channels(Eigen::Vector2d(2.0, 1.0), first);   // channel 1 left out
  c.observe(Eigen::Vector3d(4.0, 5.0, 6.0));
  c.observe_channels(Eigen::Vector2d(1.0, 3.0), both);
  EXPECT_NEAR(c.channel_power_ratios()(0), (4.0 + 1.0) / 2.0, 1e-15);   // two updates: their mean
  EXPECT_NEAR(c.channel_power_ratios()(1), 9.0, 1e-15);                 // its first: that one
}

TEST(TurbulenceAdaptation, AReferenceSetBeforeTheFirstUpdateIsTheStartingRho) {
  // A scheduled bank sets its flight condition's rho_0 at the first air data, before any
  // residual: rho (and each rho_j) starts there, not at the rho_0 of the node in force before
  // air data. Once an update is averaged (or rho is set), a new reference leaves rho alone.
  TurbulenceAdaptationOptions o = on(0.25, 1.0, 2.0, 3.0);   // rho_0 1, s = 1 + 3 (rho - rho_0) in [1, 2]
  o.channel_weight = 0.5;
  ResidualScale<Eigen::Dynamic> r;
  r.configure(o, 2, "test");
  r.set_reference(0.7);
  EXPECT_DOUBLE_EQ(r.power_ratio(), 0.7);
  EXPECT_DOUBLE_EQ(r.channel_power_ratios()(0), 0.7);
  EXPECT_DOUBLE_EQ(r.channel_power_ratios()(1), 0.7);
  EXPECT_DOUBLE_EQ(r.scale(), 1.0);
  r.set_reference(1.2);   // still before the first update: it moves again
  EXPECT_DOUBLE_EQ(r.power_ratio(), 1.2);
  const double alpha = 1.0 - std::exp(-1.0 / 16.0);
  r.observe(Eigen::Vector3d(4.0, 5.0, 6.0));   // x = 2
  const double rho = 1.2 + alpha * (2.0 - 1.2);
  EXPECT_NEAR(r.power_ratio(), rho, 1e-15);
  r.set_reference(1.0);   // after an update: rho kept, s follows the new reference
  EXPECT_NEAR(r.power_ratio(), rho, 1e-15);
  EXPECT_NEAR(r.scale(), 1.0 + 3.0 * (rho - 1.0), 1e-12);
  r.reset();   // a new start: the reference in force (1.0) until another is set before an update
  EXPECT_DOUBLE_EQ(r.power_ratio(), 1.0);
  r.set_reference(0.5);
  EXPECT_DOUBLE_EQ(r.power_ratio(), 0.5);
  r.set_power_ratio(1.5);   // a known rho ends the start too
  r.set_reference(0.6);
  EXPECT_DOUBLE_EQ(r.power_ratio(), 1.5);
  r.observe(Eigen::Vector3d(Eigen::Vector3d::Constant(std::nan(""))));   // no finite form: still no update
  ResidualScale<Eigen::Dynamic> q;
  q.configure(o, 2, "test");
  q.observe(Eigen::Vector3d(Eigen::Vector3d::Constant(std::nan(""))));
  q.set_reference(0.4);
  EXPECT_DOUBLE_EQ(q.power_ratio(), 0.4);
}

TEST(TurbulenceAdaptation, APowerScaleReadsTheFormsAsTheOtherBanksWouldBe) {
  // sigma: forms sigma q_k give the scale (common and per channel) that forms q_k give without
  // it, frame by frame (rho itself sigma times the other's); rho and rho_j start and reset at
  // sigma rho_0 (s = 1), a sigma set before the first update moves them there, after it rho is kept.
  TurbulenceAdaptationOptions o = on(0.25, 1.0, 20.0, 3.0);
  o.reference = 0.8;
  o.channel_weight = 0.5;
  const double sigma = 0.75;
  ResidualScale<Eigen::Dynamic, Eigen::Dynamic> plain, scaled;
  plain.configure(o, 2, "test");
  scaled.configure(o, 2, "test");
  scaled.set_power_scale(sigma);
  EXPECT_DOUBLE_EQ(scaled.power_scale(), sigma);
  EXPECT_DOUBLE_EQ(scaled.power_ratio(), sigma * 0.8);
  EXPECT_DOUBLE_EQ(scaled.channel_power_ratios()(1), sigma * 0.8);
  EXPECT_DOUBLE_EQ(scaled.scale(), 1.0);
  Eigen::Matrix2d a_inv;
  a_inv << 2.0, 0.3, 0.3, 1.0;
  for (int n = 0; n < 200; ++n) {
    const Eigen::Vector3d q(3.0 + 0.05 * n, 2.5 + (n % 5), 9.0);
    const Eigen::Vector2d r(0.4 + 0.01 * n, -0.7);
    plain.observe(q);
    plain.observe_channels(r, a_inv);
    scaled.observe(sigma * q);
    scaled.observe_channels(std::sqrt(sigma) * r, a_inv);
    ASSERT_NEAR(scaled.power_ratio(), sigma * plain.power_ratio(), 1e-12) << "frame " << n;
    ASSERT_NEAR(scaled.scale(), plain.scale(), 1e-9) << "frame " << n;
    ASSERT_NEAR(scaled.scale_at(0.5), plain.scale_at(0.5), 1e-9) << "frame " << n;
    for (int j = 0; j < 2; ++j)
      ASSERT_NEAR(scaled.channel_inverse_sqrt_scales()(j), plain.channel_inverse_sqrt_scales()(j), 1e-9);
  }
  EXPECT_GT(plain.scale(), 2.0);   // the air above the reference: the comparison tempers
  const double rho = scaled.power_ratio();
  scaled.set_power_scale(1.0);   // after an update: rho kept, s reads it unscaled
  EXPECT_DOUBLE_EQ(scaled.power_ratio(), rho);
  EXPECT_NEAR(scaled.scale(), std::min(20.0, 1.0 + 3.0 * (rho - 0.8)), 1e-12);
  scaled.set_power_scale(sigma);
  scaled.reset();
  EXPECT_DOUBLE_EQ(scaled.power_ratio(), sigma * 0.8);
  EXPECT_DOUBLE_EQ(scaled.scale(), 1.0);
}

TEST(TurbulenceAdaptation, TheBoundsKneeRaisesItAtTheGainByHand) {
  // s = clamp(1 + k (x - rho_0), s_min, s_max + k max(x - rho_c, 0)), x = rho / sigma: below the
  // knee rho_c the bound holds, beyond it s runs parallel to the line; per channel and scale_at
  // alike; rho_c 0 is the bound alone.
  TurbulenceAdaptationOptions o = on(0.25, 1.0, 20.0, 3.0);   // the line meets 20 at x = 1 + 19/3
  o.channel_weight = 1.0;
  TurbulenceAdaptationOptions knee = o;
  knee.scale_max_from = 9.0;
  const double sigma = 0.5;
  ResidualScale<Eigen::Dynamic, Eigen::Dynamic> bound, kneed;
  bound.configure(o, 2, "test");
  kneed.configure(knee, 2, "test");
  bound.set_power_scale(sigma);
  kneed.set_power_scale(sigma);
  const auto by_hand = [](double x, double rho_c) {
    const double top = 20.0 + (rho_c > 0.0 && x > rho_c ? 3.0 * (x - rho_c) : 0.0);
    return std::min(top, std::max(1.0, 1.0 + 3.0 * (x - 1.0)));
  };
  Eigen::Matrix2d a_inv;
  a_inv << 1.0, 0.0, 0.0, 1.0;
  bool held = false, rose = false;
  for (int n = 0; n < 400; ++n) {   // the air from calm to x = 14 and back
    const double level = n < 200 ? 0.5 + 0.07 * n : 0.5 + 0.07 * (400 - n);
    const Eigen::Vector3d q(2.0 * sigma * level, 3.0 * sigma * level, 50.0);
    const Eigen::Vector2d r(std::sqrt(sigma * level), -std::sqrt(2.0 * sigma * level));
    for (auto* a : {&bound, &kneed}) {
      a->observe(q);
      a->observe_channels(r, a_inv);
    }
    const double x = kneed.power_ratio() / sigma;
    ASSERT_NEAR(bound.scale(), by_hand(x, 0.0), 1e-12) << "frame " << n;
    ASSERT_NEAR(kneed.scale(), by_hand(x, 9.0), 1e-12) << "frame " << n;
    ASSERT_NEAR(kneed.scale_at(0.5),
                std::min(20.0 + std::max(3.0 * (x - 9.0), 0.0), std::max(1.0, 1.0 + 3.0 * (x - 0.5))), 1e-12);
    for (int j = 0; j < 2; ++j) {
      const double xj = kneed.channel_power_ratios()(j) / sigma;
      ASSERT_NEAR(kneed.channel_inverse_sqrt_scales()(j), 1.0 / std::sqrt(by_hand(xj, 9.0)), 1e-12);
    }
    held = held || (x > 8.0 && x < 9.0 && kneed.scale() == 20.0);
    rose = rose || (x > 10.0 && kneed.scale() > 20.0 && bound.scale() == 20.0);
  }
  EXPECT_TRUE(held);   // between the line's meeting the bound and the knee: s_max
  EXPECT_TRUE(rose);   // beyond the knee: above the bound
}

TEST(TurbulenceAdaptation, BankTempersTheLikelihoodsWithThePreviousFramesScale) {
  // tau far below a frame: alpha = 1 - e^-1562 = 1, so s = clamp(min_k q_k) of the last frame
  FilterBankOptions o;
  o.p_min = 0.0;
  o.adaptation = on(1e-5, 1.0, 50.0);
  ScalarBank bank({scalar_model(1.0), scalar_model(4.0)}, o);
  ASSERT_TRUE(bank.update(z1(3.0)));   // s was 1: l = -q/2 with q = (9, 2.25)
  double p0 = 1.0, p1 = 0.0;           // p_min = 0: hypothesis 1 starts at 0 and stays there
  EXPECT_NEAR(bank.probabilities()(0), p0, 1e-15);
  EXPECT_NEAR(bank.turbulence_scale(), 2.25, 1e-12);   // min(9, 2.25) / 1
  bank.set_probabilities(Eigen::Vector2d(0.5, 0.5));
  ASSERT_TRUE(bank.update(z1(2.0)));   // q = (4, 1), tempered by s = 2.25
  const double w0 = 0.5 * std::exp(-4.0 / (2 * 2.25)), w1 = 0.5 * std::exp(-1.0 / (2 * 2.25));
  p0 = w0 / (w0 + w1);
  p1 = w1 / (w0 + w1);
  EXPECT_NEAR(bank.probabilities()(0), p0, 1e-14);
  EXPECT_NEAR(bank.probabilities()(1), p1, 1e-14);
  EXPECT_NEAR(bank.log_likelihoods()(0), -4.0 / 4.5, 1e-14);
  EXPECT_DOUBLE_EQ(bank.turbulence_scale(), 1.0);   // min(4, 1) = 1 = s_min
  bank.reset();
  EXPECT_DOUBLE_EQ(bank.turbulence_scale(), 1.0);
}

namespace {

using PairModel = FilterModel<1, 1, 2>;
using PairBank = FilterBank<Eigen::Dynamic, 1, 1, 2>;

// x stays 0 (K = 0, Bd = 0), so r = z; A = [[a, b], [b, d]].
PairModel pair_model(double a, double b, double d) {
  PairModel m;
  m.phi << 0.5;
  m.bd << 0.0;
  m.h << 1.0, 1.0;
  m.k << 0.0, 0.0;
  m.a << a, b, b, d;
  return m;
}

// r' M^-1 r for M = [[a, b], [b, d]], with the inverse written out (adjugate / determinant).
double form(double a, double b, double d, double r0, double r1) {
  const double det = a * d - b * b;
  return (d * r0 * r0 - 2.0 * b * r0 * r1 + a * r1 * r1) / det;
}

}  // namespace

TEST(TurbulenceAdaptation, PerChannelScalesAndLikelihoodsByHand) {
  // tau far below a frame: alpha = 1, so rho_j = c_j of the last frame's best-fitting filter,
  // and s_j = clamp(rho_j, 1, 50) (gain 1, reference 1)
  FilterBankOptions o;
  o.p_min = 0.0;
  o.adaptation = on(1e-5, 1.0, 50.0);
  o.adaptation.channel_weight = 1.0;
  const double a0 = 1.0, b0 = 0.3, d0 = 2.0, a1 = 4.0, b1 = -0.5, d1 = 1.0;
  PairBank bank({pair_model(a0, b0, d0), pair_model(a1, b1, d1)}, o);
  // frame 1: every s_j = 1, l_k = -q_k / 2
  const double z0 = 3.0, z1v = 1.0;
  ASSERT_TRUE(bank.update(Eigen::Vector2d(z0, z1v)));
  const double q0 = form(a0, b0, d0, z0, z1v), q1 = form(a1, b1, d1, z0, z1v);
  EXPECT_NEAR(bank.log_likelihoods()(0), -q0 / 2.0, 1e-14);
  EXPECT_NEAR(bank.log_likelihoods()(1), -q1 / 2.0, 1e-14);
  ASSERT_LT(q1, q0);   // filter 1 fits best: its channel shares set the scales
  const double det1 = a1 * d1 - b1 * b1;
  const double c0 = z0 * (d1 * z0 - b1 * z1v) / det1, c1 = z1v * (-b1 * z0 + a1 * z1v) / det1;
  EXPECT_NEAR(c0 + c1, q1, 1e-14);   // the shares sum to q
  const double s0 = std::min(50.0, std::max(1.0, c0)), s1 = std::min(50.0, std::max(1.0, c1));
  ASSERT_GT(s0, 1.5);   // the channels' scales differ: the test sees them apart
  EXPECT_NEAR(bank.adaptation().channel_power_ratios()(0), c0, 1e-14);
  EXPECT_NEAR(bank.adaptation().channel_power_ratios()(1), c1, 1e-14);
  EXPECT_NEAR(bank.adaptation().channel_inverse_sqrt_scales()(0), 1.0 / std::sqrt(s0), 1e-14);
  const double s = std::min(50.0, std::max(1.0, q1 / 2.0));
  EXPECT_NEAR(bank.turbulence_scale(), s, 1e-14);   // the common s as before
  // gamma = 0.5: s_j = s^0.5 s'_j^0.5, the geometric mean of the common and the channel's own
  FilterBankOptions half = o;
  half.adaptation.channel_weight = 0.5;
  PairBank mixed({pair_model(a0, b0, d0), pair_model(a1, b1, d1)}, half);
  ASSERT_TRUE(mixed.update(Eigen::Vector2d(z0, z1v)));
  EXPECT_NEAR(mixed.adaptation().channel_inverse_sqrt_scales()(0), std::pow(s * s0, -0.25), 1e-14);
  EXPECT_NEAR(mixed.adaptation().channel_inverse_sqrt_scales()(1), std::pow(s * s1, -0.25), 1e-14);
  // frame 2: l_k = -(D r)' A_k^-1 (D r) / 2, D = diag(s_j^-1/2) of frame 1
  bank.set_probabilities(Eigen::Vector2d(0.5, 0.5));
  const double y0 = 2.0 / std::sqrt(s0), y1 = -1.0 / std::sqrt(s1);
  ASSERT_TRUE(bank.update(Eigen::Vector2d(2.0, -1.0)));
  const double l0 = -form(a0, b0, d0, y0, y1) / 2.0, l1 = -form(a1, b1, d1, y0, y1) / 2.0;
  EXPECT_NEAR(bank.log_likelihoods()(0), l0, 1e-13);
  EXPECT_NEAR(bank.log_likelihoods()(1), l1, 1e-13);
  EXPECT_NEAR(bank.probabilities()(0), 1.0 / (1.0 + std::exp(l1 - l0)), 1e-13);
  // reset: rho_j = rho_0 = 1, s_j = 1; set_power_ratio sets every rho_j
  bank.reset();
  EXPECT_DOUBLE_EQ(bank.adaptation().channel_inverse_sqrt_scales()(0), 1.0);
  EXPECT_DOUBLE_EQ(bank.adaptation().channel_power_ratios()(1), 1.0);
  bank.set_adapt_power_ratio(9.0);
  EXPECT_NEAR(bank.adaptation().channel_inverse_sqrt_scales()(0), 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(bank.adaptation().channel_inverse_sqrt_scales()(1), 1.0 / 3.0, 1e-15);
}

TEST(TurbulenceAdaptation, OwnChannelsCountsEachFormPerChannelItReads) {
  // tau far below a frame: alpha = 1, so rho = x of the last frame; gain 1, reference 1: s = rho.
  // Filter 0 reads both channels (A = I: q_0 = z0^2 + z1^2); filter 1's channel 1 is
  // uninformative (a failed sensor's unknown level), so q_1 = z0^2 sums one channel.
  PairModel failed = pair_model(1.0, 0.0, 1.0);
  failed.h << 1.0, 0.0;
  failed.uninformative_width << 0.0, 10.0;
  failed.uninformative_level_q << 0.0, 0.01;
  FilterBankOptions o;
  o.p_min = 0.0;
  o.adaptation = on(1e-5, 1.0, 50.0);
  FilterBankOptions own = o;
  own.adaptation.own_channels = true;
  PairBank plain({pair_model(1.0, 0.0, 1.0), failed}, o), counted({pair_model(1.0, 0.0, 1.0), failed}, own);
  const Eigen::Vector2d z(2.0, 3.0);
  ASSERT_TRUE(plain.update(z));
  ASSERT_TRUE(counted.update(z));
  EXPECT_NEAR(plain.quadratic_forms()(0), 13.0, 1e-14);
  EXPECT_NEAR(plain.quadratic_forms()(1), 4.0, 1e-14);
  EXPECT_NEAR(plain.adaptation().power_ratio(), std::min(13.0, 4.0) / 2.0, 1e-14);   // min_k q_k / m: 2
  EXPECT_NEAR(counted.adaptation().power_ratio(), std::min(13.0 / 2.0, 4.0 / 1.0), 1e-14);   // min_k q_k / m_k: 4
  EXPECT_NEAR(counted.adaptation().measured_power_ratio(), 4.0, 1e-14);
  EXPECT_NEAR(counted.turbulence_scale(), 4.0, 1e-14);
  EXPECT_EQ(counted.quadratic_forms(), plain.quadratic_forms());   // the likelihoods' forms are untouched
  // a bank without uninformative channels: the same, bit for bit
  PairBank full_plain({pair_model(1.0, 0.0, 1.0), pair_model(4.0, -0.5, 1.0)}, o);
  PairBank full_own({pair_model(1.0, 0.0, 1.0), pair_model(4.0, -0.5, 1.0)}, own);
  for (const double v : {2.0, -1.0, 0.5}) {
    ASSERT_TRUE(full_plain.update(Eigen::Vector2d(v, 1.0 - v)));
    ASSERT_TRUE(full_own.update(Eigen::Vector2d(v, 1.0 - v)));
  }
  EXPECT_EQ(full_plain.adaptation().power_ratio(), full_own.adaptation().power_ratio());
  EXPECT_EQ(full_plain.log_likelihoods(), full_own.log_likelihoods());
}

TEST(TurbulenceAdaptation, CountedChannelsKeepTheirShareOfThePlainMinimum) {
  // Three filters on two channels, alpha = 1, gain 1, reference 1 (s = rho): filter 0 reads both
  // (q_0 = z0^2 + z1^2), filter 1 leaves out channel 1 (q_1 = z0^2), filter 2 channel 0
  // (q_2 = z1^2). Own channels: x = min(q_0 / 2, q_1 / 1, q_2 / 1); with channel 1 counted,
  // filter 1 counts over both channels as without own channels (q_1 / 2), filter 2 still over
  // the one it reads: x = min(q_0 / 2, q_1 / 2, q_2 / 1).
  PairModel left1 = pair_model(1.0, 0.0, 1.0);
  left1.h << 1.0, 0.0;
  left1.uninformative_width << 0.0, 10.0;
  left1.uninformative_level_q << 0.0, 0.01;
  PairModel left0 = pair_model(1.0, 0.0, 1.0);
  left0.h << 0.0, 1.0;
  left0.uninformative_width << 10.0, 0.0;
  left0.uninformative_level_q << 0.01, 0.0;
  FilterBankOptions own;
  own.p_min = 0.0;
  own.adaptation = on(1e-5, 1.0, 50.0);
  own.adaptation.own_channels = true;
  FilterBankOptions counted1 = own;
  counted1.adaptation.counted_channels = 1u << 1;
  FilterBankOptions counted_both = own;
  counted_both.adaptation.counted_channels = (1u << 0) | (1u << 1);
  FilterBankOptions plain = own;
  plain.adaptation.own_channels = false;
  const auto models = [&] { return std::vector<PairModel>{pair_model(1.0, 0.0, 1.0), left1, left0}; };
  PairBank a(models(), own), b(models(), counted1), c(models(), counted_both), d(models(), plain);
  const Eigen::Vector2d z(3.0, 2.5);   // q = (15.25, 9, 6.25)
  for (PairBank* bank : {&a, &b, &c, &d}) ASSERT_TRUE(bank->update(z));
  const Eigen::Vector3d q = a.quadratic_forms();
  EXPECT_NEAR(q(0), 15.25, 1e-13);
  EXPECT_NEAR(q(1), 9.0, 1e-13);
  EXPECT_NEAR(q(2), 6.25, 1e-13);
  EXPECT_NEAR(a.adaptation().power_ratio(), std::min({15.25 / 2.0, 9.0, 6.25}), 1e-13);        // 6.25
  EXPECT_NEAR(b.adaptation().power_ratio(), std::min({15.25 / 2.0, 9.0 / 2.0, 6.25}), 1e-13);  // 4.5
  EXPECT_NEAR(b.turbulence_scale(), 4.5, 1e-13);
  // every uninformative channel counted: the plain minimum, bit for bit
  EXPECT_EQ(c.adaptation().power_ratio(), d.adaptation().power_ratio());
  EXPECT_NEAR(c.adaptation().power_ratio(), 6.25 / 2.0, 1e-13);
  EXPECT_EQ(b.quadratic_forms(), a.quadratic_forms());   // the likelihoods' forms are untouched
}

TEST(TurbulenceAdaptation, ExcludedChannelsLeaveTheMinimum) {
  // The three filters of CountedChannelsKeepTheirShareOfThePlainMinimum, alpha = 1, gain 1,
  // reference 1 (s = rho), z = (3, 2.5): q = (15.25, 9, 6.25). Filter 2 reads channel 0 as a
  // free level, filter 1 channel 1. Channel 0 excluded: filter 2 leaves the minimum,
  // x = min(q_0 / 2, q_1 / 2) = 4.5 (plain: min(.., 6.25 / 2) = 3.125); with own channels
  // x = min(q_0 / 2, q_1 / 1) = 7.625. Channel 1 excluded: filter 1 leaves it, x = 3.125, the
  // plain minimum. Filter 2 presumed: it reads channel 0 so itself, nobody leaves, the plain one.
  PairModel left1 = pair_model(1.0, 0.0, 1.0);
  left1.h << 1.0, 0.0;
  left1.uninformative_width << 0.0, 10.0;
  left1.uninformative_level_q << 0.0, 0.01;
  PairModel left0 = pair_model(1.0, 0.0, 1.0);
  left0.h << 0.0, 1.0;
  left0.uninformative_width << 10.0, 0.0;
  left0.uninformative_level_q << 0.01, 0.0;
  FilterBankOptions plain;
  plain.p_min = 0.0;
  plain.adaptation = on(1e-5, 1.0, 50.0);
  FilterBankOptions ex0 = plain;
  ex0.adaptation.excluded_channels = 1u << 0;
  FilterBankOptions ex0_own = ex0;
  ex0_own.adaptation.own_channels = true;
  FilterBankOptions ex1 = plain;
  ex1.adaptation.excluded_channels = 1u << 1;
  const auto models = [&] { return std::vector<PairModel>{pair_model(1.0, 0.0, 1.0), left1, left0}; };
  PairBank a(models(), plain), b(models(), ex0), c(models(), ex0_own), d(models(), ex1), e(models(), ex0);
  e.presume(2);
  const Eigen::Vector2d z(3.0, 2.5);
  for (PairBank* bank : {&a, &b, &c, &d, &e}) ASSERT_TRUE(bank->update(z));
  const Eigen::Vector3d q = b.quadratic_forms();
  EXPECT_NEAR(q(0), 15.25, 1e-13);
  EXPECT_NEAR(q(1), 9.0, 1e-13);
  EXPECT_NEAR(q(2), 6.25, 1e-13);
  EXPECT_NEAR(a.adaptation().power_ratio(), 6.25 / 2.0, 1e-13);
  EXPECT_NEAR(b.adaptation().power_ratio(), 9.0 / 2.0, 1e-13);
  EXPECT_NEAR(b.adaptation().measured_power_ratio(), 9.0 / 2.0, 1e-13);   // x feeds rho-bar too
  EXPECT_NEAR(b.turbulence_scale(), 4.5, 1e-13);
  EXPECT_NEAR(c.adaptation().power_ratio(), 15.25 / 2.0, 1e-13);
  EXPECT_EQ(d.adaptation().power_ratio(), a.adaptation().power_ratio());
  EXPECT_EQ(e.adaptation().power_ratio(), a.adaptation().power_ratio());
  EXPECT_EQ(b.quadratic_forms(), a.quadratic_forms());   // the likelihoods' forms are untouched
  // the excluded filter still gets s: the next frame's l_k = -q_k / (2 s) + (its footing), every k alike
  const Eigen::Vector2d z2(1.0, -2.0);
  ASSERT_TRUE(a.update(z2));
  ASSERT_TRUE(b.update(z2));
  const double s = 4.5;
  for (int k = 0; k < 3; ++k) {
    const double footing_k = a.log_likelihoods()(k) + a.quadratic_forms()(k) / (2.0 * 3.125);
    EXPECT_NEAR(b.log_likelihoods()(k), -b.quadratic_forms()(k) / (2.0 * s) + footing_k, 1e-12) << k;
  }
}

TEST(TurbulenceAdaptation, PerChannelWithOneChannelIsTheCommonScale) {
  // one measurement: c_1 = q_k*, the minimum, so rho_1 = rho and -(s^-1/2 r)' A^-1 (s^-1/2 r) / 2
  // = -q / (2 s): the two forms agree to rounding over a flight of changing scales
  FilterBankOptions common;
  common.p_min = 1e-6;
  common.adaptation = on(0.2, 1.0, 30.0, 3.0);
  FilterBankOptions per = common;
  per.adaptation.channel_weight = 1.0;
  ScalarBank a({scalar_model(1.0), scalar_model(4.0), scalar_model(0.5)}, common);
  ScalarBank b({scalar_model(1.0), scalar_model(4.0), scalar_model(0.5)}, per);
  double largest = 1.0;
  for (int i = 0; i < 400; ++i) {
    const double v = (i < 200 ? 1.0 : 6.0) * std::sin(0.7 * i + 0.3 * (i % 7));
    ASSERT_TRUE(a.update(z1(v)));
    ASSERT_TRUE(b.update(z1(v)));
    largest = std::max(largest, a.turbulence_scale());
    ASSERT_NEAR((a.log_likelihoods() - b.log_likelihoods()).cwiseAbs().maxCoeff(), 0.0, 1e-10) << "frame " << i;
    ASSERT_NEAR((a.probabilities() - b.probabilities()).cwiseAbs().maxCoeff(), 0.0, 1e-10) << "frame " << i;
    ASSERT_NEAR(1.0 / std::pow(b.adaptation().channel_inverse_sqrt_scales()(0), 2), a.turbulence_scale(), 1e-9);
  }
  EXPECT_GT(largest, 5.0);   // the scale did move
}

TEST(TurbulenceAdaptation, OffIsBitIdenticalToTheBankWithoutIt) {
  const ModelBank mb = test::f16_model_bank(7u);
  HierarchicalOptions plain, off, unit;
  off.bank.adaptation.enabled = false;
  off.bank.adaptation.time_constant_s = 0.1;
  unit.bank.adaptation = on(5.0, 1.0, 1.0);   // on, but s pinned at 1
  F16HierarchicalBank a(mb, plain), b(mb, off), c(mb, unit);
  test::fly_alike(mb, 7u, 3u, 400, [&](int i) {
    EXPECT_EQ(a.probabilities(), b.probabilities()) << "frame " << i;
    EXPECT_EQ(a.probabilities(), c.probabilities()) << "frame " << i;
    EXPECT_EQ(a.blended_state(), b.blended_state()) << "frame " << i;
    return a.probabilities() == b.probabilities() && a.probabilities() == c.probabilities() &&
           a.blended_state() == b.blended_state();
  }, a, b, c);
  EXPECT_EQ(a.declarations().size(), b.declarations().size());
  EXPECT_DOUBLE_EQ(b.turbulence_scale(), 1.0);
}

TEST(TurbulenceAdaptation, ScaleRecoversAKnownNoisePowerRatio) {
  // Truth noise (process and measurement) c times the design's: the steady-state residual
  // covariance of every filter is then c A_k, so E[q_k] = c nz and s -> c.
  const ModelBank mb = test::f16_model_bank(11u);
  for (const double c : {4.0, 16.0}) {
    HierarchicalOptions o;
    o.bank.adaptation = on(5.0);
    F16HierarchicalBank hb(mb, o);
    test::Plant plant = test::random_plant(13, 5, 7, 11u, 1e-3, 1e-3);
    plant.q *= c;
    plant.r *= c;
    test::Truth truth(plant, test::kF16Actuators, test::kF16Sensors, 5u);
    double sum = 0.0;
    int n = 0;
    for (int i = 0; i < 64 * 120; ++i) {
      const Eigen::VectorXd du = test::dither(5, i, 64.0);
      hb.step(truth.measure({}) + mb.z_trim, du + mb.u_trim);
      truth.advance(du, {});
      if (i >= 64 * 30) sum += hb.turbulence_scale(), ++n;
    }
    // the minimum over 13 averages sits a little below the no-failure filter's c
    EXPECT_GT(sum / n, 0.8 * c) << "c = " << c;
    EXPECT_LT(sum / n, 1.1 * c) << "c = " << c;
    EXPECT_TRUE(hb.declarations().empty()) << "c = " << c;
  }
}

TEST(TurbulenceAdaptation, AFailureDoesNotRaiseTheScaleAndIsDeclared) {
  for (const double per_channel : {0.0, 1.0}) {
  const ModelBank mb = test::f16_model_bank(13u);
  HierarchicalOptions o;
  // the tuned gain (κ = 20) with this synthetic bank's own healthy power ratio (ρ ≈ 1) as ρ_0
  o.bank.adaptation = on(5.0, 1.0, 100.0, TurbulenceAdaptationOptions{}.gain);
  o.bank.adaptation.channel_weight = per_channel;   // per channel: no channel's scale rises either
  F16HierarchicalBank hb(mb, o);
  const test::Plant plant = test::random_plant(13, 5, 7, 13u, 1e-3, 1e-3);
  test::Truth truth(plant, test::kF16Actuators, test::kF16Sensors, 9u);
  double s_max_after = 0.0;
  for (int i = 0; i < 64 * 20; ++i) {
    const std::vector<std::string> failed = i >= 64 * 10 ? std::vector<std::string>{"PIT"} : std::vector<std::string>{};
    const Eigen::VectorXd du = test::dither(5, i, 64.0);
    hb.step(truth.measure(failed) + mb.z_trim, du + mb.u_trim);
    truth.advance(du, failed);
    if (i >= 64 * 10) s_max_after = std::max(s_max_after, hb.turbulence_scale());
    if (i >= 64 * 10 && per_channel > 0.0)
      s_max_after = std::max(s_max_after, hb.bank().adaptation().channel_inverse_sqrt_scales().minCoeff() > 0.0
                                              ? std::pow(hb.bank().adaptation().channel_inverse_sqrt_scales().minCoeff(), -2)
                                              : 1e9);
  }
  ASSERT_FALSE(hb.declarations().empty());
  EXPECT_EQ(hb.name(hb.declarations().front().hypothesis), "PIT");
  EXPECT_LT(hb.declarations().front().time_s, 11.0);
  // the PIT filter's residuals stay at the design's power: s stays near 1 (the no-failure
  // filter's own residual power grows a hundredfold after the failure)
  EXPECT_LT(s_max_after, 4.0) << "per channel " << per_channel;
  }
}

TEST(TurbulenceAdaptation, PerHypothesisTemperingSparesTheBestFittingFailureByHand) {
  // tau far below a frame and kappa = 1, rho_0 = 1: s = clamp(min_k q_k, 1, 50) of the last frame.
  // A = (1, 4, 2, 3): q_k = z^2 / A_k.
  FilterBankOptions o;
  o.p_min = 0.0;
  o.adaptation = on(1e-5, 1.0, 50.0);
  o.adaptation.hypothesis_weight = 0.25;
  const std::vector<Scalar> models{scalar_model(1.0), scalar_model(4.0), scalar_model(2.0), scalar_model(3.0)};
  ScalarBank bank(models, o);
  ASSERT_TRUE(bank.update(z1(3.0)));   // s was 1: nothing spared, l = -q/2 with q = (9, 2.25, 4.5, 3)
  EXPECT_NEAR(bank.log_likelihoods()(1), -2.25 / 2.0, 1e-15);
  EXPECT_NEAR(bank.turbulence_scale(), 2.25, 1e-12);
  bank.set_probabilities(Eigen::Vector4d::Constant(0.25));
  ASSERT_TRUE(bank.update(z1(2.0)));   // q = (4, 1, 2, 4/3), s = 2.25; b = 1 (least q among k > 0)
  const double s = 2.25, s_b = 1.0 + 0.25 * (s - 1.0);   // 1.3125
  const double l0 = -4.0 / (2 * s), l1 = -(4.0 + (1.0 - 4.0) * s / s_b) / (2 * s);
  const double l2 = -2.0 / (2 * s), l3 = -(4.0 / 3.0) / (2 * s);
  EXPECT_NEAR(bank.log_likelihoods()(0), l0, 1e-14);
  EXPECT_NEAR(bank.log_likelihoods()(1), l1, 1e-14);
  EXPECT_NEAR(bank.log_likelihoods()(2), l2, 1e-14);
  EXPECT_NEAR(bank.log_likelihoods()(3), l3, 1e-14);
  EXPECT_NEAR(l1 - l0, -(1.0 - 4.0) / (2 * s_b), 1e-14);   // b's evidence against 0, tempered by s_b
  const double w[4] = {std::exp(l0), std::exp(l1), std::exp(l2), std::exp(l3)};
  const double sum = w[0] + w[1] + w[2] + w[3];
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(bank.probabilities()(k), w[k] / sum, 1e-14) << k;

  // hypothesis 1 fully tempered (bit 1): every l_k = -q_k / (2 s), as with weight 1
  o.adaptation.full_tempering = 1u << 1;
  ScalarBank exempt(models, o);
  o.adaptation.full_tempering = 0;
  o.adaptation.hypothesis_weight = 1.0;
  ScalarBank plain(models, o);
  for (ScalarBank* b : {&exempt, &plain}) {
    ASSERT_TRUE(b->update(z1(3.0)));
    ASSERT_TRUE(b->update(z1(2.0)));
    EXPECT_NEAR(b->log_likelihoods()(1), -1.0 / (2 * s), 1e-14);
    EXPECT_NEAR(b->log_likelihoods()(3), l3, 1e-14);
  }
  // the raw forms drive the scale: it is the same with and without the weight
  EXPECT_DOUBLE_EQ(bank.turbulence_scale(), plain.turbulence_scale());

  // another hypothesis presumed (a hierarchical bank's level 1): nothing spared
  bank.presume(3);
  const double s2 = bank.turbulence_scale();   // min q of the last frame: 1
  ASSERT_TRUE(bank.update(z1(3.0)));   // q = (9, 2.25, 4.5, 3)
  EXPECT_NEAR(bank.log_likelihoods()(1), -2.25 / (2 * s2), 1e-14);

  // not caught up: rho below half the measured rho-bar (slow tau, rho from rho_0 = 1)
  ResidualScale<Eigen::Dynamic> r;
  TurbulenceAdaptationOptions slow = on(5.0);
  slow.hypothesis_weight = 0.25;
  r.configure(slow, 1, "test");
  r.observe(Eigen::Vector2d(30.0, 40.0));   // rho-bar = 30, rho = 1 + alpha 29 (s > 1)
  EXPECT_GT(r.scale(), 1.0);
  EXPECT_FALSE(r.spares());
  for (int n = 0; n < 640; ++n) r.observe(Eigen::Vector2d(30.0, 40.0));   // 10 s: rho near 30
  EXPECT_TRUE(r.spares());
}

TEST(TurbulenceAdaptation, RoughTemperingKeepsItsHypothesesAtTheFullScaleInRoughAirOnlyByHand) {
  // tau far below a frame and kappa = 1, rho_0 = 1: s = clamp(min_k q_k, 1, 50) of the last frame,
  // rho-bar = min_k q_k of the last frame (one channel). A = (1, 4, 2, 3): q_k = z^2 / A_k.
  // w = 0.25; hypothesis 1 kept at the full s while rho-bar >= rho_r = 3 (no lull floor: the
  // air's rho is rho-bar).
  FilterBankOptions o;
  o.p_min = 0.0;
  o.adaptation = on(1e-5, 1.0, 50.0);
  o.adaptation.hypothesis_weight = 0.25;
  FilterBankOptions rough = o;
  rough.adaptation.rough_tempering = 1u << 1;
  rough.adaptation.rough_rho = 3.0;
  const std::vector<Scalar> models{scalar_model(1.0), scalar_model(4.0), scalar_model(2.0), scalar_model(3.0)};
  FilterBankOptions shared = rough;   // w_r = 0.5: the rudder's share in rough air, in place of w's
  shared.adaptation.rough_weight = 0.5;
  ScalarBank spared(models, o), gated(models, rough), half(models, shared);
  const auto l1_spared = [](double q0, double q1, double s, double w = 0.25) {
    const double s_b = 1.0 + w * (s - 1.0);
    return -(q0 + (q1 - q0) * s / s_b) / (2 * s);
  };
  // frame 1, z = 3: q = (9, 2.25, 4.5, 3); rho-bar = 2.25 < 3: moderate air
  for (ScalarBank* b : {&spared, &gated, &half}) ASSERT_TRUE(b->update(z1(3.0)));
  EXPECT_NEAR(gated.adaptation().air_power_ratio(), 2.25, 1e-12);
  EXPECT_EQ(gated.adaptation().fully_tempered(), 0u);
  // frame 2, z = 2: q = (4, 1, 2, 4/3), s = 2.25: hypothesis 1 spared in both
  for (ScalarBank* b : {&spared, &gated, &half}) ASSERT_TRUE(b->update(z1(2.0)));
  EXPECT_NEAR(gated.log_likelihoods()(1), l1_spared(4.0, 1.0, 2.25), 1e-14);
  EXPECT_EQ(gated.log_likelihoods(), spared.log_likelihoods());
  EXPECT_EQ(half.log_likelihoods(), spared.log_likelihoods());
  // frame 3, z = 4: q = (16, 4, 8, 16/3), s = 1 (rho-bar 1 of frame 2): nothing to spare;
  // rho-bar = 4 >= 3 from here: rough air
  for (ScalarBank* b : {&spared, &gated, &half}) ASSERT_TRUE(b->update(z1(4.0)));
  EXPECT_EQ(gated.adaptation().fully_tempered(), 1u << 1);
  EXPECT_EQ(spared.adaptation().fully_tempered(), 0u);
  EXPECT_EQ(half.adaptation().fully_tempered(), 0u);   // w_r < 1: spared by w_r, not fully tempered
  EXPECT_EQ(half.adaptation().rough_spared(), 1u << 1);
  // frame 4, z = 2: s = 4; the gated bank keeps 1 at s, l_1 = -q_1 / (2 s); the other spares it
  // by w, the half bank by w_r: s_b = 1 + 0.5 (4 - 1) = 2.5, l_1 = -(4 + (1 - 4) 4 / 2.5) / 8 = 0.1
  for (ScalarBank* b : {&spared, &gated, &half}) ASSERT_TRUE(b->update(z1(2.0)));
  EXPECT_NEAR(gated.log_likelihoods()(1), -1.0 / (2 * 4.0), 1e-14);
  EXPECT_NEAR(spared.log_likelihoods()(1), l1_spared(4.0, 1.0, 4.0), 1e-14);
  EXPECT_NEAR(half.log_likelihoods()(1), l1_spared(4.0, 1.0, 4.0, 0.5), 1e-14);
  EXPECT_NEAR(half.log_likelihoods()(1), 0.1, 1e-14);
  EXPECT_GT(spared.log_likelihoods()(1), half.log_likelihoods()(1));
  EXPECT_GT(half.log_likelihoods()(1), gated.log_likelihoods()(1));
  for (int k : {0, 2, 3}) EXPECT_EQ(half.log_likelihoods()(k), spared.log_likelihoods()(k)) << k;
  for (int k : {0, 2, 3}) EXPECT_EQ(gated.log_likelihoods()(k), spared.log_likelihoods()(k)) << k;
  // a fully tempered least q_k spares none: hypothesis 3 (the next best) is not spared instead
  EXPECT_NEAR(gated.log_likelihoods()(3), -(4.0 / 3.0) / (2 * 4.0), 1e-14);
  // the raw forms drive the scale in both
  EXPECT_EQ(gated.turbulence_scale(), spared.turbulence_scale());
  // back in calmer air (rho-bar 1 after frame 4): spared again
  for (ScalarBank* b : {&spared, &gated}) ASSERT_TRUE(b->update(z1(3.0)));   // s = 1 on this frame
  EXPECT_EQ(gated.adaptation().fully_tempered(), 0u);
  for (ScalarBank* b : {&spared, &gated}) ASSERT_TRUE(b->update(z1(2.0)));
  EXPECT_EQ(gated.log_likelihoods(), spared.log_likelihoods());
}

TEST(TurbulenceAdaptation, SparedHypothesisOnlyInRoughAirByHand) {
  // Three filters on two channels, tau far below a frame (alpha = 1: rho = rho-bar = x of the last
  // frame), gain 1, reference 1 (s = rho), own channels (x = min_k q_k / m_k), w = 0.25.
  // Filter 0 reads both (A = I: q_0 = z0^2 + z1^2), filter 1 leaves channel 1 out (a failed
  // sensor: q_1 = z0^2, m_1 = 1), filter 2 reads both with A = 1.5 I (q_2 = (z0^2 + z1^2) / 1.5).
  // The spared hypothesis is read off each bank's l_b against the same bank without the
  // per-hypothesis form (w = 1), whose l_k = -q_k / (2 s) + u_k: the difference is
  //   -(q_0 + (q_b - q_0) s / s_b) / (2 s) + q_b / (2 s) = (q_b - q_0)(1 - s / s_b) / (2 s),
  // every other hypothesis's difference 0.
  PairModel left1 = pair_model(1.0, 0.0, 1.0);
  left1.h << 1.0, 0.0;
  left1.uninformative_width << 0.0, 10.0;
  left1.uninformative_level_q << 0.0, 0.01;
  FilterBankOptions plain;
  plain.p_min = 0.0;
  plain.adaptation = on(1e-5, 1.0, 50.0);
  plain.adaptation.own_channels = true;
  FilterBankOptions raw = plain;
  raw.adaptation.hypothesis_weight = 0.25;
  FilterBankOptions gated = raw;
  gated.adaptation.spare_rho = 6.0;
  const auto models = [&] { return std::vector<PairModel>{pair_model(1.0, 0.0, 1.0), left1, pair_model(1.5, 0.0, 1.5)}; };
  PairBank p(models(), plain), r(models(), raw), g(models(), gated);
  const auto spared_difference = [](double q_b, double q_0, double s) {
    const double s_b = 1.0 + 0.25 * (s - 1.0);
    return (q_b - q_0) * (1.0 - s / s_b) / (2.0 * s);
  };
  const auto differences = [&](const PairBank& b) -> Eigen::Vector3d { return b.log_likelihoods() - p.log_likelihoods(); };

  // frame 1, z = (3, 2.5): s was 1, nothing spared anywhere. q = (15.25, 9, 15.25 / 1.5);
  // x = min(15.25 / 2, 9 / 1, 10.1667 / 2) = 5.0833 = rho = rho-bar = s.
  const Eigen::Vector2d z(3.0, 2.5);
  for (PairBank* b : {&p, &r, &g}) ASSERT_TRUE(b->update(z));
  for (PairBank* b : {&r, &g}) EXPECT_EQ(differences(*b), Eigen::Vector3d::Zero());
  const double q0 = 15.25, q1 = 9.0, q2 = 15.25 / 1.5, s = q2 / 2.0;
  EXPECT_NEAR(p.quadratic_forms()(1), q1, 1e-13);
  EXPECT_NEAR(p.quadratic_forms()(2), q2, 1e-13);
  EXPECT_NEAR(p.turbulence_scale(), s, 1e-13);
  EXPECT_NEAR(g.adaptation().measured_power_ratio(), s, 1e-13);

  // frame 2, the same z: filter 1 fits best (9 < 10.17) and is spared; the gated bank's
  // rho-bar 5.08 < 6: none.
  for (PairBank* b : {&p, &r, &g}) ASSERT_TRUE(b->update(z));
  EXPECT_NEAR(differences(r)(1), spared_difference(q1, q0, s), 1e-13);
  EXPECT_GT(differences(r)(1), 0.0);   // spared: a failure that fits better than NONE gains
  EXPECT_EQ(differences(r)(2), 0.0);
  EXPECT_EQ(differences(g), Eigen::Vector3d::Zero());
  for (PairBank* b : {&r, &g}) EXPECT_EQ(differences(*b)(0), 0.0);

  // frame 3, z = (4, 3): q = (25, 16, 16.667), x = min(12.5, 16, 8.333) = 8.333 = rho-bar >= 6;
  // this frame still uses s and rho-bar of frame 2 (5.08 < 6): none spared in the gated bank.
  const Eigen::Vector2d z3(4.0, 3.0);
  for (PairBank* b : {&p, &r, &g}) ASSERT_TRUE(b->update(z3));
  EXPECT_EQ(differences(g), Eigen::Vector3d::Zero());
  const double s3 = 25.0 / 1.5 / 2.0;
  EXPECT_NEAR(g.adaptation().measured_power_ratio(), s3, 1e-13);
  EXPECT_TRUE(g.adaptation().spares());
  // frame 4, z = (4, 3) again: rho-bar 8.33 >= 6, the gated bank spares filter 1 (16 < 16.67)
  // as the ungated one
  for (PairBank* b : {&p, &r, &g}) ASSERT_TRUE(b->update(z3));
  EXPECT_NEAR(differences(g)(1), spared_difference(16.0, 25.0, s3), 1e-13);
  EXPECT_EQ(differences(g)(2), 0.0);
  EXPECT_EQ(differences(g), differences(r));
  // the raw forms drive the scale in every bank
  EXPECT_EQ(g.turbulence_scale(), p.turbulence_scale());
  EXPECT_EQ(r.turbulence_scale(), p.turbulence_scale());
}

TEST(TurbulenceAdaptation, SpareMarginIsTheSparedFormOverTheBestFullyTemperedByHand) {
  // tau far below a frame, kappa = 1, rho_0 = 1: s = clamp(min_k q_k, 1, 50) of the last frame
  // (one channel). A = (1, 2.5, 3, 1.5): q_k = z^2 / A_k; filter 1 fully tempered (a
  // stabilator), w = 0.25. Frame 1, z = 3: q = (9, 3.6, 3, 6), s was 1: nothing spared; s = 3.
  // Frame 2, z = 2: q = (4, 1.6, 4/3, 8/3), b = 2 (4/3 < 1.6), s_b = 1 + 0.25 (3 - 1) = 1.5.
  //   over filter 0 (plain):  l_2 = -(4 + (4/3 - 4) 3 / 1.5) / 6 = 2/9
  //   margin, q_r = min(q_0, q_1) = 1.6:  l_2 = -(1.6 + (4/3 - 1.6) 3 / 1.5) / 6 = -0.16/0.9
  //   so l_2 - l_1 = -(4/3 - 1.6) / (2 s_b) = 4/45 (plain: 2/9 + 1.6/6 = 22/45).
  FilterBankOptions o;
  o.p_min = 0.0;
  o.adaptation = on(1e-5, 1.0, 50.0);
  o.adaptation.hypothesis_weight = 0.25;
  o.adaptation.full_tempering = 1u << 1;
  FilterBankOptions m = o;
  m.adaptation.spare_margin = true;
  const auto models = [](double a1) {
    return std::vector<Scalar>{scalar_model(1.0), scalar_model(a1), scalar_model(3.0), scalar_model(1.5)};
  };
  ScalarBank plain(models(2.5), o), margin(models(2.5), m);
  for (ScalarBank* b : {&plain, &margin}) {
    ASSERT_TRUE(b->update(z1(3.0)));
    EXPECT_NEAR(b->turbulence_scale(), 3.0, 1e-12);
    b->set_probabilities(Eigen::Vector4d::Constant(0.25));
    ASSERT_TRUE(b->update(z1(2.0)));
  }
  const double s = 3.0;
  EXPECT_NEAR(plain.log_likelihoods()(2), 2.0 / 9.0, 1e-14);
  EXPECT_NEAR(margin.log_likelihoods()(2), -(1.6 + (4.0 / 3.0 - 1.6) * 2.0) / (2.0 * s), 1e-14);
  EXPECT_NEAR(margin.log_likelihoods()(2) - margin.log_likelihoods()(1), 4.0 / 45.0, 1e-14);
  EXPECT_NEAR(plain.log_likelihoods()(2) - plain.log_likelihoods()(1), 22.0 / 45.0, 1e-14);
  for (int k : {0, 1, 3}) {   // every other l_k = -q_k / (2 s) in both
    const double q = 4.0 / std::vector<double>{1.0, 2.5, 3.0, 1.5}[k];
    EXPECT_NEAR(plain.log_likelihoods()(k), -q / (2.0 * s), 1e-14) << k;
    EXPECT_EQ(margin.log_likelihoods()(k), plain.log_likelihoods()(k)) << k;
  }
  const Eigen::Vector4d l = margin.log_likelihoods();
  const Eigen::Vector4d w = l.array().exp();
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(margin.probabilities()(k), w(k) / w.sum(), 1e-14) << k;

  // the fully tempered filter fits worse than filter 0 (A_1 = 0.8: q_1 = 5 > q_0 = 4): q_r = q_0,
  // the margin is the plain form bit for bit
  ScalarBank plain2(models(0.8), o), margin2(models(0.8), m);
  // ... and with filter 1 off line, q_r = q_0 whatever it fits
  ScalarBank margin3(models(2.5), m), plain3(models(2.5), o);
  margin3.set_live(1, false);
  plain3.set_live(1, false);
  for (ScalarBank* b : {&plain2, &margin2, &plain3, &margin3}) {
    ASSERT_TRUE(b->update(z1(3.0)));
    EXPECT_NEAR(b->turbulence_scale(), 3.0, 1e-12);
    ASSERT_TRUE(b->update(z1(2.0)));
  }
  EXPECT_NEAR(margin2.log_likelihoods()(2), 2.0 / 9.0, 1e-14);   // spared over q_0, as plain
  EXPECT_EQ(margin2.log_likelihoods(), plain2.log_likelihoods());
  EXPECT_EQ(margin3.log_likelihoods()(2), plain3.log_likelihoods()(2));
  EXPECT_NEAR(margin3.log_likelihoods()(2), 2.0 / 9.0, 1e-14);

  // spare_margin_over: the margin's reference set in place of full_tempering's. Filters 1 and 3
  // fully tempered; over both (0, the default): q_r = min(4, 1.6, 8/3) = 1.6, l_2 as above; over
  // filter 3 only: q_r = min(4, 8/3) = 8/3, l_2 = -(8/3 + (4/3 - 8/3) 3 / 1.5) / 6 = 0; over filter 1
  // only: the margin above bit for bit
  FilterBankOptions both = m;
  both.adaptation.full_tempering = (1u << 1) | (1u << 3);
  FilterBankOptions over3 = both, over1 = both;
  over3.adaptation.spare_margin_over = 1u << 3;
  over1.adaptation.spare_margin_over = 1u << 1;
  ScalarBank margin_both(models(2.5), both), margin_over3(models(2.5), over3), margin_over1(models(2.5), over1);
  for (ScalarBank* b : {&margin_both, &margin_over3, &margin_over1}) {
    ASSERT_TRUE(b->update(z1(3.0)));
    b->set_probabilities(Eigen::Vector4d::Constant(0.25));
    ASSERT_TRUE(b->update(z1(2.0)));
  }
  EXPECT_EQ(margin_both.log_likelihoods(), margin.log_likelihoods());
  EXPECT_EQ(margin_over1.log_likelihoods(), margin.log_likelihoods());
  EXPECT_NEAR(margin_over3.log_likelihoods()(2), 0.0, 1e-14);
  for (int k : {0, 1, 3}) EXPECT_EQ(margin_over3.log_likelihoods()(k), plain.log_likelihoods()(k)) << k;

  // the fully tempered filter fits best (A_1 = 4: q_1 = 1 < 4/3): none spared, with or without the margin
  ScalarBank plain4(models(4.0), o), margin4(models(4.0), m);
  for (ScalarBank* b : {&plain4, &margin4}) {   // frame 1: q = (9, 2.25, 3, 6), s = 2.25
    ASSERT_TRUE(b->update(z1(3.0)));
    ASSERT_TRUE(b->update(z1(2.0)));
    EXPECT_NEAR(b->log_likelihoods()(2), -(4.0 / 3.0) / (2.0 * 2.25), 1e-14);
  }
}

TEST(TurbulenceAdaptation, BadOptionsAreRefusedByName) {
  const auto refused = [](TurbulenceAdaptationOptions o, const std::string& what) {
    try {
      ScalarBank({scalar_model(1.0), scalar_model(2.0)}, FilterBankOptions{0.001, true, true, o});
      ADD_FAILURE() << "accepted " << what;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  TurbulenceAdaptationOptions o = on(5.0);
  o.time_constant_s = 0.0;
  refused(o, "adapt_time_constant_s");
  o = on(5.0, -1.0);
  refused(o, "adapt_scale_min");
  o = on(5.0, 2.0, 1.0);
  refused(o, "adapt_scale_max");
  o = on(5.0, 1.0, 100.0, 0.0);
  refused(o, "adapt_gain");
  o = on(5.0);
  o.reference = -1.0;
  refused(o, "adapt_reference");
  o = on(5.0);
  o.frame_rate_hz = std::nan("");
  refused(o, "frame_rate_hz");
  o = on(5.0);
  o.channel_weight = 1.5;
  refused(o, "adapt_channel_weight");
  o = on(5.0);
  o.hypothesis_weight = 0.0;
  refused(o, "adapt_hypothesis_weight");
  o.hypothesis_weight = 1.5;
  refused(o, "adapt_hypothesis_weight");
  o.hypothesis_weight = 0.5;
  o.channel_weight = 0.5;
  refused(o, "adapt_hypothesis_weight below 1 needs the common scale");
  o = on(5.0);
  o.spare_rho = -1.0;
  refused(o, "adapt_spare_rho");
  o.spare_rho = 0.0;
  o.rough_rho = 101.0;
  refused(o, "adapt_rough_rho");
  o.rough_rho = std::nan("");
  refused(o, "adapt_rough_rho");
  o.rough_rho = 0.0;
  o.rough_weight = 0.0;
  refused(o, "adapt_rough_weight");
  o.rough_weight = 1.5;
  refused(o, "adapt_rough_weight");
  o.rough_weight = 1.0;
  o.scale_max_from = -1.0;
  refused(o, "adapt_scale_max_from must be in [0, 100] (0: off), got -1");
  o.scale_max_from = std::nan("");
  refused(o, "adapt_scale_max_from");
  o.scale_max_from = 0.0;
  o.spare_rho = std::nan("");
  refused(o, "adapt_spare_rho");
  o = on(5.0);
  o = on(5.0);
  o.floor_time_constant_s = 2.0;   // shorter than the average it floors
  refused(o, "adapt_floor_time_constant_s must be 0 (off) or in [adapt_time_constant_s = 5, 3600] s, got 2");
  o.floor_time_constant_s = std::nan("");
  refused(o, "adapt_floor_time_constant_s");
  o.floor_time_constant_s = 4000.0;
  refused(o, "adapt_floor_time_constant_s");
}

TEST(TurbulenceAdaptation, F16SizedStepWithAdaptationAllocatesNothing) {
  for (const double per_channel : {0.0, 1.0, -1.0}) {   // -1: the per-hypothesis tempering, w = 0.25
  const ModelBank mb = test::f16_model_bank(31u);
  HierarchicalOptions o;
  o.bank.adaptation = on(5.0);
  o.bank.adaptation.channel_weight = per_channel > 0.0 ? per_channel : 0.0;
  o.bank.adaptation.floor_time_constant_s = 30.0;   // the lull floor on too
  if (per_channel < 0.0) o.bank.adaptation.hypothesis_weight = 0.25;
  o.bank.adaptation.spare_margin = per_channel < 0.0;    // its margin over the fully tempered (LS, RS)
  if (per_channel < 0.0) o.bank.adaptation.full_tempering = (1u << 1) | (1u << 2);
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
  EXPECT_EQ(after - before, 0) << "per channel " << per_channel;
  EXPECT_FALSE(hb.declarations().empty());   // the switch to level 1 happened inside the count
  }
}

// running_mean.h: n is the last i with 1.0 / i >= alpha, so a_i = (i <= n ? 1.0 / i : alpha)
// equals max(1.0 / i, alpha) bit for bit, also where 1 / alpha is an integer or near one.
TEST(RunningMean, TheLengthGivesMaxOfOneOverIAndAlphaBitForBit) {
  EXPECT_EQ(f16mmae::running_mean_length(1.0), 1);
  EXPECT_EQ(f16mmae::running_mean_length(0.25), 4);
  EXPECT_EQ(f16mmae::running_mean_length(0.0), std::numeric_limits<std::int64_t>::max());
  for (const double alpha : {0.5, 0.3, 0.1, 1.0 / 3.0, 1.0 / 7.0, std::nextafter(0.1, 1.0), std::nextafter(0.1, 0.0),
                             1.0 - std::exp(-1.0 / 16.0), 1.0 - std::exp(-1.0 / 64.0), 1.0 - std::exp(-1.0 / 640.0)}) {
    const std::int64_t n = f16mmae::running_mean_length(alpha);
    EXPECT_GE(1.0 / static_cast<double>(n), alpha);
    EXPECT_LT(1.0 / static_cast<double>(n + 1), alpha);
    for (std::int64_t i = 1; i <= n + 50; ++i) {
      const double a = i <= n ? 1.0 / static_cast<double>(i) : alpha;
      EXPECT_EQ(a, std::max(1.0 / static_cast<double>(i), alpha)) << "alpha " << alpha << ", i " << i;
    }
  }
}
