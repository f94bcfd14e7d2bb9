// libFuzzer target: the model-bank loader on arbitrary bytes, through both ways a hostile file
// reaches it: parse_bank_file (header, size, SHA-256, then the payload) and, so that mutations
// are not all stopped by the hash, decode_bank_payload + ModelBank::validate on the bytes as a
// payload; likewise the scheduled-bank loader (parse_schedule_file, decode_schedule_payload). A refusal is a std::invalid_argument (BankFileFormatError) or std::runtime_error;
// anything else -- a crash, an AddressSanitizer report, a std::bad_alloc, an allocation over
// libFuzzer's -malloc_limit_mb -- is a finding.
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "bankfile/bank_file.h"
#include "bankfile/schedule_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    f16mmae::parse_bank_file(data, size, "<fuzz>");
  } catch (const std::invalid_argument&) {
  } catch (const std::runtime_error&) {
  }
  try {
    f16mmae::decode_bank_payload(data, size).validate();
  } catch (const std::invalid_argument&) {
  } catch (const std::runtime_error&) {
  }
  try {
    f16mmae::parse_schedule_file(data, size, "<fuzz>");
  } catch (const std::invalid_argument&) {
  } catch (const std::runtime_error&) {
  }
  try {
    f16mmae::decode_schedule_payload(data, size);
  } catch (const std::invalid_argument&) {
  } catch (const std::runtime_error&) {
  }
  return 0;
}
