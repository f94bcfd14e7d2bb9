// The maneuver dwell (maneuver_dwell.h): the load factor's low-pass and its gate against a
// hand computation, the hold counted in frames, the air-data gate, the dwell and reference in
// force, the refusals; and in the hierarchical bank: off and in level flight bit for bit the
// bank without it, while the air data climb a declaration that needs the maneuver dwell's
// consecutive frames above the threshold instead of the declarer's.
#include "f16mmae/air_data_rates.h"
#include "f16mmae/hierarchical_bank.h"
#include "f16mmae/maneuver_dwell.h"

#include "synthetic_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

using namespace f16mmae;

namespace {

constexpr double kRate = 64.0;
const AirDataRates kNoAirData(kRate);   // no sample observed: both rates 0

ManeuverDwellOptions dwell_options(double dwell_s, double hold_s, double g, double tau_s) {
  ManeuverDwellOptions o;
  o.dwell_s = dwell_s;
  o.hold_s = hold_s;
  o.g = g;
  o.time_constant_s = tau_s;
  return o;
}

}  // namespace

TEST(ManeuverDwell, LowPassCrossesTheGateWhereTheStepResponseSays) {
  // n_lp after k frames of a step dn = 0.2 g: 0.2 (1 - exp(-k / (tau f))); it passes 0.1 g
  // first at k = ceil(tau f ln 2) = ceil(128 ln 2) = 89 (88.72).
  ManeuverDwell d(dwell_options(1.5, 0.0, 0.1, 2.0), kRate);
  int first = -1;
  for (int k = 1; k <= 200; ++k) {
    d.observe_load_factor(0.2, kNoAirData);
    EXPECT_NEAR(d.load_factor_lp(), 0.2 * (1.0 - std::exp(-k / 128.0)), 1e-12) << k;
    if (first < 0 && d.maneuvering()) first = k;
  }
  EXPECT_EQ(first, 89);
  // the dwell in force: 1.5 s = 96 frames while maneuvering, the base elsewhere
  EXPECT_EQ(d.dwell_frames(16), 96);
  d.reset();
  EXPECT_FALSE(d.maneuvering());
  EXPECT_EQ(d.load_factor_lp(), 0.0);
  EXPECT_EQ(d.dwell_frames(16), 16);
  // a negative load factor (a push-over) gates alike
  for (int k = 1; k <= 89; ++k) d.observe_load_factor(-0.2, kNoAirData);
  EXPECT_TRUE(d.maneuvering());
}

TEST(ManeuverDwell, HoldLastsRoundHoldTimesRateFramesAfterTheLastMovingFrame) {
  // no low-pass (tau 0): dn itself; hold 0.5 s = 32 frames
  ManeuverDwell d(dwell_options(1.0, 0.5, 0.1, 0.0), kRate);
  d.observe_load_factor(0.05, kNoAirData);
  EXPECT_FALSE(d.maneuvering());
  d.observe_load_factor(0.2, kNoAirData);   // moving
  EXPECT_TRUE(d.maneuvering());
  for (int k = 1; k <= 32; ++k) {
    d.observe_load_factor(0.0, kNoAirData);
    EXPECT_TRUE(d.maneuvering()) << k;
  }
  d.observe_load_factor(0.0, kNoAirData);   // the 33rd frame after
  EXPECT_FALSE(d.maneuvering());
  // a non-finite load factor leaves the low-pass where it is
  d.observe_load_factor(std::numeric_limits<double>::quiet_NaN(), kNoAirData);
  EXPECT_EQ(d.load_factor_lp(), 0.0);
  EXPECT_FALSE(d.maneuvering());
}

TEST(ManeuverDwell, AirDataClimbOrSpeedChangeGatesWithoutLoadFactor) {
  ManeuverDwell d(dwell_options(1.0, 0.0, 0.1, 2.0), kRate);
  AirDataRates rates(kRate);
  for (int i = 0; i < 640; ++i) {   // 10 s level, constant Mach
    rates.observe(0.6, 20000.0);
    d.observe_load_factor(0.0, rates);
  }
  EXPECT_FALSE(d.maneuvering());
  for (int i = 1; i <= 640; ++i) {   // 10 s of 3000 ft/min: the rate settles at 50 ft/s > 5 ft/s
    rates.observe(0.6, 20000.0 + 50.0 * i / kRate);
    d.observe_load_factor(0.0, rates);
  }
  EXPECT_TRUE(d.maneuvering());
  // a ramp of slope v from rest through the 1-s and 5-s low-passes (air_data_rates.h), t = 10 s:
  // rate = v (4 - 5 exp(-t/5) + exp(-t)) / 4 = 41.5 ft/s (continuous time; 64 Hz is within 0.5)
  EXPECT_NEAR(rates.climb_rate_ft_s(), 50.0 * (4.0 - 5.0 * std::exp(-2.0) + std::exp(-10.0)) / 4.0, 0.5);
  ManeuverDwell m(dwell_options(1.0, 0.0, 0.1, 2.0), kRate);
  AirDataRates speeding(kRate);
  for (int i = 1; i <= 640; ++i) {   // 0.01 Mach/s
    speeding.observe(0.6 + 0.01 * i / kRate, 20000.0);
    m.observe_load_factor(0.0, speeding);
  }
  EXPECT_TRUE(m.maneuvering());
}

TEST(ManeuverDwell, ReferenceWhileManeuveringOnlyWhenGiven) {
  ManeuverDwellOptions o = dwell_options(0.0, 0.0, 0.1, 0.0);
  EXPECT_FALSE(o.enabled());
  o.reference = 0.65;
  EXPECT_TRUE(o.enabled());
  ManeuverDwell d(o, kRate);
  EXPECT_EQ(d.reference(0.6), 0.6);
  d.observe_load_factor(0.3, kNoAirData);
  EXPECT_EQ(d.reference(0.6), 0.65);
  EXPECT_EQ(d.dwell_frames(16), 16);   // no dwell of its own: the base
  ManeuverDwell n(dwell_options(1.0, 0.0, 0.1, 0.0), kRate);
  n.observe_load_factor(0.3, kNoAirData);
  EXPECT_EQ(n.reference(0.6), 0.6);    // no reference of its own
}

TEST(ManeuverDwell, BadOptionsAreRefusedByName) {
  auto refused = [](const ManeuverDwellOptions& o, const std::string& what) {
    try {
      ManeuverDwell d(o, kRate);
      ADD_FAILURE() << "accepted " << what;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  refused(dwell_options(61.0, 0.0, 0.1, 2.0), "dwell_s must be in [0, 60] s");
  refused(dwell_options(-1.0, 0.0, 0.1, 2.0), "dwell_s must be in [0, 60] s");
  refused(dwell_options(1.0, -1.0, 0.1, 2.0), "hold_s must be in [0, 3600] s");
  refused(dwell_options(1.0, 0.0, 0.0, 2.0), "g must be a load factor in (0, 10] g");
  refused(dwell_options(1.0, 0.0, 0.1, 61.0), "time_constant_s must be in [0, 60] s");
  ManeuverDwellOptions o = dwell_options(1.0, 0.0, 0.1, 2.0);
  o.reference = -0.1;
  refused(o, "reference must be a power ratio in [0, 100]");
}

namespace {

// LF fails at frame 100 (test::fly_alike); every bank is handed the same air data after each
// frame: level at 20,000 ft, or climbing 50 ft/s from the start. Returns the declaration frames
// of `a` and `b` at level 0 and checks their level-0 probabilities bit for bit until the first.
struct Pair {
  std::vector<double> p_lf_b;   // b's LF probability per frame until its first declaration
  std::int64_t frame_a = -1, frame_b = -1;
  bool equal_until_first = true;
  bool b_maneuvering_at_its_declaration = false;
};

Pair fly_pair(const ModelBank& mb, const HierarchicalOptions& oa, const HierarchicalOptions& ob, bool climb) {
  F16HierarchicalBank a(mb, oa), b(mb, ob);
  const int lf = mb.find("LF");
  Pair r;
  test::fly_alike(mb, 7u, 11u, 900, [&](int i) {
    const int pos = 3;   // LF's on-line position at level 0 (LS RS LF: 1 2 3)
    if (b.level() == 0) EXPECT_EQ(b.online()[pos], lf);
    const bool none_yet = r.frame_a < 0 && r.frame_b < 0;
    if (r.frame_b < 0) r.p_lf_b.push_back(b.probabilities()(pos));
    if (r.frame_a < 0 && !a.declarations().empty()) r.frame_a = a.declarations().front().frame;
    if (r.frame_b < 0 && !b.declarations().empty()) {
      r.frame_b = b.declarations().front().frame;
      r.b_maneuvering_at_its_declaration = b.maneuver_dwell().maneuvering();
      EXPECT_EQ(b.declarations().front().hypothesis, lf);
    }
    // until a declaration switches a bank to level 1 the two run alike
    if (none_yet && r.frame_a < 0 && r.frame_b < 0 && !(a.probabilities() == b.probabilities()))
      r.equal_until_first = false;
    const AirData air{0.6, 20000.0 + (climb ? 50.0 * (i + 1) / kRate : 0.0)};
    a.schedule(air);
    b.schedule(air);
    return r.frame_b < 0 || r.frame_a < 0;
  }, a, b);
  return r;
}

// The first frame ending n consecutive frames with p > threshold, of the frames before `end`
// (a declaration frame's recorded probabilities are those after its switch to level 1).
std::int64_t first_run(const std::vector<double>& p, double threshold, int n, std::int64_t end) {
  int run = 0;
  for (std::size_t i = 0; i < p.size() && static_cast<std::int64_t>(i) < end; ++i) {
    run = p[i] > threshold ? run + 1 : 0;
    if (run >= n) return static_cast<std::int64_t>(i);
  }
  return -1;
}

}  // namespace

TEST(ManeuverDwell, BankDeclaresWithTheManeuverDwellOnlyWhileTheAirDataClimb) {
  const ModelBank mb = test::f16_model_bank(7u);
  HierarchicalOptions oa;
  oa.declarer.dwell_s = 0.25;   // 16 frames
  HierarchicalOptions ob = oa;
  ob.maneuver_dwell = dwell_options(1.0, 0.0, 10.0, 2.0);   // 64 frames; the load factor never gates here

  const Pair level = fly_pair(mb, oa, ob, false);
  ASSERT_GE(level.frame_a, 100);
  EXPECT_EQ(level.frame_b, level.frame_a);   // level flight: the declarer's dwell, bit for bit
  EXPECT_TRUE(level.equal_until_first);
  EXPECT_FALSE(level.b_maneuvering_at_its_declaration);

  const Pair climb = fly_pair(mb, oa, ob, true);
  ASSERT_GE(climb.frame_a, 100);
  EXPECT_TRUE(climb.equal_until_first);   // the dwell changes no probability
  EXPECT_TRUE(climb.b_maneuvering_at_its_declaration);
  // a declaration on frame f: p above the threshold on f and the n - 1 frames before it (the
  // last n - 1 of them recorded here, before any switch), and no earlier such run
  EXPECT_EQ(climb.frame_a - 1, first_run(climb.p_lf_b, oa.declarer.threshold, 15, climb.frame_a));
  EXPECT_EQ(climb.frame_b - 1, first_run(climb.p_lf_b, oa.declarer.threshold, 63, climb.frame_b));
  EXPECT_GT(climb.frame_b, climb.frame_a);
}

TEST(ManeuverDwell, BankWithoutAzIsRefusedByName) {
  ModelBank mb = test::f16_model_bank(7u);
  mb.measurement_names[3] = "NZ";
  HierarchicalOptions o;
  o.maneuver_dwell.dwell_s = 1.0;
  try {
    F16HierarchicalBank b(mb, o);
    ADD_FAILURE() << "accepted a bank without AZ";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("measurement 'AZ'"), std::string::npos) << e.what();
  }
}
