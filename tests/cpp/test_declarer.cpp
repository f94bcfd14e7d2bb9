// Declarer: threshold and dwell, interrupted dwells, no re-declaration of the current
// hypothesis, a new winner, validation.
#include "f16mmae/declarer.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

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

// Components (declarer.h): slots 1 and 2 are two forms of one component (group {0, 1, 1, 3}),
// dwell 4 frames. By hand: frames 1-3 put 0.50 + 0.45 = 0.95 (then 0.45 + 0.50, then 0.60 +
// 0.31) on the component, none of its forms above 0.9 alone; frame 4 puts 0.30 + 0.65 = 0.95
// on it: the dwell completes on the sum and the form with more mass, slot 2, is declared.
TEST(DeclarerComponents, TheDwellRunsOnTheSumAndTheHeaviestFormIsDeclared) {
  DeclarerOptions o;
  o.dwell_s = 4.0 / 64.0;   // 4 frames
  const int group[4] = {0, 1, 1, 3};
  const std::array<std::array<double, 4>, 4> frames{{{0.02, 0.50, 0.45, 0.03},
                                                     {0.02, 0.45, 0.50, 0.03},
                                                     {0.06, 0.60, 0.31, 0.03},
                                                     {0.02, 0.30, 0.65, 0.03}}};
  Declarer alone(o), together(o);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(alone.update(frames[i], alone.dwell_frames()), -1) << i;
    EXPECT_EQ(together.update(frames[i], together.dwell_frames(), group), -1) << i;
    EXPECT_EQ(together.candidate(), 1) << "the component's lowest slot";
    EXPECT_EQ(together.dwell_count(), i + 1);
  }
  EXPECT_EQ(alone.update(frames[3], alone.dwell_frames()), -1) << "no form alone above 0.9";
  EXPECT_EQ(together.update(frames[3], together.dwell_frames(), group), 2);
  EXPECT_EQ(together.current(), 2);
  // the mass moving to the other form is no new declaration: the component is current
  const std::array<double, 4> other{0.01, 0.97, 0.01, 0.01};
  for (int i = 0; i < 10; ++i) EXPECT_EQ(together.update(other, together.dwell_frames(), group), -1);
  EXPECT_EQ(together.current(), 2);
  // a sum at the threshold is not above it (strict); another component restarts the dwell
  const std::array<double, 4> at{0.05, 0.45, 0.45, 0.05};
  EXPECT_EQ(together.update(at, together.dwell_frames(), group), -1);
  EXPECT_EQ(together.candidate(), -1);
  const std::array<double, 4> three{0.02, 0.02, 0.01, 0.95};
  for (int i = 0; i < 3; ++i) EXPECT_EQ(together.update(three, together.dwell_frames(), group), -1);
  EXPECT_EQ(together.update(three, together.dwell_frames(), group), 3);
  // a NaN form makes its component's sum NaN: never above
  Declarer d(o);
  const std::array<double, 4> nan{0.0, std::numeric_limits<double>::quiet_NaN(), 0.95, 0.05};
  for (int i = 0; i < 8; ++i) EXPECT_EQ(d.update(nan, d.dwell_frames(), group), -1);
  EXPECT_EQ(d.candidate(), -1);
}

// Every hypothesis alone (group[k] = k) is the rule without components, frame for frame.
TEST(DeclarerComponents, EachHypothesisAloneIsTheRuleWithout) {
  DeclarerOptions o;
  o.dwell_s = 3.0 / 64.0;
  const int group[3] = {0, 1, 2};
  Declarer plain(o), alone(o);
  unsigned state = 12345u;
  for (int i = 0; i < 2000; ++i) {
    state = state * 1664525u + 1013904223u;
    const int k = static_cast<int>(state >> 30) % 3;
    const double p = 0.85 + 0.1 * static_cast<double>((state >> 8) & 0xff) / 255.0;
    const auto v = winner(k, p);
    ASSERT_EQ(plain.update(v), alone.update(v, alone.dwell_frames(), group)) << i;
    ASSERT_EQ(plain.candidate(), alone.candidate());
    ASSERT_EQ(plain.dwell_count(), alone.dwell_count());
  }
}

// Evidence dwell (declarer.h): E_n = sum of ln(P/(1-P)) - ln(T/(1-T)) over the frames above,
// declared once E_n >= dwell_nats, whichever comes first with the frame dwell.
// Hand-computed: T = 0.9: ln 9 = 2.19722; P = 0.99: ln 99 = 4.59512 (excess 2.39790 a frame);
// P = 0.95: ln 19 = 2.94444 (0.74722); P = 0.999: ln 999 = 6.90675 (4.70953).
TEST(DeclarerEvidence, HighCandidateIsDeclaredOnceItsLogOddsSumReachesTheDwell) {
  DeclarerOptions o;
  o.dwell_nats = 7.0;   // 0.99 a frame: 2.398, 4.796, 7.194 -> the third frame
  Declarer d(o);
  EXPECT_EQ(d.dwell_frames(), 16);
  EXPECT_EQ(d.update(winner(1, 0.99)), -1);
  EXPECT_NEAR(d.dwell_evidence_nats(), std::log(99.0) - std::log(9.0), 1e-12);
  EXPECT_EQ(d.update(winner(1, 0.99)), -1);
  EXPECT_NEAR(d.dwell_evidence_nats(), 4.795791, 1e-6);
  EXPECT_EQ(d.update(winner(1, 0.99)), 1);
  EXPECT_EQ(d.current(), 1);
  for (int i = 0; i < 30; ++i) EXPECT_EQ(d.update(winner(1, 0.99)), -1);   // declared once
}

TEST(DeclarerEvidence, NearTheThresholdTheFrameDwellDeclaresAsBefore) {
  DeclarerOptions o;
  o.dwell_nats = 16.0;   // 0.95 a frame: 16 frames give 11.96 < 16
  Declarer with(o), without;
  for (int i = 0; i < 15; ++i) {
    EXPECT_EQ(with.update(winner(2, 0.95)), -1) << i;
    EXPECT_EQ(without.update(winner(2, 0.95)), -1) << i;
  }
  EXPECT_NEAR(with.dwell_evidence_nats(), 15 * (std::log(19.0) - std::log(9.0)), 1e-9);
  EXPECT_EQ(with.update(winner(2, 0.95)), 2);   // the 16th frame, by the frame dwell
  EXPECT_EQ(without.update(winner(2, 0.95)), 2);
}

TEST(DeclarerEvidence, MixedSequenceInterruptionAndNewCandidateRestartTheSum) {
  DeclarerOptions o;
  o.dwell_nats = 5.0;
  Declarer d(o);
  EXPECT_EQ(d.update(winner(1, 0.999)), -1);   // 4.70953
  EXPECT_EQ(d.update(winner(1, 0.85)), -1);    // below: restarts
  EXPECT_EQ(d.dwell_evidence_nats(), 0.0);
  EXPECT_EQ(d.update(winner(1, 0.999)), -1);   // 4.70953
  EXPECT_EQ(d.update(winner(2, 0.999)), -1);   // another candidate: restarts at 4.70953
  EXPECT_NEAR(d.dwell_evidence_nats(), std::log(999.0) - std::log(9.0), 1e-12);
  EXPECT_EQ(d.update(winner(2, 0.95)), 2);     // 4.70953 + 0.74722 = 5.45675 >= 5
}

TEST(DeclarerEvidence, LongerDwellInForceAsksForAsManyMoreNats) {
  DeclarerOptions o;
  o.dwell_nats = 7.0;
  Declarer d(o);
  // dwell in force 32 frames, twice the declarer's 16: 14 nats, 0.99 a frame: 6 frames (14.39)
  for (int i = 0; i < 5; ++i) EXPECT_EQ(d.update(winner(1, 0.99), 32), -1) << i;
  EXPECT_EQ(d.update(winner(1, 0.99), 32), 1);
}

TEST(DeclarerEvidence, ComponentsSumTheirMassBeforeTheLogOdds) {
  DeclarerOptions o;
  o.dwell_nats = 4.0;
  Declarer d(o);
  const int group[4] = {0, 1, 1, 3};
  // slots 1 and 2 one component: mass 0.99 (0.5 + 0.49) -> 2.398 a frame: the second frame
  const std::array<double, 4> p{0.004, 0.5, 0.49, 0.006};
  EXPECT_EQ(d.update(p, d.dwell_frames(), group), -1);
  EXPECT_NEAR(d.dwell_evidence_nats(), std::log(0.99 / 0.01) - std::log(9.0), 1e-9);
  EXPECT_EQ(d.update(p, d.dwell_frames(), group), 1);   // the heavier form
}

TEST(DeclarerEvidence, ACertainCandidateCompletesTheDwellAtOnceAndOffIsTheFrameRule) {
  DeclarerOptions o;
  o.dwell_nats = 1000.0;
  Declarer d(o);
  EXPECT_EQ(d.update(std::array<double, 3>{0.0, 1.0, 0.0}), 1);   // ln(1/0): infinite
  // dwell_nats 0: the frame dwell alone, however high the candidate
  DeclarerOptions off;
  off.dwell_s = 5.0 / 64.0;
  Declarer a(off);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(a.update(winner(1, 0.99999)), -1) << i;
  EXPECT_EQ(a.dwell_evidence_nats(), 0.0);
  EXPECT_EQ(a.update(winner(1, 0.99999)), 1);
}

TEST(DeclarerEvidence, ValidationNamesTheBadValue) {
  DeclarerOptions o;
  o.dwell_nats = -1.0;
  try {
    Declarer d(o);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "declarer: dwell_nats must be in [0, 1e+06] nats, got -1");
  }
  o.dwell_nats = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(Declarer{o}, std::invalid_argument);
}

// Evidence dwell per hypothesis (declarer.h): N_k by name, resolved against the names at
// construction; a hypothesis the table does not name takes dwell_nats; N_k = 0: the frame dwell.
// Hand sums as above: 0.99 gives 2.39790 a frame above ln 9, 0.999 gives 4.70953.
TEST(DeclarerEvidencePerHypothesis, EachHypothesisNeedsItsOwnNats) {
  DeclarerOptions o;
  o.dwell_nats = 7.0;                                            // C, not in the table
  o.dwell_nats_per_hypothesis = {{"A", 0.0}, {"B", 4.0}};        // A: frames alone; B: 4 nats
  const std::vector<std::string> names{"NONE", "A", "B", "C"};
  Declarer d(o, 0, names);
  EXPECT_EQ(d.dwell_nats_of(0), 7.0);
  EXPECT_EQ(d.dwell_nats_of(1), 0.0);
  EXPECT_EQ(d.dwell_nats_of(2), 4.0);
  EXPECT_EQ(d.dwell_nats_of(3), 7.0);
  auto one = [](int k, double p) {
    std::array<double, 4> v{};
    for (auto& x : v) x = (1.0 - p) / 3.0;
    v[static_cast<std::size_t>(k)] = p;
    return v;
  };
  // B at 0.99: 2.398 then 4.796 >= 4 -> declared on the second frame
  EXPECT_EQ(d.update(one(2, 0.99)), -1);
  EXPECT_EQ(d.update(one(2, 0.99)), 2);
  // C at 0.99: 2.398, 4.796, 7.194 >= 7 -> the third frame
  EXPECT_EQ(d.update(one(3, 0.99)), -1);
  EXPECT_EQ(d.update(one(3, 0.99)), -1);
  EXPECT_EQ(d.update(one(3, 0.99)), 3);
  // A at 0.999 (4.7 nats a frame): no evidence dwell, the 16th frame
  for (int i = 0; i < 15; ++i) EXPECT_EQ(d.update(one(1, 0.999)), -1) << i;
  EXPECT_EQ(d.dwell_evidence_nats(), 0.0);
  EXPECT_EQ(d.update(one(1, 0.999)), 1);
}

TEST(DeclarerEvidencePerHypothesis, SlotsAreMappedToHypothesesWhenTheBankSaysWhichIsWhich) {
  DeclarerOptions o;
  o.dwell_nats_per_hypothesis = {{"B", 4.0}};   // the others: dwell_nats 0, the frame dwell
  Declarer d(o, 0, {"NONE", "A", "B"});
  const int slot_holds[3] = {0, 2, 1};           // slot 1 holds B, slot 2 holds A
  const std::array<double, 3> p{0.005, 0.99, 0.005};
  EXPECT_EQ(d.update(p, d.dwell_frames(), nullptr, slot_holds), -1);   // 2.398
  EXPECT_EQ(d.update(p, d.dwell_frames(), nullptr, slot_holds), 1);    // 4.796 >= 4: slot 1
  // the same probabilities without the map: slot 1 is A, the frame dwell alone
  Declarer plain(o, 0, {"NONE", "A", "B"});
  for (int i = 0; i < 15; ++i) EXPECT_EQ(plain.update(p), -1) << i;
  EXPECT_EQ(plain.update(p), 1);
  // components: the representative slot's hypothesis sets N (slots 1, 2 one component: B)
  Declarer c(o, 0, {"NONE", "A", "B"});
  const int group[3] = {0, 1, 1};
  const std::array<double, 3> q{0.01, 0.5, 0.49};   // mass 0.99
  EXPECT_EQ(c.update(q, c.dwell_frames(), group, slot_holds), -1);
  EXPECT_EQ(c.update(q, c.dwell_frames(), group, slot_holds), 1);
}

TEST(DeclarerEvidencePerHypothesis, ValidationNamesTheBadEntry) {
  DeclarerOptions o;
  o.dwell_nats_per_hypothesis = {{"X", 5.0}};
  try {
    Declarer d(o, 0, {"NONE", "A"});
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "declarer: dwell_nats_per_hypothesis names 'X', not a hypothesis of the bank (NONE A)");
  }
  EXPECT_THROW(Declarer{o}, std::invalid_argument);   // no names to resolve against
  o.dwell_nats_per_hypothesis = {{"A", -2.0}};
  try {
    Declarer d(o, 0, {"NONE", "A"});
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "declarer: dwell_nats_per_hypothesis 'A' must be in [0, 1e+06] nats, got -2");
  }
}

TEST(DeclarerEvidencePerHypothesis, TableFileParsesAndRefusesBadLines) {
  const auto t = f16mmae::parse_dwell_nats_table("# N_k\nLS 32  # a surface\n\nAOA 0\n", "t");
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t.at("LS"), 32.0);
  EXPECT_EQ(t.at("AOA"), 0.0);
  try {
    f16mmae::parse_dwell_nats_table("LS 32\nAZ x\n", "t");
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "t line 2: expected 'NAME N' (a hypothesis and its evidence dwell in nats), got 'AZ x'");
  }
  EXPECT_THROW(f16mmae::parse_dwell_nats_table("LS 1\nLS 2\n", "t"), std::invalid_argument);
  EXPECT_THROW(f16mmae::parse_dwell_nats_table("LS 1 2\n", "t"), std::invalid_argument);
  try {
    f16mmae::parse_dwell_nats_table("LS 32\nAOA -1\n", "t");
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "t line 2: AOA's N must lie in [0, 1e+06] nats, got -1");
  }
  EXPECT_THROW(f16mmae::parse_dwell_nats_table("LS nan\n", "t"), std::invalid_argument);
  EXPECT_THROW(f16mmae::parse_dwell_nats_table("# nothing\n", "t"), std::invalid_argument);
  EXPECT_THROW(f16mmae::read_dwell_nats_table("/nonexistent/table.txt"), std::invalid_argument);
}

TEST(DeclarerEvidencePerHypothesis, AnArgumentWithAnEqualsSignIsTheTableInline) {
  // "NAME=N,..." inline, a path otherwise (header: dwell_nats_table_argument)
  const auto t = f16mmae::dwell_nats_table_argument("LS=32,AOA=0,RUD=992.5");
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t.at("LS"), 32.0);
  EXPECT_EQ(t.at("AOA"), 0.0);
  EXPECT_EQ(t.at("RUD"), 992.5);
  EXPECT_EQ(f16mmae::parse_dwell_nats_per_hypothesis("LS=32,AOA=0,RUD=992.5"), t);
  try {
    f16mmae::dwell_nats_table_argument("LS=32,AZ=-1");
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("AZ's N must lie in [0, 1e+06] nats, got -1"), std::string::npos) << e.what();
  }
  EXPECT_THROW(f16mmae::dwell_nats_table_argument("LS=32,LS=4"), std::invalid_argument);
  EXPECT_THROW(f16mmae::dwell_nats_table_argument("LS=x"), std::invalid_argument);
  EXPECT_THROW(f16mmae::dwell_nats_table_argument("LS=32,"), std::invalid_argument);
  try {   // no '=': a file
    f16mmae::dwell_nats_table_argument("/nonexistent/table.txt");
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "dwell-nats table '/nonexistent/table.txt': cannot be read");
  }
}

TEST(DeclarerLeastDwell, AHypothesisWithItsOwnDwellWaitsForIt) {
  DeclarerOptions o;   // dwell 0.25 s: 16 frames at 64 Hz
  o.dwell_s_per_hypothesis = {{"B", 1.0}, {"C", 0.0}};   // B: 64 frames; C: the dwell in force
  const std::vector<std::string> names{"NONE", "A", "B", "C"};
  Declarer d(o, 0, names);
  EXPECT_EQ(d.least_dwell_frames_of(1), 0);
  EXPECT_EQ(d.least_dwell_frames_of(2), 64);
  EXPECT_EQ(d.least_dwell_frames_of(3), 0);
  auto one = [](int k) {
    std::array<double, 4> v{0.01, 0.01, 0.01, 0.01};
    v[static_cast<std::size_t>(k)] = 0.97;
    return v;
  };
  for (int i = 0; i < 63; ++i) ASSERT_EQ(d.update(one(2)), -1) << i;
  EXPECT_EQ(d.update(one(2)), 2);                      // the 64th frame
  for (int i = 0; i < 15; ++i) ASSERT_EQ(d.update(one(1)), -1) << i;
  EXPECT_EQ(d.update(one(1)), 1);                      // A: the 16th
  for (int i = 0; i < 15; ++i) ASSERT_EQ(d.update(one(3)), -1) << i;
  EXPECT_EQ(d.update(one(3)), 3);                      // C (0 s): the 16th
  // a dwell in force longer than B's own (a maneuver's, 100 frames) is B's too
  Declarer m(o, 0, names);
  for (int i = 0; i < 99; ++i) ASSERT_EQ(m.update(one(2), 100), -1) << i;
  EXPECT_EQ(m.update(one(2), 100), 2);
  // an interruption restarts B's count like any other's
  Declarer r(o, 0, names);
  for (int i = 0; i < 40; ++i) ASSERT_EQ(r.update(one(2)), -1) << i;
  EXPECT_EQ(r.update(one(0)), -1);
  for (int i = 0; i < 63; ++i) ASSERT_EQ(r.update(one(2)), -1) << i;
  EXPECT_EQ(r.update(one(2)), 2);
}

TEST(DeclarerLeastDwell, ADualTakesTheLongestOfItsComponentsUnlessNamed) {
  DeclarerOptions o;   // 64 Hz: VEL 64 frames, AOA 32
  o.dwell_s_per_hypothesis = {{"VEL", 1.0}, {"AOA", 0.5}, {"LS+AOA", 0.25}};
  const std::vector<std::string> names{"NONE", "LS", "VEL", "AOA", "LS+VEL", "AOA+VEL", "LS+AOA", "LS+RS"};
  Declarer d(o, 0, names);
  const int expected[] = {0, 0, 64, 32, 64, 64, 16, 0};   // LS+AOA named: its own 0.25 s
  for (int k = 0; k < static_cast<int>(names.size()); ++k)
    EXPECT_EQ(d.least_dwell_frames_of(k), expected[k]) << names[k];
  const std::array<double, 8> p{0.01, 0.01, 0.01, 0.01, 0.93, 0.01, 0.01, 0.01};   // LS+VEL at the ceiling: 64 frames
  for (int i = 0; i < 63; ++i) ASSERT_EQ(d.update(p), -1) << i;
  EXPECT_EQ(d.update(p), 4);
}

TEST(DeclarerLeastDwell, TheEvidenceDwellScalesWithItAndSlotsAreMapped) {
  DeclarerOptions o;
  o.dwell_nats_per_hypothesis = {{"B", 4.0}};
  o.dwell_s_per_hypothesis = {{"B", 0.5}};   // 32 frames: B's evidence dwell 4 * 32 / 16 = 8 nats
  Declarer d(o, 0, {"NONE", "A", "B"});
  const int slot_holds[3] = {0, 2, 1};       // slot 1 holds B
  const std::array<double, 3> p{0.005, 0.99, 0.005};   // 2.398 nats a frame above the threshold's
  for (int i = 0; i < 3; ++i) EXPECT_EQ(d.update(p, d.dwell_frames(), nullptr, slot_holds), -1) << i;
  EXPECT_EQ(d.update(p, d.dwell_frames(), nullptr, slot_holds), 1);   // 9.59 >= 8 on the 4th frame
  Declarer plain(o, 0, {"NONE", "A", "B"});   // without the map slot 1 is A: the 16-frame dwell
  for (int i = 0; i < 15; ++i) EXPECT_EQ(plain.update(p), -1) << i;
  EXPECT_EQ(plain.update(p), 1);
}

TEST(DeclarerLeastDwell, TheTextFormParsesAndBadEntriesAreRefusedByName) {
  const auto t = f16mmae::parse_dwell_s_per_hypothesis("VEL=1,AOA=0.5");
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t.at("VEL"), 1.0);
  EXPECT_EQ(t.at("AOA"), 0.5);
  try {
    f16mmae::parse_dwell_s_per_hypothesis("VEL=1,AZ");
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "dwell_s_per_hypothesis: expected NAME=S (a hypothesis and its least dwell in seconds), "
                           "got 'AZ'");
  }
  try {
    f16mmae::parse_dwell_s_per_hypothesis("VEL=61");
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "dwell_s_per_hypothesis: VEL's dwell must lie in [0, 60] s, got 61");
  }
  for (const char* bad : {"", "VEL=1,VEL=2", "VEL=nan", "VEL=x", "=1", "VEL=1,", "VEL=-1", "VEL=1s"})
    EXPECT_THROW(f16mmae::parse_dwell_s_per_hypothesis(bad), std::invalid_argument) << bad;
  DeclarerOptions o;
  o.dwell_s_per_hypothesis = {{"X", 1.0}};
  try {
    Declarer d(o, 0, {"NONE", "A"});
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "declarer: dwell_s_per_hypothesis names 'X', not a hypothesis of the bank (NONE A)");
  }
  EXPECT_THROW(Declarer{o}, std::invalid_argument);   // no names to resolve against
  o.dwell_s_per_hypothesis = {{"A", 120.0}};
  EXPECT_THROW((Declarer{o, 0, {"NONE", "A"}}), std::invalid_argument);
}

// The rough-air least dwell (declarer.h): R_k in force while the observed scale is at least
// rough_scale, max(D_k, R_k); D_k alone in calmer air, before any scale and after reset().
TEST(DeclarerRoughDwell, TheRoughTableHoldsOnlyWhileTheScaleIsAtLeastRoughScale) {
  DeclarerOptions o;   // dwell 0.25 s: 16 frames at 64 Hz
  o.dwell_s_per_hypothesis = {{"B", 0.5}};                    // B: 32 frames everywhere
  o.rough_dwell_s_per_hypothesis = {{"A", 1.0}, {"B", 0.25}};   // A: 64 in rough air; B: max(32, 16)
  o.rough_scale = 4.0;
  const std::vector<std::string> names{"NONE", "A", "B", "A+B", "A+C", "C"};
  Declarer d(o, 0, names);
  EXPECT_TRUE(d.reads_scale());
  EXPECT_FALSE(d.rough());
  const int calm[] = {0, 0, 32, 32, 0, 0};
  for (int k = 0; k < 6; ++k) EXPECT_EQ(d.least_dwell_frames_of(k), calm[k]) << names[k];
  d.observe_scale(3.999);
  EXPECT_FALSE(d.rough());
  d.observe_scale(4.0);   // at the threshold: rough
  EXPECT_TRUE(d.rough());
  const int rough[] = {0, 64, 32, 64, 64, 0};   // duals not named: the longest component, both tables
  for (int k = 0; k < 6; ++k) EXPECT_EQ(d.least_dwell_frames_of(k), rough[k]) << names[k];
  d.observe_scale(std::nan(""));   // NaN reads as calm
  EXPECT_FALSE(d.rough());

  // the frame (1-based) on which A, held at 0.95, is declared, the scale of frame i being scale(i)
  auto declared_on = [&](auto scale) {
    Declarer d(o, 0, names);
    const std::array<double, 6> a{0.01, 0.95, 0.01, 0.01, 0.01, 0.01};
    for (int i = 0; i < 1000; ++i) {
      d.observe_scale(scale(i));
      if (d.update(a) == 1) return i + 1;
    }
    return -1;
  };
  EXPECT_EQ(declared_on([](int) { return 1.5; }), 16);    // calm air: the 16-frame dwell
  EXPECT_EQ(declared_on([](int) { return 30.0; }), 64);   // rough air: A's 64 frames
  // the air turns rough on A's 10th frame: the count goes on, to the longer dwell
  EXPECT_EQ(declared_on([](int i) { return i < 9 ? 2.0 : 6.0; }), 64);
  // ... and calm again on its 40th: the count it holds already passes the shorter dwell
  EXPECT_EQ(declared_on([](int i) { return i < 39 ? 6.0 : 2.0; }), 40);

  Declarer reset(o, 0, names);
  reset.observe_scale(30.0);
  reset.reset();
  EXPECT_FALSE(reset.rough());
}

TEST(DeclarerRoughDwell, TheDwellInForceForTheCandidateIsReadAfterEachUpdate) {
  DeclarerOptions o;   // dwell 0.25 s: 16 frames at 64 Hz
  o.dwell_s_per_hypothesis = {{"B", 0.5}};
  o.rough_dwell_s_per_hypothesis = {{"A", 1.0}};
  o.rough_scale = 4.0;
  Declarer d(o, 0, {"NONE", "A", "B"});
  EXPECT_EQ(d.dwell_frames_in_force(), 0);   // before any update
  const std::array<double, 3> none_above{0.5, 0.3, 0.2}, presumed{0.95, 0.03, 0.02}, a{0.02, 0.95, 0.03},
      b{0.02, 0.03, 0.95};
  d.update(none_above);
  EXPECT_EQ(d.dwell_frames_in_force(), 0);
  d.update(presumed);
  EXPECT_EQ(d.dwell_frames_in_force(), 16);   // NONE: the declarer's own
  d.update(b);
  EXPECT_EQ(d.dwell_frames_in_force(), 32);   // B's least dwell in all air
  d.update(a);
  EXPECT_EQ(d.dwell_frames_in_force(), 16);   // A in calm air
  d.observe_scale(5.0);
  d.update(a);
  EXPECT_EQ(d.dwell_frames_in_force(), 64);   // A in rough air
  EXPECT_EQ(d.update(a, 100), -1);
  EXPECT_EQ(d.dwell_frames_in_force(), 100);   // a longer phase dwell passed in
  Declarer copy(o, 0, {"NONE", "A", "B"});
  copy.carry_over(d);
  EXPECT_EQ(copy.dwell_frames_in_force(), 100);
  d.reset();
  EXPECT_EQ(d.dwell_frames_in_force(), 0);
}

TEST(DeclarerRoughDwell, WithoutARoughTableTheScaleChangesNothingAndBadOptionsAreRefused) {
  DeclarerOptions o;
  o.dwell_s_per_hypothesis = {{"A", 0.5}};
  Declarer d(o, 0, {"NONE", "A"});
  EXPECT_FALSE(d.reads_scale());
  d.observe_scale(100.0);
  EXPECT_EQ(d.least_dwell_frames_of(1), 32);
  o.rough_dwell_s_per_hypothesis = {{"A", 1.0}};
  o.rough_scale = 1.0;   // s >= 1 always: the plain table
  try {
    Declarer bad(o, 0, {"NONE", "A"});
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "declarer: rough_scale must be in (1, 1e+06] (the adaptation's scale is never below 1), "
                           "got 1");
  }
  o.rough_scale = std::nan("");
  EXPECT_THROW((Declarer{o, 0, {"NONE", "A"}}), std::invalid_argument);
  o.rough_scale = 4.0;
  o.rough_dwell_s_per_hypothesis = {{"X", 1.0}};
  try {
    Declarer bad(o, 0, {"NONE", "A"});
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "declarer: rough_dwell_s_per_hypothesis names 'X', not a hypothesis of the bank (NONE A)");
  }
  o.rough_dwell_s_per_hypothesis = {{"A", -1.0}};
  EXPECT_THROW((Declarer{o, 0, {"NONE", "A"}}), std::invalid_argument);
  o.rough_dwell_s_per_hypothesis.clear();
  o.rough_scale = 0.0;   // no table: the scale is not read, so not checked
  EXPECT_NO_THROW((Declarer{o, 0, {"NONE", "A"}}));
}
