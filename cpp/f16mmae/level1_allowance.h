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
// apply(p, duals, k): p (the on-line probabilities after the Bayes update) with every p_s for
// which duals[s] != 0 multiplied by e^{-k}, then divided by their sum (the floor is the
// FilterBank's). Returns false (p untouched) when k == 0 or no dual has mass. Throws nothing.
// check(k): std::invalid_argument naming the problem for k < 0 or not finite.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

namespace f16mmae {

struct Level1Allowance {
  static void check(double k) {
    if (!(k >= 0.0) || !std::isfinite(k))
      throw std::invalid_argument("hierarchical bank: level1_allowance must be a finite number of nats a frame "
                                  ">= 0 (0: none), got " + std::to_string(k));
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
