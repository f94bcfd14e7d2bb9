// ColumnBank — the FilterBank's Eigen path (any sizes; the fixed-size bank when the packed
// kernel does not run): the states of its K filters, one column per filter, and the frame
// run filter by filter through the HypothesisFilter's equations (steady_state_filter.h):
//   update     r_k = z - H_k x⁻_k,  q_k = r_kᵀ A_k⁻¹ r_k,  x⁺_k = x⁻_k + K_k r_k
//   propagate  x⁻_k = Phi_k x_k + Bd_k u   (x_k = x⁺_k after an accepted update, else x⁻_k)
//   blend      x̂ = sum_k p_k x⁺_k,  z_hat = H_out x̂
// On the Eigen path this is where the filters' states live, and only here:
//   xm.col(k) = x⁻_k,   xp.col(k) = x⁺_k,   r.col(k) = r_k,   corrected[k]: x⁺_k is newer than x⁻_k.
// The interface is PackedBank's (packed_bank.h): prior / posterior / residual / corrected,
// set_prior / set_posterior / clear, update / propagate / blend. A frame is computed for
// every filter into scratch columns and committed only if every result is finite, so a
// rejected frame changes nothing. Per frame noexcept; allocation-free for fixed sizes.
// Each filter's r and x are computed into locals of update / propagate, as a stand-alone
// SteadyStateFilter computes them: Eigen splits a fixed-size product into vector and scalar
// parts by the destination's address at run time, so the destination's placement can change
// the last bit, and tests/cpp/test_bank_trace.cpp holds these results bit for bit.
#pragma once

#include "f16mmae/steady_state_filter.h"

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <type_traits>
#include <vector>

namespace f16mmae {

// A flag per hypothesis: std::array for fixed K (no heap), std::vector when dynamic.
template <int K>
struct HypothesisFlags {
  static constexpr bool kFixed = K != Eigen::Dynamic;
  std::conditional_t<kFixed, std::array<unsigned char, (kFixed ? K : 1)>, std::vector<unsigned char>> v{};
  void assign_size(int n) {
    if constexpr (!kFixed) v.assign(n, 0);
    (void)n;
  }
  unsigned char& operator[](int i) noexcept { return v[i]; }
  unsigned char operator[](int i) const noexcept { return v[i]; }
};

template <int K, int NX, int NU, int NZ>
class ColumnBank {
 public:
  using Hypothesis = HypothesisFilter<NX, NU, NZ>;
  using XVector = typename Hypothesis::XVector;
  using UVector = typename Hypothesis::UVector;
  using ZVector = typename Hypothesis::ZVector;
  using Columns = Eigen::Matrix<double, NX, K>;    // one state per column
  using ZColumns = Eigen::Matrix<double, NZ, K>;   // one residual per column
  using QVector = Eigen::Matrix<double, K, 1>;

  // k filters of nx states and nz measurements, every state zero.
  void resize(int k, int nx, int nz) {
    xm_.setZero(nx, k);
    xp_.setZero(nx, k);
    x_new_.setZero(nx, k);
    r_.setZero(nz, k);
    r_new_.setZero(nz, k);
    q_new_.setZero(k);
    x_in_.setZero(nx);
    corrected_.assign_size(k);
  }

  // ---- the state of filter k ---------------------------------------------------------------
  Eigen::Map<const XVector> prior(int k) const noexcept { return column(xm_, k); }
  Eigen::Map<const XVector> posterior(int k) const noexcept { return column(xp_, k); }
  Eigen::Map<const ZVector> residual(int k) const noexcept {
    return Eigen::Map<const ZVector>(r_.data() + k * r_.rows(), r_.rows());
  }
  bool corrected(int k) const noexcept { return corrected_[k]; }
  void set_prior(int k, const XVector& x) noexcept {
    xm_.col(k) = x;
    corrected_[k] = false;
  }
  void set_posterior(int k, const XVector& x) noexcept {
    xp_.col(k) = x;
    corrected_[k] = true;
  }
  // r_k(j) += d (a held complete channel; filter_bank.h).
  void offset_residual(int k, int j, double d) noexcept { r_(j, k) += d; }
  // x⁻_k = x⁺_k = 0, r_k = 0, not corrected.
  void clear(int k) noexcept {
    xm_.col(k).setZero();
    xp_.col(k).setZero();
    r_.col(k).setZero();
    corrected_[k] = false;
  }

  // ---- per frame ----------------------------------------------------------------------------
  // The update of every filter; q_k into q_out(k). Returns false, committing nothing, if a
  // result is not finite (q may be +inf).
  template <class Hypotheses, class QOut>
  bool update(const ZVector& z, const Hypotheses& hypotheses, QOut& q_out) noexcept {
    const int k = static_cast<int>(xm_.cols());
    ZVector r = ZVector::Zero(r_.rows());
    XVector x = XVector::Zero(xm_.rows());
    for (int i = 0; i < k; ++i) {
      x_in_ = xm_.col(i);
      const double q = hypotheses[i].innovate(x_in_, z, r);
      hypotheses[i].corrected(x_in_, r, x);
      if (std::isnan(q) || !r.allFinite() || !x.allFinite()) return false;
      q_new_(i) = q;
      r_new_.col(i) = r;
      x_new_.col(i) = x;
    }
    q_out = q_new_;  // commit
    r_ = r_new_;
    xp_ = x_new_;
    for (int i = 0; i < k; ++i) corrected_[i] = true;
    return true;
  }
  // The propagation of every filter. Returns false, committing nothing, if a result is not finite.
  template <class Hypotheses>
  bool propagate(const UVector& u, const Hypotheses& hypotheses) noexcept {
    const int k = static_cast<int>(xm_.cols());
    XVector x = XVector::Zero(xm_.rows());
    for (int i = 0; i < k; ++i) {
      x_in_ = corrected_[i] ? xp_.col(i) : xm_.col(i);
      hypotheses[i].predicted(x_in_, u, x);
      if (!x.allFinite()) return false;
      x_new_.col(i) = x;
    }
    xm_ = x_new_;  // commit
    for (int i = 0; i < k; ++i) corrected_[i] = false;
    return true;
  }
  // x̂ = sum_k p_k x⁺_k and z_hat = H_out x̂.
  template <class PVector, class OutputMatrix>
  void blend(const PVector& p, const OutputMatrix& h_out, XVector& x_blend, ZVector& z_hat) const noexcept {
    x_blend.setZero();
    for (int i = 0; i < xp_.cols(); ++i) x_blend.noalias() += p(i) * xp_.col(i);
    z_hat.noalias() = h_out * x_blend;
  }

 private:
  static Eigen::Map<const XVector> column(const Columns& m, int k) noexcept {
    return Eigen::Map<const XVector>(m.data() + k * m.rows(), m.rows());
  }

  Columns xm_, xp_, x_new_;
  ZColumns r_, r_new_;
  QVector q_new_;
  XVector x_in_;   // scratch: one filter's state
  HypothesisFlags<K> corrected_;
};

}  // namespace f16mmae
