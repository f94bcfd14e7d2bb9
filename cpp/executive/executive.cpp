#include "executive.h"

#include "f16mmae/cache_warm.h"

#include <cmath>
#include <cstdio>

namespace f16mmae::executive {

namespace {

using Clock = std::chrono::steady_clock;

std::int64_t elapsed_ns(Clock::time_point t0) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count();
}

template <int N>
bool all_finite(const double (&v)[N]) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

// Status messages stay far below this; the buffer is sized once for the bank on line.
constexpr int kNameCapacity = 32;

}  // namespace

Executive::Executive(const ModelBank& bank, const HierarchicalOptions& options)
    : Executive(bank, options, WithoutRehearsal{}) {
  rehearsal_.reset(new Executive(bank, options, WithoutRehearsal{}));  // private constructor: no make_unique
  for (int j = 0; j < MmaeEstimator::kNz; ++j) {
    rehearsal_sensor_.z[j] = estimator_.z_trim()(j);
    rehearsal_sensor_.valid[j] = 1;
  }
  for (int j = 0; j < MmaeEstimator::kNu; ++j) rehearsal_command_.u_rad[j] = estimator_.u_trim()(j);
}

Executive::~Executive() = default;

Executive::Executive(const ModelBank& bank, const HierarchicalOptions& options, WithoutRehearsal)
    : estimator_(bank, options) {
  u_held_ = estimator_.u_trim();
  const int k = estimator_.on_line();
  status_.num_hypotheses = k;
  status_.hypothesis_names.resize(k);
  status_.probabilities.assign(k, 0.0);
  for (auto& name : status_.hypothesis_names) name.reserve(kNameCapacity);
  status_.bank_hash = bank.content_hash;
  status_.level_failure.reserve(kNameCapacity);
  status_.declared.reserve(kNameCapacity);
  status_.declaration.reserve(kNameCapacity);
  // the largest status: every name at full capacity
  lcmt_mmae_status widest = status_;
  for (auto& name : widest.hypothesis_names) name.assign(kNameCapacity, 'x');
  widest.level_failure.assign(kNameCapacity, 'x');
  widest.declared.assign(kNameCapacity, 'x');
  widest.declaration.assign(kNameCapacity, 'x');
  buffer_.assign(static_cast<std::size_t>(widest.getEncodedSize()), 0);
  fill_status(lcmt_sensor_frame{}, 0);
  encoded_size_ = 0;
}

void Executive::catch_up(std::int64_t frames) noexcept {
  for (std::int64_t i = 0; i < frames; ++i) estimator_.propagate(u_held_);
}

bool Executive::on_sensor(const lcmt_sensor_frame& frame) noexcept {
  const auto t0 = Clock::now();
  bool valid = all_finite(frame.z);
  for (auto flag : frame.valid) valid = valid && flag;
  if (!valid) {
    sequencer_.on_rejected();
    return false;
  }
  const FramePlan plan = sequencer_.on_sensor(frame.frame);
  if (!plan.accept) return false;
  catch_up(plan.catch_up);
  MmaeEstimator::ZVector z;
  for (int j = 0; j < MmaeEstimator::kNz; ++j) z(j) = frame.z[j];
  estimator_.update(z);  // finite z: always applied
  fill_status(frame, sequencer_.take_stale_since_status());
  const std::int64_t ns = elapsed_ns(t0);
  status_.step_time_ns = static_cast<std::int32_t>(ns < INT32_MAX ? ns : INT32_MAX);
  encoded_size_ = status_.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
  update_stats_.record(elapsed_ns(t0));
  ++statuses_;
  return encoded_size_ > 0;
}

bool Executive::on_command(const lcmt_command_frame& frame) noexcept {
  const auto t0 = Clock::now();
  if (!all_finite(frame.u_rad)) {
    sequencer_.on_rejected();
    return false;
  }
  const FramePlan plan = sequencer_.on_command(frame.frame);
  if (!plan.accept) return false;
  catch_up(plan.catch_up);
  for (int j = 0; j < MmaeEstimator::kNu; ++j) u_held_(j) = frame.u_rad[j];
  estimator_.propagate(u_held_);
  propagate_stats_.record(elapsed_ns(t0));
  return true;
}

void Executive::on_reset() noexcept {
  estimator_.reset();
  sequencer_.reset();
  u_held_ = estimator_.u_trim();
}

void Executive::warm_up() noexcept {
  if (rehearsal_) {  // one trim frame per warm-up, numbered on, so the sequencer never drops it
    rehearsal_sensor_.frame = rehearsal_command_.frame = warm_ups_;
    rehearsal_->on_sensor(rehearsal_sensor_);
    rehearsal_->on_command(rehearsal_command_);
  }
  estimator_.warm_cache();
  touch(sequencer_);
  touch_lines(status_.probabilities.data(), sizeof(double) * status_.probabilities.size());
  for (const auto& name : status_.hypothesis_names) touch_lines(name.data(), name.size());
  touch_lines(buffer_.data(), buffer_.size());
  ++warm_ups_;
}

void Executive::fill_status(const lcmt_sensor_frame& frame, std::int64_t stale) noexcept {
  status_.utime = frame.utime;
  status_.frame = frame.frame;
  status_.bank_level = static_cast<std::int8_t>(estimator_.level());
  status_.level_failure.assign(estimator_.level_failure());
  status_.declared.assign(estimator_.declared());
  status_.declaration.assign(estimator_.declaration());
  const int k = estimator_.on_line();
  for (int i = 0; i < k; ++i) {
    const std::string& name = estimator_.hypothesis_name(i);
    if (status_.hypothesis_names[i] != name) status_.hypothesis_names[i].assign(name);
    status_.probabilities[i] = estimator_.probability(i);
  }
  const MmaeEstimator::ZVector z_hat = estimator_.z_hat();
  for (int j = 0; j < MmaeEstimator::kNz; ++j) status_.z_hat[j] = z_hat(j);
  status_.stale = stale > 0;
  status_.frames_without_update = static_cast<std::int32_t>(stale);
  const SequencerCounters& c = sequencer_.counters();
  status_.frames_updated = c.frames_updated;
  status_.frames_rejected = c.frames_rejected;
  status_.frames_dropped = c.frames_dropped();
  status_.frames_stale = c.frames_stale;
  status_.commands_missed = c.commands_missed;
}

std::string Executive::summary() const {
  const SequencerCounters& c = sequencer_.counters();
  char line[256];
  std::snprintf(line, sizeof line,
                "frames %lld updated, %lld rejected, %lld dropped (%lld duplicate, %lld out-of-order), "
                "%lld stale, %lld commands missed; ",
                static_cast<long long>(c.frames_updated), static_cast<long long>(c.frames_rejected),
                static_cast<long long>(c.frames_dropped()), static_cast<long long>(c.dropped_duplicate),
                static_cast<long long>(c.dropped_out_of_order), static_cast<long long>(c.frames_stale),
                static_cast<long long>(c.commands_missed));
  return line + ("step " + describe_us(update_stats_)) + "; propagate " + describe_us(propagate_stats_);
}

}  // namespace f16mmae::executive
