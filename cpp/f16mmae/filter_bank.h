// FilterBank — the MMAE bank of K steady-state hypothesis filters and its conditional
// hypothesis probability evaluator (Eide & Maybeck, Sec. III, Fig. 1). Eigen and std only.
//
// Per frame t_i, with z_i and u_i perturbations from the design trim:
//   update(z)     every filter k: r_k = z - H_k x⁻_k, q_k = r_kᵀ A_k⁻¹ r_k, x⁺_k = x⁻_k + K_k r_k
//                 log-likelihood (eq. 2)
//                   l_k = -q_k/2                                     (leading term stripped, default)
//                   l_k = -q_k/2 - (m/2) ln 2π - (1/2) ln|A_k|       (leading term kept)
//                 with the turbulence adaptation on (options.adaptation, turbulence_adaptation.h)
//                   q_k/2 becomes q_k/(2 s), s the residual-power scale of the frames before;
//                   the frame's q_k then update s (u_k below is not scaled); per channel
//                   (adaptation.channel_weight > 0) q_k/2 becomes (D r_k)ᵀ A_k⁻¹ (D r_k) / 2,
//                   D = diag(s_j^-1/2) of the frames before, and the best-fitting filter's
//                   residual updates s_j; per hypothesis (adaptation.hypothesis_weight w < 1,
//                   while hypothesis 0 is presumed) the frame's best-fitting failure filter b
//                   not fully tempered (adaptation.full_tempering, and rough_tempering while
//                   the air's rho reads >= rough_rho) has l_b = -(q_0 + (q_b - q_0) s / s_b)/(2 s),
//                   s_b = 1 + w (s - 1) (turbulence_adaptation.h; b = argmin q_k; only while
//                   rho-bar >= spare_rho; with adaptation.spare_margin q_0 there is min(q_0, q_f:
//                   f in full_tempering, or in spare_margin_over when it is set)).
//                 With adaptation.level_scale (off by default: bit for bit without) and one s
//                   (no channel_weight), while a failure hypothesis f is presumed (level 1),
//                     l_k += (n_kf / 2) ln s,   n_kf = |F_k ∩ F_f|,
//                   F the uninformative (level) channels: on a failed sensor's channel the
//                   level's density is not tempered (the reading is the sensor's, not the
//                   gusts'), the others' Gaussians are, s A_jj, and the stripped form drops
//                   (1/2) ln s from each tempered channel, which is common to all only if they
//                   read the same channels. Kept to the presumed failure's channels, so at level
//                   0 and among f's duals nothing changes; NONE pays its missing factor s^-1/2
//                   on f's channel and backs out only on evidence on a common footing.
//                 With adaptation.level_scale_channels S (a bit per channel; empty by default:
//                   bit for bit without), at every level and whatever is presumed,
//                     l_k += (n_kS / 2) ln max(s / s_0, 1),   n_kS = |F_k ∩ S \ F_f|
//                   (F_f empty unless level_scale counts it above), s_0 =
//                   adaptation.level_scale_from (>= 1): the same missing factor, paid on
//                   the channels of S before any failure is declared, and only the part of s
//                   above s_0. Why the margin: at level 0 a tracked level follows a healthy
//                   gusty sensor partly, so its own density is not the untempered one the full
//                   (1/2) ln s assumes; where s is small (light air) the term then buys false
//                   declarations, where s is large (severe air) the gusts' share of the failed
//                   sensor's evidence is what it restores.
//                 plus, in both forms, the hypothesis' uninformative-channel term u_k,
//                 non-zero only for a hypothesis with uninformative channels (a failed
//                 sensor's reading an unknown level anywhere in its range; q_k then leaves
//                 those channels out; u_k, the levels b̂_k and their variances the bank
//                 keeps per filter, and
//                 the derivation in steady_state_filter.h). A filter's levels are unset at
//                 the start, after reset() and when load_filter() replaces it.
//                 Common footing (leading term stripped). Filter 0's density of the
//                 readings factorises by the chain rule over the failed channels F of
//                 filter k and the others G,
//                   N(r; 0, A^0) = N(r_G; 0, A^0_GG) · N(r_F; m_F|G, A^0_FF|G),
//                   A^0_FF|G = A^0_FF - A^0_FG (A^0_GG)⁻¹ A^0_GF = (((A^0)⁻¹)_FF)⁻¹,
//                 and filter k's as N(r_G; 0, A^k_GG) · prod_{j∈F} f_j. Pairing the factors
//                 of the same readings, the stripped form removes sqrt|2π A^0_GG| against
//                 sqrt|2π A^k_GG| on G (the paper's stripped form, as between any two
//                 filters) and sqrt|2π A^0_FF|G| against sqrt(2π A^k_jj) per j on F, where
//                 u_k has put f_j on the scale of filter k's own stripped factor. The
//                 bank adds
//                   v_k = (1/2) ln|A^0_FF|G| - sum_{j∈F} (1/2) ln A^k_jj,
//                 so that on F both densities carry the same scale and l_k - l_0 there is
//                 their log-likelihood ratio. The conditional variance, not the marginal
//                 A^0_jj: filter 0's prediction of a channel whose residual it also
//                 predicts from the others (AOA from AZ: A^0_jj|G = 0.71 A^0_jj at the
//                 F-16's design point) is sharper than its marginal, and the marginal
//                 would credit the failed hypothesis (1/2) ln(A^0_jj / A^0_jj|G) (0.17 nats
//                 for AOA and for AZ) every frame, whatever the reading. v_k follows
//                 filter 0's A (a scheduled node change, a hierarchical switch: filter 0
//                 is NONE at both levels); the floor's c_k (below) is a difference of a
//                 restart against a tracked level of the same hypothesis, in which v_k
//                 cancels. Leading term kept: v_k = 0 (every density is whole).
//                 Complete channels C (set_complete_channels; calm_air_complete.h decides
//                 them): on a channel j in C that filter k reads as a level and the presumed
//                 hypothesis does not, u_k's term is the paper's complete failure,
//                 -r_j²/(2 A^k_jj) (the sensor reads the trim plus its noise), and F leaves j
//                 out of v_k: j is compared as in the paper's stripped eq. 2, one more
//                 Gaussian factor with its determinant dropped like every other's.
//                 Held complete channels (set_held_channels, set_held_offset;
//                 complete_trim_hold.h): on a channel j of filter k whose H row is zero and
//                 A row diagonal, r_kj + d_j in place of r_kj and q_k corrected by
//                 (2 r_kj + d_j) d_j (A_k⁻¹)_jj, before everything above reads them (d = 0:
//                 bit for bit without).
//                 Bayes update (eq. 1) in the log domain:
//                   p'_k = exp(l_k + ln p_k - LSE_j(l_j + ln p_j)),   LSE = log-sum-exp
//                 floor ("lock-out" prevention) by water-filling: hypotheses with
//                   p'_k < f_k are set to f_k, the rest rescaled to 1 - sum_floored f_k;
//                   repeated until no rescaled one falls below its floor. Afterwards every
//                   p_k >= f_k, sum p_k = 1, and the ratios among the hypotheses above the
//                   floor are exactly those of the Bayes update.
//                 The floor f_k = p_min exp(min(0, c_k - c_0)) (p_min: set_p_min's tier of k,
//                   one value unless two tiers are set): p_min for every hypothesis
//                   with no tracked-level channel beyond those of the presumed one (c_0 its
//                   c, presume()); for one that adds failed sensors whose level it tracks
//                   (q_j > 0), p_min times their levels' Occam factor exp(c_j),
//                   c_j = ln(sqrt(2π A_jj) / W_j) the first-frame u_k of
//                   steady_state_filter.h (c_k = tracked_level_offset(), the sum of them). The floor is the mass of "the
//                   failure may have begun now"; under a hypothesis that adds failed sensor
//                   j that mass carries a fresh level, uniform over the range, whose density
//                   the first frame pays (c_j). Its tracked level, which kept following the
//                   healthy reading while the hypothesis sat on the floor, must not let it
//                   re-enter free of that cost. (With no uninformative channel anywhere,
//                   every f_k = p_min bit for bit: the paper's floor.)
//                 Per-hypothesis floor factors (set_floor_scale(k, m_k), m_k > 0; 1 by default):
//                   f_k = m_k p_min exp(min(0, c_k - c_0)), ln f_k = ln m_k + ln p_min + ...;
//                   a class of hypotheses whose failure is more likely to begin on a given
//                   frame than the others' (a hierarchical bank's partial-loss hypotheses,
//                   hierarchical_bank.h) rises from a higher floor. With every m_k = 1 the
//                   floors are bit for bit those without it. The caller keeps sum_k f_k < 1.
//                 Fresh levels on the floor (options.fresh_floor_levels, default off): the
//                   floor mass is "the failure begins now", so after each frame's floor a
//                   hypothesis on it (p_k = f_k) carries the level of a failure that began
//                   with this reading, not one that followed the healthy reading before:
//                   every tracked level j it adds to the presumed hypothesis restarts,
//                     b̂_j <- r_j,  P_j <- A_jj     (steady_state_filter.h's first-frame posterior),
//                   whose Occam factor exp(c_j) its f_k already carries. A hypothesis that
//                   leaves the floor then predicts the failed reading from what it has read
//                   since it left: a level constant since the onset (q_j -> 0) is the exact
//                   predictive density of a stuck, held, biased or hardover reading from the
//                   onset on, while a healthy reading that wanders is no such constant.
//                   Off: the levels keep tracking on the floor.
//                 blended state  x̂ = sum_k p_k x⁺_k;   z_hat = H_out x̂ (H_out: the unfailed H,
//                   filter 0's by default, so a failed-sensor hypothesis still yields z_hat).
//                 Start-up (options.start_up_s, 0 = none): the first round(start_up_s f)
//                   accepted updates after the start or reset() (f the adaptation's frame
//                   rate) update the filters, their levels and the adaptation, but not the
//                   probabilities: the filters start at x⁻ = 0, the design trim, while the
//                   aircraft they join is in flight somewhere near it, and their first
//                   residuals measure that start, not a failure. A hierarchical switch does
//                   not restart it.
//                 Off-line filters (set_live(k, false); every filter is live by default):
//                   filter k keeps running (its x⁻, x⁺, r, levels are updated as above) but
//                   takes no part in the hypothesis space: p_k = 0, ln p_k = -inf, f_k = 0,
//                   it is left out of the LSE, of the water-filling and of the turbulence
//                   adaptation's min_k q_k and best-fitting filter. The Bayes update and the
//                   floor above then run over the live filters L exactly as over a bank of
//                   those alone: p'_k = p_k e^{l_k} / sum_{j∈L} p_j e^{l_j}, k ∈ L. Taking a
//                   filter off line conditions the probabilities on "not k":
//                   p_j <- p_j / (1 - p_k) over the live ones, then floored. Filter 0 stays
//                   live (the no-failure footing). With every filter live the arithmetic is
//                   the bank's without this, bit for bit. (A hierarchical bank of more
//                   level-0 hypotheses than a level-1 bank holds keeps the spare slots off
//                   line at level 1; hierarchical_bank.h.)
//   propagate(u)  every filter k: x⁻_k = Phi_k x⁺_k + Bd_k u
//   step(z, u)    update(z) then propagate(u).
// Start: the no-failure hypothesis (index 0) presumed, p_0 = 1 - sum_{k>0} f_k, others f_k
// (or given initial probabilities, floored as above). All states start at x⁻ = 0.
//
// Robustness: a frame with a non-finite entry in z (update) or u (propagate), or whose
// results would overflow to a non-finite state, is applied to no filter, changes nothing
// and is counted in rejected_frames(). A likelihood that underflows to zero (even every
// one of them) loses nothing: the log domain keeps the ratios, and the floor keeps each
// p_k >= p_min. If every q_k overflows to +inf the frame carries no information and the
// probabilities stay as they were (the states are still updated).
//
// Sizes: K filters of NX states, NU inputs, NZ measurements; compile-time
// (F16FilterBank = FilterBank<13, 13, 5, 7>) or Eigen::Dynamic (DynamicFilterBank).
// Storage: what each filter IS — its HypothesisFilter (model, A⁻¹, ln|A|; steady_state_filter.h)
// — is held apart from the filters' per-frame state (x⁻_k, x⁺_k, r_k), and that state is
// stored once, in one of two stores with one interface (prior / posterior / residual,
// set_prior / set_posterior / clear, update / propagate / blend):
//   PackedBank (packed_bank.h)  the packed AVX2/FMA kernels of packed_kernel.h, used with
//                               fixed sizes when the CPU has AVX2 and FMA (checked at run
//                               time; the build itself is portable);
//   ColumnBank (column_bank.h)  Eigen, one column per filter: dynamic sizes, a CPU without
//                               the extensions, or FilterBankOptions::vectorized_kernel = false.
// The two paths agree to rounding. A Phi shared by every filter (as in the paper's
// hypotheses) is read once per frame on the kernel path. q_k and the log-likelihoods are the
// bank's own (quadratic_forms(), log_likelihoods()). Readers are const and change nothing;
// load_filter, set_prior and set_posterior write the store directly.
// Throws: constructors and set_* validators throw std::invalid_argument with a sentence.
// update/propagate/step/presume are noexcept and, for fixed sizes, allocate nothing.
#pragma once

#include "f16mmae/cache_warm.h"
#include "f16mmae/column_bank.h"
#include "f16mmae/estimator_settings.h"
#include "f16mmae/packed_bank.h"
#include "f16mmae/steady_state_filter.h"
#include "f16mmae/turbulence_adaptation.h"

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace f16mmae {

struct FilterBankOptions {
  double p_min = kDefaultPMin;       // probability floor (paper: 0.001); 0 <= p_min < 1/K
  bool strip_leading_term = true;    // drop 1/((2π)^{m/2}|A_k|^{1/2}) from eq. 2 (paper)
  bool vectorized_kernel = true;     // fixed sizes: use the AVX2/FMA kernel if the CPU has it
  TurbulenceAdaptationOptions adaptation;   // likelihood scale s (turbulence_adaptation.h); off by default
  double start_up_s = 0.0;           // updates that weigh nothing after a start (header comment)
  bool fresh_floor_levels = false;   // a floored hypothesis' tracked levels restart (header comment)
};

template <int K, int NX, int NU, int NZ>
class FilterBank {
 public:
  using Hypothesis = HypothesisFilter<NX, NU, NZ>;
  using Model = FilterModel<NX, NU, NZ>;
  using XVector = typename Hypothesis::XVector;
  using UVector = typename Hypothesis::UVector;
  using ZVector = typename Hypothesis::ZVector;
  using PVector = Eigen::Matrix<double, K, 1>;             // probabilities, log-likelihoods
  using ResidualMatrix = Eigen::Matrix<double, K, NZ>;     // row k = r_k
  using StateMatrix = Eigen::Matrix<double, K, NX>;        // row k = x⁺_k
  using OutputMatrix = Eigen::Matrix<double, NZ, NX>;      // H_out
  static constexpr bool kFixed = K != Eigen::Dynamic;
  // The fixed-size bank runs its frames through the packed AVX2/FMA kernel (packed_bank.h:
  // same equations, 4-wide fused multiply-adds) when the CPU has AVX2 and FMA, else Eigen.
  static constexpr bool kPacked = kFixed && NX != Eigen::Dynamic && NU != Eigen::Dynamic &&
                                  NZ != Eigen::Dynamic && kPackedKernel;
  using Hypotheses =
      std::conditional_t<kFixed, std::array<Hypothesis, (kFixed ? K : 1)>, std::vector<Hypothesis>>;
  using Packed = PackedBank<kPacked, (kFixed ? K : 1), NX, NU, NZ>;
  using Columns = ColumnBank<K, NX, NU, NZ>;
  using XMap = Eigen::Map<const XVector>;
  using ZMap = Eigen::Map<const ZVector>;

  // Builds the bank from one model per hypothesis (index 0 = no failure). Throws
  // std::invalid_argument for a wrong count (fixed K), sizes that differ between models,
  // an invalid model (see HypothesisFilter) or p_min outside [0, 1/K).
  explicit FilterBank(const std::vector<Model>& models, const FilterBankOptions& options = {})
      : options_(options) {
    const int k = static_cast<int>(models.size());
    if (kFixed && k != K) {
      std::ostringstream s;
      s << "filter bank: expected " << K << " models, got " << k;
      throw std::invalid_argument(s.str());
    }
    if (k < 1) throw std::invalid_argument("filter bank: needs at least one model");
    if constexpr (!kFixed) hypotheses_.resize(k);
#if F16MMAE_PACKED_KERNEL
    if constexpr (kPacked) use_packed_ = options_.vectorized_kernel && Packed::available();
#endif
    for (int i = 0; i < k; ++i) {
      const std::string who = "filter bank: model " + std::to_string(i);
      if (i > 0 && (models[i].nx() != models[0].nx() || models[i].nu() != models[0].nu() ||
                    models[i].nz() != models[0].nz())) {
        std::ostringstream s;
        s << who << " has sizes (nx, nu, nz) = (" << models[i].nx() << ", " << models[i].nu()
          << ", " << models[i].nz() << "), model 0 has (" << models[0].nx() << ", "
          << models[0].nu() << ", " << models[0].nz() << ")";
        throw std::invalid_argument(s.str());
      }
      hypotheses_[i] = Hypothesis(models[i], who);
      if constexpr (kPacked) packed_.load(i, hypotheses_);
    }
    check_p_min(options_.p_min, k, "filter bank");
    const int nx = hypotheses_[0].nx(), nz = hypotheses_[0].nz();
    scale_.configure(options_.adaptation, nz, "filter bank");
    if (!(options_.start_up_s >= 0.0 && options_.start_up_s <= 3600.0)) {
      std::ostringstream s;
      s << "filter bank: start_up_s must be in [0, 3600] s, got " << options_.start_up_s;
      throw std::invalid_argument(s.str());
    }
    start_up_frames_ =
        static_cast<std::int64_t>(std::lround(options_.start_up_s * options_.adaptation.frame_rate_hz));
    p_.setZero(k);
    log_p_.setZero(k);
    log_l_.setZero(k);
    q_.setZero(k);
    columns_.resize(k, nx, nz);
    x_blend_.setZero(nx);
    z_hat_.setZero(nz);
    floored_.assign_size(k);
    live_.assign_size(k);
    for (int i = 0; i < k; ++i) live_[i] = 1;
    q_live_.setZero(k);
    floor_.setConstant(k, options_.p_min);
    log_floor_.setZero(k);
    floor_scale_.setOnes(k);
    log_floor_scale_.setZero(k);
    level_set_.assign_size(k);
    uninformative_.assign_size(k);
    footing_.setZero(k);
    own_ratio_.setOnes(k);
    q_own_.setZero(k);
    free_channels_.setZero(k);
    tracked_channels_.setZero(k);
    held_channels_.setZero(k);
    held_offset_.setZero(nz);
    for (int i = 0; i < k; ++i) note_uninformative(i);
    level_.setZero(nz, k);
    level_var_.setZero(nz, k);
    h_out_ = hypotheses_[0].model().h;
    load_h_out();
    log_p_min_ = options_.p_min > 0.0 ? std::log(options_.p_min) : -std::numeric_limits<double>::infinity();
    log_norm_ = -0.5 * nz * std::log(2.0 * 3.14159265358979323846);
    presume(0);
  }

  // ---- configuration (validated, may throw) ----------------------------------------------
  // Initial probabilities: size K, finite, >= 0, summing to 1 within 1e-9; floored as above.
  void set_probabilities(const Eigen::Ref<const Eigen::VectorXd>& p) {
    const int k = size();
    if (p.size() != k) {
      std::ostringstream s;
      s << "filter bank: probabilities must have " << k << " entries, got " << p.size();
      throw std::invalid_argument(s.str());
    }
    if (!p.allFinite() || (p.array() < 0.0).any())
      throw std::invalid_argument("filter bank: probabilities must be finite and non-negative");
    if (std::abs(p.sum() - 1.0) > 1e-9) {
      std::ostringstream s;
      s << "filter bank: probabilities must sum to 1, they sum to " << p.sum();
      throw std::invalid_argument(s.str());
    }
    for (int i = 0; i < k; ++i) p_(i) = p(i);
    for (int i = 0; i < k; ++i) log_p_(i) = std::log(p_(i));
    apply_floor();
    refresh_blend();
  }
  // H_out, the (NZ,NX) map from the blended state to z_hat (default: filter 0's H).
  void set_h_output(const Eigen::Ref<const Eigen::MatrixXd>& h) {
    if (h.rows() != nz() || h.cols() != nx()) {
      std::ostringstream s;
      s << "filter bank: h_output must be " << nz() << "x" << nx() << ", got " << h.rows() << "x" << h.cols();
      throw std::invalid_argument(s.str());
    }
    if (!h.allFinite()) throw std::invalid_argument("filter bank: h_output has a non-finite entry");
    h_out_ = h;
    load_h_out();
    refresh_blend();
  }

  // ---- per frame (noexcept, allocation-free for fixed sizes) -----------------------------
  // Returns true if the frame was applied, false if rejected (counted).
  bool update(const ZVector& z) noexcept {
    const int k = size();
    if (!z.allFinite()) return reject();
    if (!store([&](auto& s) { return s.update(z, hypotheses_, q_); })) return reject();
    if (held_on_) offset_held_channels();
    // log-likelihoods (eq. 2) and the Bayes update (eq. 1), log domain
    double a_max = -std::numeric_limits<double>::infinity();
    const bool adapt = scale_.enabled();
    const bool per_channel = scale_.per_channel();
    const double inv_s = scale_.inverse_scale();
    double q_ref = 0.0;                        // q_r of the spared form
    const int spared = spared_hypothesis(q_ref);   // the per-hypothesis tempering's b (turbulence_adaptation.h), -1: none
    // adaptation.level_scale (header): the presumed failure's level channels, and (1/2) ln s on each;
    // adaptation.level_scale_channels: the others at every level, and (1/2) ln max(s / s_0, 1) on each
    const bool level_scales = adapt && !per_channel;
    const std::uint32_t scaled_levels =
        level_scales && scale_.options().level_scale ? free_channels_(presumed_) : 0u;
    const std::uint32_t every_level = level_scales ? scale_.options().level_scale_channels & ~scaled_levels : 0u;
    const double half_log_s = scaled_levels != 0u ? 0.5 * std::log(scale_.scale()) : 0.0;
    const double half_log_over =
        every_level != 0u ? 0.5 * std::log(std::max(scale_.scale() / scale_.options().level_scale_from, 1.0)) : 0.0;
    for (int i = 0; i < k; ++i) {
      double l = -0.5 * q_(i);
      if (per_channel)
        l = -0.5 * channel_tempered_form(i);
      else if (i == spared)
        l = -0.5 * (q_ref + (q_(i) - q_ref) * (((scale_.rough_spared() >> i) & 1u) ? scale_.rough_scale_ratio()
                                                                                 : scale_.hypothesis_scale_ratio())) * inv_s;
      else if (adapt)
        l *= inv_s;
      if (extra_inv_scale_ != 1.0) l *= extra_inv_scale_;
      if (!options_.strip_leading_term) l += log_norm_ - 0.5 * hypotheses_[i].log_det_a();
      if (uninformative_[i]) {  // u_k; otherwise l_k is left bit for bit as it was
        l += hypotheses_[i].uninformative_log_density(residual(i), level_.col(i), level_var_.col(i), level_set_[i],
                                                         complete_in(i)) +
             footing_(i);
        for (std::uint32_t f = free_channels_(i) & scaled_levels; f != 0; f &= f - 1) l += half_log_s;
        for (std::uint32_t f = free_channels_(i) & every_level; f != 0; f &= f - 1) l += half_log_over;
        level_set_[i] = 1;
      }
      log_l_(i) = l;
      if (!live_[i]) continue;   // off line: p_k = 0 (header)
      const double a = l + log_p_(i);
      if (a > a_max) a_max = a;
    }
    if (frames_ >= start_up_frames_ && a_max > -std::numeric_limits<double>::infinity()) {
      double sum = 0.0;
      for (int i = 0; i < k; ++i) {
        // below e^-708 the weight is not a normal double: take 0 and skip exp's slow
        // underflow path (ln p stays exact below, so nothing is lost)
        const double d = log_l_(i) + log_p_(i) - a_max;
        const double w = (d < -708.0 || !live_[i]) ? 0.0 : std::exp(d);
        p_(i) = w;
        sum += w;
      }
      const double log_sum = std::log(sum);
      for (int i = 0; i < k; ++i) {
        log_p_(i) = live_[i] ? log_l_(i) + log_p_(i) - a_max - log_sum : -std::numeric_limits<double>::infinity();
        p_(i) /= sum;
      }
      apply_floor();
      if (options_.fresh_floor_levels) restart_floored_levels();
    }
    observe_scale();
    if (per_channel) observe_channels();
    refresh_blend();
    ++frames_;
    return true;
  }
  bool propagate(const UVector& u) noexcept {
    if (!u.allFinite()) return reject();
    if (!store([&](auto& s) { return s.propagate(u, hypotheses_); })) return reject();
    return true;
  }
  // update(z) then propagate(u). Returns true if both were applied.
  bool step(const ZVector& z, const UVector& u) noexcept {
    const bool a = update(z);
    const bool b = propagate(u);
    return a && b;
  }
  // The turbulence adaptation's reference ρ_0 from now on (ρ kept), and its restart (ρ = ρ_0).
  void set_adapt_reference(double reference) noexcept { scale_.set_reference(reference); }
  void reset_adaptation() noexcept { scale_.reset(); }
  void set_adapt_power_ratio(double rho) noexcept { scale_.set_power_ratio(rho); }
  void set_adapt_power_scale(double sigma) noexcept { scale_.set_power_scale(sigma); }
  void set_adapt_floor_held(bool held) noexcept { scale_.hold_floor(held); }   // turbulence_adaptation.h
  // A further likelihood scale s_e >= 1 for the coming updates, set by the caller frame by
  // frame (the maneuver tempering of maneuver_kinematics.h): l_k = -q_k / (2 s s_e). s_e = 1
  // (the default, and after reset()) leaves every l_k bit for bit as without it.
  void set_extra_scale(double s_e) noexcept { extra_inv_scale_ = s_e > 1.0 ? 1.0 / s_e : 1.0; }
  // The channels read with the paper's complete-failure model from the next update on (bit j:
  // channel j; calm_air_complete.h decides them): a hypothesis that tracks channel j's level while
  // the presumed hypothesis does not has u_k's term -r_j² / (2 A_jj) there in place of the level's
  // (steady_state_filter.h), and its footing v_k leaves channel j out (j counts in G, as in the
  // paper's stripped likelihood of a complete failure: no determinant); its level goes on
  // tracking. 0 (the default, and what reset() leaves alone) leaves every l_k bit for bit as
  // without it. A change sets the footings anew (K small Cholesky factorisations, no allocation for
  // fixed sizes).
  void set_complete_channels(std::uint32_t bits) noexcept {
    if (bits == complete_) return;
    complete_ = bits;
    refresh_footings();
  }
  std::uint32_t complete_channels() const noexcept { return complete_; }
  // The floor p_min from the next update (and presume()) on: the floors f_k are set anew
  // relative to the hypothesis presumed last (header comment); the probabilities in force are
  // not touched (the next update floors them). A value outside [0, 1/K) is ignored: the
  // caller checks it where it enters (a scheduled bank's node settings, ModelBank::validate).
  // Two tiers (set_p_min(p_min, head, p_min_head)): hypotheses k < head take p_min_head in
  // place of p_min (a hierarchical bank's level 1: NONE and the declared failure keep the
  // level-0 floor, the duals take their own; hierarchical_bank.h). head = 0: one floor.
  void set_p_min(double p_min, int head = 0, double p_min_head = 0.0) noexcept {
    const auto valid = [&](double p) { return p >= 0.0 && p * size() < 1.0; };
    if (!valid(p_min) || (head > 0 && !valid(p_min_head))) return;
    if (head < 0) head = 0;
    if (p_min == options_.p_min && head == head_ && (head == 0 || p_min_head == p_min_head_)) return;
    options_.p_min = p_min;
    log_p_min_ = p_min > 0.0 ? std::log(p_min) : -std::numeric_limits<double>::infinity();
    head_ = head;
    p_min_head_ = head > 0 ? p_min_head : 0.0;
    log_p_min_head_ = p_min_head_ > 0.0 ? std::log(p_min_head_) : -std::numeric_limits<double>::infinity();
    set_floors(presumed_);
  }
  // Presume hypothesis `index` (noexcept; ignored if out of range): the floors f_k are set
  // relative to it (header comment), p_index = 1 - sum of the others' f_k, every other f_k.
  void presume(int index) noexcept {
    const int k = size();
    if (index < 0 || index >= k) return;
    const bool footings = complete_ != 0 && index != presumed_;
    presumed_ = index;
    if (footings) refresh_footings();   // the complete channels are those the presumed one reads
    set_floors(index);
    double rest = 0.0;
    for (int i = 0; i < k; ++i) {
      p_(i) = floor_(i);
      log_p_(i) = log_floor_(i);
      if (i != index) rest += floor_(i);
    }
    p_(index) = 1.0 - rest;
    log_p_(index) = std::log(p_(index));
    refresh_blend();
  }
  // Floor factor m_k of hypothesis k (header comment) from the next update (and presume()) on;
  // the floors are set anew, the probabilities in force not touched. Ignored for k out of
  // range or m not finite and > 0. noexcept, no allocation.
  void set_floor_scale(int k, double m) noexcept {
    if (k < 0 || k >= size() || !(m > 0.0) || !std::isfinite(m) || m == floor_scale_(k)) return;
    floor_scale_(k) = m;
    log_floor_scale_(k) = std::log(m);
    set_floors(presumed_);
  }
  double floor_scale(int k) const noexcept { return floor_scale_(k); }
  // The floor f_k in force (header comment).
  double floor_of(int k) const noexcept { return floor_(k); }
  // Filter k on or off line (header comment; noexcept, no allocation; ignored for k = 0 or out
  // of range). Off: p_k's mass leaves by conditioning, p_j <- p_j / (1 - p_k) over the live
  // ones, then the floor; on: p_k = f_k, taken from the others by the floor's rescaling. A
  // caller that presumes a hypothesis next (a hierarchical switch) sees only presume()'s p.
  void set_live(int k, bool live) noexcept {
    if (k <= 0 || k >= size() || static_cast<bool>(live_[k]) == live) return;
    live_[k] = live ? 1 : 0;
    any_dead_ = false;
    for (int i = 0; i < size(); ++i)
      if (!live_[i]) any_dead_ = true;
    set_floors(presumed_);
    if (live) {
      p_(k) = 0.0;   // the floor below lifts it to f_k
    } else {
      const double rest = 1.0 - p_(k);
      p_(k) = 0.0;
      if (rest > 0.0) p_ /= rest;
    }
    for (int i = 0; i < size(); ++i)
      log_p_(i) = p_(i) > 0.0 ? std::log(p_(i)) : -std::numeric_limits<double>::infinity();
    apply_floor();
    refresh_blend();
  }
  bool live(int k) const noexcept { return k >= 0 && k < size() && live_[k]; }
  // f_k of the last presume() (header comment).
  const PVector& floors() const noexcept { return floor_; }
  // Every filter back to x⁻ = 0, no-failure hypothesis presumed, counters zeroed.
  void reset() noexcept {
    for (int i = 0; i < size(); ++i) store([&](auto& s) { s.clear(i); });
    for (int i = 0; i < size(); ++i) level_set_[i] = 0;
    q_.setZero();
    log_l_.setZero();
    rejected_ = 0;
    frames_ = 0;
    scale_.reset();
    extra_inv_scale_ = 1.0;
    presume(0);
  }

  // ---- outputs -------------------------------------------------------------------------
  int size() const noexcept { return static_cast<int>(hypotheses_.size()); }
  int nx() const noexcept { return hypotheses_[0].nx(); }
  int nu() const noexcept { return hypotheses_[0].nu(); }
  int nz() const noexcept { return hypotheses_[0].nz(); }
  const PVector& probabilities() const noexcept { return p_; }
  const PVector& log_probabilities() const noexcept { return log_p_; }
  const PVector& log_likelihoods() const noexcept { return log_l_; }   // l_k of the last update
  const PVector& quadratic_forms() const noexcept { return q_; }       // q_k of the last update
  // (K,NZ): row k = r_k of the last accepted update (zero for a filter loaded since).
  ResidualMatrix residuals() const noexcept {
    ResidualMatrix r(size(), nz());
    for (int i = 0; i < size(); ++i) r.row(i) = residual(i).transpose();
    return r;
  }
  // (K,NX): row k = x⁺_k, filter k's posterior estimate at the last accepted update
  // (the estimates the blended state weighs).
  StateMatrix state_estimates() const noexcept {
    StateMatrix s(size(), nx());
    for (int i = 0; i < size(); ++i) s.row(i) = posterior(i).transpose();
    return s;
  }
  // (K,NX): row k = x⁻_k, filter k's prediction for the next update.
  StateMatrix prior_states() const noexcept {
    StateMatrix s(size(), nx());
    for (int i = 0; i < size(); ++i) s.row(i) = prior(i).transpose();
    return s;
  }
  const XVector& blended_state() const noexcept { return x_blend_; }   // sum p_k x⁺_k
  const ZVector& z_hat() const noexcept { return z_hat_; }             // H_out x̂ (perturbation)
  const OutputMatrix& h_output() const noexcept { return h_out_; }
  std::int64_t rejected_frames() const noexcept { return rejected_; }
  std::int64_t accepted_updates() const noexcept { return frames_; }
  const FilterBankOptions& options() const noexcept { return options_; }
  // The turbulence adaptation's scale s in force for the next update (1 when it is off), and
  // the adaptation itself (its power ratio ρ; turbulence_adaptation.h).
  double turbulence_scale() const noexcept { return scale_.scale(); }
  const ResidualScale<K, NZ>& adaptation() const noexcept { return scale_; }
  // True when the frames run through the packed AVX2/FMA kernel (fixed sizes, CPU support).
  bool vectorized_kernel() const noexcept { return use_packed_; }

  // ---- filter k (k in [0, size()); not checked) -------------------------------------------
  // What filter k is: its model, A⁻¹ and ln|A|.
  const Hypothesis& hypothesis(int k) const noexcept { return hypotheses_[k]; }
  // Filter k's state, read from the store: x⁻_k, x⁺_k (at the last accepted update or as
  // set), r_k, and whether x⁺_k is newer than x⁻_k (the next propagate starts from it).
  XMap prior(int k) const noexcept { return store([&](const auto& s) { return s.prior(k); }); }
  XMap posterior(int k) const noexcept { return store([&](const auto& s) { return s.posterior(k); }); }
  ZMap residual(int k) const noexcept { return store([&](const auto& s) { return s.residual(k); }); }
  bool corrected(int k) const noexcept { return store([&](const auto& s) { return s.corrected(k); }); }
  // Replace filter k by `hypothesis` (same sizes; a plain copy, no heap for fixed sizes),
  // starting from x⁻ = x⁺ = 0, r = 0 (its q_k and l_k stay those of the last update). Used at
  // a hierarchical switch, with set_posterior; call presume() or refresh_blend() after.
  void load_filter(int k, const Hypothesis& hypothesis) noexcept {
    hypotheses_[k] = hypothesis;
    if constexpr (kPacked) packed_.load(k, hypotheses_);
    note_uninformative(k);
    store([&](auto& s) { s.clear(k); });
    level_set_[k] = 0;
  }
  // Held complete channels (complete_trim_hold.h): bit j of `bits` marks channel j of filter k
  // as a complete channel, whose residual the coming updates take against a held trim, r_kj + d_j,
  // d set by set_held_offset (q_k corrected exactly: A_k is diagonal on such a channel).
  void set_held_channels(int k, std::uint32_t bits) noexcept { held_channels_(k) = bits; }
  template <class Z>
  void set_held_offset(const Eigen::MatrixBase<Z>& d) noexcept {
    held_offset_ = d;
    held_on_ = !held_offset_.isZero(0.0);
  }
  // Every filter's uninformative-channel levels move by dz: b̂_k <- b̂_k + dz (a change of
  // the trim the residuals are taken from, z_trim_old - z_trim_new, so that a level stays
  // that of the absolute reading; unset levels are restarted at their first reading anyway).
  template <class Z>
  void shift_levels(const Eigen::MatrixBase<Z>& dz) noexcept {
    for (int k = 0; k < size(); ++k) level_.col(k) += dz;
  }
  // Replace what every filter is, keeping the states x⁻, x⁺, r: a change of the scheduled
  // filters (scheduled_filters.h). write(k, h) writes filter k's new HypothesisFilter into h
  // (same sizes); h_out(H) writes the new H_out into H. noexcept if they are.
  template <class Write, class HOut>
  void replace_filters(Write&& write, HOut&& h_out) noexcept {
    for (int k = 0; k < size(); ++k) write(k, hypotheses_[k]);
    for (int k = 0; k < size(); ++k) note_uninformative(k);
    if constexpr (kPacked) {
      if (use_packed_) packed_.load_all(hypotheses_);
    }
    h_out(h_out_);
    load_h_out();
    refresh_blend();
  }
  // Set filter k's posterior x⁺ and mark it current, so the next propagate starts from it
  // (a filter brought on line after the frame's update).
  void set_posterior(int k, const XVector& x_post) noexcept {
    store([&](auto& s) { s.set_posterior(k, x_post); });
  }
  // Set filter k's prior x⁻ (before an update); its posterior is left as it was.
  void set_prior(int k, const XVector& x_prior) noexcept {
    store([&](auto& s) { s.set_prior(k, x_prior); });
  }
  // Carry over `from`'s per-frame state (a bank of the same sizes whose filters stand for
  // the same hypotheses, e.g. designed for another turbulence level; turbulence_bank_set.h):
  // every filter's x⁻, x⁺ (and whether it is current), the uninformative levels, p, ln p,
  // the last q and l and the counters; what the filters ARE, the options and the
  // adaptation's ρ stay this bank's. noexcept, no allocation for fixed sizes.
  // states = false: the filters keep their own states and levels (a bank that ran on the
  // same frames, warm), only the probabilities and counters are carried over.
  void carry_over(const FilterBank& from, bool states = true) noexcept {
    if (states) {
      for (int k = 0; k < size(); ++k) {
        set_prior(k, from.prior(k));
        if (from.corrected(k)) set_posterior(k, from.posterior(k));
        level_set_[k] = from.level_set_[k];
      }
      level_ = from.level_;
      level_var_ = from.level_var_;
      q_ = from.q_;
      log_l_ = from.log_l_;
    }
    for (int k = 0; k < size(); ++k) live_[k] = from.live_[k];
    any_dead_ = from.any_dead_;
    set_floors(presumed_);
    p_ = from.p_;
    log_p_ = from.log_p_;
    rejected_ = from.rejected_;
    frames_ = from.frames_;
    refresh_blend();
  }
  // Touch the per-frame working set (cache_warm.h), ahead of a frame that has a deadline:
  // the packed kernel's buffers when it runs, else the hypotheses and the column store
  // (fixed sizes: inline; dynamic sizes keep their matrices on the heap and only the bank's
  // own vectors are touched). Reads only: the bank's state and results do not change.
  void warm_cache() const noexcept {
    const auto vec = [](const auto& m) { touch_lines(m.data(), sizeof(double) * m.size()); };
    vec(p_), vec(log_p_), vec(log_l_), vec(q_), vec(x_blend_), vec(z_hat_), vec(h_out_);
    if constexpr (kPacked) {
      if (use_packed_) return packed_.warm_cache();
    }
    if constexpr (kFixed && NX != Eigen::Dynamic && NU != Eigen::Dynamic && NZ != Eigen::Dynamic) {
      touch(hypotheses_);
      touch(columns_);
    }
  }
  // Recompute x̂ and z_hat from the filters' posteriors and the current probabilities.
  void refresh_blend() noexcept {
    store([&](const auto& s) { s.blend(p_, h_out_, x_blend_, z_hat_); });
  }

 private:
  // The one store of the filters' states (see the header comment): f(packed_) on the kernel
  // path, else f(columns_).
  template <class F>
  decltype(auto) store(F&& f) noexcept {
    if constexpr (kPacked) {
      if (use_packed_) return f(packed_);
    }
    return f(columns_);
  }
  template <class F>
  decltype(auto) store(F&& f) const noexcept {
    if constexpr (kPacked) {
      if (use_packed_) return f(packed_);
    }
    return f(columns_);
  }
  // uninformative_[k]: hypotheses_[k].has_uninformative(), kept beside the per-frame
  // members so a frame does not read it from each filter's HypothesisFilter.
  void note_uninformative(int k) noexcept {
    uninformative_[k] = hypotheses_[k].has_uninformative();
    // m_k: the channels filter k's q_k sums (its uninformative ones left out), but for the
    // adaptation's counted channels (turbulence_adaptation.h: they count as read)
    int read = nz();
    const std::uint32_t counted = options_.adaptation.counted_channels;
    std::uint32_t free = 0;   // bit j: channel j uninformative in filter k (the excluded channels' test)
    std::uint32_t tracked = 0;   // ... and its level tracked (the complete channels' test)
    if (uninformative_[k])
      for (int j = 0; j < nz(); ++j)
        if (hypotheses_[k].model().uninformative_width(j) > 0.0) {
          if (j < 32) free |= 1u << j;
          if (j < 32 && hypotheses_[k].tracks_channel(j)) tracked |= 1u << j;
          if (!(j < 32 && ((counted >> j) & 1u))) --read;
        }
    free_channels_(k) = free;
    tracked_channels_(k) = tracked;
    own_ratio_(k) = read > 0 ? static_cast<double>(nz()) / read : 1.0;
    if (k == 0 || (complete_ != 0 && k == presumed_)) {   // filter 0's A is every footing; the presumed
      refresh_footings();                                  // one's levels decide the complete channels
    } else {
      note_footing(k);
    }
  }
  // Filter k's channels read with the complete model (set_complete_channels): the complete
  // channels whose level it tracks and the presumed hypothesis does not read (a memoryless
  // level, uniform every frame, keeps its density and footing: steady_state_filter.h).
  std::uint32_t complete_in(int k) const noexcept {
    return complete_ & tracked_channels_(k) & ~free_channels_(presumed_);
  }
  void refresh_footings() noexcept {
    for (int i = 0; i < size(); ++i) note_footing(i);
  }
  // v_k of the header comment with the leading term stripped, 0 otherwise: over filter k's
  // uninformative channels F, (1/2) ln|A^0_FF|G| - sum_{j in F} (1/2) ln A^k_jj, where
  // ln|A^0_FF|G| = -ln|((A^0)⁻¹)_FF| (the Schur complement's determinant); F without the channels
  // read with the complete model (complete_in(k)).
  void note_footing(int k) noexcept {
    double v = 0.0;
    const std::uint32_t complete = complete_in(k);
    if (options_.strip_leading_term && uninformative_[k] && (free_channels_(k) & ~complete) != 0) {
      using AMatrix = typename Hypothesis::AMatrix;
      using SubMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, NZ, NZ>;
      using Channels = Eigen::Matrix<int, Eigen::Dynamic, 1, Eigen::ColMajor, NZ, 1>;
      const auto& m = hypotheses_[k].model();
      const AMatrix& a0 = hypotheses_[0].model().a;
      const AMatrix a0_inv = a0.llt().solve(AMatrix::Identity(a0.rows(), a0.cols()));
      Channels f(nz());
      int n = 0;
      for (int j = 0; j < nz(); ++j)
        if (m.uninformative_width(j) > 0.0 && !(j < 32 && ((complete >> j) & 1u))) {
          f(n++) = j;
          v -= 0.5 * std::log(m.a(j, j));
        }
      SubMatrix s(n, n);
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) s(a, b) = a0_inv(f[a], f[b]);
      v -= s.llt().matrixLLT().diagonal().array().log().sum();   // (1/2) ln|s|
    }
    footing_(k) = v;
  }
  // The per-hypothesis tempering's spared hypothesis (turbulence_adaptation.h; `reference` is set
  // to q_r of the spared form when one is spared): the on-line
  // failure hypothesis of least q_k (finite), unless it is fully tempered this frame
  // (ResidualScale::fully_tempered(): full_tempering, and rough_tempering in rough air); -1 when
  // the tempering is off or not caught up (ResidualScale::spares()), another hypothesis than
  // 0 is presumed (a hierarchical bank's level 1: its declared failure), q_0 is not finite or
  // there is none.
  int spared_hypothesis(double& reference) const noexcept {
    if (presumed_ != 0 || !scale_.spares() || !std::isfinite(q_(0))) return -1;
    int b = -1;
    double lo = std::numeric_limits<double>::infinity();
    for (int i = 1; i < size(); ++i) {
      if (live_[i] && q_(i) < lo) {
        lo = q_(i);
        b = i;
      }
    }
    const TurbulenceAdaptationOptions& o = scale_.options();
    const std::uint32_t full = scale_.fully_tempered();
    if (b < 0 || b >= 32 || ((full >> b) & 1u)) return -1;
    // q_r: q_0, or with spare_margin min(q_0, q_f: f on line in spare_margin_over, or fully tempered when it is 0)
    reference = q_(0);
    const std::uint32_t over = o.spare_margin_over != 0 ? o.spare_margin_over : full;
    if (o.spare_margin)
      for (int i = 1; i < size() && i < 32; ++i)
        if (i != b && ((over >> i) & 1u) && live_[i] && q_(i) < reference) reference = q_(i);
    return b;
  }
  // (D r_k)ᵀ A_k⁻¹ (D r_k), D = diag(s_j^-1/2): the per-channel tempering (turbulence_adaptation.h).
  double channel_tempered_form(int k) const noexcept {
    if (!(q_(k) < std::numeric_limits<double>::infinity())) return q_(k);   // +inf / NaN stay as they are
    const ZVector y = ZVector(residual(k)).cwiseProduct(scale_.channel_inverse_sqrt_scales());
    return y.dot(hypotheses_[k].a_inverse() * y);
  }
  // The per-channel powers from the best-fitting filter k* = argmin_k q_k (turbulence_adaptation.h).
  void observe_channels() noexcept {
    int best = -1;
    for (int i = 0; i < size(); ++i)
      if (live_[i] && q_(i) < std::numeric_limits<double>::infinity() && (best < 0 || q_(i) < q_(best))) best = i;
    if (best >= 0) scale_.observe_channels(ZVector(residual(best)), hypotheses_[best].a_inverse());
  }
  // The adaptation's per-update minimum (turbulence_adaptation.h): q_k, or q_k m / m_k with own
  // channels, the off-line filters and the excluded hypotheses E left out.
  void observe_scale() noexcept {
    const std::uint32_t excluded = scale_.options().excluded_channels & ~free_channels_(presumed_);
    const bool own = scale_.options().own_channels;
    if (!own && !excluded) {
      scale_.observe(live_q(q_));
      return;
    }
    if (own)   // q_k m / m_k: each form per channel it reads
      q_own_ = q_.cwiseProduct(own_ratio_);
    else
      q_own_ = q_;
    if (excluded)
      for (int i = 0; i < size(); ++i)
        if (free_channels_(i) & excluded) q_own_(i) = std::numeric_limits<double>::infinity();
    scale_.observe(live_q(q_own_));
  }
  // q with the off-line filters' entries +inf (left out of a minimum); q itself when all are live.
  const PVector& live_q(const PVector& q) noexcept {
    if (!any_dead_) return q;
    for (int i = 0; i < size(); ++i) q_live_(i) = live_[i] ? q(i) : std::numeric_limits<double>::infinity();
    return q_live_;
  }
  void load_h_out() noexcept {
    if constexpr (kPacked) packed_.load_h_out(h_out_);
  }

  bool reject() noexcept {
    ++rejected_;
    return false;
  }
  // The floors f_k relative to the presumed hypothesis `index` (header comment).
  void set_floors(int index) noexcept {
    const double c0 = hypotheses_[index].tracked_level_offset();
    for (int i = 0; i < size(); ++i) {
      if (!live_[i]) {   // off line: no floor, p_k = 0
        floor_(i) = 0.0;
        log_floor_(i) = -std::numeric_limits<double>::infinity();
        continue;
      }
      const double d = hypotheses_[i].tracked_level_offset() - c0;
      const double base = i < head_ ? p_min_head_ : options_.p_min;
      const double log_base = i < head_ ? log_p_min_head_ : log_p_min_;
      const double m = floor_scale_(i);
      floor_(i) = d < 0.0 ? m * base * std::exp(d) : m * base;
      log_floor_(i) = (d < 0.0 ? log_base + d : log_base) + log_floor_scale_(i);
    }
  }
  // r_kj += d_j and q_k += (2 r_kj + d_j) d_j (A_k⁻¹)_jj on every held complete channel
  // (set_held_channels; complete_trim_hold.h), after the store's update.
  void offset_held_channels() noexcept {
    for (int i = 0; i < size(); ++i) {
      const std::uint32_t bits = held_channels_(i);
      if (bits == 0) continue;
      for (int j = 0; j < nz() && j < 32; ++j) {
        const double d = held_offset_(j);
        if (!((bits >> j) & 1u) || d == 0.0) continue;
        const double r = residual(i)(j);
        store([&](auto& s) { s.offset_residual(i, j, d); });
        q_(i) += (2.0 * r + d) * d * hypotheses_[i].a_inverse()(j, j);
      }
    }
  }
  // The floor's fresh levels (header comment): every hypothesis on its floor after this
  // frame's Bayes update restarts the tracked levels the presumed hypothesis does not track.
  void restart_floored_levels() noexcept {
    const Hypothesis& kept = hypotheses_[presumed_];
    for (int i = 0; i < size(); ++i)
      if (floored_[i] && live_[i] && level_set_[i] && hypotheses_[i].tracks_level())
        hypotheses_[i].restart_levels(residual(i), level_.col(i), level_var_.col(i), kept);
  }
  // Water-filling floor (see the header comment); keeps log_p_ consistent with p_.
  void apply_floor() noexcept {
    const int k = size();
    for (int i = 0; i < k; ++i) floored_[i] = !live_[i];   // off line: held at f_k = 0
    double floored_sum = 0.0;
    double scale = 1.0;
    for (int iter = 0; iter <= k; ++iter) {
      double free_sum = 0.0;
      for (int i = 0; i < k; ++i)
        if (!floored_[i]) free_sum += p_(i);
      scale = (1.0 - floored_sum) / free_sum;
      bool changed = false;
      for (int i = 0; i < k; ++i) {
        if (!floored_[i] && p_(i) * scale < floor_(i)) {
          floored_[i] = true;
          floored_sum += floor_(i);
          changed = true;
        }
      }
      if (!changed) break;
    }
    const double log_scale = std::log(scale);
    for (int i = 0; i < k; ++i) {
      if (floored_[i]) {
        p_(i) = floor_(i);
        log_p_(i) = log_floor_(i);
      } else {
        p_(i) *= scale;
        log_p_(i) += log_scale;
      }
    }
  }

  FilterBankOptions options_;
  Hypotheses hypotheses_{};    // what each filter is; immutable but for load_filter
  PVector p_, log_p_, log_l_, q_;
  XVector x_blend_;
  ZVector z_hat_;
  OutputMatrix h_out_;
  HypothesisFlags<K> floored_;
  bool use_packed_ = false;    // the store: packed_ if true, else columns_
  Packed packed_{};
  Columns columns_{};
  double log_p_min_ = 0.0;
  double log_norm_ = 0.0;
  std::int64_t rejected_ = 0;
  std::int64_t frames_ = 0;
  // the uninformative channels' levels and the turbulence adaptation, last so the members
  // above keep their layout
  HypothesisFlags<K> level_set_;                  // b̂_k set
  Eigen::Matrix<double, NZ, K> level_;            // column k = b̂_k
  Eigen::Matrix<double, NZ, K> level_var_;        // column k = the levels' variances P_k
  ResidualScale<K, NZ> scale_{};                  // the turbulence adaptation
  double extra_inv_scale_ = 1.0;                  // set_extra_scale: 1 / s_e (1 = none)
  HypothesisFlags<K> uninformative_;              // note_uninformative
  HypothesisFlags<K> live_;                       // set_live: filter k on line (all by default)
  bool any_dead_ = false;                         // some filter off line
  PVector q_live_;                                // live_q's scratch
  PVector footing_;                               // v_k (note_footing)
  PVector own_ratio_, q_own_;                     // m / m_k (note_uninformative) and q_k m / m_k
  PVector floor_, log_floor_;                     // f_k and ln f_k (set_floors, at presume)
  PVector floor_scale_, log_floor_scale_;         // m_k and ln m_k (set_floor_scale; 1 and 0)
  std::int64_t start_up_frames_ = 0;              // round(start_up_s f): updates that weigh nothing
  int presumed_ = 0;                              // the hypothesis presumed last (set_p_min)
  std::uint32_t complete_ = 0;                    // set_complete_channels: bit j, channel j's complete density
  int head_ = 0;                                  // set_p_min's two tiers: k < head_ take
  double p_min_head_ = 0.0, log_p_min_head_ = 0.0;   // p_min_head_ (head_ = 0: none)
  Eigen::Matrix<std::uint32_t, K, 1> free_channels_;   // bit j: channel j uninformative in filter k
  Eigen::Matrix<std::uint32_t, K, 1> tracked_channels_;   // bit j: ... and its level tracked (q_j > 0)
  Eigen::Matrix<std::uint32_t, K, 1> held_channels_;   // bit j: channel j a held complete channel of filter k
  ZVector held_offset_;                                // set_held_offset's d
  bool held_on_ = false;                               // d != 0
};

using F16FilterBank = FilterBank<13, 13, 5, 7>;
using DynamicFilterBank = FilterBank<Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic>;

}  // namespace f16mmae
