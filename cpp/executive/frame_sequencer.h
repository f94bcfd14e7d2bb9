// FrameSequencer — what the MMAE executive does with each frame a wire delivers.
//
// The closed loop of docs/INTERFACES.md runs, for each frame i,
//     sensor frame i -> bank.update(z_i) -> status i -> command frame i -> bank.propagate(u_i)
// so every frame index i owes the bank exactly one propagate, preceded by at most one update.
// The sequencer keeps that invariant on a wire that loses, repeats, reorders and forges frames.
// Every frame handed to it gets exactly one Fate:
//
//   p            the frame whose propagate is pending; p_updated: sensor frame p was applied
//   L            max_gap_frames: the largest gap caught up frame by frame (the executive
//                uses one second of frames, round(frame_rate_hz * 1 s))
//   frame n < 0 or n = INT64_MAX                    -> rejected (no valid frame counter)
//   sensor n     n > p + L or n < p - L             -> resynchronised (below)
//                n < p, or n == p already applied  -> dropped: duplicate if n repeats the last
//                                                     accepted sensor frame, else out-of-order
//                p <= n <= p + L                    -> used: frames p..n-1 are caught up first,
//                                                     propagated with the held command u
//                                                     (commands missed), without update (stale)
//                                                     unless p itself was updated; then update z_n
//   command n    n > p + L or n < p - L             -> resynchronised (below)
//                n < p                              -> dropped (duplicate / out-of-order)
//                p <= n <= p + L                    -> used: frames p..n-1 caught up with the held
//                                                     u, then frame n propagated with this u
//   rejected     a frame with a non-finite value or an invalid flag is counted (on_rejected)
//                and otherwise ignored: the next used frame catches up through it (stale).
// The first sensor frame after construction or reset() starts the sequence at its counter;
// commands before it are dropped as out-of-order. A status reports how many frames were
// propagated without an update since the previous status (its stale flag).
//
// Re-synchronisation. A frame more than L frames away from the sequence, ahead or behind, is
// not caught up (a forged or corrupted counter such as 2^62 would otherwise cost one
// propagate per skipped frame). It restarts the flight from the STALE STATE: the state the
// executive starts a flight in (what on_reset() gives): every filter x- = 0 (trim), level 0
// with NONE presumed at the initial probabilities, declarer restarted, held command u_trim.
// A resynchronised sensor frame n then starts the new sequence at n and is applied (a status
// marked resynchronised); a resynchronised command frame is not applied and the next sensor
// frame starts the sequence. So one frame with a wild counter costs O(1) work, and the
// traffic that follows it, whether the wild counter's or the original one's, is picked up
// again within one frame. Gaps of exactly L are still caught up.
//
// Pure bookkeeping: no transport, no estimator, no allocation. Only the constructor throws
// (std::invalid_argument for max_gap_frames < 1).
#pragma once

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace f16mmae::executive {

// What became of one frame (every frame handed to the executive gets exactly one).
enum class Fate : std::uint8_t { used, rejected, duplicate, out_of_order, resynchronised };

inline const char* fate_name(Fate f) noexcept {
  switch (f) {
    case Fate::used: return "used";
    case Fate::rejected: return "rejected";
    case Fate::duplicate: return "duplicate";
    case Fate::out_of_order: return "out-of-order";
    case Fate::resynchronised: return "resynchronised";
  }
  return "?";
}

struct SequencerCounters {
  std::int64_t frames_updated = 0;         // sensor frames used: a measurement update
  std::int64_t commands_applied = 0;       // command frames used: a propagate with their u
  std::int64_t frames_rejected = 0;        // sensor or command frames: non-finite, invalid, bad counter
  std::int64_t dropped_duplicate = 0;      // sensor or command frames repeating the last one
  std::int64_t dropped_out_of_order = 0;   // sensor or command frames older than the sequence
  std::int64_t frames_resynchronised = 0;  // sensor or command frames more than L from the sequence
  std::int64_t frames_stale = 0;           // frames propagated without a measurement update
  std::int64_t commands_missed = 0;        // frames propagated with the held command
  std::int64_t frames_dropped() const { return dropped_duplicate + dropped_out_of_order; }
};

// What to do with one frame: if `restart`, the estimator goes back to the stale state first;
// then `catch_up` propagations with the held command; then, if `apply`, the frame's own action
// (an update for a sensor frame, a propagate for a command).
struct FramePlan {
  Fate fate = Fate::out_of_order;
  std::int64_t catch_up = 0;
  bool restart = false;
  bool apply = false;
};

class FrameSequencer {
 public:
  static constexpr std::int64_t kMaxFrame = std::numeric_limits<std::int64_t>::max() - 1;

  explicit FrameSequencer(std::int64_t max_gap_frames) : max_gap_(max_gap_frames) {
    if (max_gap_frames < 1)
      throw std::invalid_argument("FrameSequencer: max_gap_frames must be >= 1, got " +
                                  std::to_string(max_gap_frames));
  }

  // Sensor frame n, finite and valid.
  FramePlan on_sensor(std::int64_t n) noexcept {
    if (n < 0 || n > kMaxFrame) return rejected();
    if (!started_) start(n);
    if (far(n)) {
      restart_sequence();
      start(n);
      take_sensor(n);
      ++counters_.frames_resynchronised;
      return {Fate::resynchronised, 0, true, true};
    }
    if (n < p_ || (n == p_ && p_updated_)) return drop(have_sensor_ && n == last_sensor_);
    FramePlan plan{Fate::used, n - p_, false, true};
    account_catch_up(plan.catch_up);
    take_sensor(n);
    ++counters_.frames_updated;
    return plan;
  }

  // Command frame n, finite.
  FramePlan on_command(std::int64_t n) noexcept {
    if (n < 0 || n > kMaxFrame) return rejected();
    if (started_ && far(n)) {
      restart_sequence();
      ++counters_.frames_resynchronised;
      return {Fate::resynchronised, 0, true, false};
    }
    if (!started_ || n < p_) return drop(started_ && have_command_ && n == last_command_);
    FramePlan plan{Fate::used, n - p_, false, true};
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
    ++counters_.commands_applied;
    return plan;
  }

  // A frame the executive found non-finite or flagged invalid.
  FramePlan on_rejected() noexcept { return rejected(); }

  // Frames propagated without an update since the last call (the status's stale count).
  std::int64_t take_stale_since_status() noexcept {
    const std::int64_t s = stale_since_status_;
    stale_since_status_ = 0;
    return s;
  }

  // Starts a new sequence (a new flight); counters are kept.
  void reset() noexcept { restart_sequence(); }

  bool started() const noexcept { return started_; }
  std::int64_t pending_frame() const noexcept { return p_; }
  std::int64_t max_gap_frames() const noexcept { return max_gap_; }
  const SequencerCounters& counters() const noexcept { return counters_; }

 private:
  // |n - p| > L, computed without overflow (0 <= n, p <= kMaxFrame).
  bool far(std::int64_t n) const noexcept { return n > p_ ? n - p_ > max_gap_ : p_ - n > max_gap_; }
  void start(std::int64_t n) noexcept {
    started_ = true;
    p_ = n;
    p_updated_ = false;
  }
  void take_sensor(std::int64_t n) noexcept {
    p_ = n;
    p_updated_ = true;
    last_sensor_ = n;
    have_sensor_ = true;
  }
  void restart_sequence() noexcept {
    started_ = false;
    p_updated_ = false;
    have_sensor_ = have_command_ = false;
    stale_since_status_ = 0;
  }
  // Frames p .. p+k-1 are propagated with the held command; all but an updated p are stale.
  void account_catch_up(std::int64_t k) noexcept {
    if (k <= 0) return;
    counters_.commands_missed += k;
    const std::int64_t stale = k - (p_updated_ ? 1 : 0);
    counters_.frames_stale += stale;
    stale_since_status_ += stale;
    p_updated_ = false;
  }
  FramePlan drop(bool duplicate) noexcept {
    if (duplicate) {
      ++counters_.dropped_duplicate;
      return {Fate::duplicate};
    }
    ++counters_.dropped_out_of_order;
    return {Fate::out_of_order};
  }
  FramePlan rejected() noexcept {
    ++counters_.frames_rejected;
    return {Fate::rejected};
  }

  std::int64_t max_gap_;
  bool started_ = false;
  std::int64_t p_ = 0;
  bool p_updated_ = false;
  std::int64_t last_sensor_ = 0, last_command_ = 0;
  bool have_sensor_ = false, have_command_ = false;
  std::int64_t stale_since_status_ = 0;
  SequencerCounters counters_;
};

}  // namespace f16mmae::executive
