// The duals' drift allowance at level 1 (level1_allowance.h, HierarchicalOptions::
// level1_allowance): the probability arithmetic worked by hand, the CUSUM recursion of the
// header checked frame by frame against the bank's own log-likelihoods, and a single-then-dual
// flight of a synthetic bank (the dual later with an allowance, never with one larger than its
// evidence's drift, bit for bit the bank without it at 0 and at level 0); the per-dual
// allowance (HierarchicalOptions::level1_allowance_pairs): by hand, the recursion with each
// dual's own k, a pair acting only in its first single's bank, and the refusals.
#include "f16mmae/hierarchical_bank.h"
#include "f16mmae/level1_allowance.h"

#include "synthetic_models.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

using namespace f16mmae;

namespace {

const std::vector<std::string> kAct{"U1", "U2"};
const std::vector<std::string> kSen{"Z1", "Z2", "Z3"};

struct Flight {
  std::vector<Eigen::VectorXd> z, u;   // absolute
};

// U1 fails at frame 64, Z3 at frame 320 (the synthetic single-then-dual flight).
Flight dual_flight(const test::Plant& plant, const ModelBank& bank, int frames) {
  test::Truth truth(plant, kAct, kSen, 2u);
  Flight f;
  for (int i = 0; i < frames; ++i) {
    std::vector<std::string> failed;
    if (i >= 64) failed.push_back("U1");
    if (i >= 320) failed.push_back("Z3");
    f.z.push_back(truth.measure(failed) + bank.z_trim);
    const Eigen::VectorXd u = test::dither(2, i, bank.frame_rate_hz);
    f.u.push_back(u + bank.u_trim);
    truth.advance(u, failed);
  }
  return f;
}

struct Small {
  test::Plant plant = test::random_plant(3, 2, 3, 21u);
  ModelBank bank = test::make_bank(plant, kAct, kSen, Eigen::Vector2d(0.1, -0.2), Eigen::Vector3d(10.0, 1.0, -3.0));
};

std::vector<std::pair<std::string, std::int64_t>> declared(const DynamicHierarchicalBank& hb) {
  std::vector<std::pair<std::string, std::int64_t>> out;
  for (const auto& d : hb.declarations()) out.emplace_back(hb.name(d.hypothesis), d.frame);
  return out;
}

}  // namespace

TEST(Level1Allowance, ScalesTheDualsByExpMinusKAndRenormalizes) {
  // p = [NONE 0.1, f 0.6, f+a 0.3, f+b 0]; k = ln 2: the dual's 0.3 -> 0.15, the sum 0.85
  Eigen::Vector4d p(0.1, 0.6, 0.3, 0.0);
  const std::array<char, 4> duals{{0, 0, 1, 1}};
  ASSERT_TRUE(Level1Allowance::apply(p, duals, std::log(2.0)));
  EXPECT_NEAR(p(0), 0.1 / 0.85, 1e-15);
  EXPECT_NEAR(p(1), 0.6 / 0.85, 1e-15);
  EXPECT_NEAR(p(2), 0.15 / 0.85, 1e-15);
  EXPECT_EQ(p(3), 0.0);
  EXPECT_NEAR(std::log(p(2) / p(1)), std::log(0.3 / 0.6) - std::log(2.0), 1e-14);   // the dual's log-odds: -k
  EXPECT_NEAR(std::log(p(0) / p(1)), std::log(0.1 / 0.6), 1e-14);                   // NONE's: unchanged

  // a hand-worked sequence: NONE, f, d start at [0.001, 0.998, 0.001]; each frame the dual's
  // likelihood ratio against f (and NONE's, 1) is e^lambda, then the allowance k = 0.5:
  // L_d = ln(p_d / p_f) goes -6.905753 -> -5.405753 -> -3.905753 -> -5.405753 -> -2.905753
  Eigen::Vector3d q(0.001, 0.998, 0.001);
  const std::array<char, 3> d3{{0, 0, 1}};
  const double lambda[4] = {2.0, 2.0, -1.0, 3.0};
  const double expected[4] = {-5.405753, -3.905753, -5.405753, -2.905753};
  for (int t = 0; t < 4; ++t) {
    q(2) *= std::exp(lambda[t]);
    q /= q.sum();
    ASSERT_TRUE(Level1Allowance::apply(q, d3, 0.5));
    EXPECT_NEAR(std::log(q(2) / q(1)), expected[t], 1e-6) << "frame " << t;
    EXPECT_NEAR(q.sum(), 1.0, 1e-15);
  }

  Eigen::Vector4d same(0.1, 0.6, 0.3, 0.0);
  EXPECT_FALSE(Level1Allowance::apply(same, duals, 0.0));   // 0: untouched
  EXPECT_EQ(same, Eigen::Vector4d(0.1, 0.6, 0.3, 0.0));
  const std::array<char, 4> none{{0, 0, 0, 0}};
  EXPECT_FALSE(Level1Allowance::apply(same, none, 1.0));     // no dual: untouched
  EXPECT_EQ(same, Eigen::Vector4d(0.1, 0.6, 0.3, 0.0));
}

TEST(Level1Allowance, EachDualsLogOddsMoveByItsLikelihoodRatioLessK) {
  // the header's recursion on the bank's own numbers: on every level-1 frame where neither f
  // nor the dual d sits on its floor, ln(p_d / p_f) moves by l_d - l_f - k exactly; a dual on
  // its floor is held there (p_d = its floor)
  Small s;
  HierarchicalOptions o;
  o.level1_allowance = 0.05;
  DynamicHierarchicalBank hb(s.bank, o);
  const Flight f = dual_flight(s.plant, s.bank, 640);
  int checked = 0, floored = 0;
  for (int i = 0; i < 640; ++i) {
    // the header's regime: f presumed and current (before the dual's declaration), carrying
    // most of the mass
    const bool level1 = hb.level() == 1 && hb.name(hb.current_hypothesis()) == "U1";
    const Eigen::VectorXd before = hb.probabilities();
    const int d = hb.update(f.z[i]);
    if (level1 && d < 0 && before(1) > 0.5 && hb.probabilities()(1) > 0.5) {
      const auto& p = hb.probabilities();
      const auto& l = hb.bank().log_likelihoods();
      const auto off_floor = [&](const Eigen::VectorXd& q, int k) { return q(k) > hb.bank().floor_of(k) * (1.0 + 1e-9); };
      for (int k = 2; k < hb.size(); ++k) {
        if (!off_floor(p, k)) {
          EXPECT_GE(p(k), hb.bank().floor_of(k) * (1.0 - 1e-12)) << "frame " << i << " slot " << k;
          ++floored;
          continue;
        }
        if (!off_floor(before, k)) continue;
        const double step = std::log(p(k) / p(1)) - std::log(before(k) / before(1));
        EXPECT_NEAR(step, l(k) - l(1) - 0.05, 1e-9) << "frame " << i << " slot " << k;
        ++checked;
      }
    }
    hb.propagate(f.u[i]);
  }
  EXPECT_GE(checked, 3);   // the frames of the dual's climb off its floor (Z3 failed at 320)
  EXPECT_GT(floored, 50);
}

TEST(Level1Allowance, DelaysTheDualAndLeavesLevelZeroAndZeroAsTheyWere) {
  Small s;
  const Flight f = dual_flight(s.plant, s.bank, 640);
  auto fly = [&](double k) {
    HierarchicalOptions o;
    o.level1_allowance = k;
    DynamicHierarchicalBank hb(s.bank, o);
    for (int i = 0; i < 640; ++i) hb.step(f.z[i], f.u[i]);
    return declared(hb);
  };
  const auto ref = fly(0.0);
  ASSERT_EQ(ref.size(), 2u);
  ASSERT_EQ(ref[0].first, "U1");
  ASSERT_EQ(ref[1].first, "U1+Z3");

  // k = 0: bit for bit the bank without the option; level 0 (up to the switch) untouched by any k
  HierarchicalOptions plain, o;
  o.level1_allowance = 0.0;
  HierarchicalOptions ok = plain;
  ok.level1_allowance = 1.0;
  DynamicHierarchicalBank a(s.bank, plain), b(s.bank, o), c(s.bank, ok);
  for (int i = 0; i < 640; ++i) {
    const bool level0 = c.level() == 0;
    a.step(f.z[i], f.u[i]);
    b.step(f.z[i], f.u[i]);
    c.step(f.z[i], f.u[i]);
    ASSERT_EQ(a.probabilities(), b.probabilities()) << "frame " << i;
    if (level0) ASSERT_EQ(a.probabilities(), c.probabilities()) << "frame " << i;
  }

  // an allowance below the dual's drift (Z3's failure here gives the dual several nats a frame)
  // delays the dual by whole frames, the single not at all
  const auto small = fly(1.0);
  ASSERT_EQ(small.size(), 2u);
  EXPECT_EQ(small[0], ref[0]);
  EXPECT_EQ(small[1].first, "U1+Z3");
  EXPECT_GT(small[1].second, ref[1].second);
  // an allowance above every frame's evidence (the log-likelihood ratio a frame is far below
  // 1e3 nats here): the dual never rises
  const auto huge = fly(1e3);
  ASSERT_EQ(huge.size(), 1u);
  EXPECT_EQ(huge[0], ref[0]);
}

TEST(Level1Allowance, RefusesANegativeOrNonFiniteAllowanceByName) {
  Small s;
  HierarchicalOptions o;
  for (double k : {-0.01, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    o.level1_allowance = k;
    try {
      DynamicHierarchicalBank hb(s.bank, o);
      ADD_FAILURE() << "accepted " << k;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("level1_allowance"), std::string::npos) << e.what();
    }
  }
}

TEST(Level1Allowance, EachDualTakesItsOwnKByHand) {
  // p = [NONE 0.1, f 0.6, f+a 0.2, f+b 0.1], k = [0, 0, ln 2, ln 4]: the duals -> 0.1 and 0.025,
  // the sum 0.825
  Eigen::Vector4d p(0.1, 0.6, 0.2, 0.1);
  const std::array<double, 4> ks{{0.0, 0.0, std::log(2.0), std::log(4.0)}};
  ASSERT_TRUE(Level1Allowance::apply_each(p, ks));
  EXPECT_NEAR(p(0), 0.1 / 0.825, 1e-15);
  EXPECT_NEAR(p(1), 0.6 / 0.825, 1e-15);
  EXPECT_NEAR(p(2), 0.1 / 0.825, 1e-15);
  EXPECT_NEAR(p(3), 0.025 / 0.825, 1e-15);
  // one k on every dual: apply(), bit for bit
  Eigen::Vector4d q1(0.1, 0.6, 0.2, 0.1), q2 = q1;
  const std::array<double, 4> same{{0.0, 0.0, 0.3, 0.3}};
  const std::array<char, 4> duals{{0, 0, 1, 1}};
  ASSERT_TRUE(Level1Allowance::apply_each(q1, same));
  ASSERT_TRUE(Level1Allowance::apply(q2, duals, 0.3));
  EXPECT_EQ(q1, q2);
  // no k > 0 on a slot with mass: untouched
  Eigen::Vector4d r(0.1, 0.6, 0.3, 0.0);
  const std::array<double, 4> empty{{0.0, 0.0, 0.0, 2.0}};
  EXPECT_FALSE(Level1Allowance::apply_each(r, empty));
  EXPECT_EQ(r, Eigen::Vector4d(0.1, 0.6, 0.3, 0.0));
}

TEST(Level1Allowance, APairsAllowanceActsOnItsDualInItsFirstsBankOnly) {
  Small s;
  const Flight f = dual_flight(s.plant, s.bank, 640);
  auto fly = [&](double k, std::map<std::string, double> pairs) {
    HierarchicalOptions o;
    o.level1_allowance = k;
    o.level1_allowance_pairs = std::move(pairs);
    DynamicHierarchicalBank hb(s.bank, o);
    std::vector<Eigen::VectorXd> p;
    for (int i = 0; i < 640; ++i) {
      hb.step(f.z[i], f.u[i]);
      p.push_back(hb.probabilities());
    }
    return std::make_pair(declared(hb), p);
  };
  const auto ref = fly(0.0, {});
  ASSERT_EQ(ref.first.size(), 2u);
  ASSERT_EQ(ref.first[1].first, "U1+Z3");
  // the bank on line is U1's: "Z3>U1" (Z3's bank) changes nothing, frame for frame
  EXPECT_EQ(fly(0.0, {{"Z3>U1", 1e3}}).second, ref.second);
  // every dual of U1's bank named with k: the scalar k, bit for bit
  std::map<std::string, double> all;
  for (const char* c : {"U2", "Z1", "Z2", "Z3"}) all[std::string("U1>") + c] = 1.0;
  EXPECT_EQ(fly(0.0, all).second, fly(1.0, {}).second);
  // U1+Z3 held out by its own k; U1+Z3 declared, as without, when only the others' k is large
  const auto held = fly(0.0, {{"U1>Z3", 1e3}});
  ASSERT_EQ(held.first.size(), 1u);
  EXPECT_EQ(held.first[0], ref.first[0]);
  const auto others = fly(1e3, {{"U1>Z3", 0.0}});
  ASSERT_EQ(others.first.size(), 2u);
  EXPECT_EQ(others.first[1].first, "U1+Z3");

  // the recursion per dual: ln(p_d / p_f) moves by l_d - l_f - k_d, k_d the pair's or the scalar
  HierarchicalOptions o;
  o.level1_allowance = 0.02;
  o.level1_allowance_pairs = {{"U1>Z3", 0.05}, {"U1>U2", 0.2}};
  DynamicHierarchicalBank hb(s.bank, o);
  int checked_own = 0, checked_other = 0;
  for (int i = 0; i < 640; ++i) {
    const bool level1 = hb.level() == 1 && hb.name(hb.current_hypothesis()) == "U1";
    const Eigen::VectorXd before = hb.probabilities();
    const int d = hb.update(f.z[i]);
    if (level1 && d < 0 && before(1) > 0.5 && hb.probabilities()(1) > 0.5) {
      const auto& p = hb.probabilities();
      const auto& l = hb.bank().log_likelihoods();
      for (int k = 2; k < hb.size(); ++k) {
        const double fl = hb.bank().floor_of(k) * (1.0 + 1e-9);
        if (!(p(k) > fl) || !(before(k) > fl)) continue;
        const std::string n = hb.name(hb.online()[k]);
        const double kd = n == "U1+Z3" || n == "Z3+U1" ? 0.05 : (n == "U1+U2" || n == "U2+U1" ? 0.2 : 0.02);
        EXPECT_NEAR(std::log(p(k) / p(1)) - std::log(before(k) / before(1)), l(k) - l(1) - kd, 1e-9)
            << "frame " << i << " " << n;
        (kd == 0.02 ? checked_other : checked_own) += 1;
      }
    }
    hb.propagate(f.u[i]);
  }
  EXPECT_GE(checked_own, 1);   // a pair's own k
  EXPECT_GE(checked_other, 1);   // the scalar k
}

TEST(Level1Allowance, RefusesAPairThatIsNotTwoSinglesOrANegativeKByName) {
  Small s;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::pair<std::string, double>> bad{
      {"U1", 0.1}, {"U1>U1", 0.1}, {"U1>Q9", 0.1}, {"U1+Z3>Z1", 0.1}, {"NONE>U1", 0.1}, {"U1>Z3", -0.1}, {"U1>Z3", nan}};
  for (const auto& [key, k] : bad) {
    HierarchicalOptions o;
    o.level1_allowance_pairs = {{key, k}};
    try {
      DynamicHierarchicalBank hb(s.bank, o);
      ADD_FAILURE() << "accepted " << key << " " << k;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("level1_allowance_pairs"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
}
