// Level1Allowance — the duals' drift allowance at level 1 of the hierarchical bank
// (hierarchical_bank.h, options.level1_allowance): Page's reference value k on each dual's
// log-odds against the declared single. Eigen and std only; allocation-free.
//
// The test the level-1 bank runs. With {NONE, f, f+c, ...} on line and f presumed, the Bayes
// update (filter_bank.h) moves the log-odds of a dual d = f+c against f,
//   L_d(t) = ln(p_d(t) / p_f(t)),
// by the frame's log-likelihood ratio lambda_d(t) = l_d(t) - l_f(t), and the floor holds it from
// below; so, while f carries nearly all the mass,
//   L_d(t) = max(L_floor, L_d(t-1) + lambda_d(t)),     L_floor = ln(p_min / (1 - p_min)),
// Page's CUSUM on lambda_d with the barrier h = ln(T / (1 - T)) - L_floor (T the threshold; with
// p_min = 1e-9 and T = 0.9, h = 2.2 + 20.7 = 22.9 nats). The CUSUM separates the two cases when
// lambda_d drifts down without a second failure (E[lambda_d] = -D(f || d) < 0) and up with one
// (E[lambda_d] = r > 0). When the level-1 models explain each other's residuals (f's sensor out
// and c's surface at an unknown position both absorb a gust's roll), E[lambda_d] is about 0
// without a second failure and its spread sigma a frame is large: L_d is a walk reflected at the
// floor, and a walk reaches any barrier, h after about (h / sigma)^2 frames. A higher barrier
// (options.level1_p_min below p_min) delays the walk only as h^2 and costs a real dual dh / r
// frames.
//
// The allowance k >= 0 (nats a frame): after each level-1 update every dual's probability is
// multiplied by e^{-k} and the probabilities renormalized and floored (FilterBank::
// set_probabilities), i.e. each dual's likelihood carries the factor e^{-k}:
//   L_d(t) = max(L_floor, L_d(t-1) + lambda_d(t) - k).
// Without a second failure the walk now drifts at -k: an excursion from the floor reaches h with
// probability about exp(-2 k h / sigma^2) (a Brownian motion with drift -k and variance sigma^2
// a frame; with correlated increments sigma^2 is the variance of their sum per frame),
// exponentially small in h. A real dual climbs at r - k: h / (r - k) frames instead of h / r,
// k h / (r (r - k)) frames more, and a dual with r <= k never. Example, h = 22.9 nats,
// sigma = 1 nat a frame: k = 0.1 gives exp(-4.6) = 0.01 a walk's excursion; a dual at r = 0.5
// nats a frame pays 11 frames (0.18 s at 64 Hz), one at r = 0.15 pays 305 frames (4.8 s).
// Only the duals take the allowance: NONE (the back-out) and the declared failure's other form
// (a partial bank's c beside c:MODE, hierarchy_levels.h) do not; at level 0 nothing does. k = 0
// (the default) leaves the bank as it was, bit for bit (nothing is touched).
//
// Per dual (options.level1_allowance_pairs, "f>c" -> k_{f>c}): the allowance of the dual f+c while
// f's level-1 bank is on line (f the declared single, or the single of a declared partial c:MODE;
// c the dual's other component). The walk and the drift ask different things of k: a false dual
// is held back when k is large against sigma^2 / (2 h) (above), a real one pays
// k h / (r (r - k)) frames. With k proportional to the dual's own drift under its second
// failure, up to a ceiling,
//   k_{f>c} = min(a r_{f>c}, k_max),   0 <= a < 1,   r_{f>c} = E[l_{f+c} - l_f | f and c failed],
// every dual's climb takes at most h / (r (1 - a)) frames, 1 / (1 - a) times its climb without
// the allowance (a = 0.2: 1.25 times), whatever r; a dual slow by nature (r small) gets a small
// k, and the duals whose models explain each other's residuals -- where the walks are -- are
// the ones whose second failure shows at once (f's filter loses c's residual: r large), so they
// get a large one. The ceiling: r is the climb's mean, and a dual whose climb is a jump (a
// sensor's reading lost: h crossed on the onset's frame, r = h nats a frame) gathers far less a
// frame once above the threshold, where the dwell must survive k; k_max is an allowance the
// fast duals carry through their dwell. r_{f>c} is measured, not modelled: the climb of f+c from the level-1 floor
// to the threshold over h nats in the frames n from c's onset to the crossing, r = h / n,
// the median over the runs of a dual campaign flown without the allowance on a tuning seed
// (tools/cover/dual_rates.py writes the table; a pair never declared there gets its bound
// h / n_end). A pair not in the table takes the scalar k (options.level1_allowance).
//
// The table from the models' separation instead (tools/cover/distinguishability.py writes it).
// Without a second failure E[lambda_d] = -D_s + m, D_s = D(f || f+c) the models' separation of
// the single from the dual (the Kullback-Leibler rate of the dual's residual density from the
// single's, design/distinguish.py) and m what they do not explain; the reflected walk with
// drift -mu and long-run variance s^2 a frame reaches h in one excursion with probability about
// exp(-2 mu h / s^2), so N excursions stay below h but with probability alpha when
//   mu = D_s + k >= m0 = s^2 ln(N / alpha) / (2 h),   i.e.   k_{f>c} = min(k_max, max(0, m0 - D_s)):
// a dual is asked for evidence in proportion to how little its models separate it from the
// single, and a pair they separate faster than m0 takes none.
//
// apply(p, duals, k): p (the on-line probabilities after the Bayes update) with every p_s for
// which duals[s] != 0 multiplied by e^{-k}, then divided by their sum (the floor is the
// FilterBank's). Returns false (p untouched) when k == 0 or no dual has mass. Throws nothing.
// apply_each(p, ks): the same with k_s for slot s (0: untouched; ks[s] = k of the dual on line in
// slot s, 0 for NONE, f and any other form of f): p_s e^{-k_s} / sum_t p_t e^{-k_t}. Returns
// false (p untouched) when no k_s > 0 holds mass. With every k_s = k on the duals it is apply(),
// bit for bit. Throws nothing.
// check(k): std::invalid_argument naming the problem for k < 0 or not finite.
// check_pair(key, k, singles): the same for a pair's k, and a key that is not "f>c" with f, c
// two different singles of the bank (the names in `singles`).
#pragma once

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace f16mmae {

struct Level1Allowance {
  static void check(double k) {
    if (!(k >= 0.0) || !std::isfinite(k))
      throw std::invalid_argument("hierarchical bank: level1_allowance must be a finite number of nats a frame "
                                  ">= 0 (0: none), got " + std::to_string(k));
  }

  static void check_pair(const std::string& key, double k, const std::vector<std::string>& singles) {
    const auto gt = key.find('>');
    const std::string f = gt == std::string::npos ? std::string() : key.substr(0, gt);
    const std::string c = gt == std::string::npos ? std::string() : key.substr(gt + 1);
    const auto known = [&](const std::string& n) { return std::find(singles.begin(), singles.end(), n) != singles.end(); };
    if (gt == std::string::npos || !known(f) || !known(c) || f == c) {
      std::string names;
      for (const auto& n : singles) names += (names.empty() ? "" : ",") + n;
      throw std::invalid_argument("hierarchical bank: level1_allowance_pairs key '" + key +
                                  "' must be 'F>C', F the declared single and C the dual's other one, two different "
                                  "singles of the bank (" + names + ")");
    }
    if (!(k >= 0.0) || !std::isfinite(k))
      throw std::invalid_argument("hierarchical bank: level1_allowance_pairs['" + key +
                                  "'] must be a finite number of nats a frame >= 0, got " + std::to_string(k));
  }

  template <class P, class Ks>
  static bool apply_each(P& p, const Ks& ks) noexcept {
    double sum = 0.0, moved = 0.0;
    for (int s = 0; s < static_cast<int>(p.size()); ++s) {
      const double k = ks[static_cast<std::size_t>(s)];
      if (k > 0.0) {
        moved += p(s);
        p(s) *= std::exp(-k);
      }
      sum += p(s);
    }
    if (!(moved > 0.0) || !(sum > 0.0)) return false;
    p /= sum;
    return true;
  }

  template <class P, class Mask>
  static bool apply(P& p, const Mask& duals, double k) noexcept {
    if (!(k > 0.0)) return false;
    const double w = std::exp(-k);
    double sum = 0.0, moved = 0.0;
    for (int s = 0; s < static_cast<int>(p.size()); ++s) {
      if (duals[static_cast<std::size_t>(s)] != 0) {
        moved += p(s);
        p(s) *= w;
      }
      sum += p(s);
    }
    if (!(moved > 0.0) || !(sum > 0.0)) return false;
    p /= sum;
    return true;
  }
};

}  // namespace f16mmae
