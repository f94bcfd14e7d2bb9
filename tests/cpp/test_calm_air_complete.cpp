// The calm-air complete model (cpp/f16mmae/calm_air_complete.h): its bounds' text form, the
// decision and its hold, the complete density and footing it gives a tracked level
// (filter_bank.h, steady_state_filter.h), checked against the paper's complete model and a
// scalar bank computed by hand; a hierarchical bank's wiring.
#include "f16mmae/calm_air_complete.h"
#include "f16mmae/hierarchical_bank.h"

#include "allocation_counter.h"
#include "scalar_models.h"
#include "synthetic_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

using namespace f16mmae;
using namespace f16mmae::test;

namespace {

const std::vector<std::string> kSensors{"VEL", "AOA", "PIT"};

std::string refusal(const std::string& text) {
  try {
    parse_calm_complete(text);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(CalmAirComplete, ParsesItsBoundsAndRefusesNamingTheEntry) {
  const auto t = parse_calm_complete("VEL=0.55,AZ=1");
  EXPECT_EQ(t.size(), 2u);
  EXPECT_EQ(t.at("VEL"), 0.55);
  EXPECT_EQ(t.at("AZ"), 1.0);
  EXPECT_EQ(parse_calm_complete("VEL=0").at("VEL"), 0.0);
  EXPECT_EQ(refusal("VEL"), "calm_complete: expected NAME=RHO (a measurement and its calm-air bound), got 'VEL'");
  EXPECT_EQ(refusal("VEL=0.5,"), "calm_complete: expected NAME=RHO (a measurement and its calm-air bound), got ''");
  EXPECT_EQ(refusal("VEL=-1"), "calm_complete: VEL's bound must lie in [0, 100] (0: off), got -1");
  EXPECT_EQ(refusal("VEL=nan"), "calm_complete: VEL's bound must lie in [0, 100] (0: off), got nan");
  EXPECT_EQ(refusal("VEL=1,VEL=2"), "calm_complete: measurement 'VEL' given twice");
}

TEST(CalmAirComplete, CalmBelowTheBoundTimesTheReferenceHeldWhileAFailureRises) {
  CalmAirCompleteOptions o;
  o.rho = {{"VEL", 0.5}, {"PIT", 1.0}, {"AOA", 0.0}};   // AOA 0: off
  CalmAirComplete c(o, kSensors);
  EXPECT_TRUE(c.enabled());
  EXPECT_EQ(c.calm(), 0b101u);   // the start: every bounded channel calm (rho-bar reads 0)
  EXPECT_EQ(c.observe(0.6, true), 0b100u);   // VEL's 0.5 < 0.6 < PIT's 1.0
  EXPECT_EQ(c.observe(0.2, false), 0b100u);  // a failure presumed or rising: held
  EXPECT_EQ(c.observe(0.6, true, 2.0), 0b101u);   // relative to a reference of 2: bounds 1 and 2
  EXPECT_EQ(c.observe(1.5, true), 0u);
  EXPECT_EQ(c.observe(std::nan(""), true), 0u);   // no measure: held
  CalmAirComplete other(o, kSensors);
  other.carry_over(c);
  EXPECT_EQ(other.calm(), 0u);
  c.reset();
  EXPECT_EQ(c.calm(), 0b101u);
  EXPECT_FALSE(CalmAirComplete(CalmAirCompleteOptions{}, kSensors).enabled());
  o.rho = {{"AZ", 0.5}};
  try {
    CalmAirComplete(o, kSensors);
    ADD_FAILURE() << "accepted AZ";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "calm-air complete: 'AZ' is not a measurement of the bank; it has VEL, AOA, PIT");
  }
  o.rho = {{"VEL", 101.0}};
  EXPECT_THROW(CalmAirComplete(o, kSensors), std::invalid_argument);
  o.rho = {{"VEL", 0.5}};
  o.freeze_probability = 0.0;
  EXPECT_THROW(CalmAirComplete(o, kSensors), std::invalid_argument);
}

TEST(CalmAirComplete, ACompleteChannelIsThePapersGaussianWithoutTheFootingAndItsLevelGoesOn) {
  // NONE (A = 1) and a failed sensor whose reading is a tracked level in a range W = 40 (h = 0,
  // A = 0.5, q = 0.05). With the channel complete its l is the paper's stripped
  // -z² / (2 * 0.5): no footing (F is empty without it); the level tracks as without it, so
  // once the channel is free again its l is the plain bank's.
  Scalar failed = scalar_model(0.5, 0.0);
  failed.uninformative_width << 40.0;
  failed.uninformative_level_q << 0.05;
  ScalarBank plain({scalar_model(1.0), failed}), calm({scalar_model(1.0), failed});
  const double zs[] = {0.3, 0.25, 0.35, 0.2, 0.3, 0.28, -0.1, 0.4};
  for (int i = 0; i < 8; ++i) {
    const bool complete = i >= 2 && i < 6;
    calm.set_complete_channels(complete ? 1u : 0u);
    EXPECT_EQ(calm.complete_channels(), complete ? 1u : 0u);
    ASSERT_TRUE(plain.update(z1(zs[i])));
    ASSERT_TRUE(calm.update(z1(zs[i])));
    EXPECT_DOUBLE_EQ(calm.log_likelihoods()(0), -0.5 * zs[i] * zs[i]);
    if (complete)
      EXPECT_NEAR(calm.log_likelihoods()(1), -zs[i] * zs[i] / (2.0 * 0.5), 1e-15) << "frame " << i;
    else
      EXPECT_DOUBLE_EQ(calm.log_likelihoods()(1), plain.log_likelihoods()(1)) << "frame " << i;
    plain.propagate(Eigen::Matrix<double, 1, 1>::Zero());
    calm.propagate(Eigen::Matrix<double, 1, 1>::Zero());
  }
  // a memoryless level (q = 0: uniform every frame) keeps its density and footing
  Scalar memoryless = failed;
  memoryless.uninformative_level_q << 0.0;
  ScalarBank uniform({scalar_model(1.0), memoryless}), uniform_calm({scalar_model(1.0), memoryless});
  uniform_calm.set_complete_channels(1u);
  ASSERT_TRUE(uniform.update(z1(0.3)));
  ASSERT_TRUE(uniform_calm.update(z1(0.3)));
  EXPECT_EQ(uniform_calm.log_likelihoods()(1), uniform.log_likelihoods()(1));
  // presumed, the failed sensor's own channel is no complete channel of its hypothesis
  calm.presume(1);
  plain.presume(1);
  calm.set_complete_channels(1u);
  ASSERT_TRUE(plain.update(z1(0.3)));
  ASSERT_TRUE(calm.update(z1(0.3)));
  EXPECT_DOUBLE_EQ(calm.log_likelihoods()(1), plain.log_likelihoods()(1));
}

TEST(CalmAirComplete, AHierarchicalBankInCalmAirReadsATrackedLevelAsThePapersCompleteModel) {
  // The synthetic bank with Z1's failure as a tracked level, against the same bank with the
  // paper's complete Z1 (its model as designed): bounded far above the measured power ratio
  // (always calm) every frame's log-likelihoods are the complete bank's; bounded far below,
  // the plain tracked-level bank's, bit for bit.
  const std::vector<std::string> act{"U1", "U2"}, sen{"Z1", "Z2", "Z3"};
  const Plant plant = random_plant(3, 2, 3, 21u);
  const ModelBank complete = make_bank(plant, act, sen, Eigen::Vector2d(0.1, -0.2), Eigen::Vector3d(10.0, 1.0, -3.0));
  ModelBank level = complete;
  HypothesisModel& z1 = level.hypotheses[static_cast<std::size_t>(level.find("Z1"))];
  z1.uninformative_width = Eigen::Vector3d(50.0, 0.0, 0.0);
  z1.uninformative_level_q = Eigen::Vector3d(1e-4, 0.0, 0.0);
  HierarchicalOptions o;
  o.bank.adaptation.enabled = true;   // its measure only: s held at 1 (the two banks' minima differ)
  o.bank.adaptation.scale_max = 1.0;
  o.declarer.dwell_s = 30.0;   // no declaration: level 0 throughout
  HierarchicalOptions calm = o, rough = o;
  calm.calm_complete.rho = {{"Z1", 100.0}};
  rough.calm_complete.rho = {{"Z1", 1e-9}};
  using Bank = HierarchicalBank<Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic>;
  Bank paper(complete, o), plain(level, o), in_calm(level, calm), in_rough(level, rough);
  Truth truth(plant, act, sen, 4u);
  EXPECT_EQ(in_rough.bank().complete_channels(), 1u);   // calm until the air is measured
  for (int i = 0; i < 200; ++i) {
    const Eigen::VectorXd z = truth.measure({}) + complete.z_trim;
    const Eigen::VectorXd u = dither(2, i, complete.frame_rate_hz);
    for (Bank* b : {&paper, &plain, &in_calm, &in_rough}) b->step(z, u + complete.u_trim);
    truth.advance(u, {});
    EXPECT_EQ(in_calm.bank().complete_channels(), 1u);
    EXPECT_EQ(in_rough.bank().complete_channels(), 0u) << "frame " << i;
    for (int k = 0; k < paper.size(); ++k) {
      EXPECT_NEAR(in_calm.bank().log_likelihoods()(k), paper.bank().log_likelihoods()(k), 1e-12) << i << " " << k;
      if (i > 0)   // its first frame was read calm
        EXPECT_EQ(in_rough.bank().log_likelihoods()(k), plain.bank().log_likelihoods()(k)) << i << " " << k;
    }
  }
  HierarchicalOptions unadapted = calm;
  unadapted.bank.adaptation.enabled = false;
  EXPECT_THROW(Bank(level, unadapted), std::invalid_argument);   // it reads the adaptation's measure
  calm.calm_complete.rho = {{"AZ", 1.0}};
  EXPECT_THROW(Bank(level, calm), std::invalid_argument);   // not a measurement of this bank
}

TEST(CalmAirComplete, AnF16SizedBankChangesItsCompleteChannelsWithoutAllocating) {
  // the F-16-sized level-0 bank, VEL's failure a tracked level: switching VEL's complete model on
  // and off, and presuming VEL and back (the footings set anew), allocate nothing
  F16FilterBank bank(level_models<F16FilterBank::Model>(f16_model_bank(31u), 13, {{"VEL", 0, 50.0, 1e-4}}));
  Eigen::Matrix<double, 7, 1> z;
  const Eigen::Matrix<double, 5, 1> u = Eigen::Matrix<double, 5, 1>::Zero();
  std::mt19937 g(3);
  std::normal_distribution<double> n01(0.0, 1.0);
  const long long before = f16mmae::testing::allocation_count();
  for (int i = 0; i < 256; ++i) {
    for (int j = 0; j < 7; ++j) z(j) = 0.01 * n01(g);
    bank.set_complete_channels(i % 3 == 0 ? 1u : 0u);
    if (i % 64 == 32) bank.presume(6);   // VEL
    if (i % 64 == 48) bank.presume(0);
    ASSERT_TRUE(bank.update(z));
    bank.propagate(u);
  }
  EXPECT_EQ(f16mmae::testing::allocation_count() - before, 0);
}
