// LcmNode — mmae-daemon's edge to LCM: subscribes the executive to the sensor, command and
// reset channels of an lcm_t (C API, so the callback sees the channel as a const char* and
// nothing is allocated per message by this layer), decodes each message into a
// preallocated struct (wire.h), and publishes the executive's encoded status.
//
// With a FrameAuth (--auth-key), every message received must carry a valid tag and a fresh
// sequence before it is decoded, and every status published is signed (frame_auth.h).
// Every message received gets exactly one fate, counted (MessageCounts):
//   unauthenticated  (with a key) no valid tag: forged, tampered, unsigned or another key's
//   replayed         (with a key) a valid tag on a sequence not above the last on its channel
//   undecodable      the decoder refused it (wrong type, truncated, trailing bytes)
//   used / rejected / duplicate / out-of-order / resynchronised
//                    the executive's fate for a decoded frame (frame_sequencer.h); a decoded
//                    reset is used
// so received = unauthenticated + replayed + undecodable + used + rejected + duplicate
// + out_of_order + resynchronised.
// Publishing a status can fail (publish_errors); it does not change the message's fate.
// Subscribing never throws; the node unsubscribes on destruction. The lcm_t is not owned.
#pragma once

#include "daemon_config.h"
#include "frame_auth.h"
#include "executive/executive.h"
#include "executive/step_stats.h"

#include <lcm/lcm.h>

#include "f16mmae/lcmt_mmae_reset.hpp"

#include <chrono>
#include <cstdint>
#include <string>

namespace f16mmae::daemon {

using executive::Executive;
using executive::Fate;
using executive::StepStats;

struct MessageCounts {
  std::int64_t received = 0, used = 0, rejected = 0, duplicate = 0, out_of_order = 0, resynchronised = 0,
               undecodable = 0, unauthenticated = 0, replayed = 0;
  std::int64_t publish_errors = 0;  // statuses lcm_publish refused
  void count(Fate f) noexcept;
  // received minus the sum of the fates: 0 when every message was counted once.
  std::int64_t unaccounted() const noexcept {
    return received -
           (used + rejected + duplicate + out_of_order + resynchronised + undecodable + unauthenticated + replayed);
  }
};

class LcmNode {
 public:
  // `auth` (not owned; nullptr: no authentication) must outlive the node.
  LcmNode(lcm_t* lcm, const Channels& channels, Executive& executive, FrameAuth* auth = nullptr);
  ~LcmNode();
  LcmNode(const LcmNode&) = delete;
  LcmNode& operator=(const LcmNode&) = delete;

  std::int64_t published() const { return published_; }
  // Sensor messages received so far, and when the last one was (steady clock, at the callback).
  std::int64_t sensor_messages() const { return sensor_messages_; }
  std::chrono::steady_clock::time_point last_sensor_arrival() const { return last_sensor_arrival_; }
  const MessageCounts& messages() const { return counts_; }
  std::int64_t resets() const { return resets_; }
  // Sensor message in (the callback) -> its status published (lcm_publish returned): the
  // executive's whole share of a round trip, decode and publish included, without the
  // wake-up chain before the callback that an echo shares.
  const StepStats& sensor_to_publish() const { return sensor_to_publish_; }

  // The statistics as one JSON object on one line (no newline), for tools to parse:
  // {"messages": {received, used, rejected, duplicate, out_of_order, resynchronised,
  //  undecodable, unauthenticated, replayed, publish_errors}, "authenticated", "frames": {the executive's SequencerCounters},
  //  "statuses_published", "resets", "warm_ups", and p50/p99/max in us of "step_us",
  //  "propagate_us", "sensor_to_publish_us"}.
  std::string statistics_json() const;

 private:
  static void on_sensor(const lcm_recv_buf_t* rbuf, const char* channel, void* self);
  static void on_command(const lcm_recv_buf_t* rbuf, const char* channel, void* self);
  static void on_reset(const lcm_recv_buf_t* rbuf, const char* channel, void* self);
  // Counts the message; with a key, false (counted by fate) unless its tag and sequence pass.
  bool admit(const lcm_recv_buf_t* rbuf, const char* channel, std::int64_t& last_sequence) noexcept;

  lcm_t* lcm_;
  Channels channels_;
  Executive& executive_;
  FrameAuth* auth_;
  std::int64_t last_sequence_[3] = {0, 0, 0};  // sensors, commands, reset
  lcmt_sensor_frame sensor_{};
  lcmt_command_frame command_{};
  lcmt_mmae_reset reset_{};
  lcm_subscription_t* subs_[3] = {nullptr, nullptr, nullptr};
  std::int64_t published_ = 0, sensor_messages_ = 0, resets_ = 0;
  MessageCounts counts_;
  std::chrono::steady_clock::time_point last_sensor_arrival_{};
  StepStats sensor_to_publish_;
};

}  // namespace f16mmae::daemon
