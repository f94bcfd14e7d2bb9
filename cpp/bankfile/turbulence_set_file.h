// The turbulence-bank-set file: the member banks of a TurbulenceBankSet (turbulence_bank_set.h),
// designed for rising turbulence intensities, with each member's adaptation reference and the
// selector's settings, in one file: versioned, hashed and validated on load like the
// model-bank file (bank_file.h). Read by the Python binding (f16mmae.core.load_turbulence_set)
// and by mmae-daemon (--turbulence-banks); written by `f16mmae design --turbulence-banks`.
//
// Layout (all integers big-endian):
//   offset  size  field
//        0     8  magic "F16MMAET"
//        8     4  uint32 format version (TurbulenceSetFile::kFormatVersion)
//       12     8  uint64 payload size in bytes
//       20    32  SHA-256 of the payload
//       52     *  payload:
//                   int32 n                              members, rising intensity (2..16)
//                   per member:
//                     string level                       int32 (length + 1), bytes, NUL
//                     double adapt_reference             its adaptation's rho_0, [0, 100]
//                     double trim_time_constant_s        its trim tracking (trim_tracker.h), 0: off
//                     int64 size, size bytes             a complete model-bank file image
//                                                        (bank_file.h, checked by parse_bank_file)
//                   int32 n(n-1), doubles                selector bounds, row-major
//                   int32 n, doubles                     selector typical rho
//                   double hold_s, warm_up_s, warm_down_s, settle_s, freeze_probability
//                   int32 start, int32 start_standby
//                   double maneuver_tempering_g          version 2 on: the load-factor tempering's
//                                                        n_ref the set is flown with (g,
//                                                        maneuver_kinematics.h), 0: off; a
//                                                        version-1 file reads as 0
//                   int32 n, doubles adapt_gain          version 3 on: each member's adaptation
//                                                        gain kappa (turbulence_adaptation.h),
//                                                        (0, 1000]; an older file reads the
//                                                        core's default for every member
//                   int32 calmer_own_rho                 version 4 on: the selector's rule, 0 or
//                                                        1 (turbulence_bank_set.h); an older
//                                                        file reads 0 (the member in force's
//                                                        rho alone, the rule it was designed for)
//                   double floor_rho                     version 5 on: the selector's floor by rho
//                                                        (turbulence_bank_set.h), [0, 1e6], 0: off
//                   int32 m, doubles floor_p_min         version 5 on: m = 0 or n, each member's
//                                                        floor while its rho <= floor_rho, [0, 1e-3];
//                                                        an older file reads 0 and none (off)
// content_hash = lower-case hex SHA-256 of the payload: the set's name in mmae-daemon's status
// (bank_hash) and in the records of a flight flown with it. Deterministic: the same members
// and settings give the same bytes.
//
// validate() (on save and on load) refuses, naming the field: fewer than 2 or more than
// kMaxTurbulenceSetMembers members, a level that is empty or repeated, member banks of
// different sizes (nx, nu, nz), frame rates or hypotheses (by name and order), a scheduled
// member, an adapt_reference outside [0, 100], a trim_time_constant_s outside [0, 1e6], a
// maneuver_tempering_g outside [0, 100], an adapt_gain outside (0, 1000] or not one per member,
// and the selector settings
// check_turbulence_set_selector refuses. parse_turbulence_set_file refuses besides what the
// hashed layout refuses (bank_file.h: magic, version, truncation, hash) and every member bank
// parse_bank_file refuses (its message prefixed with the member), all as BankFileFormatError
// or std::invalid_argument with the file's name.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bankfile/bank_file.h"
#include "f16mmae/model_bank.h"
#include "f16mmae/turbulence_bank_set.h"

namespace f16mmae {

inline constexpr char kTurbulenceSetFileMagic[8] = {'F', '1', '6', 'M', 'M', 'A', 'E', 'T'};
inline constexpr int kMaxTurbulenceSetMembers = 16;
inline constexpr std::uint64_t kMaxTurbulenceSetFileBytes = kMaxTurbulenceSetMembers * kMaxBankFileBytes;

struct TurbulenceSetFile {
  static constexpr std::uint32_t kFormatVersion = 5;   // 2: maneuver_tempering_g, 3: adapt_gain, 4: calmer_own_rho, 5: floor_rho and floor_p_min; 1 to 4 are read too
  std::vector<std::string> levels;       // each member's design level ("none", "light", ...)
  std::vector<ModelBank> members;        // rising intensity
  std::vector<double> adapt_reference;   // each member's adaptation reference rho_0
  std::vector<double> trim_time_constant_s;  // each member's trim tracking time constant, s (0: off)
  TurbulenceBankSetOptions selector;
  double maneuver_tempering_g = 0.0;     // the set's recommended load-factor tempering n_ref, g (0: off)
  std::vector<double> adapt_gain;        // each member's adaptation gain kappa
  std::string content_hash;              // set by load and save

  int size() const { return static_cast<int>(members.size()); }
  // Throws std::invalid_argument "turbulence bank set: <field> ..." (header).
  void validate() const;
};

// True when the bytes begin with the set file's magic.
bool is_turbulence_set_file(const std::uint8_t* data, std::size_t size);
// The file image of a set. Validates first.
std::vector<std::uint8_t> turbulence_set_file_bytes(const TurbulenceSetFile& set);
// Parses and validates a file image; `source` names it in error messages. content_hash set.
TurbulenceSetFile parse_turbulence_set_file(const std::uint8_t* data, std::size_t size, const std::string& source);
// Reads (read_regular_file, at most kMaxTurbulenceSetFileBytes), parses and validates.
TurbulenceSetFile load_turbulence_set(const std::string& path);
// Validates, then writes the file atomically. Returns the content hash.
std::string save_turbulence_set(const TurbulenceSetFile& set, const std::string& path);

}  // namespace f16mmae
