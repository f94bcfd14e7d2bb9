// LcmNode over memq:// (in process): sensor frames in, statuses out on the prefixed channel,
// commands applied, resets honoured, undecodable messages counted, other channels ignored.
#include "daemon/lcm_node.h"
#include "test_executive_bank.h"

#include <gtest/gtest.h>

#include <lcm/lcm.h>

#include <memory>
#include <random>
#include <string>
#include <vector>

using namespace f16mmae;
using namespace f16mmae::daemon;
using namespace f16mmae::executive;

namespace {

struct Received {
  std::vector<lcmt_mmae_status> statuses;
};

void on_status(const lcm_recv_buf_t* rbuf, const char*, void* user) {
  lcmt_mmae_status s;
  ASSERT_GT(s.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)), 0);
  static_cast<Received*>(user)->statuses.push_back(s);
}

template <class T>
void publish(lcm_t* lcm, const std::string& channel, const T& msg) {
  std::vector<std::uint8_t> buf(msg.getEncodedSize());
  msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
  ASSERT_EQ(lcm_publish(lcm, channel.c_str(), buf.data(), static_cast<unsigned>(buf.size())), 0);
}

// Dispatch everything queued (memq delivers synchronously into the queue).
void drain(lcm_t* lcm) {
  while (lcm_handle_timeout(lcm, 0) > 0) {
  }
}

lcmt_sensor_frame sensor(const ModelBank& b, long long i) {
  lcmt_sensor_frame f{};
  f.utime = i * 15625;
  f.frame = i;
  for (int j = 0; j < 7; ++j) {
    f.z[j] = b.z_trim(j) + 0.01 * j;
    f.valid[j] = 1;
  }
  return f;
}
lcmt_command_frame command(const ModelBank& b, long long i) {
  lcmt_command_frame f{};
  f.utime = i * 15625;
  f.frame = i;
  for (int j = 0; j < 5; ++j) f.u_rad[j] = b.u_trim(j);
  return f;
}

}  // namespace

TEST(LcmNode, ExchangesFramesOverMemqWithAChannelPrefix) {
  lcm_t* lcm = lcm_create("memq://");
  ASSERT_NE(lcm, nullptr);
  const ModelBank b = test_support::synthetic_bank();
  Executive ex(b);
  const Channels ch = Channels::with_prefix("T1_");
  auto node_owner = std::make_unique<LcmNode>(lcm, ch, ex);
  LcmNode& node = *node_owner;
  Received rx;
  lcm_subscription_t* sub = lcm_subscribe(lcm, "T1_MMAE_STATUS", on_status, &rx);
  for (long long i = 0; i < 5; ++i) {
    publish(lcm, ch.sensors, sensor(b, i));
    drain(lcm);
    publish(lcm, ch.commands, command(b, i));
    drain(lcm);
  }
  publish(lcm, "F16_SENSORS", sensor(b, 5));  // unprefixed: another executive's channel
  drain(lcm);
  ASSERT_EQ(rx.statuses.size(), 5u);
  for (long long i = 0; i < 5; ++i) EXPECT_EQ(rx.statuses[i].frame, i);
  EXPECT_EQ(rx.statuses.back().hypothesis_names[0], "NONE");
  EXPECT_EQ(rx.statuses.back().probabilities[0], ex.status().probabilities[0]);
  EXPECT_EQ(node.published(), 5);

  // a garbled message is counted, not applied
  const std::uint8_t junk[3] = {1, 2, 3};
  lcm_publish(lcm, ch.sensors.c_str(), junk, 3);
  drain(lcm);
  EXPECT_EQ(node.messages().undecodable, 1);

  // reset: frame 0 starts a new flight
  lcmt_mmae_reset reset;
  reset.utime = 0;
  reset.reason = "test";
  publish(lcm, ch.reset, reset);
  publish(lcm, ch.sensors, sensor(b, 0));
  drain(lcm);
  ASSERT_EQ(rx.statuses.size(), 6u);
  EXPECT_EQ(rx.statuses.back().frame, 0);
  EXPECT_EQ(ex.counters().frames_dropped(), 0);

  lcm_unsubscribe(lcm, sub);
  node_owner.reset();  // unsubscribes: before the lcm_t goes
  lcm_destroy(lcm);
}

// Every message gets exactly one fate, and the statistics line says so: a flood of random
// bytes, messages of the wrong type, truncated and overlong ones, NaN frames, duplicates,
// late frames and a wild counter, all counted.
TEST(LcmNode, CountsEveryMessageByFate) {
  lcm_t* lcm = lcm_create("memq://");
  ASSERT_NE(lcm, nullptr);
  const ModelBank b = test_support::synthetic_bank();
  Executive ex(b);
  const Channels ch = Channels::with_prefix("");
  auto node_owner = std::make_unique<LcmNode>(lcm, ch, ex);
  const LcmNode& node = *node_owner;
  std::mt19937 rng(7);
  const int kJunk = 5000;
  for (int i = 0; i < kJunk; ++i) {  // random lengths and bytes on all three channels
    std::vector<std::uint8_t> junk(rng() % 200);
    for (auto& byte : junk) byte = static_cast<std::uint8_t>(rng());
    const std::string& channel = i % 3 == 0 ? ch.sensors : i % 3 == 1 ? ch.commands : ch.reset;
    lcm_publish(lcm, channel.c_str(), junk.data(), static_cast<unsigned>(junk.size()));
    drain(lcm);
  }
  publish(lcm, ch.sensors, command(b, 0));  // the wrong type on a channel
  std::vector<std::uint8_t> buf(sensor(b, 0).getEncodedSize() + 1, 0);
  sensor(b, 0).encode(buf.data(), 0, static_cast<int>(buf.size()) - 1);
  lcm_publish(lcm, ch.sensors.c_str(), buf.data(), static_cast<unsigned>(buf.size()));      // a byte too many
  lcm_publish(lcm, ch.sensors.c_str(), buf.data(), static_cast<unsigned>(buf.size()) - 2);  // a byte too few
  drain(lcm);
  for (long long i = 0; i < 10; ++i) {
    publish(lcm, ch.sensors, sensor(b, i));
    publish(lcm, ch.sensors, sensor(b, i));  // duplicate
    publish(lcm, ch.commands, command(b, i));
    drain(lcm);
  }
  publish(lcm, ch.sensors, sensor(b, 3));  // out of order
  auto nan = sensor(b, 10);
  nan.z[0] = std::nan("");
  publish(lcm, ch.sensors, nan);                           // rejected
  publish(lcm, ch.sensors, sensor(b, 1LL << 62));          // resynchronised
  drain(lcm);
  const MessageCounts& m = node.messages();
  EXPECT_EQ(m.undecodable, kJunk + 3);
  EXPECT_EQ(m.used, 20);
  EXPECT_EQ(m.duplicate, 10);
  EXPECT_EQ(m.out_of_order, 1);
  EXPECT_EQ(m.rejected, 1);
  EXPECT_EQ(m.resynchronised, 1);
  EXPECT_EQ(m.received, kJunk + 3 + 20 + 10 + 1 + 1 + 1);
  EXPECT_EQ(m.unaccounted(), 0);
  EXPECT_EQ(node.published(), 11);
  const std::string json = node.statistics_json();
  EXPECT_NE(json.find("\"received\": " + std::to_string(m.received)), std::string::npos) << json;
  EXPECT_NE(json.find("\"undecodable\": " + std::to_string(kJunk + 3)), std::string::npos) << json;
  EXPECT_NE(json.find("\"resynchronised\": 1"), std::string::npos) << json;
  EXPECT_EQ(json.find('\n'), std::string::npos);
  node_owner.reset();
  lcm_destroy(lcm);
}

// With a key: unsigned, forged and replayed messages are dropped and counted; signed frames
// run; the status comes back signed.
TEST(LcmNode, WithAKeyOnlySignedFreshMessagesAreObeyedAndStatusesAreSigned) {
  lcm_t* lcm = lcm_create("memq://");
  ASSERT_NE(lcm, nullptr);
  const ModelBank b = test_support::synthetic_bank();
  Executive ex(b);
  std::vector<std::uint8_t> key(32, 0x5a), other(32, 0xa5);
  FrameAuth daemon_auth(key.data(), key.size()), sender(key.data(), key.size()),
      stranger(other.data(), other.size()), status_check(key.data(), key.size());
  const Channels ch = Channels::with_prefix("");
  auto node_owner = std::make_unique<LcmNode>(lcm, ch, ex, &daemon_auth);
  const LcmNode& node = *node_owner;
  Received rx;
  lcm_subscription_t* sub = lcm_subscribe(lcm, ch.status.c_str(), on_status, &rx);
  std::vector<std::vector<std::uint8_t>> raw_statuses;
  auto signed_bytes = [&](FrameAuth& a, const std::string& channel, const auto& msg) {
    std::vector<std::uint8_t> buf(msg.getEncodedSize());
    msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
    a.sign(channel.c_str(), buf.data(), buf.size());
    return buf;
  };
  auto send = [&](const std::string& channel, const std::vector<std::uint8_t>& buf) {
    lcm_publish(lcm, channel.c_str(), buf.data(), static_cast<unsigned>(buf.size()));
    drain(lcm);
  };
  publish(lcm, ch.sensors, sensor(b, 0));                                  // unsigned
  drain(lcm);
  send(ch.sensors, signed_bytes(stranger, ch.sensors, sensor(b, 0)));      // another key
  send(ch.commands, signed_bytes(sender, ch.sensors, command(b, 0)));      // signed for another channel
  const auto s0 = signed_bytes(sender, ch.sensors, sensor(b, 0));
  send(ch.sensors, s0);
  send(ch.sensors, s0);                                                    // replayed
  send(ch.commands, signed_bytes(sender, ch.commands, command(b, 0)));
  lcmt_mmae_reset reset{};
  reset.reason = "forged";
  send(ch.reset, signed_bytes(stranger, ch.reset, reset));                 // a forged reset
  send(ch.sensors, signed_bytes(sender, ch.sensors, sensor(b, 1)));
  const MessageCounts& m = node.messages();
  EXPECT_EQ(m.unauthenticated, 4);
  EXPECT_EQ(m.replayed, 1);
  EXPECT_EQ(m.used, 3);
  EXPECT_EQ(m.unaccounted(), 0);
  EXPECT_EQ(node.resets(), 0);
  ASSERT_EQ(rx.statuses.size(), 2u);
  EXPECT_EQ(rx.statuses[1].frame, 1);
  // the statuses are signed with the key and numbered upwards
  EXPECT_GT(rx.statuses[1].auth_sequence, rx.statuses[0].auth_sequence);
  std::vector<std::uint8_t> st(rx.statuses[1].getEncodedSize());
  rx.statuses[1].encode(st.data(), 0, static_cast<int>(st.size()));
  std::int64_t last = 0;
  EXPECT_EQ(status_check.check(ch.status.c_str(), st.data(), st.size(), last), FrameAuth::Check::ok);
  lcm_unsubscribe(lcm, sub);
  node_owner.reset();
  lcm_destroy(lcm);
}
