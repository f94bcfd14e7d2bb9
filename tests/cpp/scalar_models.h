// Test helper: one-state, one-measurement filter models whose state never moves (K = 0,
// Bd = 0), so the residual is r = z and the quadratic form q = z^2 / A: each hypothesis is just
// its A (and H), which makes the Bayes updates of eqs. 1-2 computable by hand.
#pragma once

#include "f16mmae/filter_bank.h"

#include <Eigen/Dense>

namespace f16mmae::test {

using Scalar = FilterModel<1, 1, 1>;
using ScalarBank = FilterBank<Eigen::Dynamic, 1, 1, 1>;

inline Scalar scalar_model(double a, double h = 1.0) {
  Scalar m;
  m.phi << 0.5;
  m.bd << 0.0;
  m.h << h;
  m.k << 0.0;
  m.a << a;
  return m;
}

inline Eigen::Matrix<double, 1, 1> z1(double v) {
  Eigen::Matrix<double, 1, 1> z;
  z << v;
  return z;
}

}  // namespace f16mmae::test
