// DepartureHold — the hierarchical bank's departure hold at level 1 (hierarchical_bank.h): no
// declaration (a dual, or NONE's back-out) while the measurements put the aircraft outside the
// filters' linearization, nor for a hold after. Eigen and std only; nothing allocates per frame.
//
// Why: every filter is linear about the trim, wings level. A surface hardover (a stabilator at
// 25 deg) departs the aircraft after its single failure f is declared; no linear hypothesis then
// explains the data and the dual that fits worst-least is declared (f+AOA, f+PIT, ...). The hold
// changes only what is declared after f, never f itself (level 0 is untouched), so a wrong first
// isolation stays visible.
//
// Rule, per accepted update while a level-1 bank is on line (HierarchicalBank::update, after the
// bank's update and before the declarer), z the readings about the trim in force (z_abs - z_trim
// - dz) and f the level-1 failure:
//   outside  <=>  |z_AOA| > aoa_rad  or  max(|z_PIT|, |z_ROL|, |z_YAW|) > rate_rad_s
//             (a channel whose sensor is f is left out: its reading is not the aircraft's;
//             a channel the bank does not measure is not checked; none of them: no hold)
//   n       = round(hold_s * frame_rate_hz) + 1      on a frame outside
//           = max(n - 1, 0)                          on a frame inside
//   held    <=>  n > 0 after this frame's count.
// On a held frame the bank declares nothing and restarts the declarer's dwell, so a declaration
// after the hold needs a whole dwell inside. A switch of level (release()) ends the hold.
// The channels are found by the measurement names AOA, PIT, ROL, YAW; their sensors by the single
// hypotheses of the same names.
// Defaults (light turbulence, nominal point): failure-free flights and complete duals keep
// |dalpha| <= 1.8 deg and rates <= 4.5 deg/s; the second declarations after a hardover came at
// |dalpha| 11-35 deg (stabilators) or rates 10-24 deg/s (flaperons, rudder): aoa 5 deg, rates
// 10 deg/s, hold 1 s. Off (enabled = false): never held, bit for bit the bank without it.
// Throws: the constructor throws std::invalid_argument, when enabled, for aoa_rad <= 0,
// rate_rad_s <= 0, or a hold_s that is negative or not finite.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace f16mmae {

// The departure hold at level 1 (departure_hold.h).
struct DepartureOptions {
  bool enabled = true;
  double aoa_rad = 5.0 * 3.14159265358979323846 / 180.0;      // |measured alpha - trim| bound
  double rate_rad_s = 10.0 * 3.14159265358979323846 / 180.0;  // |measured p|, |q|, |r| bound
  double hold_s = 1.0;                                         // held this long after the last frame outside
};

class DepartureHold {
 public:
  // Never held (the hold off).
  DepartureHold() = default;
  // measurement_names: the bank's z channels; hypothesis_names: its hypotheses (the singles AOA,
  // PIT, ROL, YAW name the sensors). Throws std::invalid_argument (header) when enabled.
  DepartureHold(const DepartureOptions& options, const std::vector<std::string>& measurement_names,
                const std::vector<std::string>& hypothesis_names, double frame_rate_hz)
      : options_(options) {
    if (!options.enabled) return;
    if (!(options.aoa_rad > 0.0) || !(options.rate_rad_s > 0.0) || !(options.hold_s >= 0.0) ||
        !std::isfinite(options.hold_s))
      throw std::invalid_argument("hierarchical bank: the departure hold needs aoa_rad > 0, rate_rad_s > 0 and a "
                                  "finite hold_s >= 0, got " + std::to_string(options.aoa_rad) + ", " +
                                  std::to_string(options.rate_rad_s) + ", " + std::to_string(options.hold_s));
    static const char* const kChannels[4] = {"AOA", "PIT", "ROL", "YAW"};
    for (int c = 0; c < 4; ++c) {
      channel_[c] = index_of(measurement_names, kChannels[c]);
      sensor_[c] = index_of(hypothesis_names, kChannels[c]);   // its single hypothesis (-1: none)
    }
    hold_frames_ = static_cast<int>(std::lround(options.hold_s * frame_rate_hz));
  }

  // One level-1 frame: counts the hold down, restarted whenever the readings z (about the trim
  // in force) leave the linearization; `failure` is the level-1 failure's hypothesis index.
  // Counts a held frame in frames(). Returns whether the frame is held.
  template <class Z>
  bool observe(const Z& z, int failure) noexcept {
    if (!options_.enabled) return false;
    bool outside = false;
    for (int c = 0; c < 4; ++c) {
      if (channel_[c] < 0 || sensor_[c] == failure) continue;
      const double bound = c == 0 ? options_.aoa_rad : options_.rate_rad_s;
      if (std::abs(z(channel_[c])) > bound) outside = true;
    }
    if (outside)
      hold_ = hold_frames_ + 1;
    else if (hold_ > 0)
      --hold_;
    if (hold_ > 0) ++frames_;
    return hold_ > 0;
  }
  // Declarations are held on this frame (the count after the last observe()).
  bool held() const noexcept { return hold_ > 0; }
  // A switch of level: the hold ends (frames() keeps its count).
  void release() noexcept { hold_ = 0; }
  // Back to the start: no hold, no frames counted.
  void reset() noexcept {
    hold_ = 0;
    frames_ = 0;
  }
  // Bumpless handover: the hold and the count of `from`; this hold's own options and channels.
  void carry_over(const DepartureHold& from) noexcept {
    hold_ = from.hold_;
    frames_ = from.frames_;
  }

  bool enabled() const noexcept { return options_.enabled; }
  int hold_frames() const noexcept { return hold_frames_; }   // round(hold_s * frame_rate_hz)
  int remaining() const noexcept { return hold_; }            // frames still held, n
  std::int64_t frames() const noexcept { return frames_; }    // held frames since reset()
  // The z index of AOA, PIT, ROL, YAW (c = 0..3), -1 when the bank does not measure it.
  int channel(int c) const noexcept { return channel_[static_cast<std::size_t>(c)]; }
  const DepartureOptions& options() const noexcept { return options_; }

 private:
  static int index_of(const std::vector<std::string>& names, const char* name) {
    const auto it = std::find(names.begin(), names.end(), name);
    return it == names.end() ? -1 : static_cast<int>(it - names.begin());
  }

  DepartureOptions options_{false, 0.0, 0.0, 0.0};
  std::array<int, 4> channel_{{-1, -1, -1, -1}};   // AOA PIT ROL YAW in z
  std::array<int, 4> sensor_{{-1, -1, -1, -1}};    // their single hypotheses
  int hold_frames_ = 0;
  int hold_ = 0;               // frames still held (0: declarations allowed)
  std::int64_t frames_ = 0;
};

}  // namespace f16mmae
