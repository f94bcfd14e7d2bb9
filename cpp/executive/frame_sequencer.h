// FrameSequencer — what the MMAE executive does with each frame a wire delivers.
//
// The closed loop of docs/INTERFACES.md runs, for each frame i,
//     sensor frame i -> bank.update(z_i) -> status i -> command frame i -> bank.propagate(u_i)
// so every frame index i owes the bank exactly one propagate, preceded by at most one update.
// The sequencer keeps that invariant on a wire that loses, repeats and reorders frames:
//
//   p            the frame whose propagate is pending; p_updated: sensor frame p was applied
//   sensor n     n < p, or n == p already applied  -> dropped (duplicate if n repeats the last
//                                                     accepted sensor frame, else out-of-order)
//                n > p                              -> frames p..n-1 are caught up first:
//                                                     propagated with the held command u
//                                                     (commands missed), without update (stale)
//                                                     unless p itself was updated; then update z_n
//   command n    n < p                              -> dropped (duplicate / out-of-order)
//                n >= p                             -> frames p..n-1 caught up with the held u,
//                                                     then frame n propagated with this u
//   rejected     a frame with a non-finite value or an invalid flag is counted and otherwise
//                ignored: the next accepted frame catches up through it (stale).
// The first sensor frame after construction or reset() starts the sequence at its counter;
// commands before it are dropped. A status reports how many frames were propagated without
// an update since the previous status (its stale flag).
//
// Pure bookkeeping: no transport, no estimator, no allocation, no exceptions.
#pragma once

#include <cstdint>

namespace f16mmae::executive {

struct SequencerCounters {
  std::int64_t frames_updated = 0;      // sensor frames applied as a measurement update
  std::int64_t frames_rejected = 0;     // sensor or command frames: non-finite or invalid
  std::int64_t dropped_duplicate = 0;   // sensor or command frames repeating the last one
  std::int64_t dropped_out_of_order = 0;// sensor or command frames older than the sequence
  std::int64_t frames_stale = 0;        // frames propagated without a measurement update
  std::int64_t commands_missed = 0;     // frames propagated with the held command
  std::int64_t frames_dropped() const { return dropped_duplicate + dropped_out_of_order; }
};

// What to do with one accepted frame: `catch_up` propagations with the held command first,
// then the frame's own action (an update for a sensor frame, a propagate for a command).
struct FramePlan {
  bool accept = false;
  std::int64_t catch_up = 0;
};

class FrameSequencer {
 public:
  // Sensor frame n, finite and valid. On accept the caller propagates catch_up times with the
  // held command, then updates with z_n and publishes a status (stale_since_status()).
  FramePlan on_sensor(std::int64_t n) {
    if (!started_) {
      started_ = true;
      p_ = n;
      p_updated_ = false;
    }
    if (n < p_ || (n == p_ && p_updated_)) {
      drop(n == last_sensor_ && have_sensor_);
      return {};
    }
    FramePlan plan{true, n - p_};
    account_catch_up(plan.catch_up);
    p_ = n;
    p_updated_ = true;
    last_sensor_ = n;
    have_sensor_ = true;
    ++counters_.frames_updated;
    return plan;
  }

  // Command frame n, finite. On accept the caller propagates catch_up times with the held
  // command, then once with this command, which becomes the held command.
  FramePlan on_command(std::int64_t n) {
    if (!started_ || n < p_) {
      drop(started_ && have_command_ && n == last_command_);
      return {};
    }
    FramePlan plan{true, n - p_};
    account_catch_up(plan.catch_up);
    // frame n itself is propagated now, with this command
    if (!(plan.catch_up == 0 && p_updated_)) {
      ++counters_.frames_stale;
      ++stale_since_status_;
    }
    p_ = n + 1;
    p_updated_ = false;
    last_command_ = n;
    have_command_ = true;
    return plan;
  }

  void on_rejected() { ++counters_.frames_rejected; }

  // Frames propagated without an update since the last call (the status's stale count).
  std::int64_t take_stale_since_status() {
    const std::int64_t s = stale_since_status_;
    stale_since_status_ = 0;
    return s;
  }

  // Starts a new sequence (a new flight); counters are kept.
  void reset() {
    started_ = false;
    p_updated_ = false;
    have_sensor_ = have_command_ = false;
    stale_since_status_ = 0;
  }

  bool started() const { return started_; }
  std::int64_t pending_frame() const { return p_; }
  const SequencerCounters& counters() const { return counters_; }

 private:
  // Frames p .. p+k-1 are propagated with the held command; all but an updated p are stale.
  void account_catch_up(std::int64_t k) {
    if (k <= 0) return;
    counters_.commands_missed += k;
    const std::int64_t stale = k - (p_updated_ ? 1 : 0);
    counters_.frames_stale += stale;
    stale_since_status_ += stale;
    p_updated_ = false;
  }
  void drop(bool duplicate) {
    if (duplicate)
      ++counters_.dropped_duplicate;
    else
      ++counters_.dropped_out_of_order;
  }

  bool started_ = false;
  std::int64_t p_ = 0;
  bool p_updated_ = false;
  std::int64_t last_sensor_ = 0, last_command_ = 0;
  bool have_sensor_ = false, have_command_ = false;
  std::int64_t stale_since_status_ = 0;
  SequencerCounters counters_;
};

}  // namespace f16mmae::executive
