// Off-line filters (FilterBank::set_live) and partial hypotheses in the hierarchical bank:
// the Bayes update and the floor over the live filters against hand computation, taking a
// filter off line as conditioning on "not k", no heap allocation in set_live and in the
// fixed-size frames around it, and a hierarchical bank whose level 0 holds a partial
// hypothesis per surface ("LS:loss=0.5", B column halved): its level-1 banks keep the spare
// slots off line (p = 0), a partial declaration brings on line {NONE, c:MODE, c, c+d...}, and a
// partial name without its single is a construction error; declaring on components (a
// partial and its single summed, declarer.h) against a declarer by hand; the executive's
// estimator runs the 18-filter bank (global operator new is counted in this executable).
#include "f16mmae/filter_bank.h"
#include "f16mmae/hierarchical_bank.h"
#include "executive/mmae_estimator.h"

#include "allocation_counter.h"
#include "synthetic_models.h"
#include "scalar_models.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>

using namespace f16mmae;

namespace {

using test::Scalar;
using test::ScalarBank;
using test::scalar_model;
using test::z1;

// The F-16-sized bank of f16_model_bank(seed) plus a partial hypothesis per surface: NONE's
// model with the surface's B_d column times `fraction`, its own gains.
ModelBank partial_bank(unsigned seed, double fraction) {
  ModelBank mb = test::f16_model_bank(seed);
  const test::Plant plant = test::random_plant(13, 5, 7, seed, 1e-3, 1e-3);
  for (std::size_t j = 0; j < test::kF16Actuators.size(); ++j) {
    HypothesisModel m = mb.hypotheses[0];
    m.name = test::kF16Actuators[j] + ":loss=" + (fraction == 0.5 ? std::string("0.5") : std::to_string(fraction));
    m.bd.col(static_cast<Eigen::Index>(j)) *= fraction;
    const test::Gains g = test::steady_state_gains(m.phi, m.h, plant.q, plant.r);
    m.k = g.k;
    m.a = g.a;
    mb.hypotheses.push_back(m);
  }
  return mb;
}

// The plant of partial_bank(seed) (f16_model_bank's) with LS keeping `kept` of its
// effectiveness from frame 64 on, in process and measurement noise (a fixed generator):
// measure() draws frame i's noise and gives its absolute z; advance(i, du) moves the state
// with that frame's input perturbation du.
struct LsLoss {
  LsLoss(unsigned seed, double kept) : plant(test::random_plant(13, 5, 7, seed, 1e-3, 1e-3)), lossy(plant) {
    lossy.bd.col(0) *= kept;
    lq = Eigen::LLT<Eigen::MatrixXd>(plant.q).matrixL();
    lr = Eigen::LLT<Eigen::MatrixXd>(plant.r).matrixL();
  }
  Eigen::VectorXd measure(const ModelBank& mb) {
    for (int j = 0; j < 13; ++j) w(j) = n01(g);
    Eigen::VectorXd v(7);
    for (int j = 0; j < 7; ++j) v(j) = n01(g);
    return plant.h * x + lr * v + mb.z_trim;
  }
  void advance(int i, const Eigen::VectorXd& du) { x = (i >= 64 ? lossy.bd : plant.bd) * du + plant.phi * x + lq * w; }

  test::Plant plant, lossy;
  Eigen::MatrixXd lq, lr;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(13), w = Eigen::VectorXd::Zero(13);
  std::mt19937 g{9};
  std::normal_distribution<double> n01{0.0, 1.0};
};

}  // namespace

TEST(FilterBankLive, OffLineFilterLeavesABayesUpdateOverTheLiveOnes) {
  const double a[4] = {1.0, 4.0, 0.25, 2.0};
  const double prior[4] = {0.4, 0.3, 0.2, 0.1};
  FilterBankOptions opt;
  opt.p_min = 0.0;
  ScalarBank bank({scalar_model(a[0]), scalar_model(a[1]), scalar_model(a[2]), scalar_model(a[3])}, opt);
  bank.set_probabilities(Eigen::Vector4d(prior[0], prior[1], prior[2], prior[3]));
  // off line: conditioning on "not 2", p_j / (1 - p_2)
  bank.set_live(2, false);
  EXPECT_FALSE(bank.live(2));
  EXPECT_EQ(bank.probabilities()(2), 0.0);
  for (int k : {0, 1, 3}) EXPECT_NEAR(bank.probabilities()(k), prior[k] / 0.8, 1e-15) << k;
  const double z = 1.3;
  ASSERT_TRUE(bank.update(z1(z)));
  double f[4] = {0, 0, 0, 0}, sum = 0.0;
  for (int k : {0, 1, 3}) {
    f[k] = std::exp(-0.5 * z * z / a[k]) * prior[k] / 0.8;
    sum += f[k];
  }
  for (int k : {0, 1, 3}) EXPECT_NEAR(bank.probabilities()(k), f[k] / sum, 1e-14) << k;
  EXPECT_EQ(bank.probabilities()(2), 0.0);
  EXPECT_EQ(bank.log_probabilities()(2), -std::numeric_limits<double>::infinity());
  // its filter still runs: its likelihood is the frame's
  EXPECT_NEAR(bank.log_likelihoods()(2), -0.5 * z * z / a[2], 1e-14);
  // back on line at the floor (0 here): the next update gives it nothing from nothing
  bank.set_live(2, true);
  EXPECT_TRUE(bank.live(2));
  EXPECT_EQ(bank.probabilities()(2), 0.0);
  // filter 0 cannot go off line
  bank.set_live(0, false);
  EXPECT_TRUE(bank.live(0));
}

TEST(FilterBankLive, FloorWaterFillsOverTheLiveFiltersOnly) {
  // live Bayes posterior b = [0.7, 0.25, 0.05] over filters {0, 1, 3}; p_min = 0.1: the floor
  // gives [0.7 s, 0.25 s, 0.1], s = 0.9 / 0.95, and the off-line filter 2 keeps p = 0.
  const double b[3] = {0.7, 0.25, 0.05};
  std::vector<Scalar> models;
  for (double bk : b) models.push_back(scalar_model(1.0 / (2.0 * (1.0 - std::log(bk)))));  // l_k = ln b_k - 1 at z = 1
  models.insert(models.begin() + 2, scalar_model(1.0));
  FilterBankOptions opt;
  opt.p_min = 0.1;
  ScalarBank bank(models, opt);
  bank.set_live(2, false);
  bank.presume(0);
  EXPECT_EQ(bank.probabilities()(2), 0.0);
  EXPECT_NEAR(bank.probabilities()(0), 1.0 - 0.2, 1e-15);
  bank.set_probabilities(Eigen::Vector4d(1.0 / 3, 1.0 / 3, 0.0, 1.0 / 3));
  ASSERT_TRUE(bank.update(z1(1.0)));
  const double s = 0.9 / 0.95;
  EXPECT_NEAR(bank.probabilities()(0), 0.7 * s, 1e-14);
  EXPECT_NEAR(bank.probabilities()(1), 0.25 * s, 1e-14);
  EXPECT_EQ(bank.probabilities()(2), 0.0);
  EXPECT_DOUBLE_EQ(bank.probabilities()(3), 0.1);
  EXPECT_NEAR(bank.probabilities().sum(), 1.0, 1e-15);
  // on line again: it takes its floor from the others by the floor's rescaling
  bank.set_live(2, true);
  EXPECT_DOUBLE_EQ(bank.probabilities()(2), 0.1);
  EXPECT_NEAR(bank.probabilities().sum(), 1.0, 1e-15);
}

TEST(FilterBankLive, AllLiveIsBitForBitTheBankWithout) {
  const ModelBank mb = test::f16_model_bank(21u);
  std::vector<F16FilterModel> models;
  for (int k = 0; k < 13; ++k) {
    const auto& h = mb.hypotheses[k];
    models.push_back(F16FilterModel::from_matrices(h.phi, h.bd, h.h, h.k, h.a));
  }
  F16FilterBank a(models), b(models);
  b.set_live(4, false);
  b.set_live(4, true);
  b.presume(0);
  std::mt19937 g(3);
  std::normal_distribution<double> n01(0.0, 0.05);
  for (int i = 0; i < 200; ++i) {
    Eigen::Matrix<double, 7, 1> z;
    for (int j = 0; j < 7; ++j) z(j) = n01(g);
    const Eigen::Matrix<double, 5, 1> u = test::dither(5, i, 64.0);
    a.step(z, u);
    b.step(z, u);
    for (int k = 0; k < 13; ++k) ASSERT_EQ(a.probabilities()(k), b.probabilities()(k)) << "frame " << i;
  }
}

TEST(FilterBankLive, SetLiveAndTheFramesAroundItAllocateNothing) {
  const ModelBank mb = test::f16_model_bank(22u);
  std::vector<F16FilterModel> models;
  for (int k = 0; k < 13; ++k) {
    const auto& h = mb.hypotheses[k];
    models.push_back(F16FilterModel::from_matrices(h.phi, h.bd, h.h, h.k, h.a));
  }
  F16FilterBank bank(models);
  Eigen::Matrix<double, 7, 1> z = Eigen::Matrix<double, 7, 1>::Constant(0.01);
  const long long before = f16mmae::testing::allocation_count();
  for (int i = 0; i < 64; ++i) {
    if (i == 10) bank.set_live(12, false);
    if (i == 40) bank.set_live(12, true);
    bank.step(z, test::dither(5, i, 64.0));
    if (i >= 10 && i < 40) EXPECT_EQ(bank.probabilities()(12), 0.0);
  }
  EXPECT_EQ(f16mmae::testing::allocation_count() - before, 0);
}

TEST(FilterBankFloor, AFloorFactorWaterFillsWithItsOwnFloor) {
  // uniform prior, Bayes posterior b = [0.9, 0.08, 0.02]; p_min = 0.01 and m_2 = 5: f = [0.01,
  // 0.01, 0.05], so filter 2 is floored at 0.05 and the others share 0.95: [0.9 s, 0.08 s, 0.05],
  // s = 0.95 / 0.98.
  const double b[3] = {0.9, 0.08, 0.02};
  std::vector<Scalar> models;
  for (double bk : b) models.push_back(scalar_model(1.0 / (2.0 * (1.0 - std::log(bk)))));  // l_k = ln b_k - 1 at z = 1
  FilterBankOptions opt;
  opt.p_min = 0.01;
  ScalarBank bank(models, opt);
  bank.set_floor_scale(2, 5.0);
  EXPECT_EQ(bank.floor_scale(2), 5.0);
  EXPECT_DOUBLE_EQ(bank.floor_of(2), 0.05);
  EXPECT_DOUBLE_EQ(bank.floor_of(1), 0.01);
  bank.presume(0);
  EXPECT_NEAR(bank.probabilities()(0), 1.0 - 0.06, 1e-15);
  EXPECT_DOUBLE_EQ(bank.probabilities()(2), 0.05);
  bank.set_probabilities(Eigen::Vector3d(1.0 / 3, 1.0 / 3, 1.0 / 3));
  ASSERT_TRUE(bank.update(z1(1.0)));
  const double s = 0.95 / 0.98;
  EXPECT_NEAR(bank.probabilities()(0), 0.9 * s, 1e-14);
  EXPECT_NEAR(bank.probabilities()(1), 0.08 * s, 1e-14);
  EXPECT_DOUBLE_EQ(bank.probabilities()(2), 0.05);
  EXPECT_NEAR(bank.log_probabilities()(2), std::log(0.05), 1e-14);
  // refused values change nothing; m back to 1 is the bank without factors, bit for bit
  bank.set_floor_scale(2, -1.0);
  bank.set_floor_scale(2, std::numeric_limits<double>::quiet_NaN());
  bank.set_floor_scale(7, 2.0);
  EXPECT_EQ(bank.floor_scale(2), 5.0);
  ScalarBank plain(models, opt);
  bank.set_floor_scale(2, 1.0);
  bank.presume(0);
  for (double z : {0.3, -1.2, 2.5, 0.1}) {
    ASSERT_TRUE(bank.update(z1(z)));
    ASSERT_TRUE(plain.update(z1(z)));
    for (int k = 0; k < 3; ++k) EXPECT_EQ(bank.probabilities()(k), plain.probabilities()(k)) << k;
  }
}

TEST(FilterBankFloor, TheClimbFromAFloorTakesTheFramesTheHeaderDerives) {
  // two hypotheses, z = 1 every frame: hypothesis 1 gains r = ln L_1 - ln L_0 = 0.5 (1 - 1 / a)
  // nats a frame. From the floor f it passes T = 0.9 on the first frame n with
  //   ln(f / (1 - f)) + n r > ln(T / (1 - T))   (level_floors.h, the partial floor).
  const double a1 = 2.0, r = 0.5 * (1.0 - 1.0 / a1), T = 0.9;
  const auto frames_to_threshold = [&](double p_min, double m) {
    FilterBankOptions opt;
    opt.p_min = p_min;
    ScalarBank bank({scalar_model(1.0), scalar_model(a1)}, opt);
    bank.set_floor_scale(1, m);
    bank.presume(0);
    for (int n = 1; n <= 1000; ++n) {
      bank.update(z1(1.0));
      if (bank.probabilities()(1) > T) return n;
    }
    return -1;
  };
  const auto by_hand = [&](double f) {
    return static_cast<int>(std::floor((std::log(T / (1 - T)) - std::log(f / (1 - f))) / r)) + 1;
  };
  EXPECT_EQ(frames_to_threshold(1e-9, 1.0), by_hand(1e-9));   // 92 frames
  EXPECT_EQ(frames_to_threshold(1e-9, 1e4), by_hand(1e-5));   // 55 frames
  EXPECT_EQ(frames_to_threshold(1e-9, 1e4), frames_to_threshold(1e-5, 1.0));
  // the floor raised by m saves ln(m) / r frames
  EXPECT_NEAR(by_hand(1e-9) - by_hand(1e-5), std::log(1e4) / r, 1.0);
}

TEST(PartialHypotheses, ThePartialFloorHoldsAtLevelZeroOnly) {
  const ModelBank mb = partial_bank(31u, 0.5);
  HierarchicalOptions opt;
  opt.bank.p_min = 1e-9;
  opt.partial_p_min = 1e-5;
  DynamicHierarchicalBank hb(mb, opt);
  // NONE presumed: 12 singles at 1e-9, 5 partials at 1e-5 (no sensor levels at level 0's NONE)
  const auto level0 = hb.online_names();
  for (int k = 1; k < hb.size(); ++k) {
    const bool partial = level0[k].find(':') != std::string::npos;
    EXPECT_DOUBLE_EQ(hb.probabilities()(k), partial ? 1e-5 : 1e-9) << level0[k];
  }
  EXPECT_NEAR(hb.probabilities()(0), 1.0 - 12e-9 - 5e-5, 1e-15);
  // a complete LF failure: at level 1 no factor is left
  const test::Plant plant = test::random_plant(13, 5, 7, 31u, 1e-3, 1e-3);
  test::Truth truth(plant, test::kF16Actuators, test::kF16Sensors, 5u);
  for (int i = 0; i < 640 && hb.level() == 0; ++i) {
    const std::vector<std::string> failed = i >= 64 ? std::vector<std::string>{"LF"} : std::vector<std::string>{};
    const Eigen::VectorXd du = test::dither(5, i, 64.0);
    hb.step(truth.measure(failed) + mb.z_trim, du + mb.u_trim);
    truth.advance(du, failed);
  }
  ASSERT_EQ(hb.level(), 1);
  for (int k = 0; k < hb.size(); ++k) EXPECT_EQ(hb.bank().floor_scale(k), 1.0) << hb.online_names()[k];
  // back at level 0 the partial floor again
  hb.reset();
  for (int k = 1; k < hb.size(); ++k)
    EXPECT_DOUBLE_EQ(hb.probabilities()(k), level0[k].find(':') != std::string::npos ? 1e-5 : 1e-9) << level0[k];
  // refused: a negative floor, floors leaving no room for the threshold (5 x 0.03 > 0.1), a bank
  // without partial hypotheses
  const auto refused = [](const ModelBank& bank, double p, const std::string& words) {
    HierarchicalOptions o;
    o.bank.p_min = 1e-9;
    o.partial_p_min = p;
    try {
      DynamicHierarchicalBank b(bank, o);
      ADD_FAILURE() << "accepted partial_p_min " << p;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  refused(mb, -1e-5, "partial_p_min must be >= 0");
  refused(mb, 0.03, "leaves no hypothesis room");
  refused(test::f16_model_bank(31u), 1e-5, "no partial-loss hypothesis");
}

TEST(PartialHypotheses, LevelZeroHoldsThemAndLevelOneKeepsTheSpareSlotsOffLine) {
  const ModelBank mb = partial_bank(31u, 0.5);
  DynamicHierarchicalBank hb(mb);
  ASSERT_EQ(hb.size(), 18);
  const auto level0 = hb.online_names();
  EXPECT_EQ(level0[13], "LS:loss=0.5");
  EXPECT_EQ(level0[17], "RUD:loss=0.5");
  // a complete LF failure: LF (or its partial) declared, then its level-1 bank
  const test::Plant plant = test::random_plant(13, 5, 7, 31u, 1e-3, 1e-3);
  test::Truth truth(plant, test::kF16Actuators, test::kF16Sensors, 5u);
  bool switched = false;
  for (int i = 0; i < 640 && !switched; ++i) {
    const std::vector<std::string> failed = i >= 64 ? std::vector<std::string>{"LF"} : std::vector<std::string>{};
    const Eigen::VectorXd z = truth.measure(failed) + mb.z_trim;
    const Eigen::VectorXd du = test::dither(5, i, 64.0);
    hb.step(z, du + mb.u_trim);
    truth.advance(du, failed);
    switched = hb.level() == 1;
  }
  ASSERT_TRUE(switched);
  const auto online = hb.online_names();
  const std::set<std::string> distinct(online.begin(), online.end());
  EXPECT_EQ(distinct.size(), online.size()) << "a hypothesis on line twice";
  const std::string f = online[1];
  const bool partial = f.find(':') != std::string::npos;
  EXPECT_TRUE(f == "LF" || f == "LF:loss=0.5") << f;
  const int live = partial ? 14 : 13;   // {NONE, f, (LF,) LF+d for the 11 others}
  for (int k = 0; k < hb.size(); ++k) {
    EXPECT_EQ(hb.bank().live(k), k < live) << k << " " << online[k];
    if (k >= live) {
      EXPECT_EQ(hb.probabilities()(k), 0.0) << online[k];
      EXPECT_NE(online[k].find(':'), std::string::npos) << "spare slots hold partial hypotheses";
    } else if (k >= 2 + (partial ? 1 : 0)) {
      EXPECT_EQ(online[k].rfind("LF+", 0) == 0 || online[k].find("+LF") != std::string::npos, true) << online[k];
    }
  }
  EXPECT_NEAR(hb.probabilities().sum(), 1.0, 1e-12);
  // back to level 0: every slot on line again
  hb.reset();
  for (int k = 0; k < hb.size(); ++k) EXPECT_TRUE(hb.bank().live(k));
  EXPECT_EQ(hb.online_names(), level0);
}

TEST(PartialHypotheses, APartialDeclarationBringsOnLineTheSurfacesFailureInAnyForm) {
  const ModelBank mb = partial_bank(32u, 0.5);
  DynamicHierarchicalBank hb(mb);
  LsLoss truth(32u, 0.5);   // LS at half its effectiveness from frame 64
  for (int i = 0; i < 1280 && hb.level() == 0; ++i) {
    const Eigen::VectorXd z = truth.measure(mb);
    const Eigen::VectorXd du = 4.0 * test::dither(5, i, 64.0);
    hb.step(z, du + mb.u_trim);
    truth.advance(i, du);
  }
  ASSERT_EQ(hb.level(), 1);
  const auto online = hb.online_names();
  ASSERT_EQ(online[1], "LS:loss=0.5") << "the partial hypothesis is the one declared";
  EXPECT_EQ(online[0], "NONE");
  EXPECT_EQ(online[2], "LS");
  for (int k = 3; k < 14; ++k) EXPECT_EQ(online[k].rfind("LS+", 0), 0u) << online[k];
  for (int k = 0; k < 18; ++k) EXPECT_EQ(hb.bank().live(k), k < 14) << k;
  for (int k = 14; k < 18; ++k) {
    EXPECT_NE(online[k].find(':'), std::string::npos) << online[k];
    EXPECT_EQ(hb.probabilities()(k), 0.0) << online[k];
  }
  const std::set<std::string> distinct(online.begin(), online.end());
  EXPECT_EQ(distinct.size(), online.size()) << "a hypothesis on line twice";
  EXPECT_EQ(hb.name(hb.declarations()[0].hypothesis), "LS:loss=0.5");
}

TEST(PartialHypotheses, APartialNameWithoutItsSingleIsAConstructionError) {
  ModelBank mb = partial_bank(33u, 0.5);
  mb.hypotheses.back().name = "XX:loss=0.5";
  try {
    DynamicHierarchicalBank hb(mb);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("XX:loss=0.5"), std::string::npos) << e.what();
  }
}

TEST(PartialHypotheses, FixedSizeBankEqualsTheDynamicOneAndAllocatesNothing) {
  const ModelBank mb = partial_bank(34u, 0.5);
  F16PartialHierarchicalBank fixed(mb);
  DynamicHierarchicalBank dynamic(mb);
  const test::Plant plant = test::random_plant(13, 5, 7, 34u, 1e-3, 1e-3);
  test::Truth truth(plant, test::kF16Actuators, test::kF16Sensors, 7u);
  std::vector<Eigen::Matrix<double, 7, 1>> zs;
  std::vector<Eigen::Matrix<double, 5, 1>> us;
  for (int i = 0; i < 640; ++i) {   // RF failed from frame 64, AY from frame 320: a level-0 and a level-1 switch
    std::vector<std::string> failed;
    if (i >= 64) failed.push_back("RF");
    if (i >= 320) failed.push_back("AY");
    zs.push_back(truth.measure(failed) + mb.z_trim);
    const Eigen::VectorXd du = test::dither(5, i, 64.0);
    us.push_back(du + mb.u_trim);
    truth.advance(du, failed);
  }
  double worst = 0.0;
  long long allocated = 0;
  for (std::size_t i = 0; i < zs.size(); ++i) {
    const long long before = f16mmae::testing::allocation_count();
    fixed.step(zs[i], us[i]);
    allocated += f16mmae::testing::allocation_count() - before;
    dynamic.step(Eigen::VectorXd(zs[i]), Eigen::VectorXd(us[i]));
    worst = std::max(worst, (fixed.probabilities() - dynamic.probabilities()).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_EQ(allocated, 0);
  ASSERT_EQ(fixed.declarations().size(), dynamic.declarations().size());
  EXPECT_GE(fixed.declarations().size(), 1u);
  for (std::size_t i = 0; i < fixed.declarations().size(); ++i)
    EXPECT_EQ(fixed.declarations()[i].hypothesis, dynamic.declarations()[i].hypothesis);
}

// Declaring on components (hierarchical_bank.h): the bank's first declaration is that of a
// declarer fed the level-0 probabilities with the components written out by hand (slot 13 + j,
// surface j's partial, with slot 1 + j, surface j; every other slot alone); the probabilities
// are a twin bank's that never declares. The truth: LS at a quarter of its effectiveness
// (three quarters lost) from frame 64, between the complete and the half-loss hypothesis.
// At the partial's level-1 bank {NONE, c:MODE, c, c+d...} c:MODE and c are one component: c is
// not declared after c:MODE.
TEST(PartialHypotheses, DeclaringOnComponentsSumsASurfacesForms) {
  const ModelBank mb = partial_bank(32u, 0.5);
  HierarchicalOptions opt;
  opt.declare_components = true;
  DynamicHierarchicalBank hb(mb, opt);
  HierarchicalOptions never;
  never.declarer.threshold = 0.999999;
  never.declarer.dwell_s = 60.0;
  DynamicHierarchicalBank twin(mb, never);
  LsLoss ls(32u, 0.25);   // LS at a quarter of its effectiveness from frame 64
  std::vector<int> group(18);
  for (int s = 0; s < 18; ++s) group[s] = s;
  for (int j = 0; j < 5; ++j) group[13 + j] = 1 + j;
  Declarer by_hand(hb.declarer().options(), 0);
  int expected = -1, expected_frame = -1;
  std::vector<Eigen::VectorXd> zs, us;
  for (int i = 0; i < 1280; ++i) {
    const Eigen::VectorXd z = ls.measure(mb);
    const Eigen::VectorXd du = 4.0 * test::dither(5, i, 64.0);
    hb.step(z, du + mb.u_trim);
    twin.step(z, du + mb.u_trim);
    zs.push_back(z);
    us.push_back(du + mb.u_trim);
    if (expected < 0) {
      expected = by_hand.update(twin.probabilities(), by_hand.dwell_frames(), group.data());
      if (expected >= 0) expected_frame = i;
    }
    ls.advance(i, du);
  }
  ASSERT_GE(expected, 1) << "nothing declared by hand";
  ASSERT_GE(hb.declarations().size(), 1u);
  EXPECT_EQ(hb.declarations()[0].hypothesis, mb.find(twin.online_names()[expected]));
  EXPECT_EQ(hb.declarations()[0].frame, expected_frame);
  const std::string first = hb.name(hb.declarations()[0].hypothesis);
  EXPECT_TRUE(first == "LS" || first == "LS:loss=0.5") << first;
  for (std::size_t k = 1; k < hb.declarations().size(); ++k)
    EXPECT_TRUE(hb.name(hb.declarations()[k].hypothesis) != "LS" &&
                hb.name(hb.declarations()[k].hypothesis) != "LS:loss=0.5") << "LS again, in another form";
  EXPECT_TRUE(twin.declarations().empty());
  // each hypothesis alone, the same flight declares no earlier (a form above the threshold
  // puts its component above it)
  DynamicHierarchicalBank alone(mb);
  for (std::size_t i = 0; i < zs.size() && alone.declarations().empty(); ++i) alone.step(zs[i], us[i]);
  if (!alone.declarations().empty()) EXPECT_GE(alone.declarations()[0].frame, expected_frame);
  // a bank without partial hypotheses is unchanged by the option, bit for bit
  const ModelBank plain = test::f16_model_bank(32u);
  DynamicHierarchicalBank a(plain), b(plain, opt);
  test::Truth truth(ls.plant, test::kF16Actuators, test::kF16Sensors, 5u);
  for (int i = 0; i < 400; ++i) {
    const std::vector<std::string> failed = i >= 64 ? std::vector<std::string>{"RS"} : std::vector<std::string>{};
    const Eigen::VectorXd z = truth.measure(failed) + plain.z_trim;
    const Eigen::VectorXd du = test::dither(5, i, 64.0);
    ASSERT_EQ(a.step(z, du + plain.u_trim), b.step(z, du + plain.u_trim)) << i;
    ASSERT_EQ(a.probabilities(), b.probabilities()) << i;
    truth.advance(du, failed);
  }
}

// The executive's estimator (cpp/executive/mmae_estimator.h) runs a bank with a partial
// hypothesis per surface as the fixed 18-filter bank: 18 on line, the same names and
// probabilities frame by frame as F16PartialHierarchicalBank on the same frames.
TEST(PartialHypotheses, TheExecutivesEstimatorRunsTheEighteenFilterBank) {
  const ModelBank mb = partial_bank(35u, 0.5);
  executive::MmaeEstimator est(mb);
  F16PartialHierarchicalBank direct(mb);
  EXPECT_EQ(est.on_line(), 18);
  EXPECT_EQ(est.states(), "13 states, 18 filters (partial-loss hypotheses)");
  const test::Plant plant = test::random_plant(13, 5, 7, 35u, 1e-3, 1e-3);
  test::Truth truth(plant, test::kF16Actuators, test::kF16Sensors, 3u);
  bool level1 = false;
  for (int i = 0; i < 640; ++i) {
    const std::vector<std::string> failed = i >= 64 ? std::vector<std::string>{"LF"} : std::vector<std::string>{};
    const Eigen::Matrix<double, 7, 1> z = truth.measure(failed) + mb.z_trim;
    const Eigen::VectorXd du = test::dither(5, i, 64.0);
    executive::MmaeEstimator::CommandVector c;
    c << du + mb.u_trim, std::numeric_limits<double>::quiet_NaN();
    est.update(z);
    direct.update(z);
    for (int k = 0; k < 18; ++k) {
      ASSERT_EQ(est.probability(k), direct.probabilities()(k)) << i << " " << k;
      ASSERT_EQ(est.hypothesis_name(k), direct.name(direct.online()[k])) << i << " " << k;
    }
    est.propagate(c);
    direct.propagate(Eigen::Matrix<double, 5, 1>(du + mb.u_trim));
    truth.advance(du, failed);
    level1 = level1 || est.level() == 1;
  }
  EXPECT_TRUE(level1) << "the level-1 bank was flown too";
  // a bank of 13 at level 0 is still the 13-filter bank
  EXPECT_EQ(executive::MmaeEstimator(test::f16_model_bank(35u)).on_line(), 13);
}
