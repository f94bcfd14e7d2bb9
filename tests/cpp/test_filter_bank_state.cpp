// FilterBank's one store of the filters' states, on both paths (packed kernel and Eigen
// columns): the per-filter readers agree with stand-alone SteadyStateFilters fed the same
// frames; set_prior / set_posterior / load_filter write the store and the next frame starts
// from what they wrote (checked against the equations computed here by hand); the readers
// change nothing.
#include "f16mmae/filter_bank.h"

#include "synthetic_models.h"

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <tuple>
#include <vector>

using namespace f16mmae;

namespace {

using Z = Eigen::Matrix<double, 7, 1>;
using U = Eigen::Matrix<double, 5, 1>;
using X = Eigen::Matrix<double, 13, 1>;

std::vector<F16FilterModel> models(const ModelBank& mb, int first) {
  std::vector<F16FilterModel> out;
  for (int i = first; i < first + 13; ++i) {
    const auto& m = mb.hypotheses[i];
    out.push_back(F16FilterModel::from_matrices(m.phi, m.bd, m.h, m.k, m.a));
  }
  return out;
}

double max_abs(const Eigen::MatrixXd& m) { return m.cwiseAbs().maxCoeff(); }

class FilterBankState : public ::testing::TestWithParam<bool> {
 protected:
  FilterBankState() : mb_(test::f16_model_bank(51u)), bank_(models(mb_, 0), options()) {}
  static FilterBankOptions options() {
    FilterBankOptions o;
    o.vectorized_kernel = GetParam();
    return o;
  }
  Z frame_z() {
    Z z;
    for (int j = 0; j < 7; ++j) z(j) = 0.2 * n01_(g_);
    return z;
  }
  ModelBank mb_;
  F16FilterBank bank_;
  std::mt19937 g_{3};
  std::normal_distribution<double> n01_{0.0, 1.0};
};

}  // namespace

TEST_P(FilterBankState, ReadersAgreeWithStandAloneFiltersAndChangeNothing) {
  EXPECT_EQ(bank_.vectorized_kernel(), GetParam() && packed::cpu_has_avx2_fma());
  std::vector<F16Filter> alone;
  for (const auto& m : models(mb_, 0)) alone.emplace_back(m);
  for (int i = 0; i < 50; ++i) {
    const Z z = frame_z();
    const U u = test::dither(5, i, 64.0);
    bank_.step(z, u);
    for (auto& f : alone) {
      f.update(z);
      f.propagate(u);
    }
  }
  const auto before = std::make_tuple(bank_.prior_states(), bank_.state_estimates(), bank_.residuals());
  for (int k = 0; k < 13; ++k) {
    EXPECT_LT(max_abs(bank_.prior(k) - alone[k].prior()), 1e-12) << k;
    EXPECT_LT(max_abs(bank_.posterior(k) - alone[k].posterior()), 1e-12) << k;
    EXPECT_LT(max_abs(bank_.residual(k) - alone[k].residual()), 1e-12) << k;
    EXPECT_NEAR(bank_.quadratic_forms()(k), alone[k].quadratic_form(), 1e-9 * (1.0 + alone[k].quadratic_form()));
    EXPECT_FALSE(bank_.corrected(k));
    EXPECT_EQ(bank_.hypothesis(k).model().a, alone[k].model().a);
  }
  EXPECT_EQ(std::make_tuple(bank_.prior_states(), bank_.state_estimates(), bank_.residuals()), before);
}

TEST_P(FilterBankState, SetPriorAndSetPosteriorWriteTheStore) {
  for (int i = 0; i < 10; ++i) bank_.step(frame_z(), test::dither(5, i, 64.0));
  const X x_prior = X::LinSpaced(13, -1.0, 1.0);
  bank_.set_prior(4, x_prior);
  EXPECT_EQ(X(bank_.prior(4)), x_prior);
  EXPECT_FALSE(bank_.corrected(4));
  const Z z = frame_z();
  ASSERT_TRUE(bank_.update(z));
  const auto& m = bank_.hypothesis(4).model();
  const Z r = z - m.h * x_prior;
  EXPECT_LT(max_abs(bank_.residual(4) - r), 1e-12);
  EXPECT_LT(max_abs(bank_.posterior(4) - (x_prior + m.k * r)), 1e-12);
  EXPECT_NEAR(bank_.quadratic_forms()(4), r.dot(m.a.inverse() * r), 1e-9 * (1.0 + r.squaredNorm()));
  EXPECT_TRUE(bank_.corrected(4));

  const X x_post = X::Constant(0.5);
  bank_.set_posterior(9, x_post);
  EXPECT_EQ(X(bank_.posterior(9)), x_post);
  EXPECT_EQ(bank_.state_estimates().row(9).transpose(), x_post);
  bank_.refresh_blend();
  Eigen::VectorXd blend = Eigen::VectorXd::Zero(13);
  for (int k = 0; k < 13; ++k) blend += bank_.probabilities()(k) * bank_.state_estimates().row(k).transpose();
  EXPECT_LT(max_abs(bank_.blended_state() - blend), 1e-12);
  const U u = test::dither(5, 10, 64.0);
  ASSERT_TRUE(bank_.propagate(u));
  const auto& m9 = bank_.hypothesis(9).model();
  EXPECT_LT(max_abs(bank_.prior(9) - (m9.phi * x_post + m9.bd * u)), 1e-12);
  EXPECT_FALSE(bank_.corrected(9));
}

TEST_P(FilterBankState, LoadFilterReplacesTheHypothesisAndStartsItFromZero) {
  for (int i = 0; i < 10; ++i) bank_.step(frame_z(), test::dither(5, i, 64.0));
  ASSERT_TRUE(bank_.update(frame_z()));
  const auto q = bank_.quadratic_forms();
  const F16FilterModel dual = models(mb_, 13)[2];  // a dual hypothesis
  bank_.load_filter(6, F16HypothesisFilter(dual));
  EXPECT_EQ(bank_.hypothesis(6).model().bd, dual.bd);
  EXPECT_EQ(bank_.hypothesis(6).model().h, dual.h);
  EXPECT_EQ(max_abs(bank_.prior(6)), 0.0);
  EXPECT_EQ(max_abs(bank_.posterior(6)), 0.0);
  EXPECT_EQ(max_abs(bank_.residual(6)), 0.0);
  EXPECT_FALSE(bank_.corrected(6));
  EXPECT_EQ(bank_.quadratic_forms(), q);
  // the next frame runs the new hypothesis from x⁻ = Phi 0 + Bd u
  const U u = test::dither(5, 10, 64.0);
  ASSERT_TRUE(bank_.propagate(u));
  EXPECT_LT(max_abs(bank_.prior(6) - dual.bd * u), 1e-12);
  const Z z = frame_z();
  ASSERT_TRUE(bank_.update(z));
  EXPECT_LT(max_abs(bank_.residual(6) - (z - dual.h * dual.bd * u)), 1e-12);
}

// The paper's hypotheses share matrices (an actuator failure's filter has the no-failure H,
// A⁻¹ and K; a sensor failure's its Bd), which the kernel path reads from one copy: after a
// load_filter replaces the filter the others shared with, and in a copy of the bank (whose
// own filters it must read), every filter still runs its own equations.
TEST_P(FilterBankState, FiltersSharingMatricesRunTheirOwnAfterALoadAndInACopy) {
  ASSERT_EQ(bank_.hypothesis(1).model().h, bank_.hypothesis(0).model().h);   // shared: the case exercised
  ASSERT_EQ(bank_.hypothesis(1).model().k, bank_.hypothesis(0).model().k);
  ASSERT_EQ(bank_.hypothesis(7).model().bd, bank_.hypothesis(0).model().bd);
  for (int i = 0; i < 10; ++i) bank_.step(frame_z(), test::dither(5, i, 64.0));
  auto copy = std::make_unique<F16FilterBank>(bank_);
  const F16FilterModel dual = models(mb_, 13)[2];
  bank_.load_filter(0, F16HypothesisFilter(dual));   // the filter the others read H, A⁻¹, K, Bd from
  const auto check_frame = [&](F16FilterBank& b, int frame) {
    X prior[13];
    for (int k = 0; k < 13; ++k) prior[k] = b.prior(k);
    const Z z = frame_z();
    ASSERT_TRUE(b.update(z));
    X post[13];
    for (int k = 0; k < 13; ++k) {
      const auto& m = b.hypothesis(k).model();
      const Z r = z - m.h * prior[k];
      EXPECT_LT(max_abs(b.residual(k) - r), 1e-12) << "frame " << frame << " filter " << k;
      EXPECT_LT(max_abs(b.posterior(k) - (prior[k] + m.k * r)), 1e-12) << k;
      EXPECT_NEAR(b.quadratic_forms()(k), r.dot(m.a.inverse() * r), 1e-9 * (1.0 + r.squaredNorm())) << k;
      post[k] = b.posterior(k);
    }
    const U u = test::dither(5, 20 + frame, 64.0);
    ASSERT_TRUE(b.propagate(u));
    for (int k = 0; k < 13; ++k) {
      const auto& m = b.hypothesis(k).model();
      EXPECT_LT(max_abs(b.prior(k) - (m.phi * post[k] + m.bd * u)), 1e-12) << "frame " << frame << " filter " << k;
    }
  };
  for (int i = 0; i < 3; ++i) check_frame(bank_, i);
  check_frame(*copy, 0);
  F16FilterBank reference = *copy;   // a copy of a bank that has run: not its links, its filters
  for (int k = 0; k < 13; ++k) copy->load_filter(k, F16HypothesisFilter(dual));
  for (int i = 1; i < 3; ++i) check_frame(reference, i);
  copy.reset();
  check_frame(reference, 3);
}

INSTANTIATE_TEST_SUITE_P(BothPaths, FilterBankState, ::testing::Values(true, false),
                         [](const ::testing::TestParamInfo<bool>& i) { return i.param ? "kernel" : "eigen"; });
