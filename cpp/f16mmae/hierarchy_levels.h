// HierarchyLevels — which hypotheses the hierarchical bank (hierarchical_bank.h) has on line at
// level 0 and in each level-1 bank, resolved once by NAME from a ModelBank. A value type: built
// at construction, read per frame (nothing allocates then). Eigen and std only.
//
// Names: "NONE" (hypothesis 0); a single failure is a name without '+' or ':'; the dual of a and
// b is "a+b" or "b+a" (a missing dual is a construction error); a partial failure of the single
// c is a name "c:MODE" without '+' (`f16mmae design --partial-loss`, e.g. "LS:loss=0.5", surface
// LS at half its effectiveness); it has no duals.
// Levels (K = 1 + singles + partials; 13 for the F-16: 5 actuators, 7 sensors):
//   level 0          {NONE, every single and partial}, in the ModelBank's order.
//   level-1 bank f   brought on line when the hypothesis in level-0 slot f + 1 is declared:
//                      a single s:        {NONE, s, s+d for every other single d}
//                      a partial c:MODE:  {NONE, c:MODE, c, c+d for every other single d}
//                    (NONE first, for back-out; the failure of c in any form; its duals are c's).
// Live slots: a level-1 bank of a bank with partial hypotheses is smaller than K. Its spare slots
//   (after the n on line) hold level-0 hypotheses not among those n (no name twice, the partial
//   ones first) and are off line: level1_live(f)[s] == 0 (the bank sets them with
//   FilterBank::set_live(s, false): p_s = 0, no floor; a level-0 switch takes them on line
//   again). A bank without partial hypotheses has no spare slot.
// Components (for HierarchicalOptions::declare_components, declarer.h): a partial hypothesis
//   c:MODE and its single c are one component, any other hypothesis its own. groups[s] = the
//   lowest live slot t whose hypothesis has the component of slot s's (an off-line slot: s
//   itself), at level 0 (level0_groups()) and in each level-1 bank (level1_groups(f)).
// Partial slots (for HierarchicalOptions::partial_p_min): level0_partial()[s] = 1 when level-0
//   slot s holds a partial hypothesis.
// Duals (for HierarchicalOptions::level1_allowance, level1_allowance.h): level1_single(f) is the
//   ModelBank index of the single whose failure level-1 bank f holds (a partial c:MODE's: c), and
//   level1_partner(f)[s] the ModelBank index of the other single d when slot s holds the dual
//   c+d, -1 for NONE, the failure's forms and the spare slots. singles(): the singles' ModelBank
//   indices, in its order.
// Sizes: K on line at every level (Eigen::Dynamic: any K = 1 + singles + partials); Indices is
//   std::array<int, K> for a fixed K, else std::vector<int>.
// Throws std::invalid_argument (the messages name the bank "hierarchical bank"): an invalid
// ModelBank (ModelBank::validate), a partial hypothesis whose single the bank lacks, a scheduled
// bank with partial hypotheses (not supported), a K that does not match the template, a bank
// without a single failure, a missing dual.
#pragma once

#include "f16mmae/model_bank.h"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace f16mmae {

template <int K>
class HierarchyLevels {
 public:
  static constexpr bool kFixed = K != Eigen::Dynamic;
  using Indices = std::conditional_t<kFixed, std::array<int, (kFixed ? K : 1)>, std::vector<int>>;

  // Validates the ModelBank and resolves the levels by name (header).
  explicit HierarchyLevels(const ModelBank& mb) {
    mb.validate();
    std::vector<int> singles, level0;   // level0: the singles and partials in the ModelBank's order
    for (int i = 1; i < static_cast<int>(mb.hypotheses.size()); ++i) {
      const std::string& n = mb.hypotheses[i].name;
      if (n.find('+') != std::string::npos) continue;
      level0.push_back(i);
      if (partial_of(n).empty()) singles.push_back(i);
    }
    std::vector<int> partial_single;   // per partial hypothesis, the ModelBank index of its single
    for (int i : level0) {
      const std::string c = partial_of(mb.hypotheses[i].name);
      if (c.empty()) continue;
      const int j = mb.find(c);
      if (j < 0 || c.find(':') != std::string::npos)
        throw std::invalid_argument("hierarchical bank: partial hypothesis '" + mb.hypotheses[i].name +
                                    "' names no single-failure hypothesis of the bank ('" + c + "')");
      partial_single.push_back(j);
    }
    partial_ = !partial_single.empty();
    if (partial_ && mb.schedule)
      throw std::invalid_argument("hierarchical bank: a scheduled bank with partial hypotheses is not supported");
    const int k = 1 + static_cast<int>(level0.size());
    if (kFixed && k != K) {
      throw std::invalid_argument("hierarchical bank: the model bank has " + std::to_string(level0.size()) +
                                  " single-failure hypotheses" +
                                  (partial_ ? " (" + std::to_string(partial_single.size()) +
                                                  " of them partial, e.g. '" +
                                                  mb.hypotheses[level0.back()].name + "')"
                                            : std::string()) +
                                  ", this bank needs " + std::to_string(K - 1));
    }
    if (k < 2) throw std::invalid_argument("hierarchical bank: the model bank has no single-failure hypothesis");
    level0_ = make_indices(k);
    level0_[0] = 0;
    for (int s = 0; s < k - 1; ++s) level0_[s + 1] = level0[s];
    const int n_singles = static_cast<int>(singles.size());
    int partial_n = 0;
    for (int f = 0; f < k - 1; ++f) {
      Indices idx = level0_;   // spare slots keep their level-0 filters, off line
      Indices live = make_indices(k);
      Indices partner = make_indices(k);
      for (int s = 0; s < k; ++s) live[s] = 0, partner[s] = -1;
      idx[0] = 0;
      idx[1] = level0[f];
      int n = 2;
      const bool partial = !partial_of(mb.hypotheses[level0[f]].name).empty();
      const int single = partial ? partial_single[partial_n++] : level0[f];
      if (partial) idx[n++] = single;
      const std::string& a = mb.hypotheses[single].name;
      for (int c = 0; c < n_singles; ++c) {
        if (singles[c] == single) continue;
        const std::string& other = mb.hypotheses[singles[c]].name;
        int j = mb.find(a + "+" + other);
        if (j < 0) j = mb.find(other + "+" + a);
        if (j < 0)
          throw std::invalid_argument("hierarchical bank: the model bank has no dual hypothesis '" + a + "+" +
                                      other + "' (nor '" + other + "+" + a + "') for the level-1 bank of " + a);
        partner[n] = singles[c];
        idx[n++] = j;
      }
      for (int s = 0; s < n; ++s) live[s] = 1;
      // the spare slots hold level-0 hypotheses not among the n on line (no name twice), the
      // partial ones first
      int spare = n;
      for (int pass = 0; pass < 2; ++pass)
        for (int s = 1; s < k && spare < k; ++s) {
          if (partial_of(mb.hypotheses[level0_[s]].name).empty() != (pass == 1)) continue;
          bool on = false;
          for (int t = 0; t < spare; ++t) on = on || idx[t] == level0_[s];
          if (!on) idx[spare++] = level0_[s];
        }
      level1_.push_back(idx);
      level1_live_.push_back(live);
      level1_single_.push_back(single);
      level1_partner_.push_back(partner);
    }
    // the component of each ModelBank hypothesis: a partial's is its single's, any other its own
    std::vector<int> component(mb.hypotheses.size());
    for (std::size_t i = 0; i < component.size(); ++i) component[i] = static_cast<int>(i);
    partial_n = 0;
    for (int i : level0)
      if (!partial_of(mb.hypotheses[i].name).empty()) component[i] = partial_single[partial_n++];
    level0_groups_ = groups_of(level0_, nullptr, component);
    for (std::size_t f = 0; f < level1_.size(); ++f)
      level1_groups_.push_back(groups_of(level1_[f], &level1_live_[f], component));
    singles_ = singles;
    level0_partial_.assign(level0_.size(), 0);
    for (std::size_t s = 1; s < level0_.size(); ++s)
      level0_partial_[s] =
          partial_of(mb.hypotheses[static_cast<std::size_t>(level0_[s])].name).empty() ? 0 : 1;
  }

  // A partial hypothesis' single: "c:MODE" -> "c" (header); "" for any other name.
  static std::string partial_of(const std::string& name) {
    const std::size_t colon = name.find(':');
    if (colon == std::string::npos || name.find('+') != std::string::npos) return std::string();
    return name.substr(0, colon);
  }

  int size() const noexcept { return static_cast<int>(level0_.size()); }   // K
  // Level 0: ModelBank indices per slot, NONE in slot 0.
  const Indices& level0() const noexcept { return level0_; }
  // The level-1 bank of the hypothesis in level-0 slot f + 1 (f in [0, K - 1)): ModelBank
  // indices per slot, NONE in slot 0, the declared hypothesis in slot 1.
  const Indices& level1(int f) const noexcept { return level1_[static_cast<std::size_t>(f)]; }
  // level1_live(f)[s] == 1: slot s of level-1 bank f is on line; 0: a spare slot, off line.
  const Indices& level1_live(int f) const noexcept { return level1_live_[static_cast<std::size_t>(f)]; }
  // The declarer's components (declarer.h) at level 0 and in level-1 bank f.
  const Indices& level0_groups() const noexcept { return level0_groups_; }
  const Indices& level1_groups(int f) const noexcept { return level1_groups_[static_cast<std::size_t>(f)]; }
  // The single whose failure level-1 bank f holds, and the other single of the dual in each of its
  // slots (-1: no dual), as ModelBank indices; the singles' ModelBank indices.
  int level1_single(int f) const noexcept { return level1_single_[static_cast<std::size_t>(f)]; }
  const Indices& level1_partner(int f) const noexcept { return level1_partner_[static_cast<std::size_t>(f)]; }
  const std::vector<int>& singles() const noexcept { return singles_; }
  // The bank has partial hypotheses (its level-1 banks have spare slots).
  bool partial() const noexcept { return partial_; }
  // level0_partial()[s] == 1: level-0 slot s holds a partial hypothesis.
  const std::vector<char>& level0_partial() const noexcept { return level0_partial_; }
  int partial_count() const noexcept {
    int n = 0;
    for (char c : level0_partial_) n += c;
    return n;
  }

 private:
  static Indices make_indices(int n) {
    Indices idx{};
    if constexpr (!kFixed) idx.assign(n, -1);
    (void)n;
    return idx;
  }
  // The components of the slots of `idx` (ModelBank indices; live[s] == 0: off line, alone):
  // group[s] = the lowest live slot t with component[idx[t]] == component[idx[s]] (declarer.h).
  static Indices groups_of(const Indices& idx, const Indices* live, const std::vector<int>& component) {
    const int n = static_cast<int>(idx.size());
    Indices g = make_indices(n);
    for (int s = 0; s < n; ++s) {
      g[s] = s;
      if (live != nullptr && (*live)[s] == 0) continue;
      for (int t = 0; t < s; ++t)
        if ((live == nullptr || (*live)[t] != 0) && component[idx[t]] == component[idx[s]]) {
          g[s] = t;
          break;
        }
    }
    return g;
  }

  Indices level0_;
  std::vector<Indices> level1_;        // level1_[f]: the level-1 bank of level-0 slot f + 1
  std::vector<Indices> level1_live_;   // level1_live_[f][s]: slot s on line in it
  std::vector<Indices> level1_groups_;
  std::vector<int> level1_single_;        // level1_single_[f]: the single of level-1 bank f
  std::vector<Indices> level1_partner_;   // level1_partner_[f][s]: the dual's other single, else -1
  std::vector<int> singles_;
  Indices level0_groups_;
  std::vector<char> level0_partial_;
  bool partial_ = false;
};

}  // namespace f16mmae
