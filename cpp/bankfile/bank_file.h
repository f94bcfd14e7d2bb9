// The model-bank file: one format, versioned, hashed, validated on load. Read by the
// Python binding (f16mmae.core.load_bank) and by mmae-daemon; written by the design.
//
// Layout (all integers big-endian, like LCM's own encoding):
//   offset  size  field
//        0     8  magic "F16MMAEB"
//        8     4  uint32 format version (ModelBank::kFormatVersion)
//       12     8  uint64 payload size in bytes
//       20    32  SHA-256 of the payload
//       52     *  payload: the LCM encoding of f16mmae.lcmt_model_bank (lcm_types/),
//                 beginning with its 8-byte type fingerprint
// content_hash = lower-case hex SHA-256 of the payload. LCM encoding is deterministic, so
// the same bank always gives the same bytes and the same hash: the hash names the bank in
// every campaign record.
//
// load_bank reads only a regular file of at most kMaxBankFileBytes (read_regular_file): it
// opens without blocking (a FIFO cannot hang it) and refuses a device, FIFO, socket or folder
// by name before reading a byte. It refuses, with a message naming the file and the problem: a
// missing file (BankFileNotFound), an unreadable or non-regular one (BankFileIoError), and
// (BankFileFormatError, an std::invalid_argument) wrong magic, an unsupported version,
// truncation or trailing bytes, a hash mismatch (corruption), a payload that is not an
// lcmt_model_bank (fingerprint) or whose declared sizes do not fit (PayloadReader checks
// each against the bytes left and the limits below before allocating, and names the
// field); then everything ModelBank::validate() rejects (std::invalid_argument naming the
// field and the value: names, settings, flight condition, shapes, finiteness, SPD A_k,
// stable Phi_k (I - K_k H_k)).
//
// Format versions 1 (estimator settings in the metadata JSON), 2 (no uninformative widths) and 3
// (no per-hypothesis evidence dwell) are refused, not upgraded, with
// a sentence saying how to regenerate the bank: upgrading would keep a JSON reader alive
// only to guess settings from free text, and the upgraded bank would have another content
// hash than its file, so records would name a bank that exists nowhere. A design is
// deterministic, so regenerating gives the same filters.
//
// save_bank validates first, so a bad bank is never written, and replaces the file
// atomically (temporary file in the same folder, fsync, rename).
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "f16mmae/model_bank.h"

namespace f16mmae {

inline constexpr char kBankFileMagic[8] = {'F', '1', '6', 'M', 'M', 'A', 'E', 'B'};
inline constexpr std::size_t kBankFileHeaderSize = 52;

// Limits of a bank the loader accepts (the F-16 bank: 13 states, 5 inputs, 7 measurements,
// 79 hypotheses, names of a few bytes, ~300 KB).
inline constexpr std::int64_t kMaxBankDimension = 256;         // nx, nu, nz; matrix rows, cols
inline constexpr std::int64_t kMaxBankHypotheses = 4096;
inline constexpr std::int64_t kMaxBankNameBytes = 256;         // a state/input/measurement/hypothesis name
inline constexpr std::int64_t kMaxBankTextBytes = 1 << 20;     // tuning, metadata
inline constexpr std::uint64_t kMaxBankFileBytes = 64u << 20;  // the whole file

// The file does not exist.
class BankFileNotFound : public std::runtime_error {
  using std::runtime_error::runtime_error;
};
// The file exists but cannot be read or written (permissions, a folder, a full disk).
class BankFileIoError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};
// The bytes are not a valid bank file of this format version.
class BankFileFormatError : public std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// The LCM payload of a bank (no header, no validation). Deterministic. Throws
// std::invalid_argument if a name holds a NUL character or a size exceeds int32.
std::vector<std::uint8_t> encode_bank_payload(const ModelBank& bank);
// Decodes a payload into a bank with content_hash set; does not validate.
// Throws BankFileFormatError naming the field (wrong fingerprint, a declared size over a
// limit or over the bytes left, a cut-off field, trailing bytes).
ModelBank decode_bank_payload(const std::uint8_t* data, std::size_t size);
// Hex SHA-256 of encode_bank_payload(bank).
std::string bank_content_hash(const ModelBank& bank);

// The complete file image (header + payload) of a validated bank. Throws what
// ModelBank::validate() throws.
std::vector<std::uint8_t> bank_file_bytes(const ModelBank& bank);
// Parses and validates a file image; `source` names it in error messages.
ModelBank parse_bank_file(const std::uint8_t* data, std::size_t size, const std::string& source);

// Validates, then writes the file atomically. Returns the content hash.
std::string save_bank(const ModelBank& bank, const std::string& path);
// The bytes of a bank file (read_regular_file, at most kMaxBankFileBytes) or of a
// scheduled-bank file (at most kMaxScheduleFileBytes, schedule_file.h).
std::vector<std::uint8_t> read_bank_bytes(const std::string& path);
// parse_schedule_file for a scheduled-bank image (its magic), else parse_bank_file.
ModelBank parse_any_bank_file(const std::uint8_t* data, std::size_t size, const std::string& source);
// Reads, checks and validates a bank file or a scheduled-bank file (schedule_file.h); the
// result has content_hash set.
ModelBank load_bank(const std::string& path);

// The hashed-file layout shared by the bank and the schedule file (header above, `magic`
// and `version` the file kind's): the image of a payload; the version of an image (after
// checking it is not empty, its magic, and that the header is whole; `kind` names the file
// kind in the wrong-magic message); and its payload, once the declared size matches the bytes
// present and the SHA-256 matches (BankFileFormatError, messages prefixed with `who`).
std::vector<std::uint8_t> hashed_file_image(const char (&magic)[8], std::uint32_t version,
                                            const std::vector<std::uint8_t>& payload);
std::uint32_t hashed_file_version(const std::uint8_t* data, std::size_t size, const char (&magic)[8],
                                  const std::string& who, const std::string& kind);
const std::uint8_t* hashed_file_payload(const std::uint8_t* data, std::size_t size, const std::string& who);
// Writes `image` to `path` atomically (temporary file in the same folder, fsync, rename);
// BankFileIoError "<what> '<path>': ..." on failure.
void write_file_atomically(const std::vector<std::uint8_t>& image, const std::string& path, const std::string& what);

// The bytes of a regular file of at most max_bytes, opened without blocking: a missing file
// is BankFileNotFound; a folder, FIFO, device or socket, or a read error, BankFileIoError; a
// larger file BankFileFormatError. Messages start with "<what> '<path>': ".
std::vector<std::uint8_t> read_regular_file(const std::string& path, std::uint64_t max_bytes,
                                            const std::string& what);

}  // namespace f16mmae
