// FilterBank: hand-computed Bayes updates (eqs. 1-2), the p_min floor's exact semantics,
// huge residuals, rejected frames, fixed vs dynamic sizes, and no heap allocation in the
// fixed-size per-frame step (global operator new is counted in this executable).
#include "f16mmae/filter_bank.h"

#include "allocation_counter.h"
#include "synthetic_models.h"
#include "scalar_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <cstdio>
#include <random>

using namespace f16mmae;

namespace {

using test::Scalar;
using test::ScalarBank;
using test::scalar_model;
using test::z1;

// Independent form of the floor: p_k = max(p_min, s b_k) for one s, b = Bayes posterior.
void expect_water_filled(const Eigen::VectorXd& p, const Eigen::VectorXd& bayes, double p_min) {
  EXPECT_NEAR(p.sum(), 1.0, 1e-12);
  Eigen::Index top;
  bayes.maxCoeff(&top);
  const double s = p(top) / bayes(top);
  for (Eigen::Index k = 0; k < p.size(); ++k) {
    EXPECT_GE(p(k), p_min);
    EXPECT_NEAR(p(k), std::max(p_min, s * bayes(k)), 1e-12) << "hypothesis " << k;
  }
}

std::vector<F16FilterModel> f16_models(unsigned seed) {
  const test::Plant plant = test::random_plant(13, 5, 7, seed, 1e-2, 1e-2);
  const std::vector<std::string> act{"LS", "RS", "LF", "RF", "RUD"};
  const std::vector<std::string> sen{"VEL", "AOA", "PIT", "AZ", "ROL", "YAW", "AY"};
  std::vector<std::string> comps = act;
  comps.insert(comps.end(), sen.begin(), sen.end());
  std::vector<F16FilterModel> out;
  for (int k = 0; k < 13; ++k) {
    const std::vector<std::string> failed =
        k == 0 ? std::vector<std::string>{} : std::vector<std::string>{comps[k - 1]};
    Eigen::MatrixXd bd, h;
    test::hypothesis_matrices(plant, act, sen, failed, bd, h);
    const test::Gains g = test::steady_state_gains(plant.phi, h, plant.q, plant.r);
    out.push_back(F16FilterModel::from_matrices(plant.phi, bd, h, g.k, g.a));
  }
  return out;
}

}  // namespace

TEST(FilterBank, StartsWithNoFailurePresumed) {
  ScalarBank bank({scalar_model(1.0), scalar_model(2.0), scalar_model(3.0)});
  EXPECT_NEAR(bank.probabilities()(0), 1.0 - 2 * 0.001, 1e-15);
  EXPECT_DOUBLE_EQ(bank.probabilities()(1), 0.001);
  EXPECT_DOUBLE_EQ(bank.probabilities()(2), 0.001);
}

TEST(FilterBank, HandComputedBayesUpdateLeadingTermStrippedAndKept) {
  const double a[3] = {1.0, 4.0, 0.25};
  const double prior[3] = {0.5, 0.3, 0.2};
  for (bool strip : {true, false}) {
    FilterBankOptions opt;
    opt.p_min = 0.0;
    opt.strip_leading_term = strip;
    ScalarBank bank({scalar_model(a[0]), scalar_model(a[1]), scalar_model(a[2])}, opt);
    Eigen::Vector3d p0(prior[0], prior[1], prior[2]);
    bank.set_probabilities(p0);
    const double z = 1.3;
    ASSERT_TRUE(bank.update(z1(z)));
    double f[3], sum = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double lead = strip ? 1.0 : 1.0 / (std::sqrt(2.0 * M_PI) * std::sqrt(a[k]));
      f[k] = lead * std::exp(-0.5 * z * z / a[k]) * prior[k];
      sum += f[k];
    }
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(bank.probabilities()(k), f[k] / sum, 1e-14) << "strip=" << strip << " k=" << k;
      const double l = -0.5 * z * z / a[k] + (strip ? 0.0 : -0.5 * std::log(2.0 * M_PI) - 0.5 * std::log(a[k]));
      EXPECT_NEAR(bank.log_likelihoods()(k), l, 1e-14);
    }
    EXPECT_DOUBLE_EQ(bank.residuals()(1, 0), z);
  }
}

TEST(FilterBank, FloorWaterFillsIteratively) {
  // Bayes posterior b = [0.6, 0.25, 0.102, 0.048] with p_min = 0.1: flooring 0.048 rescales
  // 0.102 below the floor too; the exact answer is [0.6 s, 0.25 s, 0.1, 0.1], s = 0.8 / 0.85.
  const double b[4] = {0.6, 0.25, 0.102, 0.048};
  std::vector<Scalar> models;
  for (double bk : b) models.push_back(scalar_model(1.0 / (2.0 * (1.0 - std::log(bk)))));  // l_k = ln b_k - 1 at z = 1
  FilterBankOptions opt;
  opt.p_min = 0.1;
  ScalarBank bank(models, opt);
  bank.set_probabilities(Eigen::Vector4d::Constant(0.25));
  ASSERT_TRUE(bank.update(z1(1.0)));
  const double s = 0.8 / 0.85;
  EXPECT_NEAR(bank.probabilities()(0), 0.6 * s, 1e-14);
  EXPECT_NEAR(bank.probabilities()(1), 0.25 * s, 1e-14);
  EXPECT_DOUBLE_EQ(bank.probabilities()(2), 0.1);
  EXPECT_DOUBLE_EQ(bank.probabilities()(3), 0.1);
  EXPECT_NEAR(bank.probabilities().sum(), 1.0, 1e-15);
}

TEST(FilterBank, FloorOfAFailedSensorHypothesisCarriesItsLevelsOccamFactor) {
  // NONE (A = 1), a failed sensor whose reading is an unknown level in a range W = 40
  // (h = 0, R = A = 0.5, the level tracked: q = 0.05), and another Gaussian hypothesis
  // (A = 2). The failed sensor's floor is p_min sqrt(2 pi 0.5) / 40 while NONE is presumed,
  // p_min once it is presumed itself; with no level memory (q = 0) it is p_min.
  const double p_min = 1e-3, w = 40.0, a_f = 0.5;
  Scalar failed = scalar_model(a_f, 0.0);
  failed.uninformative_width << w;
  failed.uninformative_level_q << 0.05;
  Scalar memoryless = failed;
  memoryless.uninformative_level_q << 0.0;
  EXPECT_DOUBLE_EQ(ScalarBank({scalar_model(1.0), memoryless}).floors()(1), p_min);
  ScalarBank bank({scalar_model(1.0), failed, scalar_model(2.0)});
  const double f1 = p_min * std::sqrt(2.0 * M_PI * a_f) / w;
  EXPECT_NEAR(bank.probabilities()(1), f1, 1e-18);
  EXPECT_NEAR(bank.floors()(1), f1, 1e-18);
  EXPECT_DOUBLE_EQ(bank.probabilities()(2), p_min);
  EXPECT_NEAR(bank.probabilities()(0), 1.0 - p_min - f1, 1e-15);
  // A first frame near zero: Bayes by hand (stripped eq. 2; the failed one's density 1/W,
  // i.e. l = ln(sqrt(2 pi A) / W)), then p_k = max(f_k, s b_k) for one s.
  const double z = 0.3;
  ASSERT_TRUE(bank.update(z1(z)));
  const double l[3] = {-0.5 * z * z, std::log(std::sqrt(2.0 * M_PI * a_f) / w), -0.25 * z * z};
  const double prior[3] = {1.0 - p_min - f1, f1, p_min};
  Eigen::Vector3d bayes;
  for (int k = 0; k < 3; ++k) bayes(k) = std::exp(l[k]) * prior[k];
  bayes /= bayes.sum();
  const Eigen::Vector3d floors(p_min, f1, p_min);
  const double s = bank.probabilities()(0) / bayes(0);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(bank.probabilities()(k), std::max(floors(k), s * bayes(k)), 1e-15) << "hypothesis " << k;
  EXPECT_NEAR(bank.probabilities()(1), f1, 1e-18);  // below its floor: held at it
  EXPECT_NEAR(bank.probabilities().sum(), 1.0, 1e-15);
  // Presumed, the failed sensor's hypothesis is the reference: no one's floor is below p_min.
  bank.presume(1);
  EXPECT_DOUBLE_EQ(bank.floors()(0), p_min);
  EXPECT_DOUBLE_EQ(bank.floors()(2), p_min);
  EXPECT_NEAR(bank.probabilities()(1), 1.0 - 2 * p_min, 1e-15);
  bank.presume(0);
  EXPECT_NEAR(bank.floors()(1), f1, 1e-18);
}

TEST(FilterBank, FloorSemanticsOnRandomFramesAndRecoveryFromTheFloor) {
  // Three hypotheses that differ in A: small residuals favour A = 0.1, large ones A = 10.
  FilterBankOptions opt;  // p_min = 0.001; the leading term kept, so a small A can win
  opt.strip_leading_term = false;
  ScalarBank bank({scalar_model(1.0), scalar_model(0.1), scalar_model(10.0)}, opt);
  std::mt19937 g(5);
  std::normal_distribution<double> n01(0.0, 1.0);
  // Phase 1: residuals of variance 0.1 -> hypothesis 1 wins, hypothesis 2 sits at the floor.
  for (int i = 0; i < 200; ++i) {
    const Eigen::VectorXd prior = bank.probabilities();
    const double z = std::sqrt(0.1) * n01(g);
    ASSERT_TRUE(bank.update(z1(z)));
    Eigen::VectorXd bayes(3);
    for (int k = 0; k < 3; ++k) bayes(k) = prior(k) * std::exp(bank.log_likelihoods()(k));
    bayes /= bayes.sum();
    expect_water_filled(bank.probabilities(), bayes, opt.p_min);
  }
  EXPECT_GT(bank.probabilities()(1), 0.99);
  EXPECT_DOUBLE_EQ(bank.probabilities()(2), 0.001);
  // Phase 2: the evidence turns (variance 10): the floored hypothesis recovers and wins.
  int frames_to_win = -1;
  for (int i = 0; i < 200; ++i) {
    ASSERT_TRUE(bank.update(z1(std::sqrt(10.0) * n01(g))));
    if (frames_to_win < 0 && bank.probabilities()(2) > 0.9) frames_to_win = i + 1;
  }
  EXPECT_GT(frames_to_win, 0);
  EXPECT_LT(frames_to_win, 40);
  EXPECT_GT(bank.probabilities()(2), 0.99);
}

TEST(FilterBank, HugeResidualsNeverNaNAndTheBestHypothesisWins) {
  ScalarBank bank({scalar_model(1.0), scalar_model(100.0), scalar_model(2.0)});
  ASSERT_TRUE(bank.update(z1(1e100)));  // q_k = 1e200 / A_k, all likelihoods underflow
  EXPECT_TRUE(bank.probabilities().allFinite());
  EXPECT_NEAR(bank.probabilities()(1), 1.0 - 2 * 0.001, 1e-12);
  EXPECT_DOUBLE_EQ(bank.probabilities()(0), 0.001);
  // q overflows to +inf for every hypothesis: no information, probabilities kept, no NaN
  const Eigen::VectorXd before = bank.probabilities();
  ASSERT_TRUE(bank.update(z1(1e300)));
  EXPECT_TRUE(bank.probabilities().allFinite());
  EXPECT_EQ(bank.probabilities(), before);
  EXPECT_TRUE(bank.blended_state().allFinite());
  EXPECT_TRUE(bank.z_hat().allFinite());
}

TEST(FilterBank, NonFiniteFramesAreRejectedCountedAndChangeNothing) {
  const auto models = f16_models(11u);
  F16FilterBank bank(models);
  Eigen::Matrix<double, 7, 1> z = Eigen::Matrix<double, 7, 1>::Constant(0.1);
  Eigen::Matrix<double, 5, 1> u = Eigen::Matrix<double, 5, 1>::Constant(0.2);
  for (int i = 0; i < 5; ++i) bank.step(z, u);
  const auto p = bank.probabilities();
  const auto x_post = bank.state_estimates();
  const auto x_prior = bank.prior_states();
  const auto r = bank.residuals();
  Eigen::Matrix<double, 7, 1> z_bad = z;
  z_bad(3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(bank.update(z_bad));
  Eigen::Matrix<double, 5, 1> u_bad = u;
  u_bad(4) = -std::numeric_limits<double>::infinity();
  EXPECT_FALSE(bank.propagate(u_bad));
  EXPECT_FALSE(bank.step(z_bad, u_bad));
  EXPECT_EQ(bank.rejected_frames(), 4);
  EXPECT_EQ(bank.probabilities(), p);
  EXPECT_EQ(bank.state_estimates(), x_post);
  EXPECT_EQ(bank.prior_states(), x_prior);
  EXPECT_EQ(bank.residuals(), r);
  EXPECT_TRUE(bank.step(z, u));
  EXPECT_TRUE(bank.probabilities().allFinite());
}

TEST(FilterBank, BlendedStateAndZHat) {
  const auto models = f16_models(12u);
  F16FilterBank bank(models);
  Eigen::MatrixXd h_out = Eigen::MatrixXd::Random(7, 13);
  bank.set_h_output(h_out);
  std::mt19937 g(2);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (int i = 0; i < 20; ++i) {
    Eigen::Matrix<double, 7, 1> z;
    for (int j = 0; j < 7; ++j) z(j) = n01(g);
    bank.step(z, test::dither(5, i, 64.0));
  }
  Eigen::VectorXd blend = Eigen::VectorXd::Zero(13);
  for (int k = 0; k < 13; ++k) blend += bank.probabilities()(k) * bank.state_estimates().row(k).transpose();
  EXPECT_LT((blend - bank.blended_state()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((h_out * blend - bank.z_hat()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(FilterBank, FixedAndDynamicSizesAgree) {
  const auto models = f16_models(13u);
  F16FilterBank fixed(models);
  std::vector<DynamicFilterModel> dyn_models;
  for (const auto& m : models) dyn_models.push_back(DynamicFilterModel::from_matrices(
      Eigen::MatrixXd(m.phi), Eigen::MatrixXd(m.bd), Eigen::MatrixXd(m.h), Eigen::MatrixXd(m.k), Eigen::MatrixXd(m.a)));
  DynamicFilterBank dynamic(dyn_models);
  std::mt19937 g(3);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (int i = 0; i < 100; ++i) {
    Eigen::Matrix<double, 7, 1> z;
    for (int j = 0; j < 7; ++j) z(j) = n01(g);
    const Eigen::Matrix<double, 5, 1> u = test::dither(5, i, 64.0);
    fixed.step(z, u);
    dynamic.step(Eigen::VectorXd(z), Eigen::VectorXd(u));
    ASSERT_LT((fixed.probabilities() - dynamic.probabilities()).cwiseAbs().maxCoeff(), 1e-12);
    ASSERT_LT((fixed.residuals() - dynamic.residuals()).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(FilterBank, VectorizedKernelAgreesWithTheEigenPath) {
  const auto models = f16_models(15u);
  FilterBankOptions eigen_only;
  eigen_only.vectorized_kernel = false;
  F16FilterBank fast(models), plain(models, eigen_only);
  EXPECT_FALSE(plain.vectorized_kernel());
  std::mt19937 g(6);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (int i = 0; i < 300; ++i) {
    Eigen::Matrix<double, 7, 1> z;
    for (int j = 0; j < 7; ++j) z(j) = n01(g);
    if (i == 100) z(2) = 1e150;  // huge residuals through both
    const Eigen::Matrix<double, 5, 1> u = test::dither(5, i, 64.0);
    ASSERT_EQ(fast.step(z, u), plain.step(z, u));
    ASSERT_LT((fast.probabilities() - plain.probabilities()).cwiseAbs().maxCoeff(), 1e-12) << i;
    ASSERT_LT((fast.residuals() - plain.residuals()).cwiseAbs().maxCoeff(),
              1e-12 * (1.0 + plain.residuals().cwiseAbs().maxCoeff())) << i;
    ASSERT_LT((fast.state_estimates() - plain.state_estimates()).cwiseAbs().maxCoeff(),
              1e-12 * (1.0 + plain.state_estimates().cwiseAbs().maxCoeff())) << i;
    ASSERT_TRUE(fast.probabilities().allFinite());
  }
  // every q_k overflows to +inf: an uninformative frame (probabilities kept), never NaN
  const auto p = fast.probabilities();
  Eigen::Matrix<double, 7, 1> z = Eigen::Matrix<double, 7, 1>::Constant(1e308);
  EXPECT_EQ(fast.update(z), plain.update(z));
  EXPECT_EQ(fast.probabilities(), p);
  EXPECT_TRUE(fast.quadratic_forms().array().isInf().all());
  EXPECT_TRUE(fast.state_estimates().allFinite());
  EXPECT_TRUE(fast.z_hat().allFinite());
  std::printf("vectorized kernel on this CPU: %s\n", fast.vectorized_kernel() ? "yes (AVX2/FMA)" : "no (Eigen path)");
}

TEST(FilterBank, VectorizedKernelWithADifferentPhiPerFilter) {
  auto models = f16_models(16u);
  for (int k = 1; k < 13; ++k) models[k].phi *= 1.0 - 0.01 * k;  // no shared Phi
  FilterBankOptions eigen_only;
  eigen_only.vectorized_kernel = false;
  F16FilterBank fast(models), plain(models, eigen_only);
  std::mt19937 g(7);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (int i = 0; i < 100; ++i) {
    Eigen::Matrix<double, 7, 1> z;
    for (int j = 0; j < 7; ++j) z(j) = n01(g);
    fast.step(z, test::dither(5, i, 64.0));
    plain.step(z, test::dither(5, i, 64.0));
    ASSERT_LT((fast.prior_states() - plain.prior_states()).cwiseAbs().maxCoeff(), 1e-11) << i;
    ASSERT_LT((fast.probabilities() - plain.probabilities()).cwiseAbs().maxCoeff(), 1e-12) << i;
  }
}

TEST(FilterBank, FixedSizeStepAllocatesNothing) {
  const auto models = f16_models(14u);
  F16FilterBank bank(models);
  std::vector<Eigen::Matrix<double, 7, 1>> zs(256);
  std::vector<Eigen::Matrix<double, 5, 1>> us(256);
  std::mt19937 g(4);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (int i = 0; i < 256; ++i) {
    for (int j = 0; j < 7; ++j) zs[i](j) = n01(g);
    us[i] = test::dither(5, i, 64.0);
  }
  zs[17](2) = std::numeric_limits<double>::quiet_NaN();  // the rejection path too
  const long long before = f16mmae::testing::allocation_count();
  for (int i = 0; i < 256; ++i) bank.step(zs[i], us[i]);
  bank.presume(3);
  bank.reset();
  const long long after = f16mmae::testing::allocation_count();
  EXPECT_EQ(after - before, 0);
  // the counter does count: a std::vector allocates
  std::vector<double>* v = new std::vector<double>(10);
  delete v;
  EXPECT_GE(f16mmae::testing::allocation_count() - after, 1);
}

TEST(FilterBank, StartUpUpdatesTheFiltersButWeighsNothingUntilItEnds) {
  // start_up_s = 3 frames at 64 Hz (3 / 64 s): the first three accepted updates leave the
  // probabilities at the start; the fourth is the hand-computed Bayes update from them. The
  // filters run alike with and without the start-up; a non-finite frame does not count.
  const double a[3] = {1.0, 4.0, 0.25};
  FilterBankOptions opt;
  opt.p_min = 0.0;
  FilterBankOptions held = opt;
  held.start_up_s = 3.0 / 64.0;
  ScalarBank plain({scalar_model(a[0]), scalar_model(a[1]), scalar_model(a[2])}, opt);
  ScalarBank bank({scalar_model(a[0]), scalar_model(a[1]), scalar_model(a[2])}, held);
  const Eigen::Vector3d start(0.5, 0.3, 0.2);
  plain.set_probabilities(start);
  bank.set_probabilities(start);
  EXPECT_FALSE(bank.update(z1(std::numeric_limits<double>::quiet_NaN())));
  const double zs[4] = {0.7, -1.1, 2.0, 1.3};
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(bank.update(z1(zs[i])));
    ASSERT_TRUE(plain.update(z1(zs[i])));
    EXPECT_EQ(bank.probabilities(), start) << "frame " << i;
    EXPECT_EQ(bank.residuals(), plain.residuals());
    EXPECT_EQ(bank.log_likelihoods(), plain.log_likelihoods());
  }
  EXPECT_NE(plain.probabilities(), start);
  ASSERT_TRUE(bank.update(z1(zs[3])));
  double f[3], sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    f[k] = std::exp(-0.5 * zs[3] * zs[3] / a[k]) * start(k);
    sum += f[k];
  }
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(bank.probabilities()(k), f[k] / sum, 1e-14) << "k=" << k;
  bank.reset();  // a reset starts it again
  bank.set_probabilities(start);
  ASSERT_TRUE(bank.update(z1(zs[3])));
  EXPECT_EQ(bank.probabilities(), start);
  held.start_up_s = -1.0;
  try {
    ScalarBank b({scalar_model(1.0), scalar_model(2.0)}, held);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("start_up_s"), std::string::npos);
  }
}

TEST(FilterBank, ConfigurationErrorsNameTheProblem) {
  EXPECT_THROW(F16FilterBank(std::vector<F16FilterModel>(3)), std::invalid_argument);
  FilterBankOptions opt;
  opt.p_min = 0.5;
  try {
    ScalarBank b({scalar_model(1.0), scalar_model(2.0), scalar_model(3.0)}, opt);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("p_min"), std::string::npos);
  }
  ScalarBank b({scalar_model(1.0), scalar_model(2.0)});
  EXPECT_THROW(b.set_probabilities(Eigen::Vector3d(0.2, 0.3, 0.5)), std::invalid_argument);
  EXPECT_THROW(b.set_probabilities(Eigen::Vector2d(0.2, 0.3)), std::invalid_argument);
  EXPECT_THROW(b.set_probabilities(Eigen::Vector2d(-0.2, 1.2)), std::invalid_argument);
  EXPECT_THROW(b.set_h_output(Eigen::MatrixXd::Zero(2, 1)), std::invalid_argument);
  b.set_probabilities(Eigen::Vector2d(1.0, 0.0));  // floored
  EXPECT_DOUBLE_EQ(b.probabilities()(1), 0.001);
  EXPECT_NEAR(b.probabilities()(0), 0.999, 1e-15);
}
