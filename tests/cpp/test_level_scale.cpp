// The level channels' scale term of the tempered likelihoods (TurbulenceAdaptationOptions::
// level_scale, filter_bank.h): off, and at level 0 on, the bank is bit for bit the one without it;
// while a level hypothesis f is presumed every hypothesis reading f's level channel gains
// (1/2) ln s on the one without, s the adaptation's scale of the frames before, and no other.
// level_scale_channels: at every level the hypotheses reading a set channel as a level gain
// (1/2) ln max(s / s_0, 1), and no other; the empty mask is bit for bit the bank without it.
#include "f16mmae/filter_bank.h"

#include "allocation_counter.h"
#include "synthetic_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace f16mmae;
using namespace f16mmae::test;

namespace {

// The F-16-sized level-0 bank with VEL's and ROL's failures as tracked levels (the scheduled
// design's constant=VEL+ROL model).
std::vector<F16FilterBank::Model> vel_rol_models() {
  return level_models<F16FilterBank::Model>(f16_model_bank(31u), 13, {{"VEL", 0, 50.0, 1e-4}, {"ROL", 4, 1.0, 1e-6}});
}

FilterBankOptions adapted(bool level_scale) {
  FilterBankOptions o;
  o.adaptation.enabled = true;
  o.adaptation.reference = 0.0;   // tempering from the first frames
  o.adaptation.level_scale = level_scale;
  return o;
}

}  // namespace

TEST(LevelScale, AtLevelZeroNothingChangesAndPresumedALevelItsReadersGainHalfLnS) {
  const auto models = vel_rol_models();
  F16FilterBank plain(models, adapted(false)), scaled(models, adapted(true));
  const ModelBank mb = f16_model_bank(31u);
  const int kVel = mb.find("VEL"), kRol = mb.find("ROL");
  std::mt19937 g(5);
  std::normal_distribution<double> n01(0.0, 1.0);
  Eigen::Matrix<double, 7, 1> z;
  const Eigen::Matrix<double, 5, 1> u = Eigen::Matrix<double, 5, 1>::Zero();
  const long long before = f16mmae::testing::allocation_count();
  for (int i = 0; i < 200; ++i) {
    if (i == 100) plain.presume(kVel), scaled.presume(kVel);
    for (int j = 0; j < 7; ++j) z(j) = 0.05 * n01(g);   // residuals far above the design's: s > 1
    const double s = plain.turbulence_scale();
    ASSERT_EQ(s, scaled.turbulence_scale()) << "frame " << i;   // the term does not move s
    ASSERT_TRUE(plain.update(z));
    ASSERT_TRUE(scaled.update(z));
    for (int k = 0; k < 13; ++k) {
      const double gain = i >= 100 && k == kVel ? 0.5 * std::log(s) : 0.0;   // VEL's channel: VEL alone reads it as a level
      if (gain == 0.0)
        ASSERT_EQ(scaled.log_likelihoods()(k), plain.log_likelihoods()(k)) << "frame " << i << " hypothesis " << k;
      else
        ASSERT_NEAR(scaled.log_likelihoods()(k) - plain.log_likelihoods()(k), gain, 1e-12) << "frame " << i;
    }
    plain.propagate(u);
    scaled.propagate(u);
  }
  EXPECT_EQ(f16mmae::testing::allocation_count() - before, 0);
  EXPECT_GT(plain.turbulence_scale(), 2.0);   // the term was in play
  EXPECT_NE(scaled.probabilities()(0), plain.probabilities()(0));
  // presumed ROL, ROL's reader gains and VEL's does not
  scaled.presume(kRol), plain.presume(kRol);
  const double s = plain.turbulence_scale();
  ASSERT_TRUE(plain.update(z));
  ASSERT_TRUE(scaled.update(z));
  EXPECT_NEAR(scaled.log_likelihoods()(kRol) - plain.log_likelihoods()(kRol), 0.5 * std::log(s), 1e-12);
  EXPECT_EQ(scaled.log_likelihoods()(kVel), plain.log_likelihoods()(kVel));
}

TEST(LevelScale, ChannelsScaledAtEveryLevelGainHalfLnOfSOverS0) {
  const auto models = vel_rol_models();
  const ModelBank mb = f16_model_bank(31u);
  const int kVel = mb.find("VEL"), kRol = mb.find("ROL");
  for (const double s0 : {1.0, 1.5}) {
    FilterBankOptions o = adapted(false);
    o.adaptation.level_scale_channels = 1u << 0;   // VEL's channel
    o.adaptation.level_scale_from = s0;
    F16FilterBank plain(models, adapted(false)), scaled(models, o);
    std::mt19937 g(9);
    std::normal_distribution<double> n01(0.0, 1.0);
    Eigen::Matrix<double, 7, 1> z;
    const Eigen::Matrix<double, 5, 1> u = Eigen::Matrix<double, 5, 1>::Zero();
    const long long before = f16mmae::testing::allocation_count();
    bool below = false, above = false;   // frames with s below and above s_0 (s_0 = 1.5)
    for (int i = 0; i < 200; ++i) {
      if (i == 150) plain.presume(kRol), scaled.presume(kRol);   // level 1 too: the mask is every level's
      for (int j = 0; j < 7; ++j) z(j) = 0.05 * n01(g);
      const double s = plain.turbulence_scale();
      ASSERT_EQ(s, scaled.turbulence_scale()) << "frame " << i;
      below |= s < s0, above |= s > s0;
      ASSERT_TRUE(plain.update(z));
      ASSERT_TRUE(scaled.update(z));
      const double gain = s > s0 ? 0.5 * std::log(s / s0) : 0.0;   // computed apart from the bank's form
      for (int k = 0; k < 13; ++k) {
        if (k == kVel && gain > 0.0)
          ASSERT_NEAR(scaled.log_likelihoods()(k) - plain.log_likelihoods()(k), gain, 1e-12) << "frame " << i;
        else
          ASSERT_EQ(scaled.log_likelihoods()(k), plain.log_likelihoods()(k)) << "frame " << i << " hypothesis " << k;
      }
      plain.propagate(u);
      scaled.propagate(u);
    }
    EXPECT_EQ(f16mmae::testing::allocation_count() - before, 0);
    EXPECT_TRUE(above) << "s0 " << s0;
    if (s0 > 1.0) EXPECT_TRUE(below);   // the scale rises through s_0: frames without the gain too
  }
  FilterBankOptions o = adapted(false);
  o.adaptation.level_scale_from = 0.5;
  EXPECT_THROW(check_adaptation(o.adaptation, "test"), std::invalid_argument);
}

TEST(LevelScale, AChannelInBothTermsCountsOnceWhileItsFailureIsPresumed) {
  // the scheduled default's pair: level_scale on and VEL's channel at every level (s_0 = 1, so
  // the two terms are equal and a double count would show as twice the gain)
  const auto models = vel_rol_models();
  const ModelBank mb = f16_model_bank(31u);
  const int kVel = mb.find("VEL");
  FilterBankOptions both = adapted(true);
  both.adaptation.level_scale_channels = 1u << 0;
  F16FilterBank plain(models, adapted(false)), scaled(models, both);
  std::mt19937 g(5);
  std::normal_distribution<double> n01(0.0, 1.0);
  Eigen::Matrix<double, 7, 1> z;
  const Eigen::Matrix<double, 5, 1> u = Eigen::Matrix<double, 5, 1>::Zero();
  for (int i = 0; i < 200; ++i) {
    if (i == 100) plain.presume(kVel), scaled.presume(kVel);
    for (int j = 0; j < 7; ++j) z(j) = 0.05 * n01(g);
    const double s = plain.turbulence_scale();
    ASSERT_TRUE(plain.update(z));
    ASSERT_TRUE(scaled.update(z));
    ASSERT_NEAR(scaled.log_likelihoods()(kVel) - plain.log_likelihoods()(kVel), 0.5 * std::log(s), 1e-12)
        << "frame " << i;   // once, at level 0 (the mask) and at level 1 (the presumed failure's)
    plain.propagate(u);
    scaled.propagate(u);
  }
  EXPECT_GT(plain.turbulence_scale(), 2.0);
}
