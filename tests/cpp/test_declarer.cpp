// Declarer: threshold and dwell, interrupted dwells, no re-declaration of the current
// hypothesis, a new winner, validation.
#include "f16mmae/declarer.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>

using f16mmae::Declarer;
using f16mmae::DeclarerOptions;

namespace {
std::array<double, 3> winner(int k, double p) {
  std::array<double, 3> v{};
  for (auto& x : v) x = (1.0 - p) / 2.0;
  v[static_cast<std::size_t>(k)] = p;
  return v;
}
}  // namespace

TEST(Declarer, DefaultsAreSixteenFramesAboveNinetyPercent) {
  Declarer d;
  EXPECT_EQ(d.dwell_frames(), 16);  // 0.25 s at 64 Hz
  EXPECT_DOUBLE_EQ(d.options().threshold, 0.9);
  for (int i = 0; i < 15; ++i) EXPECT_EQ(d.update(winner(2, 0.95)), -1) << i;
  EXPECT_EQ(d.update(winner(2, 0.95)), 2);  // the 16th consecutive frame
  EXPECT_EQ(d.current(), 2);
  for (int i = 0; i < 50; ++i) EXPECT_EQ(d.update(winner(2, 0.95)), -1);  // declared once
}

TEST(Declarer, InterruptedDwellStartsAgain) {
  DeclarerOptions o;
  o.dwell_s = 0.1;
  o.frame_rate_hz = 50.0;  // 5 frames
  Declarer d(o);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(d.update(winner(1, 0.95)), -1);
  EXPECT_EQ(d.update(winner(1, 0.9)), -1);  // not above (strict): the dwell restarts
  for (int i = 0; i < 4; ++i) EXPECT_EQ(d.update(winner(1, 0.95)), -1);
  EXPECT_EQ(d.update(winner(2, 0.95)), -1);  // another candidate: restarts too
  for (int i = 0; i < 3; ++i) EXPECT_EQ(d.update(winner(2, 0.95)), -1);
  EXPECT_EQ(d.update(winner(2, 0.95)), 2);
  // back to the presumed hypothesis 0 after a dwell
  for (int i = 0; i < 4; ++i) EXPECT_EQ(d.update(winner(0, 0.99)), -1);
  EXPECT_EQ(d.update(winner(0, 0.99)), 0);
}

TEST(Declarer, PresumedHypothesisIsNotDeclaredAndNaNNeverCounts) {
  DeclarerOptions o;
  o.dwell_s = 0.0;  // one frame
  Declarer d(o, 0);
  EXPECT_EQ(d.dwell_frames(), 1);
  EXPECT_EQ(d.update(winner(0, 0.99)), -1);
  std::array<double, 3> nan{std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0};
  EXPECT_EQ(d.update(nan), -1);
  EXPECT_EQ(d.update(winner(1, 0.99)), 1);
  d.reset(1);
  EXPECT_EQ(d.update(winner(1, 0.99)), -1);
}

TEST(Declarer, ValidationNamesTheBadValue) {
  DeclarerOptions o;
  o.threshold = 0.4;
  try {
    Declarer d(o);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("threshold must be in (0.5, 1), got 0.4"), std::string::npos) << e.what();
  }
  o = {};
  o.dwell_s = -1.0;
  EXPECT_THROW(Declarer{o}, std::invalid_argument);
  // issue 16: dwell 3.4e7 s once became dwell_frames = INT_MIN (declare at once)
  o.dwell_s = 3.4e7;
  try {
    Declarer d(o);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "declarer: dwell_s must be in [0, 60] s, got 3.4e+07");
  }
  o.dwell_s = 60.0;  // the longest dwell, at a rate that would make it more than 2^24 frames
  o.frame_rate_hz = 1e6;
  try {
    Declarer d(o);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("= 6e+07 frames exceeds the limit of 16777216 frames"), std::string::npos)
        << e.what();
  }
  o.frame_rate_hz = 64.0;
  EXPECT_EQ(Declarer(o).dwell_frames(), 3840);
  o.dwell_s = NAN;
  EXPECT_THROW(Declarer{o}, std::invalid_argument);
  o = {};
  o.frame_rate_hz = 0.0;
  EXPECT_THROW(Declarer{o}, std::invalid_argument);
}
