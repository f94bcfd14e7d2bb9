// LcmNode over memq:// (in process): sensor frames in, statuses out on the prefixed channel,
// commands applied, resets honoured, undecodable messages counted, other channels ignored.
#include "daemon/lcm_node.h"
#include "test_executive_bank.h"

#include <gtest/gtest.h>

#include <lcm/lcm.h>

#include <memory>
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
  EXPECT_EQ(node.undecodable(), 1);

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
