#include "lcm_node.h"

namespace f16mmae::daemon {

LcmNode::LcmNode(lcm_t* lcm, const Channels& channels, Executive& executive)
    : lcm_(lcm), channels_(channels), executive_(executive) {
  subs_[0] = lcm_subscribe(lcm_, channels_.sensors.c_str(), &LcmNode::on_sensor, this);
  subs_[1] = lcm_subscribe(lcm_, channels_.commands.c_str(), &LcmNode::on_command, this);
  subs_[2] = lcm_subscribe(lcm_, channels_.reset.c_str(), &LcmNode::on_reset, this);
}

LcmNode::~LcmNode() {
  for (auto* s : subs_)
    if (s) lcm_unsubscribe(lcm_, s);
}

void LcmNode::on_sensor(const lcm_recv_buf_t* rbuf, const char*, void* user) {
  auto* self = static_cast<LcmNode*>(user);
  self->last_sensor_arrival_ = std::chrono::steady_clock::now();
  ++self->sensor_messages_;
  if (self->sensor_.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) {
    ++self->undecodable_;
    return;
  }
  if (!self->executive_.on_sensor(self->sensor_)) return;
  if (lcm_publish(self->lcm_, self->channels_.status.c_str(), self->executive_.encoded_status(),
                  static_cast<unsigned int>(self->executive_.encoded_status_size())) == 0) {
    ++self->published_;
    self->sensor_to_publish_.record(std::chrono::duration_cast<std::chrono::nanoseconds>(
        std::chrono::steady_clock::now() - self->last_sensor_arrival_).count());
  } else {
    ++self->publish_errors_;
  }
}

void LcmNode::on_command(const lcm_recv_buf_t* rbuf, const char*, void* user) {
  auto* self = static_cast<LcmNode*>(user);
  if (self->command_.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) {
    ++self->undecodable_;
    return;
  }
  self->executive_.on_command(self->command_);
}

void LcmNode::on_reset(const lcm_recv_buf_t* rbuf, const char*, void* user) {
  auto* self = static_cast<LcmNode*>(user);
  lcmt_mmae_reset reset;  // not the per-frame path: a reset starts a flight
  if (reset.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) {
    ++self->undecodable_;
    return;
  }
  self->executive_.on_reset();
}

}  // namespace f16mmae::daemon
