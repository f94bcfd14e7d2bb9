// PackedBank — the fixed-size FilterBank's kernel path: the K filters' matrices and states
// in the padded column-major layout of packed_kernel.h, and the frame run through its
// AVX2/FMA kernels. Same equations as HypothesisFilter and FilterBank:
//   update     r_k = z - H_k x⁻_k,  q_k = r_kᵀ A_k⁻¹ r_k,  x⁺_k = x⁻_k + K_k r_k
//   propagate  x⁻_k = Phi_k x_k + Bd_k u   (x_k = x⁺_k after an accepted update, else x⁻_k)
//   blend      x̂ = sum_k p_k x⁺_k,  z_hat = H_out x̂
// On the kernel path this is where the filters' states live, and only here: the bank reads
// and writes them through prior(k), posterior(k), residual(k), set_prior, set_posterior and
// clear (the same interface as ColumnBank, the Eigen path's store, column_bank.h). The
// matrices are a padded copy of the bank's HypothesisFilters, loaded by load(): the K
// filters' H, A⁻¹, K, Bd one contiguous run in the order a frame reads them (packed_kernel.h),
// the Phis apart, and when every filter has the same Phi only the first is read. Likewise each
// of a filter's H, A⁻¹, K and Bd is read from the first filter whose copy is the same bit for
// bit (PackedRefs, relinked before the first frame after a load): the paper's hypotheses share
// most of them (an actuator failure's filter has the no-failure H, A⁻¹ and K, a sensor
// failure's its Bd), so a frame reads about 40 % fewer lines, the same values in the same
// order. Each state is double-buffered:
//   xm[cur_m][k] = x⁻_k,   xp[cur_p][k] = x⁺_k,   r[cur_p][k] = r_k,
//   corrected[k]: x⁺_k is newer than x⁻_k.
// A frame is computed into the spare slot and committed by flipping cur_p / cur_m only if
// every result is finite, so a rejected frame changes nothing. Padding rows stay zero.
// Everything is noexcept and allocation-free. Use only when available() (AVX2 and FMA).
#pragma once

#include "f16mmae/cache_warm.h"
#include "f16mmae/packed_kernel.h"
#include "f16mmae/steady_state_filter.h"

#include <Eigen/Dense>

#include <cmath>
#include <cstring>

namespace f16mmae {

// Empty when the kernel is not used (dynamic sizes, or a compiler without the extensions).
template <bool Enabled, int K, int NX, int NU, int NZ>
class PackedBank {};

#if F16MMAE_PACKED_KERNEL
template <int K, int NX, int NU, int NZ>
class PackedBank<true, K, NX, NU, NZ> {
 public:
  using Hypothesis = HypothesisFilter<NX, NU, NZ>;
  using XVector = typename Hypothesis::XVector;
  using UVector = typename Hypothesis::UVector;
  using ZVector = typename Hypothesis::ZVector;
  using P = PackedFilter<NX, NU, NZ>;
  using Phi = PackedPhi<NX>;
  using Kernels = packed::Kernels<K, NX, NU, NZ>;
  static constexpr int PX = P::PX, PZ = P::PZ;

  static bool available() noexcept { return Kernels::available(); }

  // Filter i's matrices from hypotheses[i]. Filter i's state is left as it was (see clear).
  // Which copies the frames read (link: the shared matrices, whether every Phi is the same) is
  // worked out once, before the next frame, however many filters were loaded.
  template <class Hypotheses>
  void load(int i, const Hypotheses& hypotheses) noexcept {
    filters_[i].load(hypotheses[i]);
    phis_[i].load(hypotheses[i]);
    links_.valid = false;
  }
  // Every filter's matrices from hypotheses (a schedule change).
  template <class Hypotheses>
  void load_all(const Hypotheses& hypotheses) noexcept {
    for (int i = 0; i < K; ++i) filters_[i].load(hypotheses[i]), phis_[i].load(hypotheses[i]);
    links_.valid = false;
  }
  template <class Matrix>
  void load_h_out(const Matrix& h) noexcept {
    for (int j = 0; j < NX; ++j)
      for (int i = 0; i < NZ; ++i) h_out_[j][i] = h(i, j);
  }

  // ---- the state of filter k ---------------------------------------------------------------
  Eigen::Map<const XVector> prior(int k) const noexcept { return Eigen::Map<const XVector>(xm_[cur_m_][k]); }
  Eigen::Map<const XVector> posterior(int k) const noexcept { return Eigen::Map<const XVector>(xp_[cur_p_][k]); }
  Eigen::Map<const ZVector> residual(int k) const noexcept { return Eigen::Map<const ZVector>(r_[cur_p_][k]); }
  bool corrected(int k) const noexcept { return corrected_[k]; }
  void set_prior(int k, const XVector& x) noexcept {
    for (int i = 0; i < NX; ++i) xm_[cur_m_][k][i] = x(i);
    corrected_[k] = false;
  }
  void set_posterior(int k, const XVector& x) noexcept {
    for (int i = 0; i < NX; ++i) xp_[cur_p_][k][i] = x(i);
    corrected_[k] = true;
  }
  // r_k(j) += d (a held complete channel; filter_bank.h).
  void offset_residual(int k, int j, double d) noexcept { r_[cur_p_][k][j] += d; }
  // x⁻_k = x⁺_k = 0, r_k = 0, not corrected.
  void clear(int k) noexcept {
    for (double& v : xm_[cur_m_][k]) v = 0.0;
    for (double& v : xp_[cur_p_][k]) v = 0.0;
    for (double& v : r_[cur_p_][k]) v = 0.0;
    corrected_[k] = false;
  }

  // ---- per frame ----------------------------------------------------------------------------
  // The update of every filter; q_k into q_out(k). A q that overflows is recomputed by
  // hypotheses[k].quadratic_form (the robust form). Returns false, committing nothing, if a
  // result is not finite (q may be +inf).
  template <class Hypotheses, class QVector>
  bool update(const ZVector& z, const Hypotheses& hypotheses, QVector& q_out) noexcept {
    const int spare = 1 - cur_p_;
    const double* x[K];
    for (int i = 0; i < K; ++i) x[i] = xm_[cur_m_][i];
    static const auto kernel = Kernels::update();
    if (!links_.valid) link();
    double probe = 0.0;
    kernel(links_.refs, z.data(), x, &r_[spare][0][0], q_, &xp_[spare][0][0], &probe);
    for (int i = 0; i < K; ++i)
      if (!std::isfinite(q_[i])) q_[i] = hypotheses[i].quadratic_form(Eigen::Map<const ZVector>(r_[spare][i]));
    if (probe != 0.0) return false;
    for (int i = 0; i < K; ++i)
      if (std::isnan(q_[i])) return false;
    for (int i = 0; i < K; ++i) {
      q_out(i) = q_[i];
      corrected_[i] = true;
    }
    cur_p_ = spare;  // commit
    return true;
  }
  // The propagation of every filter. Returns false, committing nothing, if a result is not finite.
  template <class Hypotheses>
  bool propagate(const UVector& u, const Hypotheses&) noexcept {
    const int spare = 1 - cur_m_;
    const double* x[K];
    for (int i = 0; i < K; ++i) x[i] = corrected_[i] ? xp_[cur_p_][i] : xm_[cur_m_][i];
    static const auto kernel = Kernels::propagate();
    if (!links_.valid) link();
    // one Phi for all (the paper's hypotheses share it): filter 0's, read once, stays in L1
    const double* phi = &phis_[0].phi[0][0];
    const long stride = shared_phi_ ? 0 : static_cast<long>(sizeof(Phi) / sizeof(double));
    double probe = 0.0;
    kernel(links_.refs, phi, stride, u.data(), x, &xm_[spare][0][0], &probe);
    if (probe != 0.0) return false;
    for (int i = 0; i < K; ++i) corrected_[i] = false;
    cur_m_ = spare;  // commit
    return true;
  }
  // x̂ = sum_k p_k x⁺_k and z_hat = H_out x̂ (H_out as loaded by load_h_out), in one pass.
  template <class PVector, class OutputMatrix>
  void blend(const PVector& p, const OutputMatrix&, XVector& x_blend, ZVector& z_hat) const noexcept {
    static const auto kernel = Kernels::blend();
    alignas(32) double xb[PX], zh[PZ];
    kernel(p.data(), &xp_[cur_p_][0][0], &h_out_[0][0], xb, zh);
    x_blend = Eigen::Map<const XVector>(xb);
    z_hat = Eigen::Map<const ZVector>(zh);
  }
  // Touch everything a frame reads (cache_warm.h): the packed matrices (the Phis in use) and
  // both state slots.
  void warm_cache() const noexcept {
    touch(filters_);   // every copy: the links may be stale until the next frame
    touch_lines(&phis_[0], shared_phi_ && links_.valid ? sizeof(Phi) : sizeof(phis_));
    touch(h_out_), touch(xm_), touch(xp_), touch(r_), touch(q_), touch(corrected_);
  }

 private:
  // links_.refs[i]: each of filter i's matrices in the first filter j <= i whose copy is the
  // same bit for bit (memcmp of the padded arrays: -0.0 and 0.0 differ, as they may in
  // arithmetic); shared_phi_: every filter's Phi is filter 0's, bit for bit.
  void link() noexcept {
    bool same = true;
    for (int f = 1; f < K && same; ++f) same = std::memcmp(&phis_[f], &phis_[0], sizeof(Phi)) == 0;
    shared_phi_ = same;
    PackedRefs* refs = links_.refs;
    for (int i = 0; i < K; ++i) {
      const P& f = filters_[i];
      refs[i] = PackedRefs{&f.h[0][0], &f.a_inv[0][0], &f.k[0][0], &f.bd[0][0]};
      for (int j = 0; j < i; ++j) {
        const P& g = filters_[j];
        if (refs[i].h == &f.h[0][0] && std::memcmp(f.h, g.h, sizeof(f.h)) == 0) refs[i].h = refs[j].h;
        if (refs[i].a_inv == &f.a_inv[0][0] && std::memcmp(f.a_inv, g.a_inv, sizeof(f.a_inv)) == 0)
          refs[i].a_inv = refs[j].a_inv;
        if (refs[i].k == &f.k[0][0] && std::memcmp(f.k, g.k, sizeof(f.k)) == 0) refs[i].k = refs[j].k;
        if (refs[i].bd == &f.bd[0][0] && std::memcmp(f.bd, g.bd, sizeof(f.bd)) == 0) refs[i].bd = refs[j].bd;
      }
    }
    links_.valid = true;
  }

  // Every padded column starts on a 32-byte boundary, so the kernels' 4-wide loads and
  // stores never straddle a cache line (their speed otherwise depends on where the bank lies).
  alignas(64) P filters_[K];                // H, A⁻¹, K, Bd: one run, in the frame's order
  alignas(64) double h_out_[NX][PZ] = {};   // H_out, column j = H_out(:, j)
  alignas(64) double xm_[2][K][PX] = {};    // x⁻
  alignas(64) double xp_[2][K][PX] = {};    // x⁺
  alignas(64) double r_[2][K][PZ] = {};     // r
  double q_[K] = {};            // the kernel's q output (before the overflow fix-up)
  bool shared_phi_ = false;
  // Where the kernels read each filter's matrices (link), valid until the next load. A copy of
  // the bank is not linked (its pointers would be into the original's filters_): it relinks.
  struct Links {
    PackedRefs refs[K];
    bool valid = false;
    Links() = default;
    Links(const Links&) noexcept {}
    Links& operator=(const Links&) noexcept {
      valid = false;
      return *this;
    }
  };
  Links links_;
  bool corrected_[K] = {};
  int cur_m_ = 0, cur_p_ = 0;
  Phi phis_[K];                             // filter k's Phi; phis_[0] alone when shared_phi_
};
#endif

}  // namespace f16mmae
