// ResidualMonitor — the "additional voters" of Eide & Maybeck, Sec. VII: simple tests on
// each scalar residual r_j (j = 0..m-1) of one chosen filter, which for a well-matched
// filter is zero-mean, white, Gaussian, of variance A_jj (the diagonal of eq. 5's A_k).
// Eigen and std only.
//
// Over a sliding window of the last n <= N frames (N = window_frames) of channel j:
//   mean        m_j = (1/n) sum r                     statistic  mean_z = m_j / sqrt(A_jj / n)
//                                                      (N(0,1) for white noise; bias moves it)
//   whiteness   c_j = number of sign changes between consecutive samples (0 counts as +)
//               zero_crossing_rate = c_j / (n-1)       statistic  zero_crossing_z =
//                                                      (c_j - (n-1)/2) / sqrt((n-1)/4)
//               (Binomial(n-1, 1/2) for white zero-mean symmetric noise: a bias or a slow
//                oscillation gives too few crossings, an alternation too many)
//   variance    variance_ratio = (1/n) sum r^2 / A_jj  statistic  variance_z =
//                                                      (variance_ratio - 1) / sqrt(2/n)
//               (chi-square_n / n for white Gaussian noise of variance A_jj)
//   dither tone Goertzel recursion at w = 2π dither_hz / frame_rate_hz over the window:
//               s_t = r_t + 2 cos(w) s_{t-1} - s_{t-2},
//               |X|^2 = s_{n-1}^2 + s_{n-2}^2 - 2 cos(w) s_{n-1} s_{n-2}
//               tone_ratio = |X|^2 / (n A_jj)          (about Exp(1), mean 1, for white noise;
//                                                      a tone of amplitude a at dither_hz gives
//                                                      about a^2 n / (4 A_jj))
// Votes (flags): |mean_z| > mean_threshold, |zero_crossing_z| > zero_crossing_threshold,
// |variance_z| > variance_threshold, tone_ratio > tone_threshold. Defaults 5, 5, 5, 14:
// per-frame false-vote probabilities about 6e-7 (normal tails at 5 sigma) and e^-14 ≈ 8e-7
// for white Gaussian residuals. Votes are raised only once the window is full (n = N).
// The tone test is off when dither_hz = 0.
//
// Sizes: m channels (runtime), window N frames; the buffer is allocated at construction.
// Throws: the constructor throws std::invalid_argument for an A diagonal that is empty,
// non-finite or not positive, N < 2, a frame rate not positive, dither_hz outside
// [0, frame_rate_hz / 2), or a negative threshold. update() is noexcept and allocation-free;
// a residual vector with a non-finite entry (or of the wrong size) is skipped and counted.
#pragma once

#include <Eigen/Dense>

#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace f16mmae {

struct ResidualMonitorOptions {
  int window_frames = 64;              // N: 1 s at 64 Hz
  double frame_rate_hz = 64.0;
  double dither_hz = 0.0;              // known dither frequency; 0 = no tone test
  double mean_threshold = 5.0;         // |mean_z| vote
  double zero_crossing_threshold = 5.0;  // |zero_crossing_z| vote
  double variance_threshold = 5.0;     // |variance_z| vote
  double tone_threshold = 14.0;        // tone_ratio vote
};

struct ResidualChannelStatistics {
  double mean = 0.0, mean_z = 0.0;
  double zero_crossing_rate = 0.0, zero_crossing_z = 0.0;
  double variance_ratio = 0.0, variance_z = 0.0;
  double tone_ratio = 0.0;
  bool mean_vote = false, zero_crossing_vote = false, variance_vote = false, tone_vote = false;
  bool any_vote() const noexcept { return mean_vote || zero_crossing_vote || variance_vote || tone_vote; }
};

class ResidualMonitor {
 public:
  // a_diag: the m diagonal entries A_jj of the monitored filter's residual covariance.
  ResidualMonitor(const Eigen::Ref<const Eigen::VectorXd>& a_diag, const ResidualMonitorOptions& options = {})
      : options_(options), a_diag_(a_diag) {
    auto fail = [](const std::string& s) { throw std::invalid_argument("residual monitor: " + s); };
    if (a_diag_.size() == 0) fail("a_diag must have at least one entry");
    for (Eigen::Index j = 0; j < a_diag_.size(); ++j)
      if (!(a_diag_(j) > 0.0) || !std::isfinite(a_diag_(j))) {
        std::ostringstream s;
        s << "a_diag entries must be positive and finite, entry " << j << " is " << a_diag_(j);
        fail(s.str());
      }
    if (options.window_frames < 2) fail("window_frames must be >= 2, got " + std::to_string(options.window_frames));
    if (!(options.frame_rate_hz > 0.0) || !std::isfinite(options.frame_rate_hz)) {
      std::ostringstream s;
      s << "frame_rate_hz must be positive and finite, got " << options.frame_rate_hz;
      fail(s.str());
    }
    if (!(options.dither_hz >= 0.0 && options.dither_hz < 0.5 * options.frame_rate_hz)) {
      std::ostringstream s;
      s << "dither_hz must be in [0, frame_rate_hz/2 = " << 0.5 * options.frame_rate_hz << "), got "
        << options.dither_hz;
      fail(s.str());
    }
    for (double t : {options.mean_threshold, options.zero_crossing_threshold, options.variance_threshold,
                     options.tone_threshold})
      if (!(t >= 0.0)) fail("thresholds must be >= 0");
    buffer_.setZero(options.window_frames, a_diag_.size());
    stats_.resize(static_cast<std::size_t>(a_diag_.size()));
    two_cos_w_ = 2.0 * std::cos(2.0 * 3.14159265358979323846 * options.dither_hz / options.frame_rate_hz);
  }

  // Feed one residual vector (any Eigen vector expression of size m, e.g. a bank's
  // residuals().row(k)). Returns true if any channel votes after this frame.
  template <class Vector>
  bool update(const Vector& r) noexcept {
    const int m = channels();
    if (static_cast<int>(r.size()) != m) {
      ++skipped_;
      return any_vote_;
    }
    for (int j = 0; j < m; ++j)
      if (!std::isfinite(static_cast<double>(r(j)))) {
        ++skipped_;
        return any_vote_;
      }
    for (int j = 0; j < m; ++j) buffer_(head_, j) = r(j);
    head_ = (head_ + 1) % window();
    if (count_ < window()) ++count_;
    ++frames_;
    evaluate();
    return any_vote_;
  }

  void reset() noexcept {
    buffer_.setZero();
    head_ = 0;
    count_ = 0;
    frames_ = 0;
    skipped_ = 0;
    any_vote_ = false;
    for (auto& s : stats_) s = ResidualChannelStatistics{};
  }

  int channels() const noexcept { return static_cast<int>(a_diag_.size()); }
  int window() const noexcept { return options_.window_frames; }
  int samples() const noexcept { return count_; }          // n, samples in the window
  bool ready() const noexcept { return count_ >= window(); }
  std::int64_t frames() const noexcept { return frames_; }
  std::int64_t skipped_frames() const noexcept { return skipped_; }
  bool any_vote() const noexcept { return any_vote_; }
  const ResidualChannelStatistics& channel(int j) const { return stats_.at(static_cast<std::size_t>(j)); }
  const std::vector<ResidualChannelStatistics>& statistics() const noexcept { return stats_; }
  const ResidualMonitorOptions& options() const noexcept { return options_; }
  const Eigen::VectorXd& a_diag() const noexcept { return a_diag_; }

 private:
  void evaluate() noexcept {
    const int n = count_, N = window();
    const int first = (head_ - n + N) % N;  // oldest sample in the window
    const double nd = n;
    any_vote_ = false;
    for (int j = 0; j < channels(); ++j) {
      double sum = 0.0, sum_sq = 0.0, s1 = 0.0, s2 = 0.0;
      int crossings = 0;
      bool prev_negative = false;
      for (int t = 0; t < n; ++t) {
        const double x = buffer_((first + t) % N, j);
        sum += x;
        sum_sq += x * x;
        const bool negative = x < 0.0;
        if (t > 0 && negative != prev_negative) ++crossings;
        prev_negative = negative;
        const double s0 = x + two_cos_w_ * s1 - s2;
        s2 = s1;
        s1 = s0;
      }
      const double a = a_diag_(j);
      ResidualChannelStatistics& st = stats_[static_cast<std::size_t>(j)];
      st.mean = sum / nd;
      st.mean_z = st.mean / std::sqrt(a / nd);
      const double pairs = nd - 1.0;
      st.zero_crossing_rate = pairs > 0.0 ? crossings / pairs : 0.0;
      st.zero_crossing_z = pairs > 0.0 ? (crossings - 0.5 * pairs) / std::sqrt(0.25 * pairs) : 0.0;
      st.variance_ratio = sum_sq / nd / a;
      st.variance_z = (st.variance_ratio - 1.0) / std::sqrt(2.0 / nd);
      const double power = s1 * s1 + s2 * s2 - two_cos_w_ * s1 * s2;
      st.tone_ratio = options_.dither_hz > 0.0 ? power / (nd * a) : 0.0;
      const bool full = n >= N;
      st.mean_vote = full && std::abs(st.mean_z) > options_.mean_threshold;
      st.zero_crossing_vote = full && std::abs(st.zero_crossing_z) > options_.zero_crossing_threshold;
      st.variance_vote = full && std::abs(st.variance_z) > options_.variance_threshold;
      st.tone_vote = full && options_.dither_hz > 0.0 && st.tone_ratio > options_.tone_threshold;
      any_vote_ = any_vote_ || st.any_vote();
    }
  }

  ResidualMonitorOptions options_;
  Eigen::VectorXd a_diag_;
  Eigen::MatrixXd buffer_;   // (N, m) ring buffer, row = frame
  std::vector<ResidualChannelStatistics> stats_;
  double two_cos_w_ = 2.0;
  int head_ = 0;             // next row to write
  int count_ = 0;
  std::int64_t frames_ = 0;
  std::int64_t skipped_ = 0;
  bool any_vote_ = false;
};

}  // namespace f16mmae
