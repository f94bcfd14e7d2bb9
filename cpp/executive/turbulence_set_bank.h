// TurbulenceSetBank — a turbulence bank set (turbulence_bank_set.h) of a set file
// (bankfile/turbulence_set_file.h) as the executive steps it: it owns the member banks and the
// set, and answers the hierarchical bank's calls MmaeEstimator makes (update, propagate,
// schedule, reset, warm_cache, and the outputs of the member in force), so the executive, its
// status and the wire are those of one hierarchical bank.
//
// Member i is HierarchicalBank(set.members[i], its options): `options` (the daemon's flags over
// the START member's recommended settings, as the in-process set takes them:
// loop/estimator.py) with the turbulence adaptation on (the selector's measure; each filter's
// residual power per channel it reads, own_channels: turbulence_adaptation.h) and its
// reference the set file's adapt_reference[i], unless one reference was given for all
// (options.schedule.node_adapt_reference false: the flag that also overrides a schedule's
// per-node references), and its trim tracking the set file's trim_time_constant_s[i] unless
// `options` track the trim themselves (time_constant_s > 0: every member then tracks with it),
// and its load-factor tempering the set file's maneuver_tempering_g unless `options` temper
// themselves (tempering_g > 0: every member then tempers with it), and its adaptation gain the
// set file's adapt_gain[i] (no flag sets the gain).
// Throws std::invalid_argument for members the set refuses.
// Per frame noexcept and allocation-free (TurbulenceBankSet's contract).
#pragma once

#include "bankfile/turbulence_set_file.h"
#include "f16mmae/hierarchical_bank.h"
#include "f16mmae/turbulence_bank_set.h"

#include <memory>
#include <vector>

namespace f16mmae::executive {

template <class Bank>
class TurbulenceSetBank {
 public:
  using ZVector = typename Bank::ZVector;
  using UVector = typename Bank::UVector;

  TurbulenceSetBank(const TurbulenceSetFile& file, const HierarchicalOptions& options)
      : owned_(make_members(file, options)), set_(pointers(owned_), file.selector) {}

  int update(const ZVector& z_abs) noexcept { return set_.update(z_abs); }
  bool propagate(const UVector& u_abs) noexcept { return set_.propagate(u_abs); }
  void schedule(const AirData& a) noexcept { set_.schedule(a); }
  void reset() noexcept { set_.reset(); }
  void warm_cache() const noexcept { set_.warm_cache(); }

  // The member in force's outputs (HierarchicalBank's).
  int level() const noexcept { return running().level(); }
  int level1_failure() const noexcept { return running().level1_failure(); }
  int current_hypothesis() const noexcept { return running().current_hypothesis(); }
  const std::string& name(int k) const noexcept { return running().name(k); }
  decltype(auto) online() const noexcept { return running().online(); }
  decltype(auto) probabilities() const noexcept { return running().probabilities(); }
  ZVector z_hat() const noexcept { return running().z_hat(); }
  decltype(auto) u_trim() const noexcept { return running().u_trim(); }
  const ZVector& z_trim() const noexcept { return running().z_trim(); }
  const AirData& air_data() const noexcept { return running().air_data(); }
  // The options the member in force runs with (`options` with the set file's rules applied:
  // the one place they are applied; the daemon's ready line reads them here).
  const HierarchicalOptions& options() const noexcept { return running().options(); }

  const TurbulenceBankSet<Bank>& set() const noexcept { return set_; }
  TurbulenceBankSet<Bank>& set() noexcept { return set_; }
  const Bank& running() const noexcept { return set_.running(); }

 private:
  static std::vector<std::unique_ptr<Bank>> make_members(const TurbulenceSetFile& file, const HierarchicalOptions& options) {
    file.validate();
    std::vector<std::unique_ptr<Bank>> out;
    for (int i = 0; i < file.size(); ++i) {
      HierarchicalOptions o = options;
      o.bank.adaptation.enabled = true;
      o.bank.adaptation.own_channels = true;   // the selector's rho per channel each filter reads
      o.bank.adaptation.gain = file.adapt_gain[i];
      if (options.schedule.node_adapt_reference) o.bank.adaptation.reference = file.adapt_reference[i];
      if (!options.trim.enabled()) o.trim.time_constant_s = file.trim_time_constant_s[i];
      if (!options.maneuver.tempering()) o.maneuver.tempering_g = file.maneuver_tempering_g;
      out.push_back(std::make_unique<Bank>(file.members[i], o));
    }
    return out;
  }
  static std::vector<Bank*> pointers(const std::vector<std::unique_ptr<Bank>>& owned) {
    std::vector<Bank*> out;
    for (const auto& m : owned) out.push_back(m.get());
    return out;
  }

  std::vector<std::unique_ptr<Bank>> owned_;
  TurbulenceBankSet<Bank> set_;
};

}  // namespace f16mmae::executive
