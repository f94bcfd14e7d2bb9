// SHA-256 (FIPS 180-4), the content hash of a model-bank file. Standard library only.
//
// Message schedule and compression per FIPS 180-4 Sec. 6.2: for each 64-byte block,
//   W_t = M_t (t < 16),  W_t = s1(W_{t-2}) + W_{t-7} + s0(W_{t-15}) + W_{t-16}
//   T1 = h + S1(e) + Ch(e,f,g) + K_t + W_t,  T2 = S0(a) + Maj(a,b,c)
// padding: 0x80, zeros, then the message length in bits as a big-endian uint64.
// Checked against the FIPS/NIST test vectors (tests/cpp/test_bank_file.cpp) and Python's
// hashlib (tests/python/test_bank_file.py).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace f16mmae {

using Sha256Digest = std::array<std::uint8_t, 32>;

class Sha256 {
 public:
  Sha256();
  // Appends `size` bytes to the message. Never fails.
  void update(const void* data, std::size_t size);
  // Pads, finishes and returns the digest; the object is then reset for a new message.
  Sha256Digest finish();

 private:
  void compress(const std::uint8_t* block);
  std::array<std::uint32_t, 8> state_;
  std::array<std::uint8_t, 64> buffer_;
  std::size_t buffered_ = 0;      // bytes waiting in buffer_
  std::uint64_t total_bytes_ = 0; // message length so far
};

// One-shot digest of a byte range.
Sha256Digest sha256(const void* data, std::size_t size);
// Lower-case hex of a digest (64 characters).
std::string to_hex(const Sha256Digest& digest);

}  // namespace f16mmae
