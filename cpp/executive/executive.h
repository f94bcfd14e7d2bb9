// Executive — the MMAE executive of mmae-daemon and of `f16mmae replay`, transport-free:
// decoded LCM frames in, an encoded status out. It owns the estimator (MmaeEstimator: the
// hierarchical bank of a model-bank file, or the turbulence bank set of a set file; absolute u
// and z), the FrameSequencer and the step-time statistics. It uses the LCM message types (lcm-coretypes) but no transport.
//
// Per frame (docs/INTERFACES.md), each returning the frame's Fate (frame_sequencer.h):
//   on_sensor(z_i)   rejected (non-finite z, an invalid flag, a bad counter), or dropped
//                    (duplicate, out-of-order), or resynchronised (a counter more than
//                    max_gap_frames() from the sequence: the estimator restarts from the
//                    stale state, then z_i is applied), or used: the frames the wire lost
//                    are caught up by propagating with the held command (no update: the
//                    status is marked stale), then bank.schedule(air data of the frame:
//                    mach, pressure_altitude_ft), then bank.update(z_i). Non-finite air data
//                    does not reject the frame: the schedule stays at its last usable value
//                    and the frame is counted in air_data_rejected(). A used or
//                    resynchronised sensor frame fills the status (probabilities, z_hat,
//                    level, declaration, counters) and encodes it into a buffer owned here.
//   on_command(u_i)  rejected (a non-finite u_rad, or a non-finite throttle with a bank that
//                    models the throttle), dropped, resynchronised (the estimator restarts
//                    from the stale state; u_i is not applied), or used: catch up, then
//                    bank.propagate(u_i); u_i becomes the held command (initially u_trim).
//                    u_i = (u_rad, throttle): the throttle reaches only a 6-input bank.
//   on_reset()       a new flight: estimator and sequencer back to their initial state.
// max_gap_frames() = round(frame_rate_hz * kResyncAfterS): one second of frames.
// Nothing on these paths allocates once the executive is constructed (the status message's
// vectors and strings are sized and reserved up front for the bank's longest name; the
// encode buffer is preallocated), and nothing throws. Construction throws
// std::invalid_argument for a bank this build cannot run (see MmaeEstimator).
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
  // The turbulence bank set of a set file (MmaeEstimator); the status's bank_hash is the
  // set's content hash.
  explicit Executive(const TurbulenceSetFile& set, const HierarchicalOptions& options = {});
  ~Executive();
  Executive(const Executive&) = delete;
  Executive& operator=(const Executive&) = delete;

  static constexpr double kResyncAfterS = 1.0;  // the largest gap caught up, in seconds

  // A used or resynchronised sensor frame produced a status: encoded_status() holds it.
  Fate on_sensor(const lcmt_sensor_frame& frame) noexcept;
  Fate on_command(const lcmt_command_frame& frame) noexcept;
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
  // The same bytes, for a transport to fill in the status's auth trailer (auth_sequence,
  // auth_tag: its last 40 bytes) before publishing; zeros as the executive leaves them.
  std::uint8_t* mutable_encoded_status() noexcept { return buffer_.data(); }

  const SequencerCounters& counters() const noexcept { return sequencer_.counters(); }
  // Used or resynchronised sensor frames whose air data was not finite, since construction.
  std::int64_t air_data_rejected() const noexcept { return air_data_rejected_; }
  const StepStats& update_stats() const noexcept { return update_stats_; }
  const StepStats& propagate_stats() const noexcept { return propagate_stats_; }
  const MmaeEstimator& estimator() const noexcept { return estimator_; }
  std::int64_t statuses() const noexcept { return statuses_; }
  std::int64_t max_gap_frames() const noexcept { return sequencer_.max_gap_frames(); }

  // "frames 512 updated, 511 commands applied, 0 rejected, 0 dropped (0 duplicate,
  //  0 out-of-order), 0 resynchronised, 0 stale, 0 commands missed,
  //  0 air data rejected; step p50 3.1 us, ..."
  std::string summary() const;

 private:
  // The plan's restart and catch-up; false when the frame's own action is not to follow.
  bool prepare(const FramePlan& plan) noexcept;
  void fill_status(const lcmt_sensor_frame& frame, std::int64_t stale) noexcept;

  // The executive warm_up() flies (no rehearsal of its own): `estimator`, the frame rate and
  // hypothesis names of `shape` (the bank, or the set's start member), `hash` in the status.
  Executive(MmaeEstimator estimator, const ModelBank& shape, const std::string& hash);
  void rehearse_with(std::unique_ptr<Executive> rehearsal);

  MmaeEstimator estimator_;
  std::unique_ptr<Executive> rehearsal_;  // flies trim frames for warm_up()
  lcmt_sensor_frame rehearsal_sensor_{};
  lcmt_command_frame rehearsal_command_{};
  std::int64_t warm_ups_ = 0;
  FrameSequencer sequencer_;
  StepStats update_stats_, propagate_stats_;
  MmaeEstimator::CommandVector u_held_;
  lcmt_mmae_status status_;
  std::vector<std::uint8_t> buffer_;
  int encoded_size_ = 0;
  std::int64_t statuses_ = 0;
  std::int64_t air_data_rejected_ = 0;
};

}  // namespace f16mmae::executive
