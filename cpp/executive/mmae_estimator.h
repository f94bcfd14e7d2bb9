// MmaeEstimator — the estimator the executive steps: the core's hierarchical bank
// (paper Fig. 2) built from a model-bank file, fed ABSOLUTE u and z exactly as the
// in-process closed loop feeds it (docs/INTERFACES.md); the bank subtracts its trim:
//   schedule(a)   bank.schedule(a)   measured air data for the coming frames (air_data.h)
//   update(z)     bank.update(z)     r_k = (z - z_trim) - H_k x-_k, Bayes (eqs. 1-2), floor,
//                                    declaration, level switch / back-out
//   propagate(c)  bank.propagate(u)  x-_{i+1} = Phi_k x+_i + Bd_k (u - u_trim)
//   z_hat         blended H_out x^ + z_trim (absolute)
// The command c (CommandVector, 6) is what the command frame carries: the five surface
// commands, then the throttle command. u is its first five elements for a bank with five
// inputs (the throttle is not used: it may be NaN), all six for a bank that models the
// throttle (its input names end with THR).
// Sizes are the F-16's: 7 measurements, 13 filters on line (18 with partial hypotheses), and the bank file's (nx, nu)
// select the fixed-size core, as the binding does (core.HierarchicalBank):
//   (13, 5)   F16HierarchicalBank          (the shipped banks)
//   (19, 5)   F16GustHierarchicalBank      (six Dryden gust states, `f16mmae design --gust-states`)
//   (13, 6)   F16ThrottleHierarchicalBank  (the throttle input, `f16mmae design --throttle-input`)
//   (19, 6)   F16GustThrottleHierarchicalBank  (both: the scheduled default since its revision 15,
//             `f16mmae design --schedule`, whose nodes at or below 20,000 ft carry the gust states)
//   (13, 5) with 18 filters at level 0  F16PartialHierarchicalBank  (a partial-loss hypothesis per
//             surface, `f16mmae design --partial-loss F`; its level-1 banks keep spare slots off
//             line at p = 0, hierarchical_bank.h)
// or, built from a turbulence-bank-set file (turbulence_set_file.h), the set of its members
// (TurbulenceSetBank, turbulence_set_bank.h) of (19, 6) F16GustThrottleHierarchicalBank, the
// member in force answering.
// They differ in NX or NU only; z, the probabilities and the names have the same sizes, so
// the executive, the status and the wire do not depend on which one runs.
// Construction throws std::invalid_argument naming what does not fit and the sizes it runs;
// the per-frame calls are noexcept and allocate nothing (one std::visit over a variant
// chosen at construction; the names it reports are the bank's own strings).
#pragma once

#include "f16mmae/hierarchical_bank.h"
#include "f16mmae/model_bank.h"
#include "turbulence_set_bank.h"

#include <Eigen/Dense>

#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>

namespace f16mmae::executive {

class MmaeEstimator {
 public:
  static constexpr int kNu = 5, kNz = 7, kOnLine = 13;  // kNu: the surface commands
  static constexpr int kOnLinePartial = 18;              // with a partial hypothesis per surface
  static constexpr int kNuThrottle = 6;                  // with the throttle command
  static constexpr int kNxPlain = 13, kNxGust = 19;      // the state sizes it runs
  using ZVector = F16HierarchicalBank::ZVector;
  using CommandVector = Eigen::Matrix<double, kNuThrottle, 1>;  // LS RS LF RF RUD THR
  static_assert(std::is_same_v<ZVector, F16GustHierarchicalBank::ZVector> &&
                    std::is_same_v<ZVector, F16ThrottleHierarchicalBank::ZVector>,
                "the banks share z");
  static_assert(F16ThrottleHierarchicalBank::UVector::RowsAtCompileTime == kNuThrottle &&
                    F16HierarchicalBank::UVector::RowsAtCompileTime == kNu,
                "the command holds every bank's u");

  // f(bank) on the bank that runs: F16HierarchicalBank, F16GustHierarchicalBank,
  // F16ThrottleHierarchicalBank, F16GustThrottleHierarchicalBank, the set or the partial bank.
  template <class F>
  decltype(auto) visit(F&& f) noexcept {
    return std::visit([&](auto& p) -> decltype(auto) { return f(*p); }, bank_);
  }
  template <class F>
  decltype(auto) visit(F&& f) const noexcept {
    return std::visit(
        [&](const auto& p) -> decltype(auto) {
          return f(static_cast<const typename std::decay_t<decltype(p)>::element_type&>(*p));
        },
        bank_);
  }

  explicit MmaeEstimator(const ModelBank& model_bank, const HierarchicalOptions& options = {})
      : bank_(make(model_bank, options)), nx_(model_bank.nx()), nu_(model_bank.nu()) {}
  // The set of the file's members (header); throws std::invalid_argument for a set of other
  // sizes than (19, 6, 7) and what TurbulenceSetBank throws.
  explicit MmaeEstimator(const TurbulenceSetFile& set, const HierarchicalOptions& options = {})
      : bank_(make(set, options)), nx_(set.members.at(0).nx()), nu_(set.members.at(0).nu()), members_(set.size()) {}

  bool update(const ZVector& z_abs) noexcept {
    declared_now_ = visit([&](auto& b) { return b.update(z_abs); });
    return true;
  }
  // c: the five surface commands and the throttle command (used by a throttle bank only).
  bool propagate(const CommandVector& c_abs) noexcept {
    return visit([&](auto& b) {
      using U = typename std::decay_t<decltype(b)>::UVector;
      if constexpr (U::RowsAtCompileTime == kNuThrottle)
        return b.propagate(c_abs);
      else
        return b.propagate(U(c_abs.template head<U::RowsAtCompileTime>()));
    });
  }
  void schedule(const AirData& a) noexcept {
    visit([&](auto& b) { b.schedule(a); });
  }
  void reset() noexcept {
    visit([](auto& b) { b.reset(); });
    declared_now_ = -1;
  }

  // Touch the per-frame working set ahead of the next frame (cache_warm.h). Reads only.
  void warm_cache() const noexcept {
    visit([](const auto& b) { b.warm_cache(); });
  }

  // The filters' state size: 13, or 19 with the gust states.
  int nx() const noexcept { return nx_; }
  // The bank's input size: 5, or 6 when it models the throttle.
  int nu() const noexcept { return nu_; }
  bool models_throttle() const noexcept { return nu_ == kNuThrottle; }
  int level() const noexcept {
    return visit([](const auto& b) { return b.level(); });
  }
  // The single failure whose level-1 bank is on line, "" at level 0.
  const std::string& level_failure() const noexcept {
    return visit([&](const auto& b) -> const std::string& {
      const int f = b.level1_failure();
      return f < 0 ? empty_ : b.name(f);
    });
  }
  // The current (presumed or last declared) hypothesis: "NONE" until a failure is declared.
  const std::string& declared() const noexcept {
    return visit([](const auto& b) -> const std::string& { return b.name(b.current_hypothesis()); });
  }
  // The hypothesis declared by the last update ("" if none; a back-out declares "NONE").
  const std::string& declaration() const noexcept {
    return visit([&](const auto& b) -> const std::string& { return declared_now_ < 0 ? empty_ : b.name(declared_now_); });
  }
  // Filters on line: 13, or 18 for a bank with partial hypotheses (off-line slots at p = 0).
  int on_line() const noexcept {
    return std::holds_alternative<std::unique_ptr<F16PartialHierarchicalBank>>(bank_) ? kOnLinePartial : kOnLine;
  }
  const std::string& hypothesis_name(int k) const noexcept {
    return visit([&](const auto& b) -> const std::string& { return b.name(b.online()[k]); });
  }
  double probability(int k) const noexcept {
    return visit([&](const auto& b) { return b.probabilities()(k); });
  }
  ZVector z_hat() const noexcept {
    return visit([](const auto& b) -> ZVector { return b.z_hat(); });
  }
  // The bank's u_trim in force (a scheduled bank's follows the air data) as a command: the
  // throttle element NaN for a bank with five inputs.
  CommandVector u_trim() const noexcept {
    CommandVector c;
    c.fill(std::numeric_limits<double>::quiet_NaN());
    visit([&](const auto& b) { c.template head<std::decay_t<decltype(b)>::UVector::RowsAtCompileTime>() = b.u_trim(); });
    return c;
  }
  const ZVector& z_trim() const noexcept {
    return visit([](const auto& b) -> const ZVector& { return b.z_trim(); });
  }
  // The air data in force (HierarchicalBank::air_data).
  const AirData& air_data() const noexcept {
    return visit([](const auto& b) -> const AirData& { return b.air_data(); });
  }
  // The options the bank runs with: the given ones for one hierarchical bank, the member in
  // force's for a turbulence bank set (the set file's trim tracking and tempering applied:
  // TurbulenceSetBank).
  const HierarchicalOptions& options() const noexcept {
    return visit([](const auto& b) -> const HierarchicalOptions& { return b.options(); });
  }
  const char* kind() const noexcept { return members_ > 0 ? "turbulence bank set" : "hierarchical bank"; }
  // "13 states", "19 states (gust)", "13 states, 6 inputs (throttle)" or "19 states (gust), 6 inputs
  // (throttle)", for the daemon's ready line;
  // "4 members of 19 states, 6 inputs" for a turbulence bank set.
  std::string states() const {
    if (members_ > 0) return std::to_string(members_) + " members of 19 states, 6 inputs";
    if (on_line() == kOnLinePartial) return "13 states, 18 filters (partial-loss hypotheses)";
    const std::string inputs = models_throttle() ? ", 6 inputs (throttle)" : "";
    return (nx_ == kNxGust ? "19 states (gust)" : "13 states") + inputs;
  }
  // The number of member banks of a turbulence bank set, 0 for one hierarchical bank.
  int members() const noexcept { return members_; }
  // The turbulence bank set's member in force (its index), -1 for one hierarchical bank.
  int turbulence_member() const noexcept {
    const auto* s = turbulence_set();
    return s ? s->active() : -1;
  }
  // The measured residual power ratio the air is read by: the set member's in force
  // (TurbulenceBankSet::power_ratio, the selector's measure) or one hierarchical bank's
  // turbulence adaptation's (TurbulenceAdaptation::measured_power_ratio); NaN for one bank
  // without the adaptation.
  double turbulence_power_ratio() const noexcept {
    constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
    return std::visit([](const auto& p) -> double {
      using B = std::decay_t<decltype(*p)>;
      if constexpr (std::is_same_v<B, SetBank>) {
        return p->set().power_ratio();
      } else {
        const auto& a = p->bank().adaptation();
        return a.enabled() ? a.measured_power_ratio() : kNone;
      }
    }, bank_);
  }
  // The turbulence bank set, or nullptr for one hierarchical bank.
  const TurbulenceBankSet<F16GustThrottleHierarchicalBank>* turbulence_set() const noexcept {
    const auto* p = std::get_if<std::unique_ptr<SetBank>>(&bank_);
    return p ? &(*p)->set() : nullptr;
  }

 private:
  using SetBank = TurbulenceSetBank<F16GustThrottleHierarchicalBank>;
  using Variant = std::variant<std::unique_ptr<F16HierarchicalBank>, std::unique_ptr<F16GustHierarchicalBank>,
                               std::unique_ptr<F16ThrottleHierarchicalBank>, std::unique_ptr<SetBank>,
                               std::unique_ptr<F16PartialHierarchicalBank>,
                               std::unique_ptr<F16GustThrottleHierarchicalBank>>;
  // Level-0 hypotheses of a bank (the names without '+', NONE included).
  static int level0_size(const ModelBank& b) {
    int n = 0;
    for (const auto& h : b.hypotheses) n += h.name.find('+') == std::string::npos ? 1 : 0;
    return n;
  }

  static Variant make(const TurbulenceSetFile& set, const HierarchicalOptions& options) {
    set.validate();
    if (set.size() > std::numeric_limits<std::int8_t>::max())   // the status's turbulence_member is an int8
      throw std::invalid_argument("mmae-daemon runs a turbulence bank set of at most 127 members; this set has " +
                                  std::to_string(set.size()));
    const ModelBank& b = set.members[0];
    if (b.nz() != kNz || b.nx() != kNxGust || b.nu() != kNuThrottle) {
      std::ostringstream s;
      s << "mmae-daemon runs a turbulence bank set of (nx, nu, nz) = (" << kNxGust << ", " << kNuThrottle << ", "
        << kNz << ") members (the gust states and the throttle input); this set's members have (" << b.nx() << ", "
        << b.nu() << ", " << b.nz() << ")";
      throw std::invalid_argument(s.str());
    }
    return std::make_unique<SetBank>(set, options);
  }

  static Variant make(const ModelBank& b, const HierarchicalOptions& options) {
    if (b.nz() == kNz) {
      if (b.nx() == kNxPlain && b.nu() == kNu && level0_size(b) == kOnLinePartial)
        return std::make_unique<F16PartialHierarchicalBank>(b, options);
      if (b.nx() == kNxPlain && b.nu() == kNu) return std::make_unique<F16HierarchicalBank>(b, options);
      if (b.nx() == kNxGust && b.nu() == kNu) return std::make_unique<F16GustHierarchicalBank>(b, options);
      if (b.nx() == kNxPlain && b.nu() == kNuThrottle) return std::make_unique<F16ThrottleHierarchicalBank>(b, options);
      if (b.nx() == kNxGust && b.nu() == kNuThrottle)
        return std::make_unique<F16GustThrottleHierarchicalBank>(b, options);
    }
    std::ostringstream s;
    s << "mmae-daemon runs the F-16 bank (nx, nu, nz) = (" << kNxPlain << ", " << kNu << ", " << kNz << "), ("
      << kNxGust << ", " << kNu << ", " << kNz << ") with the gust states, (" << kNxPlain << ", " << kNuThrottle
      << ", " << kNz << ") with the throttle input or (" << kNxGust << ", " << kNuThrottle << ", " << kNz
      << ") with both; this bank has (" << b.nx() << ", " << b.nu() << ", " << b.nz()
      << ")";
    throw std::invalid_argument(s.str());
  }

  Variant bank_;
  int nx_ = 0;
  int nu_ = 0;
  int members_ = 0;
  int declared_now_ = -1;
  std::string empty_;
};

}  // namespace f16mmae::executive
