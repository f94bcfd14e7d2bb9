// FrameAuth — optional authentication of the executive's LCM messages with a pre-shared key.
//
// Every message of the link (lcmt_sensor_frame, lcmt_command_frame, lcmt_mmae_reset,
// lcmt_mmae_status) ends with the fields
//     int64_t auth_sequence;  int64_t auth_tag[4];   (the tag's 32 bytes as four big-endian words)
// so the last kTrailer = 40 bytes of its encoding are the sequence (big-endian) and the tag.
// With a key K (16 to 64 bytes, read from a file):
//     tag = HMAC-SHA256(K, channel || 0x00 || bytes[0, size - 32))      (RFC 2104)
// over the channel name and every byte of the encoding before the tag: the fingerprint, every
// field and the sequence. A sender numbers its messages from the realtime clock in
// nanoseconds at its start, +1 per message (so a restarted sender is still ahead of what its
// receivers have seen). A receiver accepts a message only if its tag is right (compared in
// constant time) -- else it is `unauthenticated` (forged, tampered, sent without the key or
// with another) -- and its sequence is above the last accepted on that channel -- else it is
// `replayed`.
// What a key protects and what it does not: docs/INTERFACES.md (threat model).
// Construction (from_key_file) throws std::invalid_argument naming the file and what is wrong;
// sign and check are noexcept and allocate nothing.
#pragma once

#include "bankfile/sha256.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace f16mmae::daemon {

class FrameAuth {
 public:
  static constexpr std::size_t kTrailer = 40;  // auth_sequence (8) + auth_tag (32)
  static constexpr std::size_t kMinKey = 16, kMaxKey = 64;
  enum class Check : std::uint8_t { ok, unauthenticated, replayed };

  // The key in `path`: a regular file of kMinKey..kMaxKey bytes (e.g. head -c 32 /dev/urandom).
  static FrameAuth from_key_file(const std::string& path);
  // A key given as bytes (kMinKey..kMaxKey of them).
  FrameAuth(const std::uint8_t* key, std::size_t size);

  // Numbers and signs the encoded message data[0, size) in place (its last kTrailer bytes).
  // False (nothing written) when size < kTrailer + 8.
  bool sign(const char* channel, std::uint8_t* data, std::size_t size) noexcept;
  // Checks a received message against the last sequence accepted on its channel, which it
  // advances when the message is accepted.
  Check check(const char* channel, const std::uint8_t* data, std::size_t size,
              std::int64_t& last_sequence) const noexcept;

  std::int64_t next_sequence() const noexcept { return sequence_; }

 private:
  Sha256Digest tag(const char* channel, const std::uint8_t* data, std::size_t size) const noexcept;

  std::array<std::uint8_t, 64> ipad_{}, opad_{};  // K xor 0x36.., K xor 0x5c.. (K zero-padded)
  std::int64_t sequence_;
};

}  // namespace f16mmae::daemon
