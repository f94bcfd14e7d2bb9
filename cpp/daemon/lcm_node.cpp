#include "lcm_node.h"

#include "wire.h"

#include <cstdio>

namespace f16mmae::daemon {

void MessageCounts::count(Fate f) noexcept {
  switch (f) {
    case Fate::used: ++used; break;
    case Fate::rejected: ++rejected; break;
    case Fate::duplicate: ++duplicate; break;
    case Fate::out_of_order: ++out_of_order; break;
    case Fate::resynchronised: ++resynchronised; break;
  }
}

LcmNode::LcmNode(lcm_t* lcm, const Channels& channels, Executive& executive, FrameAuth* auth)
    : lcm_(lcm), channels_(channels), executive_(executive), auth_(auth) {
  subs_[0] = lcm_subscribe(lcm_, channels_.sensors.c_str(), &LcmNode::on_sensor, this);
  subs_[1] = lcm_subscribe(lcm_, channels_.commands.c_str(), &LcmNode::on_command, this);
  subs_[2] = lcm_subscribe(lcm_, channels_.reset.c_str(), &LcmNode::on_reset, this);
}

LcmNode::~LcmNode() {
  for (auto* s : subs_)
    if (s) lcm_unsubscribe(lcm_, s);
}

bool LcmNode::admit(const lcm_recv_buf_t* rbuf, const char* channel, std::int64_t& last_sequence) noexcept {
  ++counts_.received;
  if (auth_ == nullptr) return true;
  switch (auth_->check(channel, static_cast<const std::uint8_t*>(rbuf->data), rbuf->data_size, last_sequence)) {
    case FrameAuth::Check::ok: return true;
    case FrameAuth::Check::unauthenticated: ++counts_.unauthenticated; return false;
    case FrameAuth::Check::replayed: ++counts_.replayed; return false;
  }
  return false;
}

void LcmNode::on_sensor(const lcm_recv_buf_t* rbuf, const char* channel, void* user) {
  auto* self = static_cast<LcmNode*>(user);
  self->last_sensor_arrival_ = std::chrono::steady_clock::now();
  ++self->sensor_messages_;
  if (!self->admit(rbuf, channel, self->last_sequence_[0])) return;
  if (!decode_message(rbuf->data, rbuf->data_size, self->sensor_)) {
    ++self->counts_.undecodable;
    return;
  }
  const Fate fate = self->executive_.on_sensor(self->sensor_);
  self->counts_.count(fate);
  if (fate != Fate::used && fate != Fate::resynchronised) return;
  if (self->auth_)
    self->auth_->sign(self->channels_.status.c_str(), self->executive_.mutable_encoded_status(),
                      static_cast<std::size_t>(self->executive_.encoded_status_size()));
  if (lcm_publish(self->lcm_, self->channels_.status.c_str(), self->executive_.encoded_status(),
                  static_cast<unsigned int>(self->executive_.encoded_status_size())) == 0) {
    ++self->published_;
    self->sensor_to_publish_.record(std::chrono::duration_cast<std::chrono::nanoseconds>(
        std::chrono::steady_clock::now() - self->last_sensor_arrival_).count());
  } else {
    ++self->counts_.publish_errors;
  }
}

void LcmNode::on_command(const lcm_recv_buf_t* rbuf, const char* channel, void* user) {
  auto* self = static_cast<LcmNode*>(user);
  if (!self->admit(rbuf, channel, self->last_sequence_[1])) return;
  if (!decode_message(rbuf->data, rbuf->data_size, self->command_)) {
    ++self->counts_.undecodable;
    return;
  }
  self->counts_.count(self->executive_.on_command(self->command_));
}

void LcmNode::on_reset(const lcm_recv_buf_t* rbuf, const char* channel, void* user) {
  auto* self = static_cast<LcmNode*>(user);
  if (!self->admit(rbuf, channel, self->last_sequence_[2])) return;
  if (!decode_message(rbuf->data, rbuf->data_size, self->reset_)) {  // not the per-frame path
    ++self->counts_.undecodable;
    return;
  }
  self->executive_.on_reset();
  ++self->resets_;
  self->counts_.count(Fate::used);
}

std::string LcmNode::statistics_json() const {
  const MessageCounts& m = counts_;
  const executive::SequencerCounters& c = executive_.counters();
  char head[768];
  std::snprintf(head, sizeof head,
                "{\"messages\": {\"received\": %lld, \"used\": %lld, \"rejected\": %lld, \"duplicate\": %lld, "
                "\"out_of_order\": %lld, \"resynchronised\": %lld, \"undecodable\": %lld, \"unauthenticated\": %lld, "
                "\"replayed\": %lld, \"publish_errors\": %lld}, \"authenticated\": %s, \"frames\": {\"updated\": %lld, \"commands_applied\": %lld, \"rejected\": %lld, \"duplicate\": %lld, "
                "\"out_of_order\": %lld, \"resynchronised\": %lld, \"stale\": %lld, \"commands_missed\": %lld}, "
                "\"statuses_published\": %lld, \"resets\": %lld, \"warm_ups\": %lld, ",
                static_cast<long long>(m.received), static_cast<long long>(m.used), static_cast<long long>(m.rejected),
                static_cast<long long>(m.duplicate), static_cast<long long>(m.out_of_order),
                static_cast<long long>(m.resynchronised), static_cast<long long>(m.undecodable),
                static_cast<long long>(m.unauthenticated), static_cast<long long>(m.replayed),
                static_cast<long long>(m.publish_errors), auth_ ? "true" : "false", static_cast<long long>(c.frames_updated),
                static_cast<long long>(c.commands_applied), static_cast<long long>(c.frames_rejected),
                static_cast<long long>(c.dropped_duplicate), static_cast<long long>(c.dropped_out_of_order),
                static_cast<long long>(c.frames_resynchronised), static_cast<long long>(c.frames_stale),
                static_cast<long long>(c.commands_missed), static_cast<long long>(published_),
                static_cast<long long>(resets_), static_cast<long long>(executive_.warm_ups()));
  return head + ("\"step_us\": " + executive::quantiles_json_us(executive_.update_stats())) +
         ", \"propagate_us\": " + executive::quantiles_json_us(executive_.propagate_stats()) +
         ", \"sensor_to_publish_us\": " + executive::quantiles_json_us(sensor_to_publish_) + "}";
}

}  // namespace f16mmae::daemon
