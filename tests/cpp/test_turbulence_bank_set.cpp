// TurbulenceBankSet (turbulence_bank_set.h) on F-16-sized synthetic banks: a "calm" member
// designed for the plant's process noise and a "rough" one designed for 30 times more, the
// truth's process noise stepping up and back. Checked: until the first switch the set is the
// start member stepped alone, bit for bit; the set moves up in the rough segment and back
// down in the calm one, once each (hysteresis), each after its standby ran hold_s beside the
// member in force; every handover is bumpless (the new member's probabilities, level and
// declarations are the old one's at that frame, its states its own, warmed up); a failure
// freezes the selector (no switch while it is rising or declared, even when the noise steps
// up with it); the selector's rho is the member in force's measured power ratio, averaged by
// hand; the floor by rho (the member in force's floor raised while its rho reads calm air, its
// own above, before settle and while frozen, restored by reset()); no heap allocation per
// frame, handovers included; the constructor's refusals.
#include "f16mmae/turbulence_bank_set.h"

#include "allocation_counter.h"
#include "synthetic_models.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

using namespace f16mmae;

namespace {

constexpr unsigned kPlantSeed = 11;
constexpr double kQ = 1e-3, kRough = 30.0;

ModelBank member(double q_scale) {
  test::Plant p = test::random_plant(13, 5, 7, kPlantSeed, kQ * q_scale, 1e-3);
  Eigen::VectorXd u_trim = Eigen::VectorXd::Constant(5, 0.02), z_trim(7);
  z_trim << 400.0, 0.1, 0.0, 1.0, 0.0, 0.0, 0.0;
  return test::make_bank(p, test::kF16Actuators, test::kF16Sensors, u_trim, z_trim);
}

HierarchicalOptions adapting() {
  HierarchicalOptions o;
  o.bank.p_min = 1e-9;
  o.bank.adaptation.enabled = true;
  o.bank.adaptation.reference = 1.0;
  return o;
}

TurbulenceBankSetOptions selector() {
  TurbulenceBankSetOptions s;
  s.bounds = {1.5,    // the calm member's rho between calm and rough
              0.3};   // the rough member's
  s.typical = {0.5, 0.5};
  s.hold_s = 0.5;
  s.warm_up_s = 0.5;
  s.warm_down_s = 0.5;
  s.settle_s = 2.0;
  s.start = 0;
  s.start_standby = -1;
  return s;
}

// The truth: the calm plant with process noise scaled by `noise(frame)`, `failed(frame)` failed.
template <class Noise, class Failed, class Frame>
void fly(int frames, Noise&& noise, Failed&& failed, Frame&& frame, unsigned seed = 5) {
  const test::Plant calm = test::random_plant(13, 5, 7, kPlantSeed, kQ, 1e-3);
  test::Truth truth(calm, test::kF16Actuators, test::kF16Sensors, seed);
  Eigen::Matrix<double, 5, 1> u_trim = Eigen::Matrix<double, 5, 1>::Constant(0.02);
  Eigen::Matrix<double, 7, 1> z_trim;
  z_trim << 400.0, 0.1, 0.0, 1.0, 0.0, 0.0, 0.0;
  for (int i = 0; i < frames; ++i) {
    truth.plant.q = kQ * noise(i) * Eigen::MatrixXd::Identity(13, 13);
    const std::vector<std::string> f = failed(i);
    const Eigen::Matrix<double, 7, 1> z = truth.measure(f) + z_trim;
    const Eigen::VectorXd du = 0.05 * test::dither(5, i, 64.0);
    const Eigen::Matrix<double, 5, 1> u = du + u_trim;
    frame(i, z, u);
    truth.advance(du, f);
  }
}

std::vector<std::string> none(int) { return {}; }

}  // namespace

TEST(TurbulenceBankSet, MovesUpAndBackDownBumplesslyAndIsTheStartMemberUntilThen) {
  const ModelBank calm_mb = member(1.0), rough_mb = member(kRough);
  F16HierarchicalBank calm(calm_mb, adapting()), rough(rough_mb, adapting());
  F16HierarchicalBank alone(calm_mb, adapting());   // the start member stepped by itself
  TurbulenceBankSet<F16HierarchicalBank> set({&calm, &rough}, selector());
  const auto noise = [](int i) { return i >= 1500 && i < 3000 ? kRough : 1.0; };
  std::vector<int> switch_frames;
  int last_active = set.active();
  bool same_until_switch = true;
  int standby_run = 0;
  fly(4500, noise, none, [&](int i, const auto& z, const auto& u) {
    // the state the next member takes over: the running member's after this frame's update
    if (set.switches() == 0) alone.update(z);
    const int running = set.active();
    set.update(z);
    if (set.active() != last_active) {
      switch_frames.push_back(i);
      const F16HierarchicalBank& from = running == 0 ? calm : rough;
      const F16HierarchicalBank& to = set.running();
      EXPECT_EQ(to.probabilities(), from.probabilities()) << "frame " << i;
      EXPECT_EQ(to.level(), from.level());
      EXPECT_EQ(to.frames(), from.frames());
      EXPECT_EQ(to.declarations().size(), from.declarations().size());
      EXPECT_EQ(standby_run, 32) << "the standby ran hold_s = 0.5 s beside the member in force";
      // warm: the new member's states are its own, not the old one's, and close to them
      EXPECT_NE(to.blended_state(), from.blended_state());
      EXPECT_LT((to.blended_state() - from.blended_state()).norm(), 0.5 * from.blended_state().norm() + 1e-3);
      last_active = set.active();
    }
    standby_run = set.standby() == (set.active() == 0 ? 1 : 0) ? standby_run + 1 : 0;
    set.propagate(u);
    if (set.switches() == 0) {
      alone.propagate(u);
      same_until_switch = same_until_switch && alone.probabilities() == set.running().probabilities() &&
                          alone.z_hat() == set.running().z_hat();
    }
  });
  EXPECT_TRUE(same_until_switch);
  ASSERT_EQ(switch_frames.size(), 2u) << "up once in the rough segment, down once after it";
  EXPECT_GT(switch_frames[0], 1500);
  EXPECT_LT(switch_frames[0], 1500 + 64 * 8);
  EXPECT_GT(switch_frames[1], 3000);
  EXPECT_EQ(set.active(), 0);
  EXPECT_EQ(set.running().level(), 0);
  EXPECT_TRUE(set.running().declarations().empty()) << "no false declaration across the handovers";
}

TEST(TurbulenceBankSet, ItsRhoIsTheMemberInForcesMinimumPowerRatioAveragedByHand) {
  // rho of the member in force, from its own quadratic forms: x = min_k q_k / 7 per update,
  // a plain mean over the first tau f = 320 updates, then the average over tau = 5 s
  const ModelBank calm_mb = member(1.0), rough_mb = member(kRough);
  F16HierarchicalBank calm(calm_mb, adapting()), rough(rough_mb, adapting());
  TurbulenceBankSet<F16HierarchicalBank> set({&calm, &rough}, selector());
  const double alpha = 1.0 - std::exp(-1.0 / (5.0 * 64.0));
  const auto noise = [](int i) { return i >= 1500 ? kRough : 1.0; };
  double rho = 0.0;
  int n = 0, checked = 0;
  fly(2500, noise, none, [&](int, const auto& z, const auto& u) {
    set.update(z);
    if (set.switches() == 0) {   // the start member, averaged from the first frame
      const auto& q = set.running().bank().quadratic_forms();
      const double a = 1.0 / ++n;
      rho += std::max(a, alpha) * (q.minCoeff() / 7.0 - rho);
      EXPECT_NEAR(set.power_ratio(), rho, 1e-12 * (1.0 + rho));
      EXPECT_EQ(set.power_ratio(), set.power_ratio(set.active()));
      ++checked;
    }
    set.propagate(u);
  });
  EXPECT_GT(checked, 1500);
  EXPECT_GE(set.switches(), 1);
  set.reset();
  EXPECT_EQ(set.power_ratio(0), 0.0);
  EXPECT_EQ(set.power_ratio(1), 0.0);
}

// The rule calmer_own_rho in calm air, the rough member in force and the calm one beside it
// from frame 0: the calm member's own rho (by hand: x = min_k q_k / 7 of its own filters, a
// plain mean at first) against its own bound decides, whatever the rough member's reads.
TEST(TurbulenceBankSet, CalmerOwnRhoHandsDownByTheCalmerMembersOwnRho) {
  const ModelBank calm_mb = member(1.0), rough_mb = member(kRough);
  const double alpha = 1.0 - std::exp(-1.0 / (5.0 * 64.0));
  struct Outcome {
    int switch_frame = -1, standby_at_end = -2;
    double rho_max = 0.0;   // the calm member's rho by hand from settle to the switch (or the end)
    bool rho_by_hand = true;
  };
  const auto flight = [&](bool rule, double calm_bound, double rough_bound) {
    F16HierarchicalBank calm(calm_mb, adapting()), rough(rough_mb, adapting());
    auto s = selector();
    s.start = 1;
    s.start_standby = 0;
    s.bounds = {calm_bound, rough_bound};
    s.calmer_own_rho = rule;
    TurbulenceBankSet<F16HierarchicalBank> set({&calm, &rough}, s);
    Outcome o;
    double rho = 0.0;
    int n = 0;
    fly(600, [](int) { return 1.0; }, none, [&](int i, const auto& z, const auto& u) {
      set.update(z);
      if (o.switch_frame < 0) {   // the calm member ran beside the rough one from frame 0
        const double a = 1.0 / ++n;
        rho += std::max(a, alpha) * (calm.bank().quadratic_forms().minCoeff() / 7.0 - rho);
        o.rho_by_hand = o.rho_by_hand && std::abs(set.power_ratio(0) - rho) <= 1e-12 * (1.0 + rho);
        if (i >= 127) o.rho_max = std::max(o.rho_max, rho);
        if (set.switches() == 1) o.switch_frame = i;
      }
      set.propagate(u);
    });
    EXPECT_EQ(set.frozen_frames(), 0);
    o.standby_at_end = set.standby();
    return o;
  };
  // settle_s = 2 s and hold_s = 0.5 s at 64 Hz: the first decision on frame 127 (the 128th
  // update), the 32nd held on frame 158, handed over there
  const Outcome wanted = flight(true, 1.5, 1e-6);
  EXPECT_TRUE(wanted.rho_by_hand);
  EXPECT_LT(wanted.rho_max, 1.5) << "the calm member reads calm air below its bound";
  EXPECT_EQ(wanted.switch_frame, 158);
  // the same bounds, the member in force's rho alone: it reads its own level, the standby is dropped
  const Outcome in_force = flight(false, 1.5, 1e-6);
  EXPECT_EQ(in_force.switch_frame, -1);
  EXPECT_EQ(in_force.standby_at_end, -1);
  // the calm member's own bound below its rho: not wanted by it; dropped, the rough member's rho
  // wanting its own level
  const Outcome refused = flight(true, 1e-3, 1e-6);
  EXPECT_EQ(refused.switch_frame, -1);
  EXPECT_EQ(refused.standby_at_end, -1);
  // the rough member's rho wanting the calm member, the calm one's own not: it runs on, never held
  const Outcome unheld = flight(true, 1e-3, 10.0);
  EXPECT_EQ(unheld.switch_frame, -1);
  EXPECT_EQ(unheld.standby_at_end, 0);
  EXPECT_EQ(flight(false, 1e-3, 10.0).switch_frame, 158) << "without the rule the rough member's rho hands down";
}

TEST(TurbulenceBankSet, FloorByRhoRaisesTheFloorOfTheMemberInForceWhileItsRhoReadsCalmAir) {
  const ModelBank calm_mb = member(1.0), rough_mb = member(kRough);
  // the calm member in force and wanted throughout (its bound far above its rho), its floor raised
  // to 1e-6 while its rho <= floor_rho; the noise 30 times the design's from frame 600 to 1800
  const auto noise = [](int i) { return i >= 600 && i < 1800 ? kRough : 1.0; };
  struct Outcome {
    int raised = 0, own = 0, wrong = 0, floor_not_min = 0, switches = 0, level = 0;
    double least = 0.0;   // the least probability on the last frame
    double rho_calm = 0.0, rho_rough = 0.0;   // the calm member's rho at frames 599 and 1799
  };
  const auto flight = [&](double floor_rho, const std::vector<std::string>& failed_from_400) {
    F16HierarchicalBank calm(calm_mb, adapting()), rough(rough_mb, adapting());
    auto s = selector();
    s.bounds = {1e5, 1e6};
    s.floor_rho = floor_rho;
    s.floor_p_min = {1e-6, 0.0};
    TurbulenceBankSet<F16HierarchicalBank> set({&calm, &rough}, s);
    Outcome o;
    double before = 1e-9;   // the floor in force before this frame's update
    const auto failed = [&](int i) { return i >= 400 ? failed_from_400 : std::vector<std::string>{}; };
    fly(2400, noise, failed, [&](int i, const auto& z, const auto& u) {
      set.update(z);
      const auto& p = set.running().probabilities();
      const bool frozen = set.running().level() != 0 || set.running().current_hypothesis() != 0 ||
                          (p.tail(p.size() - 1).array() > s.freeze_probability).any();
      const double p_min = set.running().options().bank.p_min;
      // the rule, from the set's rho (its own test: averaged by hand above): frozen, the own floor;
      // settle_s = 2 s at 64 Hz, the first decision on frame 127, the floor in force till then
      const double expected = frozen && floor_rho > 0.0 ? 1e-9
                              : i < 127                 ? before
                              : set.power_ratio(0) <= floor_rho ? 1e-6 : 1e-9;
      o.wrong += p_min != expected;
      (p_min == 1e-6 ? o.raised : o.own) += 1;
      // the floor is the one the probabilities sit on: at level 0 with nothing declared, the
      // least probable hypothesis at the floor in force (from the update after a change)
      if (!frozen && set.running().level() == 0 && p_min == before)
        o.floor_not_min += std::abs(set.running().probabilities().minCoeff() - p_min) > 1e-6 * p_min;
      if (i == 599) o.rho_calm = set.power_ratio(0);
      if (i == 1799) o.rho_rough = set.power_ratio(0);
      before = p_min;
      set.propagate(u);
    });
    o.switches = static_cast<int>(set.switches());
    o.level = set.running().level();
    o.least = set.running().probabilities().minCoeff();
    set.reset();
    EXPECT_EQ(calm.options().bank.p_min, 1e-9) << "reset() gives every member its own floor again";
    return o;
  };
  const Outcome on = flight(1.5, {});
  EXPECT_EQ(on.switches, 0);
  EXPECT_EQ(on.wrong, 0);
  EXPECT_EQ(on.floor_not_min, 0);
  EXPECT_LT(on.rho_calm, 1.5);
  EXPECT_GT(on.rho_rough, 1.5);
  EXPECT_GT(on.raised, 600 - 127 - 1) << "raised in calm air after settle";
  EXPECT_GT(on.own, 127 + 300) << "its own floor before settle and in the rough segment";
  const Outcome off = flight(0.0, {});   // floor_rho 0: off, the member's own floor throughout
  EXPECT_EQ(off.raised, 0);
  EXPECT_EQ(off.wrong, 0);
  // a failure at frame 400 freezes the selector: from its rise on, the member's own floor (raised
  // from frame 127 until then); declared, the level-1 bank's NONE, LS and duals on it
  const Outcome failed = flight(1.5, {"LS"});
  EXPECT_EQ(failed.wrong, 0);
  EXPECT_GE(failed.raised, 400 - 127);
  EXPECT_LT(failed.raised, 400 - 127 + 64);
  ASSERT_EQ(failed.level, 1);
  EXPECT_NEAR(failed.least, 1e-9, 1e-15);
}

TEST(TurbulenceBankSet, AFailureFreezesTheSelector) {
  const ModelBank calm_mb = member(1.0), rough_mb = member(kRough);
  F16HierarchicalBank calm(calm_mb, adapting()), rough(rough_mb, adapting());
  TurbulenceBankSet<F16HierarchicalBank> set({&calm, &rough}, selector());
  // the noise steps up on the frame the left flaperon fails: the failure's rise must not be
  // read as turbulence, and once declared the set holds the member that declared it
  const auto noise = [](int i) { return i >= 1000 ? kRough : 1.0; };
  const auto failed = [](int i) { return i >= 1000 ? std::vector<std::string>{"LS"} : std::vector<std::string>{}; };
  int switched_while_failing = 0;
  fly(3000, noise, failed, [&](int, const auto& z, const auto& u) {
    const bool failing = set.running().current_hypothesis() != 0 || set.running().level() != 0;
    const auto n = set.switches();
    set.update(z);
    switched_while_failing += failing && set.switches() != n;
    set.propagate(u);
  });
  ASSERT_FALSE(set.running().declarations().empty());
  EXPECT_EQ(set.running().name(set.running().declarations().front().hypothesis), "LS");
  EXPECT_EQ(switched_while_failing, 0);
  EXPECT_GT(set.frozen_frames(), 0);
}

TEST(TurbulenceBankSet, AllocatesNothingPerFrameHandoversIncluded) {
  const ModelBank calm_mb = member(1.0), rough_mb = member(kRough);
  F16HierarchicalBank calm(calm_mb, adapting()), rough(rough_mb, adapting());
  TurbulenceBankSet<F16HierarchicalBank> set({&calm, &rough}, selector());
  long long allocations = 0;
  const auto noise = [](int i) { return i >= 500 && i < 1500 ? kRough : 1.0; };
  fly(2500, noise, none, [&](int, const auto& z, const auto& u) {
    const long long before = f16mmae::testing::allocation_count();
    set.step(z, u);
    allocations += f16mmae::testing::allocation_count() - before;
  });
  EXPECT_GE(set.switches(), 2);
  EXPECT_EQ(allocations, 0);
}

TEST(TurbulenceBankSet, RefusesInvalidSetsNamingWhy) {
  const ModelBank calm_mb = member(1.0), rough_mb = member(kRough);
  F16HierarchicalBank calm(calm_mb, adapting()), rough(rough_mb, adapting());
  F16HierarchicalBank plain(calm_mb);   // adaptation off
  const auto refused = [](auto&& make, const std::string& says) {
    try {
      make();
      ADD_FAILURE() << "accepted; expected a refusal saying " << says;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  using Set = TurbulenceBankSet<F16HierarchicalBank>;
  refused([&] { Set({&calm}, selector()); }, "at least 2");
  refused([&] { Set({&calm, &plain}, selector()); }, "without the turbulence adaptation");
  auto s = selector();
  s.bounds = {1.5, -0.2};
  refused([&] { Set({&calm, &rough}, s); }, "bounds row 1 must be finite, positive and rising");
  s = selector();
  s.bounds = {1.5};
  refused([&] { Set({&calm, &rough}, s); }, "bounds must have n x (n-1) = 2 values");
  s = selector();
  s.typical = {0.5};
  refused([&] { Set({&calm, &rough}, s); }, "typical must have 2 values");
  s = selector();
  s.start = 2;
  refused([&] { Set({&calm, &rough}, s); }, "start must be a member index");
  s = selector();
  s.freeze_probability = 0.0;
  refused([&] { Set({&calm, &rough}, s); }, "freeze_probability");
  s = selector();
  s.floor_p_min = {1e-6};
  refused([&] { Set({&calm, &rough}, s); }, "floor_p_min must be empty or have 2 values (one per member), got 1");
  s = selector();
  s.floor_rho = std::nan("");
  refused([&] { Set({&calm, &rough}, s); }, "floor_rho must be in [0, 1e6]");
}
