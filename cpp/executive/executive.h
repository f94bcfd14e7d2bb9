// Executive — the MMAE executive of mmae-daemon, transport-free: decoded LCM frames in,
// an encoded status out. It owns the estimator (MmaeEstimator: the hierarchical bank of a
// model-bank file, absolute u and z), the FrameSequencer and the step-time statistics.
//
// Per frame (docs/INTERFACES.md):
//   on_sensor(z_i)   reject (non-finite z or an invalid flag), or drop (duplicate,
//                    out-of-order), or: catch up the frames the wire lost by propagating
//                    with the held command (no update: the status is marked stale), then
//                    bank.update(z_i) and fill the status (probabilities, z_hat, level,
//                    declaration, counters) and encode it into a buffer owned here.
//   on_command(u_i)  reject (non-finite), or drop, or catch up, then bank.propagate(u_i);
//                    u_i becomes the held command (initially the bank's u_trim).
//   on_reset()       a new flight: estimator and sequencer back to their initial state.
// Nothing on these paths allocates once the executive is constructed (the status message's
// vectors and strings are sized and reserved up front; the encode buffer is preallocated),
// and nothing throws. Construction throws std::invalid_argument for a bank this build cannot
// run (see MmaeEstimator).
#pragma once

#include "frame_sequencer.h"
#include "mmae_estimator.h"
#include "step_stats.h"

#include "f16mmae/lcmt_command_frame.hpp"
#include "f16mmae/lcmt_mmae_status.hpp"
#include "f16mmae/lcmt_sensor_frame.hpp"

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace f16mmae::executive {

class Executive {
 public:
  explicit Executive(const ModelBank& bank, const HierarchicalOptions& options = {});
  ~Executive();
  Executive(const Executive&) = delete;
  Executive& operator=(const Executive&) = delete;

  // Returns true when a status was produced: encoded_status() holds it.
  bool on_sensor(const lcmt_sensor_frame& frame) noexcept;
  // Returns true when the command was applied (possibly after a catch-up).
  bool on_command(const lcmt_command_frame& frame) noexcept;
  void on_reset() noexcept;
  // Ahead of the next sensor frame (WarmUpSchedule): make on_sensor run warm after the idle
  // time between frames. Measured on a 2-vCPU VM after 15.6 ms of sleep, on_sensor costs
  // ~20 us cold against ~2 us right after another on_sensor; rehearsing the estimator alone
  // and touching the data brought it to ~5.8 us, rehearsing the whole frame path and
  // touching to ~2.5 us. So warm_up
  //   1. rehearses: a second Executive of the same bank flies one trim frame (z = z_trim,
  //      u = u_trim: zero residuals, it never declares) through on_sensor and on_command --
  //      the sequencer, the update, the status fill and encode, the propagate: every
  //      instruction of the real frame, with its branch history;
  //   2. touches what on_sensor reads and writes: the estimator's working set, the sequencer,
  //      the status message and its encode buffer.
  // The estimator, the sequencer and the published status do not change; allocation-free.
  void warm_up() noexcept;
  std::int64_t warm_ups() const noexcept { return warm_ups_; }

  const lcmt_mmae_status& status() const noexcept { return status_; }
  const std::uint8_t* encoded_status() const noexcept { return buffer_.data(); }
  int encoded_status_size() const noexcept { return encoded_size_; }

  const SequencerCounters& counters() const noexcept { return sequencer_.counters(); }
  const StepStats& update_stats() const noexcept { return update_stats_; }
  const StepStats& propagate_stats() const noexcept { return propagate_stats_; }
  const MmaeEstimator& estimator() const noexcept { return estimator_; }
  std::int64_t statuses() const noexcept { return statuses_; }

  // "frames 512 updated, 0 rejected, 0 dropped (0 duplicate, 0 out-of-order), 0 stale,
  //  0 commands missed; step p50 3.1 us, p99 5.0 us, max 20.1 us; propagate p50 ..."
  std::string summary() const;

 private:
  void catch_up(std::int64_t frames) noexcept;
  void fill_status(const lcmt_sensor_frame& frame, std::int64_t stale) noexcept;

  struct WithoutRehearsal {};  // the executive warm_up() flies has no rehearsal of its own
  Executive(const ModelBank& bank, const HierarchicalOptions& options, WithoutRehearsal);

  MmaeEstimator estimator_;
  std::unique_ptr<Executive> rehearsal_;  // flies trim frames for warm_up()
  lcmt_sensor_frame rehearsal_sensor_{};
  lcmt_command_frame rehearsal_command_{};
  std::int64_t warm_ups_ = 0;
  FrameSequencer sequencer_;
  StepStats update_stats_, propagate_stats_;
  MmaeEstimator::UVector u_held_;
  lcmt_mmae_status status_;
  std::vector<std::uint8_t> buffer_;
  int encoded_size_ = 0;
  std::int64_t statuses_ = 0;
};

}  // namespace f16mmae::executive
