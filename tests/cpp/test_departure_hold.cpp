// The departure hold (departure_hold.h) against a hand-worked sequence: the "outside the
// linearization" test on AOA and the body rates, the countdown of round(hold_s f) frames after
// the last frame outside, the failed sensor's channel left out, a channel the bank does not
// measure, the count of held frames, release/reset/carry-over, off, and the refusals.
#include "f16mmae/departure_hold.h"

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

using namespace f16mmae;

namespace {

// z = (VEL, AOA, PIT, AZ, ROL, YAW); hypotheses NONE, U1, AOA, PIT.
const std::vector<std::string> kZ = {"VEL", "AOA", "PIT", "AZ", "ROL", "YAW"};
const std::vector<std::string> kH = {"NONE", "U1", "AOA", "PIT"};
constexpr int kU1 = 1, kAOA = 2, kPIT = 3;

DepartureOptions options(double aoa, double rate, double hold_s) {
  DepartureOptions o;
  o.aoa_rad = aoa;
  o.rate_rad_s = rate;
  o.hold_s = hold_s;
  return o;
}

Eigen::VectorXd z_of(double vel, double aoa, double pit, double az, double rol, double yaw) {
  Eigen::VectorXd z(6);
  z << vel, aoa, pit, az, rol, yaw;
  return z;
}

}  // namespace

TEST(DepartureHold, CountsDownTheHoldAfterTheLastFrameOutside) {
  // 4 Hz, hold_s 0.5: n = round(0.5 * 4) + 1 = 3 on a frame outside, then 2, 1, 0.
  DepartureHold d(options(0.1, 0.2, 0.5), kZ, kH, 4.0);
  EXPECT_EQ(d.hold_frames(), 2);
  EXPECT_EQ(d.channel(0), 1);
  EXPECT_EQ(d.channel(3), 5);
  const std::vector<Eigen::VectorXd> z = {
      z_of(50.0, 0.0, 0.0, 3.0, 0.0, 0.0),    // 0 inside (VEL and AZ are not checked): n 0
      z_of(0.0, -0.15, 0.0, 0.0, 0.0, 0.0),   // 1 |AOA| 0.15 > 0.1: n 3
      z_of(0.0, 0.1, 0.0, 0.0, 0.0, 0.0),     // 2 |AOA| = 0.1 is inside: n 2
      z_of(0.0, 0.0, 0.0, 0.0, 0.0, 0.0),     // 3 n 1
      z_of(0.0, 0.0, 0.15, 0.0, 0.0, 0.0),    // 4 |PIT| 0.15 < 0.2: n 0, not held
      z_of(0.0, 0.0, -0.25, 0.0, 0.0, 0.0),   // 5 |PIT| 0.25 > 0.2: n 3
      z_of(0.0, 0.0, 0.0, 0.0, 0.2, 0.0),     // 6 |ROL| = 0.2 is inside: n 2
      z_of(0.0, 0.0, 0.0, 0.0, 0.0, 0.21),    // 7 |YAW| 0.21 > 0.2: n 3 again
      z_of(0.0, 0.0, 0.0, 0.0, -0.3, 0.0),    // 8 |ROL| 0.3 > 0.2: n 3
      z_of(0.0, 0.0, 0.0, 0.0, 0.0, 0.0),     // 9 n 2
      z_of(0.0, 0.0, 0.0, 0.0, 0.0, 0.0),     // 10 n 1
      z_of(0.0, 0.0, 0.0, 0.0, 0.0, 0.0),     // 11 n 0
  };
  const std::vector<int> remaining = {0, 3, 2, 1, 0, 3, 2, 3, 3, 2, 1, 0};
  for (std::size_t i = 0; i < z.size(); ++i) {
    EXPECT_EQ(d.observe(z[i], kU1), remaining[i] > 0) << "frame " << i;
    EXPECT_EQ(d.remaining(), remaining[i]) << "frame " << i;
    EXPECT_EQ(d.held(), remaining[i] > 0) << "frame " << i;
  }
  EXPECT_EQ(d.frames(), 9);   // frames 1-3 and 5-10
}

TEST(DepartureHold, LeavesOutTheFailedSensorsChannel) {
  DepartureHold d(options(0.1, 0.2, 0.0), kZ, kH, 64.0);
  EXPECT_EQ(d.hold_frames(), 0);   // hold_s 0: only the frame outside itself is held
  EXPECT_FALSE(d.observe(z_of(0.0, 0.0, 1.0, 0.0, 0.0, 0.0), kPIT));   // PIT failed: its reading left out
  EXPECT_TRUE(d.observe(z_of(0.0, 0.0, 1.0, 0.0, 0.0, 0.0), kAOA));    // AOA failed: PIT is checked
  EXPECT_EQ(d.remaining(), 1);
  EXPECT_FALSE(d.observe(z_of(0.0, 1.0, 0.0, 0.0, 0.0, 0.0), kAOA));
  EXPECT_TRUE(d.observe(z_of(0.0, 1.0, 0.0, 0.0, 0.0, 0.0), kPIT));
  EXPECT_FALSE(d.observe(z_of(0.0, 0.0, 0.0, 0.0, 0.0, 0.0), kPIT));
  EXPECT_EQ(d.frames(), 2);
}

TEST(DepartureHold, AChannelTheBankDoesNotMeasureIsNotChecked) {
  const std::vector<std::string> z_names = {"VEL", "AOA", "PIT", "AZ", "ROL"};   // no YAW
  DepartureHold d(options(0.1, 0.2, 1.0), z_names, kH, 4.0);
  EXPECT_EQ(d.channel(3), -1);
  Eigen::VectorXd z = Eigen::VectorXd::Zero(5);
  z(4) = 0.3;   // ROL
  EXPECT_TRUE(d.observe(z, kU1));
  EXPECT_EQ(d.remaining(), 5);   // round(1.0 * 4) + 1
  // no channel at all: never held
  DepartureHold none(options(0.1, 0.2, 1.0), {"VEL", "AZ"}, kH, 4.0);
  EXPECT_FALSE(none.observe(Eigen::Vector2d(100.0, 100.0), kU1));
  EXPECT_EQ(none.frames(), 0);
}

TEST(DepartureHold, ReleaseResetAndCarryOver) {
  DepartureHold a(options(0.1, 0.2, 1.0), kZ, kH, 4.0), b(options(0.1, 0.2, 0.25), kZ, kH, 4.0);
  const Eigen::VectorXd out = z_of(0.0, 0.5, 0.0, 0.0, 0.0, 0.0), in = Eigen::VectorXd::Zero(6);
  EXPECT_TRUE(a.observe(out, kU1));
  EXPECT_TRUE(a.observe(in, kU1));
  EXPECT_EQ(a.remaining(), 4);
  b.carry_over(a);   // the hold and its count; b's own hold length
  EXPECT_EQ(b.remaining(), 4);
  EXPECT_EQ(b.frames(), 2);
  EXPECT_EQ(b.hold_frames(), 1);
  EXPECT_TRUE(b.observe(out, kU1));
  EXPECT_EQ(b.remaining(), 2);   // round(0.25 * 4) + 1
  a.release();   // a switch of level: the hold ends, the count stays
  EXPECT_FALSE(a.held());
  EXPECT_EQ(a.frames(), 2);
  EXPECT_FALSE(a.observe(in, kU1));
  a.reset();
  EXPECT_EQ(a.frames(), 0);
  EXPECT_EQ(a.remaining(), 0);
}

TEST(DepartureHold, OffIsNeverHeldAndRefusesNothing) {
  DepartureOptions o = options(-1.0, 0.0, -1.0);
  o.enabled = false;
  DepartureHold d(o, kZ, kH, 64.0);
  EXPECT_FALSE(d.enabled());
  EXPECT_FALSE(d.observe(z_of(9.0, 9.0, 9.0, 9.0, 9.0, 9.0), kU1));
  EXPECT_EQ(d.frames(), 0);
  EXPECT_FALSE(DepartureHold().observe(z_of(9.0, 9.0, 9.0, 9.0, 9.0, 9.0), kU1));
}

TEST(DepartureHold, DefaultsAreFiveDegreesTenDegreesPerSecondOneSecond) {
  const DepartureOptions o;
  EXPECT_TRUE(o.enabled);
  EXPECT_DOUBLE_EQ(o.aoa_rad * 180.0 / M_PI, 5.0);
  EXPECT_DOUBLE_EQ(o.rate_rad_s * 180.0 / M_PI, 10.0);
  EXPECT_EQ(o.hold_s, 1.0);
  EXPECT_EQ(DepartureHold(o, kZ, kH, 64.0).hold_frames(), 64);
}

TEST(DepartureHold, RefusesBoundsAndHoldOutOfRangeByName) {
  const double inf = std::numeric_limits<double>::infinity();
  for (const DepartureOptions& o : {options(0.0, 0.2, 1.0), options(0.1, -0.2, 1.0), options(0.1, 0.2, -1.0),
                                     options(0.1, 0.2, inf), options(std::nan(""), 0.2, 1.0)}) {
    try {
      DepartureHold d(o, kZ, kH, 64.0);
      ADD_FAILURE() << o.aoa_rad << " " << o.rate_rad_s << " " << o.hold_s;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("departure hold needs aoa_rad > 0"), std::string::npos) << e.what();
    }
  }
}
