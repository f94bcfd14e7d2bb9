// LevelFloors — the probability floors and the dwell of the hierarchical bank's levels
// (hierarchical_bank.h: options.level1_p_min, level1_dwell_s, partial_p_min): which floor each
// on-line hypothesis takes at level 0 and at level 1, the dwell a level-1 declaration needs, and
// the bounds the options must keep. Std only; throws only from the checks; the floors are set
// without allocation.
//
// The floor is the prior mass of "this failure may have begun now" (filter_bank.h: the floor
// f_k = m_k p_min exp(min(0, c_k - c_0)), FilterBank::set_p_min's tiers and set_floor_scale's
// factors m_k). The level-0 floor p_min is options.bank.p_min, or a scheduled bank's node floor
// in force (ScheduleOptions::node_p_min).
//
// The floor at level 1 (level1_p_min in [0, (1 - threshold)/(K - 1)); 0, the default: the
//   level-0 floor, bit for bit): while a level-1 bank is on line its duals f+c (on-line
//   positions 2...) take the floor level1_p_min, NONE and f keep the level-0 floor
//   (FilterBank::set_p_min(level1_p_min, 2, p_min), two tiers); back at level 0 (back-out,
//   reset()) the level-0 floor is in force for all again. NONE keeps it because "the
//   declaration of f was false" is no event that may begin now: backing out needs the evidence
//   a level-0 declaration needs. Why a floor of its own: a dual f+c must gather ln(1/p_min)
//   nats over f alone before it leads, and without f's sensor (or surface) the evidence for c
//   comes at a fraction of its level-0 rate (the pitch-rate gyro out, a stabilator is seen
//   through α and n_z only), so with the level-0 floor (1e-9 tuned against false alarms in
//   failure-free flight) the dual rises seconds after the lone failure would. The level-1 floor
//   is the prior of "the second failure may have begun now" given that one already has.
//   Bound: with the K - 1 others on their floors a hypothesis holds at most 1 - (K - 1) P, so
//   above P = (1 - threshold) / (K - 1) none could pass the threshold (K: the hypotheses on
//   line, the level-0 count).
//
// The dwell at level 1 (level1_dwell_s >= 0; 0, the default: the level-0 dwell, bit for bit):
//   while a level-1 bank is on line a declaration (a dual, or NONE's back-out) needs
//   p > threshold on round(level1_dwell_s * rate) consecutive frames (declarer.h). A raised
//   level-1 floor lets a short burst of evidence (a gust the filters model poorly) lift a false
//   dual f+c above the threshold for a few frames; a real second failure keeps it there.
//
// The partial hypotheses' floor (partial_p_min >= 0; 0, the default: the level-0 floor, bit for
//   bit): at level 0 every partial hypothesis c:MODE takes the floor partial_p_min, the others
//   the level-0 floor p_min (FilterBank::set_floor_scale, m = partial_p_min / p_min; m = 1 when
//   p_min = 0); at level 1 every hypothesis has its level-1 floor as above (m = 1).
//   Derivation: a hypothesis whose log-likelihood ratio against the presumed one grows by r
//   nats a frame climbs from its floor f to the threshold T (the rest of the mass on the
//   presumed hypothesis) in
//     n(f) = [ln(T / (1 - T)) - ln(f / (1 - f))] / r   frames,
//   so a floor raised from p_min to f saves ln(f / p_min) / r frames (f << 1). A partial loss's
//   evidence comes at a fraction of a complete failure's (its mean residual is (1 - R) times
//   the complete failure's, the log-likelihood ratio's drift (1 - R)^2 times), so from the
//   common floor its climb is the long part of its latency. The false-alarm side is the same
//   count in failure-free flight: the ratio's excursions above zero are unchanged by the floor,
//   and the threshold lies ln(f / p_min) nats nearer. Refused: partial_p_min < 0 or not
//   finite, a partial_p_min set for a bank without partial hypotheses, and floors that leave
//   no room for a declaration:
//     n_partial partial_p_min + (K - 1 - n_partial) p_min >= 1 - threshold.
//
// level1_bound(threshold, K) = (1 - threshold) / (K - 1).
// check_level1(level1_p_min, level1_dwell_s, threshold, K), check_partial(partial_p_min,
//   n_partial, K, p_min, threshold): std::invalid_argument naming the problem.
// own_level1_dwell(level, level1_dwell_s): level 1 with level1_dwell_s > 0 (the level-1
//   declarer is in force); level1_dwell(level1_dwell_s, level0_dwell_s): the level-1
//   declarer's dwell.
// floor_scale(level, partial, partial_p_min, p_min): m_k of one hypothesis (above).
// apply(bank, level, p_min, level1_p_min, partial_p_min, level0_partial): the floors of the
//   level on line set on the FilterBank (level0_partial[k] != 0: on-line position k holds a
//   partial hypothesis at level 0). noexcept, no allocation.
#pragma once

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace f16mmae {

struct LevelFloors {
  static double level1_bound(double threshold, int k) noexcept {
    return (1.0 - threshold) / static_cast<double>(k - 1);
  }

  static void check_level1(double level1_p_min, double level1_dwell_s, double threshold, int k) {
    const double bound = level1_bound(threshold, k);
    if (!(level1_p_min >= 0.0) || !(level1_p_min < bound))
      throw std::invalid_argument("hierarchical bank: level1_p_min must lie in [0, (1 - threshold)/(K - 1)) = [0, " +
                                  std::to_string(bound) + "), got " + std::to_string(level1_p_min));
    if (!(level1_dwell_s >= 0.0))
      throw std::invalid_argument("hierarchical bank: level1_dwell_s must be >= 0 (0: the level-0 dwell), got " +
                                  std::to_string(level1_dwell_s));
  }

  static void check_partial(double partial_p_min, int n_partial, int k, double p_min, double threshold) {
    if (!(partial_p_min >= 0.0) || !std::isfinite(partial_p_min))
      throw std::invalid_argument("hierarchical bank: partial_p_min must be >= 0 (0: the level-0 floor), got " +
                                  std::to_string(partial_p_min));
    if (partial_p_min == 0.0) return;
    if (n_partial == 0)
      throw std::invalid_argument("hierarchical bank: partial_p_min is set but the bank has no partial-loss "
                                  "hypothesis (design --partial-loss)");
    const double others = static_cast<double>(k - 1 - n_partial) * p_min;
    if (!(n_partial * partial_p_min + others < 1.0 - threshold))
      throw std::invalid_argument("hierarchical bank: partial_p_min " + std::to_string(partial_p_min) + " for " +
                                  std::to_string(n_partial) + " partial hypotheses leaves no hypothesis room to "
                                  "pass the threshold: n_partial partial_p_min + the others' floors must stay "
                                  "below 1 - threshold = " + std::to_string(1.0 - threshold));
  }

  static bool own_level1_dwell(int level, double level1_dwell_s) noexcept {
    return level == 1 && level1_dwell_s > 0.0;
  }
  static double level1_dwell(double level1_dwell_s, double level0_dwell_s) noexcept {
    return level1_dwell_s > 0.0 ? level1_dwell_s : level0_dwell_s;
  }

  static double floor_scale(int level, bool partial, double partial_p_min, double p_min) noexcept {
    return level == 0 && p_min > 0.0 && partial ? partial_p_min / p_min : 1.0;
  }

  template <class Bank, class Flags>
  static void apply(Bank& bank, int level, double p_min, double level1_p_min, double partial_p_min,
                    const Flags& level0_partial) noexcept {
    if (partial_p_min > 0.0)
      for (int k = 1; k < bank.size(); ++k)
        bank.set_floor_scale(k, floor_scale(level, level0_partial[static_cast<std::size_t>(k)] != 0,
                                            partial_p_min, p_min));
    if (level == 1 && level1_p_min > 0.0)
      bank.set_p_min(level1_p_min, 2, p_min);
    else
      bank.set_p_min(p_min);
  }
};

}  // namespace f16mmae
