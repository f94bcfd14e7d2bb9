// The complete failures' held trim (cpp/f16mmae/complete_trim_hold.h): which channels are
// complete, the bank bit for bit as without it while no failure is suspected, the held (or
// averaged) reference and the exact q_k once one is (each filter's residual and likelihood
// against the reading minus the reference, computed here from its A⁻¹), and no allocation per
// frame.
#include "f16mmae/complete_trim_hold.h"
#include "f16mmae/hierarchical_bank.h"

#include "allocation_counter.h"
#include "synthetic_models.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

using namespace f16mmae;
using namespace f16mmae::test;

namespace {

const std::vector<std::string> kAct{"U1", "U2"}, kSen{"Z1", "Z2", "Z3"};

ModelBank synthetic_bank() {
  const Plant plant = random_plant(3, 2, 3, 21u);
  return make_bank(plant, kAct, kSen, Eigen::Vector2d(0.1, -0.2), Eigen::Vector3d(10.0, 1.0, -3.0));
}

using DynBank = HierarchicalBank<Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic>;

}  // namespace

TEST(CompleteTrimHold, ACompleteChannelIsAFailedSensorsZeroRowThatNoLevelReads) {
  ModelBank mb = synthetic_bank();
  EXPECT_EQ(CompleteTrimHold<Eigen::Dynamic>::channels_of(mb.hypotheses[mb.find("NONE")]), 0u);
  EXPECT_EQ(CompleteTrimHold<Eigen::Dynamic>::channels_of(mb.hypotheses[mb.find("U1")]), 0u);
  EXPECT_EQ(CompleteTrimHold<Eigen::Dynamic>::channels_of(mb.hypotheses[mb.find("Z2")]), 0b010u);
  EXPECT_EQ(CompleteTrimHold<Eigen::Dynamic>::channels_of(mb.hypotheses[mb.find("U1+Z3")]), 0b100u);
  EXPECT_EQ(CompleteTrimHold<Eigen::Dynamic>::channels_of(mb.hypotheses[mb.find("Z1+Z3")]), 0b101u);
  HypothesisModel level = mb.hypotheses[mb.find("Z1+Z3")];   // Z1 read as a level: not complete
  level.uninformative_width = Eigen::Vector3d(5.0, 0.0, 0.0);
  EXPECT_EQ(CompleteTrimHold<Eigen::Dynamic>::channels_of(level), 0b100u);
  HypothesisModel coupled = mb.hypotheses[mb.find("Z2")];   // A couples channel 1: not complete
  coupled.a(1, 0) = coupled.a(0, 1) = 1e-6;
  EXPECT_EQ(CompleteTrimHold<Eigen::Dynamic>::channels_of(coupled), 0u);
}

TEST(CompleteTrimHold, ItsWordsAreParsedAndNamed) {
  for (const char* w : {"off", "suspected", "declared"}) EXPECT_STREQ(trim_hold_name(parse_trim_hold(w)), w);
  EXPECT_THROW(parse_trim_hold("on"), std::invalid_argument);
  EXPECT_FALSE(CompleteTrimHoldOptions{}.enabled());
}

TEST(CompleteTrimHold, FollowsTheTrimUntilAFailureIsSuspectedThenHoldsIt) {
  CompleteTrimHold<3> hold(CompleteTrimHoldOptions{TrimHold::kSuspected}, 3);
  EXPECT_TRUE(hold.observe(Eigen::Vector3d(1.0, 2.0, 3.0), true).isZero(0.0));   // the first frame sets it
  EXPECT_TRUE(hold.observe(Eigen::Vector3d(1.5, 2.0, 3.0), false).isZero(0.0));
  EXPECT_EQ(hold.reference(), Eigen::Vector3d(1.5, 2.0, 3.0));
  EXPECT_EQ(hold.observe(Eigen::Vector3d(1.75, 1.0, 3.0), true), Eigen::Vector3d(0.25, -1.0, 0.0));
  EXPECT_EQ(hold.reference(), Eigen::Vector3d(1.5, 2.0, 3.0));
  EXPECT_TRUE(hold.holding());
  EXPECT_TRUE(hold.observe(Eigen::Vector3d(2.0, 2.0, 2.0), false).isZero(0.0));   // followed again
  EXPECT_EQ(hold.reference(), Eigen::Vector3d(2.0, 2.0, 2.0));
  hold.reset();
  EXPECT_FALSE(hold.holding());
}

TEST(CompleteTrimHold, AveragesTheTrimOverItsTimeConstantAndHoldsTheAverage) {
  CompleteTrimHoldOptions o{TrimHold::kDeclared, 1.0};   // T = 1 s at 4 frames a second
  EXPECT_TRUE(o.enabled());
  EXPECT_TRUE((CompleteTrimHoldOptions{TrimHold::kOff, 1.0}.enabled()));
  CompleteTrimHold<2> hold(o, 2, 4.0);
  const double a = 1.0 - std::exp(-0.25);
  EXPECT_TRUE(hold.observe(Eigen::Vector2d(1.0, 2.0), false).isZero(0.0));   // the first frame sets it
  Eigen::Vector2d ref(1.0, 2.0), sum(1.0, 2.0);
  for (int i = 1; i <= 8; ++i) {
    const Eigen::Vector2d trim(1.0 + 0.1 * i, 2.0);
    sum += trim;
    if (i < 4) ref = sum / (i + 1);   // a plain mean over the first T f = 4 updates
    else ref += a * (trim - ref);      // then the exponential average
    EXPECT_TRUE(hold.observe(trim, false).isApprox(trim - ref, 1e-12)) << i;
  }
  EXPECT_TRUE(hold.reference().isApprox(ref, 1e-12));
  EXPECT_TRUE(hold.observe(Eigen::Vector2d(5.0, 1.0), true).isApprox(Eigen::Vector2d(5.0, 1.0) - ref, 1e-12));
  EXPECT_TRUE(hold.reference().isApprox(ref, 1e-12));   // held: the average stops
  hold.reset();
  EXPECT_TRUE(hold.observe(Eigen::Vector2d(3.0, 3.0), false).isZero(0.0));
  for (const double bad : {-1.0, 3600.5, std::nan("")})
    EXPECT_THROW(CompleteTrimHold<2>(CompleteTrimHoldOptions{TrimHold::kOff, bad}, 2), std::invalid_argument) << bad;
  EXPECT_THROW(CompleteTrimHold<2>(o, 2, 0.0), std::invalid_argument);
}

TEST(CompleteTrimHold, IsBitForBitTheBankWithoutItWhileNoFailureIsSuspected) {
  const ModelBank mb = synthetic_bank();
  HierarchicalOptions off;
  off.declarer.dwell_s = 30.0;              // no declaration: level 0 throughout
  off.trim.freeze_probability = 1.0;        // and never a rising failure (p > 1)
  HierarchicalOptions on = off;
  on.complete_trim_hold.hold = TrimHold::kSuspected;
  DynBank a(mb, off), b(mb, on);
  Truth truth(random_plant(3, 2, 3, 21u), kAct, kSen, 5u);
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d dz(0.0, 0.002 * i, -0.001 * i);   // a trim in force that moves
    a.set_trim_offset(Eigen::Vector2d::Zero(), dz);
    b.set_trim_offset(Eigen::Vector2d::Zero(), dz);
    const Eigen::VectorXd z = truth.measure({}) + mb.z_trim;
    const Eigen::VectorXd u = dither(2, i, mb.frame_rate_hz);
    a.step(z, u + mb.u_trim);
    b.step(z, u + mb.u_trim);
    truth.advance(u, {});
    ASSERT_FALSE(b.failure_suspected());
    EXPECT_TRUE(b.complete_trim_offset().isZero(0.0)) << i;
    EXPECT_EQ(a.bank().log_likelihoods(), b.bank().log_likelihoods()) << i;
    EXPECT_EQ(a.bank().probabilities(), b.bank().probabilities()) << i;
    for (int k = 0; k < a.size(); ++k) EXPECT_EQ(a.bank().residual(k), b.bank().residual(k)) << i << " " << k;
  }
}

namespace {

// Z2 fails (reads its trim plus noise) at frame 100 and is declared; the trim in force then
// drifts on Z2 and Z3. Every frame, with the hold: the offset is the trim in force less the
// reference, which follows the trim in force (time constant T = 0) or its average over T, and
// stops while a failure is suspected (`declared`: declared; `off`: never); every on-line
// filter's complete channel j reads z_j - z_ref_j, and its l_k is -q_k / 2 of its residual as
// computed here from its A⁻¹.
void fly_a_failed_sensor_on_a_drifting_trim(TrimHold rule, double time_constant_s = 0.0) {
  const ModelBank mb = synthetic_bank();
  HierarchicalOptions o;
  o.complete_trim_hold = {rule, time_constant_s};
  const double gain = time_constant_s > 0.0 ? 1.0 - std::exp(-1.0 / (time_constant_s * mb.frame_rate_hz)) : 1.0;
  int averaged = 0;   // updates averaged (the plain mean's count first)
  DynBank bank(mb, o);
  Truth truth(random_plant(3, 2, 3, 21u), kAct, kSen, 7u);
  Eigen::Vector3d ref = mb.z_trim, dz = Eigen::Vector3d::Zero();
  int held_frames = 0, level1_frames = 0;
  for (int i = 0; i < 600; ++i) {
    const std::vector<std::string> failed = i >= 100 ? std::vector<std::string>{"Z2"} : std::vector<std::string>{};
    if (i >= 100) dz += Eigen::Vector3d(0.0, 0.004, -0.002);
    bank.set_trim_offset(Eigen::Vector2d::Zero(), dz);
    const bool held = rule == TrimHold::kDeclared ? bank.level() != 0
                      : rule == TrimHold::kSuspected ? bank.failure_suspected()
                                                     : false;
    if (!held) ref += std::max(1.0 / ++averaged, gain) * (mb.z_trim + dz - ref);   // this update's reference
    const Eigen::VectorXd z = truth.measure(failed) + mb.z_trim;
    const Eigen::VectorXd u = dither(2, i, mb.frame_rate_hz);
    const int switched = bank.update(z);
    const Eigen::Vector3d offset = mb.z_trim + dz - ref;
    EXPECT_TRUE(bank.complete_trim_offset().isApprox(offset, 1e-12) || offset.isZero(0.0)) << i;
    for (int k = 0; k < bank.size() && switched < 0; ++k) {   // (a switch's new filters start at r = 0)
      const std::uint32_t bits = CompleteTrimHold<Eigen::Dynamic>::channels_of(mb.hypotheses[bank.online()[k]]);
      const Eigen::VectorXd r = bank.bank().residual(k);
      for (int j = 0; j < 3; ++j)
        if ((bits >> j) & 1u) EXPECT_NEAR(r(j), z(j) - ref(j), 1e-12) << i << " " << k << " " << j;
      const Eigen::MatrixXd& a_inv = bank.bank().hypothesis(k).a_inverse();
      EXPECT_NEAR(bank.bank().log_likelihoods()(k), -0.5 * r.dot(a_inv * r), 1e-9) << i << " " << k;
    }
    held_frames += !offset.isZero(0.0);
    level1_frames += bank.level() == 1;
    bank.propagate(u + mb.u_trim);
    truth.advance(u, failed);
  }
  ASSERT_FALSE(bank.declarations().empty());
  EXPECT_EQ(mb.hypotheses[bank.declarations().front().hypothesis].name, "Z2");
  EXPECT_GT(level1_frames, 300);
  if (rule != TrimHold::kOff) EXPECT_GT(held_frames, 300);
  if (time_constant_s > 0.0) EXPECT_GT(held_frames, 490);   // from the drift's first frame on
  bank.reset();
  EXPECT_TRUE(bank.complete_trim_offset().isZero(0.0));
}

}  // namespace

TEST(CompleteTrimHold, AFailedSensorIsReadAgainstTheTrimHeldWhenItsFailureBeganToShow) {
  fly_a_failed_sensor_on_a_drifting_trim(TrimHold::kSuspected);
}

TEST(CompleteTrimHold, FromTheDeclarationTheTrimIsHeldOnlyOnceAFailureIsDeclared) {
  fly_a_failed_sensor_on_a_drifting_trim(TrimHold::kDeclared);
}

TEST(CompleteTrimHold, AFailedSensorIsReadAgainstTheTrimsAverageHeldOnceDeclared) {
  fly_a_failed_sensor_on_a_drifting_trim(TrimHold::kDeclared, 2.0);
}

TEST(CompleteTrimHold, AFailedSensorIsReadAgainstTheTrimsAverageWithoutAHold) {
  fly_a_failed_sensor_on_a_drifting_trim(TrimHold::kOff, 2.0);
}

TEST(CompleteTrimHold, StepsWithoutAllocating) {
  const ModelBank mb = f16_model_bank(3u);
  HierarchicalOptions o;
  o.complete_trim_hold = {TrimHold::kDeclared, 30.0};
  F16HierarchicalBank bank(mb, o);
  Truth truth(random_plant(13, 5, 7, 3u, 1e-3, 1e-3), kF16Actuators, kF16Sensors, 9u);
  Eigen::Matrix<double, 7, 1> dz = Eigen::Matrix<double, 7, 1>::Zero();
  long long allocations = 0;
  for (int i = 0; i < 800; ++i) {
    const std::vector<std::string> failed = i >= 100 ? std::vector<std::string>{"AOA"} : std::vector<std::string>{};
    dz(1) += 1e-5;
    const Eigen::Matrix<double, 7, 1> z = truth.measure(failed) + mb.z_trim;
    const Eigen::VectorXd du = dither(5, i, 64.0);
    const Eigen::Matrix<double, 5, 1> u = du + mb.u_trim;
    const long long before = f16mmae::testing::allocation_count();
    bank.set_trim_offset(Eigen::Matrix<double, 5, 1>::Zero(), dz);
    bank.step(z, u);
    if (i >= 10) allocations += f16mmae::testing::allocation_count() - before;
    truth.advance(du, failed);
  }
  EXPECT_EQ(allocations, 0);
  EXPECT_FALSE(bank.complete_trim_offset().isZero(0.0));   // a failure suspected: the trim held
}
