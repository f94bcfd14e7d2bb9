#include "executive.h"

#include "f16mmae/cache_warm.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

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

// The longest name a status can carry: every name it reports is one of the bank's.
std::size_t name_capacity(const ModelBank& bank) {
  std::size_t n = 4;  // "NONE"
  for (const auto& h : bank.hypotheses) n = std::max(n, h.name.size());
  return n;
}

// One second of frames (Executive::kResyncAfterS), at least one.
std::int64_t max_gap(double frame_rate_hz) {
  if (!(frame_rate_hz > 0.0 && frame_rate_hz <= 1e6))
    throw std::invalid_argument("Executive: the bank's frame_rate_hz must be in (0, 1e6] Hz, got " +
                                std::to_string(frame_rate_hz));
  return std::max<std::int64_t>(1, std::llround(frame_rate_hz * Executive::kResyncAfterS));
}

}  // namespace

Executive::Executive(const ModelBank& bank, const HierarchicalOptions& options)
    : Executive(MmaeEstimator(bank, options), bank, bank.content_hash) {
  rehearse_with(std::unique_ptr<Executive>(new Executive(MmaeEstimator(bank, options), bank, bank.content_hash)));
}

Executive::Executive(const TurbulenceSetFile& set, const HierarchicalOptions& options)
    : Executive(MmaeEstimator(set, options), set.members.at(static_cast<std::size_t>(set.selector.start)),
                set.content_hash) {
  const ModelBank& shape = set.members[static_cast<std::size_t>(set.selector.start)];
  rehearse_with(std::unique_ptr<Executive>(new Executive(MmaeEstimator(set, options), shape, set.content_hash)));
}

void Executive::rehearse_with(std::unique_ptr<Executive> rehearsal) {
  rehearsal_ = std::move(rehearsal);  // private constructor: no make_unique
  for (int j = 0; j < MmaeEstimator::kNz; ++j) {
    rehearsal_sensor_.z[j] = estimator_.z_trim()(j);
    rehearsal_sensor_.valid[j] = 1;
  }
  const MmaeEstimator::CommandVector u_trim = estimator_.u_trim();
  for (int j = 0; j < MmaeEstimator::kNu; ++j) rehearsal_command_.u_rad[j] = u_trim(j);
  rehearsal_command_.throttle = u_trim(MmaeEstimator::kNu);  // NaN without the throttle input
  rehearsal_sensor_.mach = estimator_.air_data().mach;  // the design condition
  rehearsal_sensor_.pressure_altitude_ft = estimator_.air_data().pressure_altitude_ft;
}

Executive::~Executive() = default;

Executive::Executive(MmaeEstimator estimator, const ModelBank& bank, const std::string& hash)
    : estimator_(std::move(estimator)),
      sequencer_(max_gap(bank.frame_rate_hz)) {
  const std::size_t kNameCapacity = name_capacity(bank);
  u_held_ = estimator_.u_trim();
  const int k = estimator_.on_line();
  status_.num_hypotheses = k;
  status_.hypothesis_names.resize(k);
  status_.probabilities.assign(k, 0.0);
  for (auto& name : status_.hypothesis_names) name.reserve(kNameCapacity);
  status_.bank_hash = hash;
  status_.auth_sequence = 0;  // the transport signs (the generated struct leaves them unset)
  std::fill(std::begin(status_.auth_tag), std::end(status_.auth_tag), std::int64_t{0});
  status_.resynchronised = false;
  status_.frames_resynchronised = 0;
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

bool Executive::prepare(const FramePlan& plan) noexcept {
  if (plan.restart) {
    estimator_.reset();
    u_held_ = estimator_.u_trim();
  }
  for (std::int64_t i = 0; i < plan.catch_up; ++i) estimator_.propagate(u_held_);  // <= max gap
  return plan.apply;
}

Fate Executive::on_sensor(const lcmt_sensor_frame& frame) noexcept {
  const auto t0 = Clock::now();
  bool valid = all_finite(frame.z);
  for (auto flag : frame.valid) valid = valid && flag;
  const FramePlan plan = valid ? sequencer_.on_sensor(frame.frame) : sequencer_.on_rejected();
  if (!prepare(plan)) return plan.fate;
  MmaeEstimator::ZVector z;
  for (int j = 0; j < MmaeEstimator::kNz; ++j) z(j) = frame.z[j];
  const AirData air{frame.mach, frame.pressure_altitude_ft};
  if (!air.finite()) ++air_data_rejected_;
  estimator_.schedule(air);  // a non-finite value: the bank keeps the last usable one
  estimator_.update(z);      // finite z: always applied
  fill_status(frame, sequencer_.take_stale_since_status());
  status_.resynchronised = plan.restart;
  const std::int64_t ns = elapsed_ns(t0);
  status_.step_time_ns = static_cast<std::int32_t>(ns < INT32_MAX ? ns : INT32_MAX);
  encoded_size_ = status_.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
  update_stats_.record(elapsed_ns(t0));
  ++statuses_;
  return plan.fate;
}

Fate Executive::on_command(const lcmt_command_frame& frame) noexcept {
  const auto t0 = Clock::now();
  const bool valid = all_finite(frame.u_rad) && (!estimator_.models_throttle() || std::isfinite(frame.throttle));
  const FramePlan plan = valid ? sequencer_.on_command(frame.frame) : sequencer_.on_rejected();
  if (!prepare(plan)) return plan.fate;
  for (int j = 0; j < MmaeEstimator::kNu; ++j) u_held_(j) = frame.u_rad[j];
  u_held_(MmaeEstimator::kNu) = frame.throttle;  // propagated only by a bank that models the throttle
  estimator_.propagate(u_held_);
  propagate_stats_.record(elapsed_ns(t0));
  return plan.fate;
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
  status_.frames_resynchronised = c.frames_resynchronised;
  status_.air_data_rejected = air_data_rejected_;
  status_.turbulence_member = static_cast<std::int8_t>(estimator_.turbulence_member());
  status_.turbulence_power_ratio = estimator_.turbulence_power_ratio();
}

std::string Executive::summary() const {
  const SequencerCounters& c = sequencer_.counters();
  char line[360];
  std::snprintf(line, sizeof line,
                "frames %lld updated, %lld commands applied, %lld rejected, %lld dropped (%lld duplicate, "
                "%lld out-of-order), %lld resynchronised, %lld stale, %lld commands missed, "
                "%lld air data rejected; ",
                static_cast<long long>(c.frames_updated), static_cast<long long>(c.commands_applied),
                static_cast<long long>(c.frames_rejected), static_cast<long long>(c.frames_dropped()),
                static_cast<long long>(c.dropped_duplicate), static_cast<long long>(c.dropped_out_of_order),
                static_cast<long long>(c.frames_resynchronised), static_cast<long long>(c.frames_stale),
                static_cast<long long>(c.commands_missed), static_cast<long long>(air_data_rejected_));
  return line + ("step " + describe_us(update_stats_)) + "; propagate " + describe_us(propagate_stats_);
}

}  // namespace f16mmae::executive
