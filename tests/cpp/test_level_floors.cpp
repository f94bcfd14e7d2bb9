// The floors and dwell of the hierarchical bank's levels (level_floors.h): the bounds and their
// refusals against values worked by hand, the level-1 dwell, the partial hypotheses' floor
// factor, and the floors apply() sets on a filter bank of scalar models (no tracked levels, so
// f_k = m_k p_min on its tier exactly) at level 0, at level 1 and back, without allocation; and the
// level-0 floor that follows the air (rough_air_floor.h): the weight and the floor against values
// worked by hand, off and the band's ends bit for bit, and the refusals.
#include "f16mmae/level_floors.h"
#include "f16mmae/rough_air_floor.h"

#include "allocation_counter.h"
#include "scalar_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

using namespace f16mmae;
using test::scalar_model;
using test::Scalar;
using test::ScalarBank;

namespace {

// The message of the std::invalid_argument `f` throws ("" if none).
template <class F>
std::string refusal(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

RoughAirFloorOptions on(double p_min = 1e-9, double from = 1.3, double to = 1.5) {
  RoughAirFloorOptions o;
  o.p_min = p_min;
  o.from = from;
  o.to = to;
  return o;
}

}  // namespace

TEST(LevelFloors, TheLevelOneBoundLeavesRoomToPassTheThreshold) {
  // T = 0.9, K = 5: (1 - 0.9) / 4 = 0.025; K = 18 (the F-16 bank's level 0): 0.1 / 17
  EXPECT_NEAR(LevelFloors::level1_bound(0.9, 5), 0.025, 1e-15);
  EXPECT_NEAR(LevelFloors::level1_bound(0.9, 18), 0.00588235294117647, 1e-15);
  EXPECT_NEAR(LevelFloors::level1_bound(0.99, 11), 0.001, 1e-15);
  EXPECT_NO_THROW(LevelFloors::check_level1(0.0, 0.0, 0.9, 5));
  EXPECT_NO_THROW(LevelFloors::check_level1(0.0249, 0.5, 0.9, 5));
  EXPECT_EQ(refusal([] { LevelFloors::check_level1(0.025, 0.0, 0.9, 5); }),
            "hierarchical bank: level1_p_min must lie in [0, (1 - threshold)/(K - 1)) = [0, 0.025000), got 0.025000");
  EXPECT_EQ(refusal([] { LevelFloors::check_level1(0.006, 0.0, 0.9, 18); }),
            "hierarchical bank: level1_p_min must lie in [0, (1 - threshold)/(K - 1)) = [0, 0.005882), got 0.006000");
  EXPECT_NE(refusal([] { LevelFloors::check_level1(-1e-12, 0.0, 0.9, 5); }), "");
  EXPECT_NE(refusal([] { LevelFloors::check_level1(kNaN, 0.0, 0.9, 5); }), "");
  EXPECT_EQ(refusal([] { LevelFloors::check_level1(0.0, -0.1, 0.9, 5); }),
            "hierarchical bank: level1_dwell_s must be >= 0 (0: the level-0 dwell), got -0.100000");
  EXPECT_NE(refusal([] { LevelFloors::check_level1(0.0, kNaN, 0.9, 5); }), "");
}

TEST(LevelFloors, ThePartialFloorsMustLeaveRoomForADeclaration) {
  // K = 4, 2 partial hypotheses, p_min = 0.01, T = 0.9: 2 f + 1 x 0.01 < 0.1, f < 0.045
  EXPECT_NO_THROW(LevelFloors::check_partial(0.0449, 2, 4, 0.01, 0.9));
  EXPECT_EQ(refusal([] { LevelFloors::check_partial(0.0451, 2, 4, 0.01, 0.9); }),
            "hierarchical bank: partial_p_min 0.045100 for 2 partial hypotheses leaves no hypothesis room to pass "
            "the threshold: n_partial partial_p_min + the others' floors must stay below 1 - threshold = 0.100000");
  // K = 18 with 5 partials, p_min = 1e-9: f < (0.1 - 12e-9) / 5 = 0.0199999976
  EXPECT_NO_THROW(LevelFloors::check_partial(0.0199999975, 5, 18, 1e-9, 0.9));
  EXPECT_NE(refusal([] { LevelFloors::check_partial(0.0199999977, 5, 18, 1e-9, 0.9); }), "");
  // unset: nothing to check, with or without partial hypotheses
  EXPECT_NO_THROW(LevelFloors::check_partial(0.0, 0, 4, 0.01, 0.9));
  EXPECT_NO_THROW(LevelFloors::check_partial(0.0, 2, 4, 0.01, 0.9));
  EXPECT_EQ(refusal([] { LevelFloors::check_partial(1e-5, 0, 4, 0.01, 0.9); }),
            "hierarchical bank: partial_p_min is set but the bank has no partial-loss hypothesis "
            "(design --partial-loss)");
  EXPECT_EQ(refusal([] { LevelFloors::check_partial(-1e-5, 2, 4, 0.01, 0.9); }),
            "hierarchical bank: partial_p_min must be >= 0 (0: the level-0 floor), got -0.000010");
  EXPECT_NE(refusal([] { LevelFloors::check_partial(kInf, 2, 4, 0.01, 0.9); }), "");
  EXPECT_NE(refusal([] { LevelFloors::check_partial(kNaN, 2, 4, 0.01, 0.9); }), "");
}

TEST(LevelFloors, TheLevelOneDwellIsItsOwnOnlyWhenSetAndAtLevelOne) {
  EXPECT_TRUE(LevelFloors::own_level1_dwell(1, 0.5));
  EXPECT_FALSE(LevelFloors::own_level1_dwell(0, 0.5));
  EXPECT_FALSE(LevelFloors::own_level1_dwell(1, 0.0));
  EXPECT_EQ(LevelFloors::level1_dwell(0.0, 0.25), 0.25);
  EXPECT_EQ(LevelFloors::level1_dwell(1.5, 0.25), 1.5);
}

TEST(LevelFloors, ThePartialFloorFactorHoldsAtLevelZeroOnly) {
  // m = partial_p_min / p_min = 1e-5 / 1e-9 = 1e4 for a partial hypothesis at level 0, else 1
  EXPECT_NEAR(LevelFloors::floor_scale(0, true, 1e-5, 1e-9), 1e4, 1e-8);
  EXPECT_EQ(LevelFloors::floor_scale(0, false, 1e-5, 1e-9), 1.0);
  EXPECT_EQ(LevelFloors::floor_scale(1, true, 1e-5, 1e-9), 1.0);
  EXPECT_EQ(LevelFloors::floor_scale(0, true, 1e-5, 0.0), 1.0);   // no level-0 floor: no factor
}

TEST(LevelFloors, ApplySetsTheFloorsOfTheLevelOnLine) {
  // NONE, f, and two hypotheses that are partial at level 0 (duals f+c at level 1); p_min = 0.01
  const std::vector<Scalar> models{scalar_model(1.0), scalar_model(2.0), scalar_model(3.0), scalar_model(4.0)};
  FilterBankOptions opt;
  opt.p_min = 0.01;
  ScalarBank bank(models, opt);
  const std::vector<char> partial{0, 0, 1, 1};
  const auto floors = [&] {
    return std::vector<double>{bank.floor_of(0), bank.floor_of(1), bank.floor_of(2), bank.floor_of(3)};
  };
  const auto expect_floors = [&](const std::vector<double>& want, const char* where) {
    const std::vector<double> got = floors();
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(got[k], want[k], 1e-15) << where << ", hypothesis " << k;
  };

  // level 0, partial_p_min 0.05: the partial ones at 0.05 (m = 5), the others at 0.01;
  // NONE presumed holds 1 - (0.01 + 0.05 + 0.05) = 0.89
  LevelFloors::apply(bank, 0, 0.01, 0.002, 0.05, partial);
  expect_floors({0.01, 0.01, 0.05, 0.05}, "level 0");
  EXPECT_NEAR(bank.floor_scale(2), 5.0, 1e-15);
  bank.presume(0);
  EXPECT_NEAR(bank.probabilities()(0), 0.89, 1e-15);

  // level 1, level1_p_min 0.002: NONE and f keep 0.01, the duals 0.002, no factor;
  // f presumed holds 1 - (0.01 + 0.002 + 0.002) = 0.986
  LevelFloors::apply(bank, 1, 0.01, 0.002, 0.05, partial);
  expect_floors({0.01, 0.01, 0.002, 0.002}, "level 1");
  EXPECT_EQ(bank.floor_scale(2), 1.0);
  EXPECT_EQ(bank.floor_scale(3), 1.0);
  bank.presume(1);
  EXPECT_NEAR(bank.probabilities()(1), 0.986, 1e-15);

  // level 1 without level1_p_min: the level-0 floor for all
  LevelFloors::apply(bank, 1, 0.01, 0.0, 0.05, partial);
  expect_floors({0.01, 0.01, 0.01, 0.01}, "level 1, unset");

  // back at level 0 with a new level-0 floor 0.02: the partial floor stays 0.05 (m = 2.5)
  LevelFloors::apply(bank, 0, 0.02, 0.002, 0.05, partial);
  expect_floors({0.02, 0.02, 0.05, 0.05}, "level 0 again");
  EXPECT_NEAR(bank.floor_scale(3), 2.5, 1e-15);

  // with nothing set the floors are those of the bank as built, bit for bit
  ScalarBank plain(models, opt), set(models, opt);
  LevelFloors::apply(set, 0, 0.01, 0.0, 0.0, partial);
  LevelFloors::apply(set, 1, 0.01, 0.0, 0.0, partial);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(set.floor_of(k), plain.floor_of(k));
    EXPECT_EQ(set.floor_scale(k), 1.0);
  }
}

TEST(LevelFloors, ApplyAllocatesNothing) {
  const std::vector<Scalar> models{scalar_model(1.0), scalar_model(2.0), scalar_model(3.0), scalar_model(4.0)};
  FilterBankOptions opt;
  opt.p_min = 0.01;
  ScalarBank bank(models, opt);
  const std::vector<char> partial{0, 0, 1, 1};
  const long long before = f16mmae::testing::allocation_count();
  for (int i = 0; i < 8; ++i) LevelFloors::apply(bank, i % 2, 0.01, 0.002, 0.05, partial);
  EXPECT_EQ(f16mmae::testing::allocation_count() - before, 0);
}


TEST(RoughAirFloor, TheWeightRunsAcrossTheBandInHundredths) {
  const RoughAirFloorOptions o = on();
  EXPECT_EQ(RoughAirFloor::weight(o, 0.0), 0.0);
  EXPECT_EQ(RoughAirFloor::weight(o, 1.3), 0.0);
  EXPECT_EQ(RoughAirFloor::weight(o, 1.4), 0.5);
  EXPECT_EQ(RoughAirFloor::weight(o, 1.45), 0.75);
  EXPECT_EQ(RoughAirFloor::weight(o, 1.3 + 0.2 * 0.123), 0.12);   // rounded to 1/100
  EXPECT_EQ(RoughAirFloor::weight(o, 1.3 + 0.2 * 0.127), 0.13);
  EXPECT_EQ(RoughAirFloor::weight(o, 1.5), 1.0);
  EXPECT_EQ(RoughAirFloor::weight(o, 7.0), 1.0);
  EXPECT_EQ(RoughAirFloor::weight(o, std::numeric_limits<double>::quiet_NaN()), 0.0);
  EXPECT_EQ(RoughAirFloor::weight(o, std::numeric_limits<double>::infinity()), 1.0);
}

TEST(RoughAirFloor, TheFloorIsTheLogLinearBlendAndEachEndBitForBit) {
  const RoughAirFloorOptions o = on();
  EXPECT_EQ(RoughAirFloor::floor(o, 1e-5, 1.0), 1e-5);    // light air: the node's
  EXPECT_EQ(RoughAirFloor::floor(o, 1e-5, 1.6), 1e-9);    // moderate: the rough-air floor
  EXPECT_NEAR(std::log10(RoughAirFloor::floor(o, 1e-5, 1.4)), -7.0, 1e-12);    // w 1/2: 10^-(5+9)/2
  EXPECT_NEAR(std::log10(RoughAirFloor::floor(o, 1e-5, 1.45)), -8.0, 1e-12);   // w 3/4: 10^-(5/4 + 27/4)
  EXPECT_NEAR(std::log10(RoughAirFloor::floor(o, 1e-3, 1.35)), -4.5, 1e-12);   // w 1/4: 10^-(9/4 + 9/4)
  EXPECT_EQ(RoughAirFloor::floor(o, 1e-9, 1.4), 1e-9);                          // equal ends
  EXPECT_EQ(RoughAirFloor::floor(o, 0.0, 1.4), 0.0);                            // no floor below the top
  EXPECT_EQ(RoughAirFloor::floor(o, 0.0, 1.5), 1e-9);
  EXPECT_NEAR(std::log10(RoughAirFloor::floor(on(1e-3), 1e-7, 1.4)), -5.0, 1e-12);   // a floor that rises
  const RoughAirFloorOptions off;
  for (const double x : {0.0, 1.4, 100.0}) EXPECT_EQ(RoughAirFloor::floor(off, 3.7e-6, x), 3.7e-6);
}

TEST(RoughAirFloor, RefusesWhatLeavesNoFloorOrNoBandNamingTheValue) {
  EXPECT_NO_THROW(RoughAirFloor::check(on(), 13, true));
  EXPECT_NO_THROW(RoughAirFloor::check(RoughAirFloorOptions{}, 13, false));   // off needs no adaptation
  EXPECT_EQ(refusal([] { RoughAirFloor::check(on(1.0 / 13), 13, true); }),
            "hierarchical bank: rough_p_min must lie in [0, 1/K) with K = 13 hypotheses (0: off), got 0.07692307692307693");
  EXPECT_NE(refusal([] { RoughAirFloor::check(on(-1e-9), 13, true); }), "");
  EXPECT_NE(refusal([] { RoughAirFloor::check(on(std::numeric_limits<double>::quiet_NaN()), 13, true); }), "");
  EXPECT_EQ(refusal([] { RoughAirFloor::check(on(1e-9, 1.5, 1.5), 13, true); }),
            "hierarchical bank: the rough-air floor's band needs 0 <= rough_p_min_from < rough_p_min_to <= 1000 "
            "(calm-air units), got 1.5 and 1.5");
  EXPECT_NE(refusal([] { RoughAirFloor::check(on(1e-9, -0.1, 1.5), 13, true); }), "");
  EXPECT_NE(refusal([] { RoughAirFloor::check(on(1e-9, 1.3, 1001.0), 13, true); }), "");
  EXPECT_NE(refusal([] { RoughAirFloor::check(on(1e-9, 1.3, std::numeric_limits<double>::infinity()), 13, true); }),
            "");
  EXPECT_EQ(refusal([] { RoughAirFloor::check(on(), 13, false); }),
            "hierarchical bank: rough_p_min reads the air from the turbulence adaptation's measured power ratio; "
            "it needs adapt_turbulence on");
}
