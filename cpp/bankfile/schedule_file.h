// The scheduled-bank file: banks designed on a Mach x altitude grid (bank_schedule.h) in one
// file, versioned, hashed and validated on load like the model-bank file (bank_file.h).
//
// Layout (all integers big-endian):
//   offset  size  field
//        0     8  magic "F16MMAES"
//        8     4  uint32 format version (BankSchedule::kFormatVersion)
//       12     8  uint64 payload size in bytes
//       20    32  SHA-256 of the payload
//       52     *  payload:
//                   int32 n_mach, n_mach doubles          the Mach axis (ascending)
//                   int32 n_alt, n_alt doubles            the altitude axis, ft (ascending)
//                   int32 primary                         the node in force before air data
//                   string metadata                       int32 n (length + 1), bytes, NUL (JSON)
//                   int32 switch_state                    version 2 only: the configuration law
//                   int32 n, n doubles                    version 2 only: switch_thresholds
//                   double start_up_s                     version 3 only: the estimator start-up
//                                                         the schedule recommends, s (bank_schedule.h)
//                   int32 n_nodes, then per node:
//                     int32 i_mach, int32 i_alt           its grid index
//                     int32 layer                         version 2 only: configuration layer
//                     int32 nx, nx doubles                x_trim
//                     double adapt_reference              version 2 only: rho_0 at the node,
//                                                         NaN when not carried (bank_schedule.h)
//                     double calm_reference               version 4 only: the node's calm-air
//                                                         reference, NaN when not carried
//                     double reference_scale              version 5 only: the node's reference
//                                                         scale, NaN when not carried
//                     int64 n, n bytes                    a complete model-bank file image
//                                                         (bank_file.h, checked by parse_bank_file)
// content_hash = lower-case hex SHA-256 of the payload (deterministic: the same schedule gives
// the same bytes). Each node's bank is stored whole, so each is validated exactly as a bank
// file is, and a node can be taken out and used alone; shared parts are not factored out.
//
// Version 1 files (one layer, no adapt_reference) are still read: their nodes carry none.
// Versions 1 and 2 carry no start_up_s: they recommend none (0); versions 1 to 3 no
// calm_reference (NaN); versions 1 to 4 no reference_scale (NaN). A schedule is written as
// version 5 when its nodes carry a reference scale, else as version 4 when they carry a calm-air
// reference, else as version 3 when it recommends a start-up (start_up_s > 0), else as version
// 2, byte for byte as before (schedule_file_version). The ModelBank parse_schedule_file returns reports the
// schedule's start_up_s as its estimator.start_up_s.
// parse_schedule_file refuses, naming the file and the field (BankFileFormatError, an
// std::invalid_argument): wrong magic or version, truncation, trailing bytes, a hash
// mismatch, a declared count over its limit or over the bytes left (checked before anything
// is allocated), a node bank that parse_bank_file refuses (its message, prefixed with the
// node), then everything BankSchedule::validate refuses. The result is the primary node's
// ModelBank with `schedule` set and content_hash the schedule file's.
// load_bank (bank_file.h) reads either kind of file: a scheduled one may be up to
// kMaxScheduleFileBytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bankfile/bank_file.h"
#include "f16mmae/bank_schedule.h"

namespace f16mmae {

inline constexpr char kScheduleFileMagic[8] = {'F', '1', '6', 'M', 'M', 'A', 'E', 'S'};
inline constexpr std::int64_t kMaxScheduleAxis = 64;              // points per axis
inline constexpr std::int64_t kMaxScheduleNodes = 1024;
inline constexpr std::uint64_t kMaxScheduleFileBytes = 512ull << 20;

// The format version a schedule is written as (see above): 2 to 5.
std::uint32_t schedule_file_version(const BankSchedule& schedule);
// True when the bytes begin with the scheduled-bank magic.
bool is_schedule_file(const std::uint8_t* data, std::size_t size);

// The file image of a schedule. Validates first (throws std::invalid_argument naming the field).
std::vector<std::uint8_t> schedule_file_bytes(const BankSchedule& schedule);
// Parses and validates a file image; `source` names it in error messages.
ModelBank parse_schedule_file(const std::uint8_t* data, std::size_t size, const std::string& source);
// The payload alone (no header, no hash check), validated: what parse_schedule_file does
// after the header, for a payload of format `version` (1 to 5). Throws as
// parse_schedule_file does, without the file's name.
ModelBank decode_schedule_payload(const std::uint8_t* payload, std::size_t size,
                                  std::uint32_t version = BankSchedule::kFormatVersion);
// Validates, then writes the file atomically. Returns the content hash.
std::string save_schedule(const BankSchedule& schedule, const std::string& path);

}  // namespace f16mmae
