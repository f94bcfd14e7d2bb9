// MmaeEstimator — the estimator the executive steps: the core's hierarchical bank
// (F16HierarchicalBank, paper Fig. 2) built from a model-bank file, fed ABSOLUTE u and z
// exactly as the in-process closed loop feeds it (docs/INTERFACES.md); the bank subtracts
// its trim:
//   schedule(a)   bank.schedule(a)   measured air data for the coming frames (air_data.h)
//   update(z)     bank.update(z)     r_k = (z - z_trim) - H_k x-_k, Bayes (eqs. 1-2), floor,
//                                    declaration, level switch / back-out
//   propagate(u)  bank.propagate(u)  x-_{i+1} = Phi_k x+_i + Bd_k (u - u_trim)
//   z_hat         blended H_out x^ + z_trim (absolute)
// Sizes are the F-16's (13 states, 5 inputs, 7 measurements, 13 filters on line).
// Construction throws std::invalid_argument naming what does not fit; the per-frame calls
// are noexcept and allocate nothing (the names it reports are the bank's own strings).
#pragma once

#include "f16mmae/hierarchical_bank.h"
#include "f16mmae/model_bank.h"

#include <Eigen/Dense>

#include <sstream>
#include <stdexcept>
#include <string>

namespace f16mmae::executive {

class MmaeEstimator {
 public:
  static constexpr int kNx = 13, kNu = 5, kNz = 7, kOnLine = 13;
  using Bank = F16HierarchicalBank;
  using ZVector = Bank::ZVector;
  using UVector = Bank::UVector;

  explicit MmaeEstimator(const ModelBank& model_bank, const HierarchicalOptions& options = {})
      : bank_(checked(model_bank), options) {}

  bool update(const ZVector& z_abs) noexcept {
    declared_now_ = bank_.update(z_abs);
    return true;
  }
  bool propagate(const UVector& u_abs) noexcept { return bank_.propagate(u_abs); }
  void schedule(const AirData& a) noexcept { bank_.schedule(a); }
  void reset() noexcept {
    bank_.reset();
    declared_now_ = -1;
  }

  // Touch the per-frame working set ahead of the next frame (cache_warm.h). Reads only.
  void warm_cache() const noexcept { bank_.warm_cache(); }

  int level() const noexcept { return bank_.level(); }
  // The single failure whose level-1 bank is on line, "" at level 0.
  const std::string& level_failure() const noexcept {
    const int f = bank_.level1_failure();
    return f < 0 ? empty_ : bank_.name(f);
  }
  // The current (presumed or last declared) hypothesis: "NONE" until a failure is declared.
  const std::string& declared() const noexcept { return bank_.name(bank_.current_hypothesis()); }
  // The hypothesis declared by the last update ("" if none; a back-out declares "NONE").
  const std::string& declaration() const noexcept { return declared_now_ < 0 ? empty_ : bank_.name(declared_now_); }
  int on_line() const noexcept { return kOnLine; }
  const std::string& hypothesis_name(int k) const noexcept { return bank_.name(bank_.online()[k]); }
  double probability(int k) const noexcept { return bank_.probabilities()(k); }
  ZVector z_hat() const noexcept { return bank_.z_hat(); }
  const UVector& u_trim() const noexcept { return bank_.u_trim(); }
  const ZVector& z_trim() const noexcept { return bank_.z_trim(); }
  const Bank& bank() const noexcept { return bank_; }
  static const char* kind() noexcept { return "hierarchical bank"; }

 private:
  static const ModelBank& checked(const ModelBank& b) {
    if (b.nx() != kNx || b.nu() != kNu || b.nz() != kNz) {
      std::ostringstream s;
      s << "mmae-daemon runs the F-16 bank (nx, nu, nz) = (" << kNx << ", " << kNu << ", " << kNz
        << "); this bank has (" << b.nx() << ", " << b.nu() << ", " << b.nz() << ")";
      throw std::invalid_argument(s.str());
    }
    return b;
  }

  Bank bank_;
  int declared_now_ = -1;
  std::string empty_;
};

}  // namespace f16mmae::executive
