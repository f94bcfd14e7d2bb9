// LcmNode — mmae-daemon's edge to LCM: subscribes the executive to the sensor, command and
// reset channels of an lcm_t (C API, so the callback sees the channel as a const char* and
// nothing is allocated per message by this layer), decodes each message into a
// preallocated struct, and publishes the executive's encoded status.
// Subscribing never throws; the node unsubscribes on destruction. The lcm_t is not owned.
#pragma once

#include "daemon_config.h"
#include "executive/executive.h"
#include "executive/step_stats.h"

#include <lcm/lcm.h>

#include "f16mmae/lcmt_mmae_reset.hpp"

#include <chrono>
#include <cstdint>

namespace f16mmae::daemon {

using executive::Executive;
using executive::StepStats;

class LcmNode {
 public:
  LcmNode(lcm_t* lcm, const Channels& channels, Executive& executive);
  ~LcmNode();
  LcmNode(const LcmNode&) = delete;
  LcmNode& operator=(const LcmNode&) = delete;

  std::int64_t published() const { return published_; }
  // Sensor messages received so far, and when the last one was (steady clock, at the callback).
  std::int64_t sensor_messages() const { return sensor_messages_; }
  std::chrono::steady_clock::time_point last_sensor_arrival() const { return last_sensor_arrival_; }
  std::int64_t undecodable() const { return undecodable_; }  // messages that failed to decode
  std::int64_t publish_errors() const { return publish_errors_; }
  // Sensor message in (the callback) -> its status published (lcm_publish returned): the
  // executive's whole share of a round trip, decode and publish included, without the
  // wake-up chain before the callback that an echo shares.
  const StepStats& sensor_to_publish() const { return sensor_to_publish_; }

 private:
  static void on_sensor(const lcm_recv_buf_t* rbuf, const char* channel, void* self);
  static void on_command(const lcm_recv_buf_t* rbuf, const char* channel, void* self);
  static void on_reset(const lcm_recv_buf_t* rbuf, const char* channel, void* self);

  lcm_t* lcm_;
  Channels channels_;
  Executive& executive_;
  lcmt_sensor_frame sensor_{};
  lcmt_command_frame command_{};
  lcm_subscription_t* subs_[3] = {nullptr, nullptr, nullptr};
  std::int64_t published_ = 0, undecodable_ = 0, publish_errors_ = 0, sensor_messages_ = 0;
  std::chrono::steady_clock::time_point last_sensor_arrival_{};
  StepStats sensor_to_publish_;
};

}  // namespace f16mmae::daemon
