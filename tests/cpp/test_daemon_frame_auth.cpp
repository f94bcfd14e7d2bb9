// FrameAuth: a signed message passes once; a replay, any changed byte, another channel, another
// key or no signature fail; key files are refused by name. The tag's bytes are held to
// Python's hmac module in tests/python/test_frame_auth.py.
#include "daemon/frame_auth.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

using f16mmae::daemon::FrameAuth;
using Check = FrameAuth::Check;

namespace {

std::vector<std::uint8_t> key(std::uint8_t first, std::size_t n = 32) {
  std::vector<std::uint8_t> k(n);
  for (std::size_t i = 0; i < n; ++i) k[i] = static_cast<std::uint8_t>(first + 7 * i);
  return k;
}

std::vector<std::uint8_t> message() {
  std::vector<std::uint8_t> m(100);
  for (std::size_t i = 0; i < m.size(); ++i) m[i] = static_cast<std::uint8_t>(i * 13);
  return m;
}

}  // namespace

TEST(FrameAuth, ASignedMessagePassesOnceThenIsAReplay) {
  const auto k = key(1);
  FrameAuth sender(k.data(), k.size()), receiver(k.data(), k.size());
  auto m = message();
  ASSERT_TRUE(sender.sign("F16_SENSORS", m.data(), m.size()));
  std::int64_t last = 0;
  EXPECT_EQ(receiver.check("F16_SENSORS", m.data(), m.size(), last), Check::ok);
  EXPECT_GT(last, 0);
  EXPECT_EQ(receiver.check("F16_SENSORS", m.data(), m.size(), last), Check::replayed);
  auto m2 = message();
  ASSERT_TRUE(sender.sign("F16_SENSORS", m2.data(), m2.size()));
  EXPECT_EQ(receiver.check("F16_SENSORS", m2.data(), m2.size(), last), Check::ok);
  EXPECT_EQ(receiver.check("F16_SENSORS", m.data(), m.size(), last), Check::replayed);  // an older one
}

TEST(FrameAuth, AnyChangedByteAnotherChannelOrKeyOrNoSignatureIsUnauthenticated) {
  const auto k = key(1), other = key(2);
  FrameAuth sender(k.data(), k.size()), receiver(k.data(), k.size()), stranger(other.data(), other.size());
  auto m = message();
  ASSERT_TRUE(sender.sign("F16_COMMANDS", m.data(), m.size()));
  for (std::size_t i = 0; i < m.size(); ++i) {
    auto t = m;
    t[i] ^= 0x01;
    std::int64_t last = 0;
    EXPECT_EQ(receiver.check("F16_COMMANDS", t.data(), t.size(), last), Check::unauthenticated) << "byte " << i;
    EXPECT_EQ(last, 0);
  }
  std::int64_t last = 0;
  EXPECT_EQ(receiver.check("F16_SENSORS", m.data(), m.size(), last), Check::unauthenticated);
  EXPECT_EQ(receiver.check("X_F16_COMMANDS", m.data(), m.size(), last), Check::unauthenticated);
  auto forged = message();
  ASSERT_TRUE(stranger.sign("F16_COMMANDS", forged.data(), forged.size()));
  EXPECT_EQ(receiver.check("F16_COMMANDS", forged.data(), forged.size(), last), Check::unauthenticated);
  const auto unsigned_message = message();
  EXPECT_EQ(receiver.check("F16_COMMANDS", unsigned_message.data(), unsigned_message.size(), last),
            Check::unauthenticated);
  EXPECT_EQ(receiver.check("F16_COMMANDS", m.data(), 20, last), Check::unauthenticated);  // too short
  EXPECT_EQ(receiver.check("F16_COMMANDS", m.data(), m.size(), last), Check::ok);
}

TEST(FrameAuth, KeysAndKeyFilesAreCheckedByName) {
  const auto short_key = key(1, 15), long_key = key(1, 65);
  EXPECT_THROW(FrameAuth(short_key.data(), short_key.size()), std::invalid_argument);
  EXPECT_THROW(FrameAuth(long_key.data(), long_key.size()), std::invalid_argument);
  const std::string dir = ::testing::TempDir();
  const std::string small = dir + "/f16mmae_small.key", good = dir + "/f16mmae_good.key";
  std::ofstream(small, std::ios::binary) << "too short";
  {
    std::ofstream out(good, std::ios::binary);
    const auto k = key(9);
    out.write(reinterpret_cast<const char*>(k.data()), static_cast<std::streamsize>(k.size()));
  }
  try {
    FrameAuth::from_key_file(small);
    FAIL() << "a 9-byte key was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("f16mmae_small.key' holds 9 bytes; a key is 16 to 64 bytes"),
              std::string::npos) << e.what();
  }
  EXPECT_THROW(FrameAuth::from_key_file(dir + "/f16mmae_missing.key"), std::invalid_argument);
  EXPECT_THROW(FrameAuth::from_key_file("/dev/zero"), std::invalid_argument);  // not a regular file
  EXPECT_THROW(FrameAuth::from_key_file(dir), std::invalid_argument);
  FrameAuth a = FrameAuth::from_key_file(good);
  const auto k = key(9);
  FrameAuth b(k.data(), k.size());
  auto m = message();
  a.sign("C", m.data(), m.size());
  std::int64_t last = 0;
  EXPECT_EQ(b.check("C", m.data(), m.size(), last), Check::ok);
  std::remove(small.c_str());
  std::remove(good.c_str());
}
