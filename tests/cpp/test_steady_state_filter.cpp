// SteadyStateFilter: the frame equations by hand, equality with a covariance-propagating
// Kalman filter started at the Riccati solution, overflow robustness, validation errors.
#include "f16mmae/steady_state_filter.h"

#include "synthetic_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace f16mmae;

namespace {

FilterModel<2, 1, 1> tiny_model() {
  FilterModel<2, 1, 1> m;
  m.phi << 0.9, 0.1, 0.0, 0.8;
  m.bd << 0.0, 1.0;
  m.h << 1.0, 0.5;
  m.k << 0.3, 0.2;
  m.a << 2.0;
  return m;
}

}  // namespace

TEST(SteadyStateFilter, OneFrameByHand) {
  SteadyStateFilter<2, 1, 1> f(tiny_model());
  EXPECT_DOUBLE_EQ(f.prior()(0), 0.0);
  EXPECT_DOUBLE_EQ(f.log_det_a(), std::log(2.0));
  Eigen::Matrix<double, 1, 1> z;
  z << 4.0;
  ASSERT_TRUE(f.update(z));
  // r = 4 - [1 0.5] 0 = 4; q = 16 / 2 = 8; x+ = [1.2, 0.8]
  EXPECT_DOUBLE_EQ(f.residual()(0), 4.0);
  EXPECT_DOUBLE_EQ(f.quadratic_form(), 8.0);
  EXPECT_DOUBLE_EQ(f.posterior()(0), 1.2);
  EXPECT_DOUBLE_EQ(f.posterior()(1), 0.8);
  Eigen::Matrix<double, 1, 1> u;
  u << -1.0;
  ASSERT_TRUE(f.propagate(u));
  // x- = Phi x+ + Bd u = [0.9*1.2 + 0.1*0.8, 0.8*0.8 - 1] = [1.16, -0.36]
  EXPECT_NEAR(f.prior()(0), 1.16, 1e-15);
  EXPECT_NEAR(f.prior()(1), -0.36, 1e-15);
  // second frame: r = 1 - (1.16 - 0.18) = 0.02
  z << 1.0;
  ASSERT_TRUE(f.update(z));
  EXPECT_NEAR(f.residual()(0), 0.02, 1e-14);
  EXPECT_NEAR(f.quadratic_form(), 0.0002, 1e-15);
}

TEST(SteadyStateFilter, PropagateWithoutUpdateStartsFromPrior) {
  SteadyStateFilter<2, 1, 1> f(tiny_model());
  Eigen::Matrix<double, 1, 1> u;
  u << 1.0;
  ASSERT_TRUE(f.propagate(u));
  ASSERT_TRUE(f.propagate(u));  // no update in between: x- = Phi x- + Bd u
  EXPECT_NEAR(f.prior()(0), 0.1, 1e-15);
  EXPECT_NEAR(f.prior()(1), 1.8, 1e-15);
}

TEST(SteadyStateFilter, NonFiniteInputChangesNothing) {
  SteadyStateFilter<2, 1, 1> f(tiny_model());
  Eigen::Matrix<double, 1, 1> z, u;
  z << 1.0;
  u << 0.5;
  f.update(z);
  f.propagate(u);
  const auto prior = f.prior();
  const auto post = f.posterior();
  z << std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(f.update(z));
  u << std::numeric_limits<double>::infinity();
  EXPECT_FALSE(f.propagate(u));
  EXPECT_EQ(f.prior(), prior);
  EXPECT_EQ(f.posterior(), post);
}

TEST(SteadyStateFilter, QuadraticFormNeverNaN) {
  FilterModel<2, 1, 2> m;
  m.phi << 0.5, 0.0, 0.0, 0.5;
  m.bd << 1.0, 0.0;
  m.h.setIdentity();
  m.k.setZero();
  m.a << 2.0, -1.9, -1.9, 2.0;  // strong negative correlation: mixed-sign terms
  SteadyStateFilter<2, 1, 2> f(m);
  Eigen::Vector2d r(1e100, 1e100);
  const double q_big = f.quadratic_form(r);
  EXPECT_TRUE(std::isfinite(q_big));
  EXPECT_NEAR(q_big / (1e200 * 7.8 / 0.39), 1.0, 1e-9);  // [1 1] A^-1 [1 1]^T = 7.8 / 0.39
  r << 1e200, -1e200;  // overflows: must be +inf, not NaN
  const double q_inf = f.quadratic_form(r);
  EXPECT_TRUE(std::isinf(q_inf) && q_inf > 0.0);
}

TEST(SteadyStateFilter, EqualsCovariancePropagatingKalmanFilterAtRiccatiSolution) {
  const test::Plant p = test::random_plant(4, 2, 3, 7u, 1e-2, 1e-2);
  const test::Gains g = test::steady_state_gains(p.phi, p.h, p.q, p.r);
  using Dyn = DynamicFilterModel;
  const Dyn m = Dyn::from_matrices(p.phi, p.bd, p.h, g.k, g.a);
  DynamicFilter f(m);
  test::Truth truth(p, {"a", "b"}, {"x", "y", "z"}, 3u);
  // the full Kalman filter, started at the steady-state prior covariance
  Eigen::MatrixXd P = g.p_prior;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(4);
  for (int i = 0; i < 200; ++i) {
    const Eigen::VectorXd z = truth.measure({});
    const Eigen::MatrixXd A = p.h * P * p.h.transpose() + p.r;
    const Eigen::MatrixXd K = P * p.h.transpose() * A.inverse();
    const Eigen::VectorXd r = z - p.h * x;
    x = x + K * r;
    P = (Eigen::MatrixXd::Identity(4, 4) - K * p.h) * P;
    ASSERT_TRUE(f.update(z));
    EXPECT_LT((f.residual() - r).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_NEAR(f.quadratic_form(), r.dot(A.ldlt().solve(r)), 1e-8 * (1.0 + f.quadratic_form()));
    const Eigen::VectorXd u = test::dither(2, i, 64.0);
    x = p.phi * x + p.bd * u;
    P = p.phi * P * p.phi.transpose() + p.q;
    ASSERT_TRUE(f.propagate(u));
    EXPECT_LT((f.prior() - x).cwiseAbs().maxCoeff(), 1e-9);
    truth.advance(u, {});
  }
}

TEST(SteadyStateFilter, ValidationNamesTheProblem) {
  auto expect_throw = [](const DynamicFilterModel& m, const std::string& needle) {
    try {
      DynamicFilter f(m, "model 3");
      ADD_FAILURE() << "no exception, expected one mentioning '" << needle << "'";
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(needle), std::string::npos) << what;
      EXPECT_NE(what.find("model 3"), std::string::npos) << what;
    }
  };
  const auto t = tiny_model();
  DynamicFilterModel m;
  m.phi = t.phi;
  m.bd = t.bd;
  m.h = t.h;
  m.k = t.k;
  m.a = t.a;
  DynamicFilter ok(m);
  EXPECT_EQ(ok.nx(), 2);

  DynamicFilterModel bad = m;
  bad.k = Eigen::MatrixXd::Zero(3, 1);
  expect_throw(bad, "k is 3x1, expected 2x1");
  bad = m;
  bad.a(0, 0) = -1.0;
  expect_throw(bad, "not positive definite");
  bad = m;
  bad.phi(0, 1) = std::numeric_limits<double>::quiet_NaN();
  expect_throw(bad, "phi has a non-finite entry");
  bad = m;
  bad.phi << 1.5, 0.0, 0.0, 0.5;
  expect_throw(bad, "unstable");
  bad = m;
  bad.a = Eigen::MatrixXd::Identity(2, 2);
  expect_throw(bad, "a is 2x2, expected 1x1");

  Eigen::MatrixXd wrong = Eigen::MatrixXd::Zero(3, 3);
  EXPECT_THROW(F16FilterModel::from_matrices(wrong, wrong, wrong, wrong, wrong), std::invalid_argument);
}
