// ResidualMonitor (Sec. VII voters) on white Gaussian noise of the design variance, on
// noise plus a bias, on noise plus a tone at the dither frequency, and on wrong variance.
#include "f16mmae/residual_monitor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using f16mmae::ResidualMonitor;
using f16mmae::ResidualMonitorOptions;

namespace {
constexpr double kPi = 3.14159265358979323846;

ResidualMonitorOptions options() {
  ResidualMonitorOptions o;
  o.window_frames = 128;
  o.frame_rate_hz = 64.0;
  o.dither_hz = 4.0;  // 8 cycles in the window
  return o;
}

struct Votes {
  int mean = 0, zcr = 0, var = 0, tone = 0, frames = 0;
};

// Channel 0 gets the test signal, channel 1 white noise of its own variance.
template <class Signal>
Votes run(ResidualMonitor& m, Signal signal, int frames, unsigned seed) {
  std::mt19937 g(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  Votes v;
  for (int i = 0; i < frames; ++i) {
    Eigen::Vector2d r(signal(i, n01(g)), 3.0 * n01(g));
    m.update(r);
    if (!m.ready()) continue;
    ++v.frames;
    const auto& s = m.channel(0);
    v.mean += s.mean_vote;
    v.zcr += s.zero_crossing_vote;
    v.var += s.variance_vote;
    v.tone += s.tone_vote;
    EXPECT_FALSE(m.channel(1).any_vote()) << "white channel voted at frame " << i;
  }
  return v;
}
}  // namespace

TEST(ResidualMonitor, WhiteNoiseOfTheDesignVarianceDoesNotVote) {
  ResidualMonitor m(Eigen::Vector2d(4.0, 9.0), options());
  const Votes v = run(m, [](int, double e) { return 2.0 * e; }, 3000, 1u);
  EXPECT_EQ(v.mean + v.zcr + v.var + v.tone, 0);
  const auto& s = m.channel(0);
  EXPECT_NEAR(s.variance_ratio, 1.0, 0.4);
  EXPECT_NEAR(s.zero_crossing_rate, 0.5, 0.15);
  EXPECT_LT(std::abs(s.mean_z), 4.0);
}

TEST(ResidualMonitor, StatisticsByHandOnAShortWindow) {
  ResidualMonitorOptions o;
  o.window_frames = 4;
  o.frame_rate_hz = 4.0;
  o.dither_hz = 1.0;  // w = pi/2: X = sum r_t (-i)^t
  ResidualMonitor m(Eigen::VectorXd::Constant(1, 2.0), o);
  const double r[6] = {5.0, 1.0, -1.0, 2.0, -3.0, 0.5};  // window holds the last 4
  for (double x : r) m.update(Eigen::VectorXd::Constant(1, x));
  const auto& s = m.channel(0);
  // window: -1, 2, -3, 0.5
  EXPECT_DOUBLE_EQ(s.mean, -0.375);
  EXPECT_NEAR(s.mean_z, -0.375 / std::sqrt(2.0 / 4.0), 1e-15);
  EXPECT_NEAR(s.zero_crossing_rate, 1.0, 1e-15);  // 3 sign changes in 3 pairs
  EXPECT_NEAR(s.zero_crossing_z, (3.0 - 1.5) / std::sqrt(0.75), 1e-12);
  EXPECT_NEAR(s.variance_ratio, (1.0 + 4.0 + 9.0 + 0.25) / 4.0 / 2.0, 1e-15);
  // X = -1 + 2(-i) + (-3)(-1) + 0.5(i) = 2 - 1.5 i, |X|^2 = 6.25
  EXPECT_NEAR(s.tone_ratio, 6.25 / (4.0 * 2.0), 1e-12);
}

TEST(ResidualMonitor, BiasVotesOnTheMeanAndWhitenessNotOnTheTone) {
  ResidualMonitor m(Eigen::Vector2d(1.0, 9.0), options());
  const Votes v = run(m, [](int i, double e) { return e + (i >= 500 ? 1.5 : 0.0); }, 1200, 2u);
  EXPECT_EQ(v.tone, 0);
  EXPECT_GT(v.mean, 500);  // all frames with the window inside the biased part
  EXPECT_GT(v.zcr, 300);
  // before the bias no vote
  ResidualMonitor clean(Eigen::Vector2d(1.0, 9.0), options());
  const Votes c = run(clean, [](int, double e) { return e; }, 500, 2u);
  EXPECT_EQ(c.mean + c.zcr + c.var + c.tone, 0);
}

TEST(ResidualMonitor, ToneAtTheDitherFrequencyVotesOnTheTone) {
  ResidualMonitor m(Eigen::Vector2d(1.0, 9.0), options());
  const Votes v = run(m, [](int i, double e) { return e + 1.0 * std::sin(2.0 * kPi * 4.0 * i / 64.0 + 0.3); }, 1000, 3u);
  EXPECT_GT(v.tone, v.frames * 9 / 10);
  EXPECT_EQ(v.mean, 0);
  // a tone elsewhere (11 Hz) is not the dither
  ResidualMonitor other(Eigen::Vector2d(1.0, 9.0), options());
  const Votes w = run(other, [](int i, double e) { return e + 1.0 * std::sin(2.0 * kPi * 11.0 * i / 64.0); }, 1000, 3u);
  EXPECT_EQ(w.tone, 0);
}

TEST(ResidualMonitor, WrongVarianceVotesOnTheVariance) {
  ResidualMonitor m(Eigen::Vector2d(1.0, 9.0), options());
  const Votes v = run(m, [](int, double e) { return 3.0 * e; }, 1000, 4u);
  EXPECT_EQ(v.var, v.frames);  // (the other voters, calibrated on A too, may also vote)
}

TEST(ResidualMonitor, SkipsNonFiniteAndValidates) {
  ResidualMonitor m(Eigen::Vector2d(1.0, 1.0), options());
  m.update(Eigen::Vector2d(std::numeric_limits<double>::quiet_NaN(), 0.0));
  m.update(Eigen::Vector3d(0.0, 0.0, 0.0));
  EXPECT_EQ(m.skipped_frames(), 2);
  EXPECT_EQ(m.samples(), 0);
  ResidualMonitorOptions o = options();
  EXPECT_THROW(ResidualMonitor(Eigen::Vector2d(1.0, 0.0), o), std::invalid_argument);
  o.dither_hz = 40.0;
  try {
    ResidualMonitor bad(Eigen::Vector2d(1.0, 1.0), o);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("dither_hz"), std::string::npos);
  }
  o = options();
  o.window_frames = 1;
  EXPECT_THROW(ResidualMonitor(Eigen::Vector2d(1.0, 1.0), o), std::invalid_argument);
}
