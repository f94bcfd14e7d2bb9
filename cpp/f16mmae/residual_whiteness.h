// ResidualWhiteness — how white the presumed filter's residuals are: the calm-air complete
// model's measure of the air when it is given channels (calm_air_complete.h). Std only.
//
// A steady-state filter whose model matches the air has white residuals. The scheduled banks
// are designed for light turbulence, and their residuals tell the two airs apart by colour far
// better than by power (docs/results/envelope_scheduled.md, round 25):
//   - in light turbulence they are about white;
//   - in calm air the filter's gains, set for gusts, chase the sensors' noise, so successive
//     residuals are negatively correlated and their low frequencies are thin.
// The power ratio ρ̄ (turbulence_adaptation.h) sees the second air only as a residual power some
// 20 % lower, within its own scatter over the first seconds of a flight.
//
// Per channel j of the set J, with r_j,i the presumed filter's residual (filter 0 of the bank on
// line) at update i, from update S on (the start's first second left out: its transient is
// low-frequency in both airs), in blocks n of B updates:
//     b_j,n = (1/B) Σ_{i∈n} r_j,i                 (the block's mean)
//     u_j,n = B b_j,n²                            (its power, scaled to one update's)
//     v_j,n = (1/B) Σ_{i∈n} r_j,i²                (the block's mean power)
//     Ū_j ← Ū_j + a_n (u_j,n − Ū_j),   V̄_j ← V̄_j + a_n (v_j,n − V̄_j),
//       a_n = max(1/n, α_B), α_B = 1 − exp(−B / (τ f))   (running_mean.h: a mean over the first
//       τ f / B blocks, then a low-pass of time constant τ)
//     W̄ = (1/|J|) Σ_{j∈J} Ū_j / V̄_j               (channels with V̄_j = 0 count as 1)
// For white residuals E[u_j] = E[v_j] = σ_j², so W̄ ≈ 1 whatever the channels' scales; residuals
// correlated negatively from one update to the next give W̄ < 1, gust-coloured ones W̄ > 1.
// W̄ is NaN until the first block after S is complete. B = 8 updates and S = 1 s at the frame
// rate f (kBlockUpdates, kStartS); τ is the caller's (the turbulence adaptation's).
// Cost per update: |J| additions and multiply-adds; per block |J| more and |J| divisions (W̄ is
// kept from one block to the next); no allocation after configure(). Non-finite residuals are
// skipped (the block waits for finite ones).
#pragma once

#include "f16mmae/running_mean.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace f16mmae {

class ResidualWhiteness {
 public:
  static constexpr int kBlockUpdates = 8;   // B
  static constexpr double kStartS = 1.0;    // S / f

  // `channels` bit j: residual j is in J (nz measurements); τ the averages' time constant in s,
  // f the update rate. Throws std::invalid_argument naming a bad argument.
  void configure(std::uint32_t channels, int nz, double time_constant_s, double frame_rate_hz) {
    if (nz < 1 || nz > 32)
      throw std::invalid_argument("residual whiteness: 1 to 32 measurements, got " + std::to_string(nz));
    if (channels == 0 || (nz < 32 && channels >> nz) != 0)
      throw std::invalid_argument("residual whiteness: the channels must be a non-empty set of the bank's " +
                                  std::to_string(nz) + " measurements");
    if (!(time_constant_s > 0.0 && frame_rate_hz > 0.0 && std::isfinite(time_constant_s * frame_rate_hz)))
      throw std::invalid_argument("residual whiteness: the time constant and frame rate must be positive and finite");
    index_.clear();
    for (int j = 0; j < nz; ++j)
      if (channels >> j & 1u) index_.push_back(j);
    sum_.assign(index_.size(), 0.0);
    sum_sq_.assign(index_.size(), 0.0);
    u_.assign(index_.size(), 0.0);
    v_.assign(index_.size(), 0.0);
    start_updates_ = static_cast<std::int64_t>(std::llround(kStartS * frame_rate_hz));
    const double alpha = 1.0 - std::exp(-kBlockUpdates / (time_constant_s * frame_rate_hz));
    blocks_length_ = running_mean_length(alpha);
    alpha_ = alpha;
    reset();
  }
  bool enabled() const noexcept { return !index_.empty(); }
  void reset() noexcept {
    updates_ = 0;
    in_block_ = 0;
    blocks_ = 0;
    value_ = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t c = 0; c < index_.size(); ++c) sum_[c] = sum_sq_[c] = u_[c] = v_[c] = 0.0;
  }
  // Another's averages and block (a bank taking over, turbulence_bank_set.h), when it averages
  // the same channels; else this one's are kept. No allocation.
  void carry_over(const ResidualWhiteness& from) noexcept {
    if (from.index_ != index_ || from.start_updates_ != start_updates_) return;
    for (std::size_t c = 0; c < index_.size(); ++c) {
      sum_[c] = from.sum_[c];
      sum_sq_[c] = from.sum_sq_[c];
      u_[c] = from.u_[c];
      v_[c] = from.v_[c];
    }
    updates_ = from.updates_;
    in_block_ = from.in_block_;
    blocks_ = from.blocks_;
    value_ = from.value_;
  }
  // One update's residual r (indexable by measurement, e.g. an Eigen vector).
  template <class R>
  void observe(const R& r) noexcept {
    if (index_.empty() || ++updates_ <= start_updates_) return;
    for (std::size_t c = 0; c < index_.size(); ++c)
      if (!std::isfinite(static_cast<double>(r[index_[c]]))) return;
    for (std::size_t c = 0; c < index_.size(); ++c) {
      const double x = r[index_[c]];
      sum_[c] += x;
      sum_sq_[c] += x * x;
    }
    if (++in_block_ < kBlockUpdates) return;
    const double a = blocks_ < blocks_length_ ? 1.0 / static_cast<double>(++blocks_) : alpha_;
    double w = 0.0;
    for (std::size_t c = 0; c < index_.size(); ++c) {
      const double mean = sum_[c] / kBlockUpdates;
      u_[c] += a * (kBlockUpdates * mean * mean - u_[c]);
      v_[c] += a * (sum_sq_[c] / kBlockUpdates - v_[c]);
      sum_[c] = sum_sq_[c] = 0.0;
      w += v_[c] > 0.0 ? u_[c] / v_[c] : 1.0;
    }
    value_ = w / static_cast<double>(index_.size());   // W̄ changes once a block
    in_block_ = 0;
  }
  // W̄ of the header (NaN before the first block).
  double value() const noexcept { return value_; }

 private:
  std::vector<int> index_;                      // J
  std::vector<double> sum_, sum_sq_, u_, v_;    // the block's sums; Ū_j, V̄_j
  std::int64_t start_updates_ = 0, updates_ = 0, blocks_ = 0, blocks_length_ = 1;
  int in_block_ = 0;
  double alpha_ = 1.0;
  double value_ = std::numeric_limits<double>::quiet_NaN();   // W̄ as of the last block
};

}  // namespace f16mmae
