#include "frame_auth.h"

#include <sys/stat.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace f16mmae::daemon {

namespace {

std::int64_t read_be64(const std::uint8_t* p) noexcept {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];
  return static_cast<std::int64_t>(v);
}

void write_be64(std::uint8_t* p, std::int64_t value) noexcept {
  auto v = static_cast<std::uint64_t>(value);
  for (int i = 7; i >= 0; --i, v >>= 8) p[i] = static_cast<std::uint8_t>(v & 0xff);
}

}  // namespace

FrameAuth FrameAuth::from_key_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw std::invalid_argument("auth key file '" + path + "' cannot be read: " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw std::invalid_argument("auth key file '" + path + "' is not a regular file");
  if (st.st_size < static_cast<off_t>(kMinKey) || st.st_size > static_cast<off_t>(kMaxKey))
    throw std::invalid_argument("auth key file '" + path + "' holds " + std::to_string(st.st_size) +
                                " bytes; a key is 16 to 64 bytes (make one with: head -c 32 /dev/urandom > FILE)");
  std::ifstream in(path, std::ios::binary);
  std::vector<std::uint8_t> key(static_cast<std::size_t>(st.st_size));
  if (!in.read(reinterpret_cast<char*>(key.data()), static_cast<std::streamsize>(key.size())))
    throw std::invalid_argument("auth key file '" + path + "' cannot be read");
  return FrameAuth(key.data(), key.size());
}

FrameAuth::FrameAuth(const std::uint8_t* key, std::size_t size)
    : sequence_(std::chrono::duration_cast<std::chrono::nanoseconds>(
                    std::chrono::system_clock::now().time_since_epoch()).count()) {
  if (size < kMinKey || size > kMaxKey)
    throw std::invalid_argument("an auth key is 16 to 64 bytes, got " + std::to_string(size));
  for (std::size_t i = 0; i < 64; ++i) {
    const std::uint8_t k = i < size ? key[i] : 0;
    ipad_[i] = k ^ 0x36;
    opad_[i] = k ^ 0x5c;
  }
}

Sha256Digest FrameAuth::tag(const char* channel, const std::uint8_t* data, std::size_t size) const noexcept {
  Sha256 inner;
  inner.update(ipad_.data(), ipad_.size());
  inner.update(channel, std::strlen(channel) + 1);  // the name and its terminating 0x00
  inner.update(data, size - 32);
  const Sha256Digest h = inner.finish();
  Sha256 outer;
  outer.update(opad_.data(), opad_.size());
  outer.update(h.data(), h.size());
  return outer.finish();
}

bool FrameAuth::sign(const char* channel, std::uint8_t* data, std::size_t size) noexcept {
  if (size < kTrailer + 8) return false;
  write_be64(data + size - kTrailer, ++sequence_);
  const Sha256Digest t = tag(channel, data, size);
  std::memcpy(data + size - 32, t.data(), t.size());
  return true;
}

FrameAuth::Check FrameAuth::check(const char* channel, const std::uint8_t* data, std::size_t size,
                                  std::int64_t& last_sequence) const noexcept {
  if (data == nullptr || size < kTrailer + 8) return Check::unauthenticated;
  const Sha256Digest t = tag(channel, data, size);
  std::uint8_t diff = 0;  // constant time: every byte compared
  for (std::size_t i = 0; i < 32; ++i) diff |= static_cast<std::uint8_t>(t[i] ^ data[size - 32 + i]);
  if (diff != 0) return Check::unauthenticated;
  const std::int64_t sequence = read_be64(data + size - kTrailer);
  if (sequence <= last_sequence) return Check::replayed;
  last_sequence = sequence;
  return Check::ok;
}

}  // namespace f16mmae::daemon
