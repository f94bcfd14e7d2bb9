// SteadyStateFilter — one hypothesis filter of the MMAE bank: a steady-state (constant-gain)
// discrete Kalman filter (Eide & Maybeck, Sec. III-IV). Eigen and std only.
//
// Model of hypothesis k (eqs. 3-4), all quantities perturbations from the design trim:
//   x(t_{i+1}) = Phi x(t_i) + Bd u(t_i) + w_d(t_i),      z(t_i) = H x(t_i) + v(t_i)
// Steady-state filter with gain K and residual covariance A = H P⁻ Hᵀ + R (eq. 5):
//   update     r_i  = z_i - H x⁻_i                       residual
//              q_i  = r_iᵀ A⁻¹ r_i                        quadratic form of eq. 2
//              x⁺_i = x⁻_i + K r_i
//   propagate  x⁻_{i+1} = Phi x⁺_i + Bd u_i   (from x⁻_i when no update was accepted at t_i)
// Initial x⁻_0 = 0 (the trim). A⁻¹ (through a Cholesky factorisation of A) and ln|A| are
// computed once, at construction.
//
// Uninformative channels (a failed sensor whose reading says nothing about the aircraft,
// whatever it reads: held at trim, zero, stuck, full scale, biased, drifting). The model may
// mark channels j ∈ F with a width W_j > 0 (the sensor's full range) and a level noise
// q_j >= 0. Such a channel has H row j = 0, so r_j = z_j - z_trim,j, and A coupled to no
// other channel (checked), so the Gaussian residual density of eq. 2 factorises,
//     N(r; 0, A) = N(r_G; 0, A_GG) · prod_{j∈F} N(r_j; 0, A_jj),      G = the other channels,
// and the hypothesis replaces each failed factor by the density of a reading that is an
// unknown level b_j (uniform over the range, independent of the aircraft) plus the sensor's
// noise (variance A_jj = R_jj), the level a random walk of q_j per frame that may also jump
// anywhere in the range, with probability ε = kLevelJumpProbability per frame (a sensor that
// fails again: goes hardover, sticks, is reset):
//   first frame (level unknown):   ln f_j = -ln W_j
//   later frames (q_j > 0):        ln f_j = ln[ (1 - ε) N(e_j; 0, s_j) + ε / W_j ],  e_j = r_j - b̂_j,
//       the scalar Kalman filter of the level, from its first reading (P_j = A_jj, the
//       reading's noise: the uniform prior over W_j >> sqrt(A_jj) adds nothing):
//       P⁻ = P_j + q_j, s_j = P⁻ + A_jj, g_j = P⁻ / s_j, b̂_j <- b̂_j + g_j e_j,
//       P_j <- P⁻ A_jj / s_j (the bank keeps P_j with b̂_j per filter); but b̂_j <- r_j,
//       P_j <- A_jj on the first frame and whenever the jump term is the larger (the level
//       restarts at the reading: the most probable branch is kept, a one-branch
//       approximation). With q_j << A_jj (a level constant over the flight: P_j = A_jj / n
//       after n readings, the exact predictive density of an unknown constant, s_j =
//       A_jj (1 + 1/n)) and with q_j ~ A_jj (P_j reaches the steady state
//       (q_j + sqrt(q_j² + 4 q_j A_jj)) / 2 within a few frames) alike;
//   q_j = 0: every frame as the first (a reading uniform over the range, no memory).
// The hypothesis' log-density is then
//     ln f_k = -q/2 - (m/2) ln 2π - (1/2) ln|A| + u_k,
//     q   = r_Gᵀ A_GG⁻¹ r_G  (= rᵀ A⁻¹ r with row and column j of A⁻¹ zeroed, exact here),
//     u_k = sum_{j∈F} [ ln f_j + (1/2) ln(2π A_jj) ]
//         = sum_{j∈F} c_j,  c_j = (1/2) ln(2π A_jj) - ln W_j            (first frame, q_j = 0)
//         = sum_{j∈F} ln[ (1-ε) exp(-e_j²/(2 s_j) + (1/2) ln(A_jj/s_j)) + ε exp(c_j) ]
//                                                                           (tracked level)
// So every hypothesis, whatever the number of channels it believes, is a density over the
// same seven readings, and the bank adds u_k to l_k in both forms of eq. 2 (filter_bank.h,
// which keeps b̂ and whether it is set per filter): with the leading term stripped, u_k puts
// the failed channel's density on the scale of its stripped Gaussian factor exp(-r_j²/2A_jj).
// A reading at a constant value costs about ln(W_j / sqrt(2π A_jj)) once (and again on each
// re-entry from the floor, filter_bank.h), then what a healthy channel costs. With no channel
// marked, A⁻¹ is the full inverse and u_k = 0 (the paper's models).
//
// Two parts, kept apart:
//   HypothesisFilter   what a hypothesis filter IS: its FilterModel, A⁻¹, ln|A| and c, fixed at
//                      construction, and the frame equations above as const functions of a
//                      state passed in. A FilterBank holds these and stores the states of all
//                      its filters itself, once (filter_bank.h).
//   SteadyStateFilter  one stand-alone filter: a HypothesisFilter and its own state
//                      (x⁻, x⁺, r, q).
//
// Sizes: Phi (NX,NX), Bd (NX,NU), H (NZ,NX), K (NX,NZ), A (NZ,NZ). Template arguments are
// compile-time sizes (F16Filter = SteadyStateFilter<13, 5, 7>) or Eigen::Dynamic, in which
// case the sizes are taken from the model.
//
// Throws: the constructors throw std::invalid_argument with a sentence when the model's
// shapes disagree (or differ from the compile-time sizes), an entry is not finite, A is not
// symmetric positive definite, or the error dynamics Phi (I - K H) are not stable (spectral
// radius >= 1). Everything per frame is noexcept and, for fixed sizes, allocation-free.
// A per-frame call whose input or result is not finite changes nothing and returns false.
#pragma once

#include <Eigen/Dense>

#include "f16mmae/model_checks.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace f16mmae {

// The matrices of one hypothesis filter (see the header comment for the equations).
template <int NX, int NU, int NZ>
struct FilterModel {
  using PhiMatrix = Eigen::Matrix<double, NX, NX>;
  using BdMatrix = Eigen::Matrix<double, NX, NU>;
  using HMatrix = Eigen::Matrix<double, NZ, NX>;
  using KMatrix = Eigen::Matrix<double, NX, NZ>;
  using AMatrix = Eigen::Matrix<double, NZ, NZ>;

  PhiMatrix phi;  // (NX,NX) state transition
  BdMatrix bd;    // (NX,NU) discrete input matrix
  HMatrix h;      // (NZ,NX) measurement matrix
  KMatrix k;      // (NX,NZ) steady-state Kalman gain
  AMatrix a;      // (NZ,NZ) residual covariance, eq. 5
  // (NZ) width W_j of channel j's uniform density when its reading is uninformative under
  // this hypothesis, 0 for an informative channel (header comment); zeros by default.
  Eigen::Matrix<double, NZ, 1> uninformative_width =
      Eigen::Matrix<double, NZ, 1>::Zero(NZ == Eigen::Dynamic ? 0 : NZ);
  // (NZ) random-walk variance q_j per frame of an uninformative channel's level (sensor
  // units²; 0: the reading uniform over W_j every frame); zeros by default.
  Eigen::Matrix<double, NZ, 1> uninformative_level_q =
      Eigen::Matrix<double, NZ, 1>::Zero(NZ == Eigen::Dynamic ? 0 : NZ);

  // Builds a model from dynamic-size matrices, checking each shape against the compile-time
  // sizes first (throws std::invalid_argument naming `who`); validate() is not called here.
  template <class M>
  static FilterModel from_matrices(const M& phi_, const M& bd_, const M& h_, const M& k_,
                                   const M& a_, const std::string& who = "filter model") {
    return from_matrices(phi_, bd_, h_, k_, a_, Eigen::VectorXd(), Eigen::VectorXd(), who);
  }
  // The same with the uninformative widths and level noises (each empty or NZ entries;
  // empty: every channel informative, every level noise zero).
  template <class M>
  static FilterModel from_matrices(const M& phi_, const M& bd_, const M& h_, const M& k_,
                                   const M& a_, const Eigen::VectorXd& width_,
                                   const Eigen::VectorXd& level_q_ = Eigen::VectorXd(),
                                   const std::string& who = "filter model") {
    auto check = [&](const char* name, const M& x, int r, int c) {
      if ((r != Eigen::Dynamic && x.rows() != r) || (c != Eigen::Dynamic && x.cols() != c)) {
        std::ostringstream s;
        s << who << ": " << name << " is " << x.rows() << "x" << x.cols() << ", expected "
          << (r == Eigen::Dynamic ? std::string("n") : std::to_string(r)) << "x"
          << (c == Eigen::Dynamic ? std::string("n") : std::to_string(c));
        throw std::invalid_argument(s.str());
      }
    };
    check("phi", phi_, NX, NX);
    check("bd", bd_, NX, NU);
    check("h", h_, NZ, NX);
    check("k", k_, NX, NZ);
    check("a", a_, NZ, NZ);
    FilterModel m;
    m.phi = phi_;
    m.bd = bd_;
    m.h = h_;
    m.k = k_;
    m.a = a_;
    for (const auto* v : {&width_, &level_q_}) {
      if (v->size() != 0 && v->size() != m.h.rows()) {
        std::ostringstream s;
        s << who << ": " << (v == &width_ ? "uninformative_width" : "uninformative_level_q") << " has size "
          << v->size() << ", expected 0 or " << m.h.rows();
        throw std::invalid_argument(s.str());
      }
    }
    m.uninformative_width.setZero(m.h.rows());
    if (width_.size() != 0) m.uninformative_width = width_;
    m.uninformative_level_q.setZero(m.h.rows());
    if (level_q_.size() != 0) m.uninformative_level_q = level_q_;
    return m;
  }

  int nx() const { return static_cast<int>(phi.rows()); }
  int nu() const { return static_cast<int>(bd.cols()); }
  int nz() const { return static_cast<int>(h.rows()); }

  // Throws std::invalid_argument naming `who` and the problem (see the header comment).
  void validate(const std::string& who = "filter model") const {
    check_filter_matrices(phi, bd, h, k, a, phi.rows(), bd.cols(), h.rows(), who);
    check_uninformative_width(h, a, uninformative_width, uninformative_level_q, h.rows(), who);
  }
  // True when some channel is uninformative (width > 0).
  bool has_uninformative() const { return (uninformative_width.array() > 0.0).any(); }
};

// What one hypothesis filter is: its model, A⁻¹ and ln|A| (immutable after construction),
// and the frame equations of the header comment as functions of a state passed in.
template <int NX, int NU, int NZ>
class HypothesisFilter {
 public:
  using Model = FilterModel<NX, NU, NZ>;
  using XVector = Eigen::Matrix<double, NX, 1>;
  using UVector = Eigen::Matrix<double, NU, 1>;
  using ZVector = Eigen::Matrix<double, NZ, 1>;
  using AMatrix = typename Model::AMatrix;

  // An empty filter (sizes zero when dynamic); only for filling fixed-size containers.
  HypothesisFilter() = default;

  // Validates the model (throws std::invalid_argument, see the header) and precomputes
  // A⁻¹ and ln|A|. `who` names the filter in error messages.
  explicit HypothesisFilter(const Model& model, const std::string& who = "filter model") : m_(model) {
    m_.validate(who);
    const AMatrix a_sym = 0.5 * (m_.a + m_.a.transpose());
    const Eigen::LLT<AMatrix> llt(a_sym);
    a_inv_ = llt.solve(AMatrix::Identity(m_.nz(), m_.nz()));
    a_inv_ = 0.5 * (a_inv_ + a_inv_.transpose()).eval();
    log_det_a_ = 2.0 * llt.matrixLLT().diagonal().array().log().sum();
    const Eigen::Index nz = m_.nz();
    unf_c_.setZero(nz);
    unf_q_.setZero(nz);
    unf_a_.setZero(nz);
    for (Eigen::Index j = 0; j < m_.uninformative_width.size(); ++j) {
      const double w = m_.uninformative_width(j);
      if (!(w > 0.0)) continue;
      a_inv_.row(j).setZero();
      a_inv_.col(j).setZero();
      uninformative_ = true;
      const double a_jj = a_sym(j, j);
      unf_c_(j) = 0.5 * std::log(2.0 * kPi * a_jj) - std::log(w);
      first_frame_ += unf_c_(j);
      const double q = j < m_.uninformative_level_q.size() ? m_.uninformative_level_q(j) : 0.0;
      if (q > 0.0) {  // the level's scalar Kalman filter (its variance kept by the caller)
        unf_q_(j) = q;
        unf_a_(j) = a_jj;
        tracked_ = true;
      } else {
        memoryless_ += unf_c_(j);
      }
    }
  }

  // u_k of the header comment for residual r, given the levels b̂ (NZ) of this filter, their
  // variances P (NZ) and whether they are set; sets them (first frame) or updates them.
  // `complete` (a bit per channel j): a tracked channel whose bit is set contributes the paper's
  // complete-failure density on the stripped scale, -r_j² / (2 A_jj) (the failed sensor reads the
  // trim plus its noise: N(r_j; 0, A_jj)), in place of its level's term; its level is set or
  // updated all the same (calm_air_complete.h). Bits of untracked or informative channels are
  // ignored. noexcept, no allocation.
  template <class R, class L, class V>
  double uninformative_log_density(const Eigen::MatrixBase<R>& r, const Eigen::MatrixBase<L>& level_out,
                                   const Eigen::MatrixBase<V>& variance_out, bool level_set,
                                   std::uint32_t complete = 0) const noexcept {
    if (!tracked_) return memoryless_;
    auto& level = const_cast<Eigen::MatrixBase<L>&>(level_out);  // Eigen's writable-expression idiom
    auto& var = const_cast<Eigen::MatrixBase<V>&>(variance_out);
    if (!level_set) {
      double u = first_frame_;
      for (Eigen::Index j = 0; j < unf_q_.size(); ++j) {
        if (unf_q_(j) == 0.0) continue;
        level(j) = r(j), var(j) = unf_a_(j);
        if (complete >> j & 1u) u += -0.5 * r(j) * r(j) / unf_a_(j) - unf_c_(j);
      }
      return u;
    }
    double u = memoryless_;
    for (Eigen::Index j = 0; j < unf_q_.size(); ++j) {
      if (unf_q_(j) == 0.0) continue;
      const double a_jj = unf_a_(j);
      const double p = var(j) + unf_q_(j);
      const double s = p + a_jj;
      const double e = r(j) - level(j);
      const double stay = kLogStay + 0.5 * std::log(a_jj / s) - 0.5 * e * e / s;
      const double jump = kLogJump + unf_c_(j);
      const bool pinned = complete >> j & 1u;
      if (pinned) u += -0.5 * r(j) * r(j) / a_jj;
      if (stay >= jump) {
        if (!pinned) u += stay + std::log1p(std::exp(jump - stay));
        level(j) += p / s * e;
        var(j) = p * a_jj / s;
      } else {
        if (!pinned) u += jump + std::log1p(std::exp(stay - jump));
        level(j) = r(j);
        var(j) = a_jj;
      }
    }
    return u;
  }
  // A fresh level on the channels that track theirs (q_j > 0) and that `kept` does not track:
  // b̂_j <- r_j, P_j <- A_jj, the level's posterior after this one reading under its uniform
  // prior (the first frame's). The bank calls it for a hypothesis on its floor
  // (filter_bank.h); `kept` is the presumed hypothesis, whose failed channels' levels go on.
  // noexcept, no allocation.
  template <class R, class L, class V>
  void restart_levels(const Eigen::MatrixBase<R>& r, const Eigen::MatrixBase<L>& level_out,
                      const Eigen::MatrixBase<V>& variance_out, const HypothesisFilter& kept) const noexcept {
    auto& level = const_cast<Eigen::MatrixBase<L>&>(level_out);  // Eigen's writable-expression idiom
    auto& var = const_cast<Eigen::MatrixBase<V>&>(variance_out);
    for (Eigen::Index j = 0; j < unf_q_.size(); ++j)
      if (unf_q_(j) > 0.0 && !kept.tracks_channel(j)) level(j) = r(j), var(j) = unf_a_(j);
  }
  // True when some uninformative channel tracks its level (the bank then keeps b̂).
  bool tracks_level() const noexcept { return tracked_; }
  // True when channel j is uninformative and tracks its level (q_j > 0).
  bool tracks_channel(Eigen::Index j) const noexcept {
    return j >= 0 && j < unf_q_.size() && unf_q_(j) > 0.0;
  }
  // True when some channel is uninformative (u_k is then added to l_k).
  bool has_uninformative() const noexcept { return uninformative_; }

  // ---- the frame equations, on a state passed in (noexcept) --------------------------
  // r = z - H x⁻ and returns q = rᵀ A⁻¹ r (+inf when it overflows, never NaN for finite r).
  double innovate(const XVector& x_prior, const ZVector& z, ZVector& r) const noexcept {
    r.noalias() = z - m_.h * x_prior;
    return quadratic_form(r);
  }
  // rᵀ A⁻¹ r, robust to overflow: a non-finite plain result is recomputed on r scaled by
  // its largest magnitude, so huge residuals give a huge or infinite q, never NaN.
  double quadratic_form(const ZVector& r) const noexcept {
    const double q = r.dot(a_inv_ * r);
    if (std::isfinite(q)) return q < 0.0 ? 0.0 : q;
    const double s = r.cwiseAbs().maxCoeff();
    if (!std::isfinite(s)) return std::numeric_limits<double>::quiet_NaN();
    const ZVector rs = r / s;
    const double inner = rs.dot(a_inv_ * rs);
    return (inner > 0.0 ? inner : 0.0) * s * s;
  }
  // x⁺ = x⁻ + K r.
  void corrected(const XVector& x_prior, const ZVector& r, XVector& x_post) const noexcept {
    x_post.noalias() = x_prior + m_.k * r;
  }
  // x⁻_next = Phi x + Bd u, from the current estimate x (x⁺ after an accepted update, else x⁻).
  void predicted(const XVector& x, const UVector& u, XVector& x_prior) const noexcept {
    x_prior.noalias() = m_.phi * x + m_.bd * u;
  }

  // The blend of n filters of one hypothesis at neighbouring grid nodes (bank_schedule.h):
  // Phi, Bd, H, K, A, A⁻¹, ln|A| and the uninformative channels' constants (c_j, A_jj, their
  // sums; q_j is the same at every node) each set to sum_i w_i (that of f[i]). A weight of
  // exactly 1 copies that filter bit for bit; zero weights are skipped. The weights are the
  // caller's (bilinear: >= 0, summing to 1); the result is not re-validated. noexcept; for
  // fixed sizes no allocation.
  void assign_blend(const HypothesisFilter* const* f, const double* w, int n) noexcept {
    int first = -1;
    for (int i = 0; i < n && first < 0; ++i)
      if (w[i] != 0.0) first = i;
    if (first < 0) return;
    if (w[first] == 1.0) {
      *this = *f[first];
      return;
    }
    const HypothesisFilter& a = *f[first];
    const double wa = w[first];
    m_.phi = wa * a.m_.phi;
    m_.bd = wa * a.m_.bd;
    m_.h = wa * a.m_.h;
    m_.k = wa * a.m_.k;
    m_.a = wa * a.m_.a;
    a_inv_ = wa * a.a_inv_;
    log_det_a_ = wa * a.log_det_a_;
    // The uninformative channels are the same at every node of a hypothesis (which channels,
    // their widths and level noises); their per-channel constants are blended like A.
    m_.uninformative_width = a.m_.uninformative_width;
    m_.uninformative_level_q = a.m_.uninformative_level_q;
    uninformative_ = a.uninformative_;
    tracked_ = a.tracked_;
    first_frame_ = wa * a.first_frame_;
    memoryless_ = wa * a.memoryless_;
    unf_c_ = wa * a.unf_c_;
    unf_q_ = a.unf_q_;
    unf_a_ = wa * a.unf_a_;
    for (int i = first + 1; i < n; ++i) {
      if (w[i] == 0.0) continue;
      const HypothesisFilter& b = *f[i];
      m_.phi += w[i] * b.m_.phi;
      m_.bd += w[i] * b.m_.bd;
      m_.h += w[i] * b.m_.h;
      m_.k += w[i] * b.m_.k;
      m_.a += w[i] * b.m_.a;
      a_inv_ += w[i] * b.a_inv_;
      log_det_a_ += w[i] * b.log_det_a_;
      first_frame_ += w[i] * b.first_frame_;
      memoryless_ += w[i] * b.memoryless_;
      unf_c_ += w[i] * b.unf_c_;
      unf_a_ += w[i] * b.unf_a_;
    }
  }

  const Model& model() const noexcept { return m_; }
  const AMatrix& a_inverse() const noexcept { return a_inv_; }
  double log_det_a() const noexcept { return log_det_a_; }          // ln|A|
  // u_k on a first frame: sum of c_j over the uninformative channels (header comment).
  double log_density_offset() const noexcept { return first_frame_; }
  // The same over the channels that track their level (q_j > 0) only: the Occam factor a
  // restarted level pays once (filter_bank.h lowers such a hypothesis' floor by it); a
  // memoryless channel pays its c_j every frame anyway.
  double tracked_level_offset() const noexcept { return first_frame_ - memoryless_; }
  int nx() const noexcept { return m_.nx(); }
  int nu() const noexcept { return m_.nu(); }
  int nz() const noexcept { return m_.nz(); }

 private:
  static constexpr double kPi = 3.14159265358979323846;

 public:
  // ε of the header comment: the probability per frame that a failed sensor's level jumps
  // anywhere in its range (a model constant of the core).
  static constexpr double kLevelJumpProbability = 1e-3;

 private:
  static constexpr double kLogJump = -6.907755278982137;        // ln 1e-3
  static constexpr double kLogStay = -1.0005003335835335e-3;    // ln(1 - 1e-3)
  Model m_;
  AMatrix a_inv_;  // A⁻¹, rows/columns of uninformative channels zeroed
  double log_det_a_ = 0.0;
  double first_frame_ = 0.0;   // u_k when the levels are not set: sum c_j
  double memoryless_ = 0.0;    // sum c_j over the channels with q_j = 0
  bool tracked_ = false;       // some channel has q_j > 0
  bool uninformative_ = false;  // some channel has W_j > 0
  ZVector unf_c_, unf_q_, unf_a_;  // per channel: c_j, q_j (0: not tracked), A_jj
};

// One stand-alone filter: a HypothesisFilter and its state.
template <int NX, int NU, int NZ>
class SteadyStateFilter {
 public:
  using Hypothesis = HypothesisFilter<NX, NU, NZ>;
  using Model = typename Hypothesis::Model;
  using XVector = typename Hypothesis::XVector;
  using UVector = typename Hypothesis::UVector;
  using ZVector = typename Hypothesis::ZVector;
  using AMatrix = typename Hypothesis::AMatrix;

  // An empty filter (sizes zero when dynamic); only for filling fixed-size containers.
  SteadyStateFilter() = default;

  // Validates the model (throws std::invalid_argument, see the header) and precomputes
  // A⁻¹ and ln|A|. `who` names the filter in error messages.
  explicit SteadyStateFilter(const Model& model, const std::string& who = "filter model") : f_(model, who) {
    reset();
  }

  // x⁻ = x⁺ = 0 (the trim); the residual and quadratic form are zeroed.
  void reset() noexcept {
    x_prior_.setZero(f_.nx());
    x_post_.setZero(f_.nx());
    r_.setZero(f_.nz());
    q_ = 0.0;
    corrected_ = false;
  }

  // Update with z (eqs. above). Returns false, changing nothing, if z or a result is not finite.
  bool update(const ZVector& z) noexcept {
    if (!z.allFinite()) return false;
    ZVector r = ZVector::Zero(f_.nz());
    const double q = f_.innovate(x_prior_, z, r);
    XVector x = XVector::Zero(f_.nx());
    f_.corrected(x_prior_, r, x);
    if (!r.allFinite() || std::isnan(q) || !x.allFinite()) return false;
    r_ = r;
    q_ = q;
    x_post_ = x;
    corrected_ = true;
    return true;
  }
  // Propagate with u. Returns false, changing nothing, if u or the result is not finite.
  bool propagate(const UVector& u) noexcept {
    if (!u.allFinite()) return false;
    XVector x = XVector::Zero(f_.nx());
    f_.predicted(estimate(), u, x);
    if (!x.allFinite()) return false;
    x_prior_ = x;
    corrected_ = false;
    return true;
  }

  // Set the posterior x⁺ (and mark it current, so the next propagate starts from it).
  void set_posterior(const XVector& x_post) noexcept {
    x_post_ = x_post;
    corrected_ = true;
  }
  // Set the prior x⁻ (before an update); the posterior is left as it was.
  void set_prior(const XVector& x_prior) noexcept {
    x_prior_ = x_prior;
    corrected_ = false;
  }

  // ---- state and outputs ---------------------------------------------------------------
  const Hypothesis& hypothesis() const noexcept { return f_; }
  const Model& model() const noexcept { return f_.model(); }
  const XVector& prior() const noexcept { return x_prior_; }        // x⁻
  const XVector& posterior() const noexcept { return x_post_; }     // x⁺ at the last accepted update
  // The current estimate: x⁺ if an update was accepted since the last propagation, else x⁻.
  const XVector& estimate() const noexcept { return corrected_ ? x_post_ : x_prior_; }
  // True when an update was accepted since the last propagation (estimate() is x⁺).
  bool corrected() const noexcept { return corrected_; }
  const ZVector& residual() const noexcept { return r_; }           // r at the last update
  double quadratic_form() const noexcept { return q_; }             // rᵀ A⁻¹ r at the last update
  double quadratic_form(const ZVector& r) const noexcept { return f_.quadratic_form(r); }
  const AMatrix& a_inverse() const noexcept { return f_.a_inverse(); }
  double log_det_a() const noexcept { return f_.log_det_a(); }      // ln|A|
  int nx() const noexcept { return f_.nx(); }
  int nu() const noexcept { return f_.nu(); }
  int nz() const noexcept { return f_.nz(); }

 private:
  Hypothesis f_;
  XVector x_prior_, x_post_;
  ZVector r_;
  double q_ = 0.0;
  bool corrected_ = false;
};

using F16FilterModel = FilterModel<13, 5, 7>;
using F16HypothesisFilter = HypothesisFilter<13, 5, 7>;
using F16Filter = SteadyStateFilter<13, 5, 7>;
using DynamicFilterModel = FilterModel<Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic>;
using DynamicFilter = SteadyStateFilter<Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic>;

}  // namespace f16mmae
