// The hierarchy's structure (hierarchy_levels.h) on a small bank worked by hand: actuators U1
// U2, sensors Z1 Z2, hypotheses NONE(0) U1(1) U2(2) Z1(3) Z2(4) U1+U2(5) U1+Z1(6) U1+Z2(7)
// U2+Z1(8) U2+Z2(9) Z1+Z2(10), and with a partial hypothesis U1:loss=0.5(11): level 0, each
// level-1 bank, its live slots, the components' groups, the partial slots; the refusals.
#include "f16mmae/hierarchy_levels.h"

#include "synthetic_models.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

using namespace f16mmae;

namespace {

using Levels = HierarchyLevels<Eigen::Dynamic>;
using V = std::vector<int>;

ModelBank small_bank() {
  const test::Plant plant = test::random_plant(3, 2, 2, 5u, 1e-3, 1e-3);
  return test::make_bank(plant, {"U1", "U2"}, {"Z1", "Z2"}, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(2));
}

ModelBank with_partial(ModelBank mb, const std::string& name = "U1:loss=0.5") {
  HypothesisModel m = mb.hypotheses[0];   // the structure reads names only
  m.name = name;
  mb.hypotheses.push_back(m);
  return mb;
}

void expect_refused(const ModelBank& mb, const std::string& words) {
  try {
    Levels levels(mb);
    ADD_FAILURE() << "accepted; expected: " << words;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(HierarchyLevels, SinglesAndTheirDuals) {
  const Levels l(small_bank());
  EXPECT_EQ(l.size(), 5);
  EXPECT_FALSE(l.partial());
  EXPECT_EQ(l.level0(), (V{0, 1, 2, 3, 4}));
  EXPECT_EQ(l.level1(0), (V{0, 1, 5, 6, 7}));    // U1: U1+U2, U1+Z1, U1+Z2
  EXPECT_EQ(l.level1(1), (V{0, 2, 5, 8, 9}));    // U2: "U1+U2" found as b+a
  EXPECT_EQ(l.level1(2), (V{0, 3, 6, 8, 10}));   // Z1
  EXPECT_EQ(l.level1(3), (V{0, 4, 7, 9, 10}));   // Z2
  for (int f = 0; f < 4; ++f) {
    EXPECT_EQ(l.level1_live(f), (V{1, 1, 1, 1, 1}));
    EXPECT_EQ(l.level1_groups(f), (V{0, 1, 2, 3, 4}));
  }
  EXPECT_EQ(l.level0_groups(), (V{0, 1, 2, 3, 4}));
  EXPECT_EQ(l.level0_partial(), (std::vector<char>{0, 0, 0, 0, 0}));
  EXPECT_EQ(l.partial_count(), 0);
  // the duals' other singles: U1's bank holds U1+U2, U1+Z1, U1+Z2; U2's holds "U1+U2" as U2's dual with U1
  EXPECT_EQ(l.singles(), (V{1, 2, 3, 4}));
  EXPECT_EQ(l.level1_single(0), 1);
  EXPECT_EQ(l.level1_partner(0), (V{-1, -1, 2, 3, 4}));
  EXPECT_EQ(l.level1_single(1), 2);
  EXPECT_EQ(l.level1_partner(1), (V{-1, -1, 1, 3, 4}));
  EXPECT_EQ(l.level1_single(3), 4);
  EXPECT_EQ(l.level1_partner(3), (V{-1, -1, 1, 2, 3}));
}

TEST(HierarchyLevels, APartialHypothesisItsBankSpareSlotsAndComponents) {
  const Levels l(with_partial(small_bank()));
  EXPECT_EQ(l.size(), 6);
  EXPECT_TRUE(l.partial());
  EXPECT_EQ(l.level0(), (V{0, 1, 2, 3, 4, 11}));
  // U1's bank: five on line, the spare slot holds the partial hypothesis, off line
  EXPECT_EQ(l.level1(0), (V{0, 1, 5, 6, 7, 11}));
  EXPECT_EQ(l.level1_live(0), (V{1, 1, 1, 1, 1, 0}));
  EXPECT_EQ(l.level1(2), (V{0, 3, 6, 8, 10, 11}));
  EXPECT_EQ(l.level1_live(2), (V{1, 1, 1, 1, 1, 0}));
  // U1:loss=0.5's bank: {NONE, U1:loss=0.5, U1, U1's duals}, no spare slot
  EXPECT_EQ(l.level1(4), (V{0, 11, 1, 5, 6, 7}));
  EXPECT_EQ(l.level1_live(4), (V{1, 1, 1, 1, 1, 1}));
  // components: U1:loss=0.5 and U1 are one (the lowest live slot names the group)
  EXPECT_EQ(l.level0_groups(), (V{0, 1, 2, 3, 4, 1}));
  EXPECT_EQ(l.level1_groups(4), (V{0, 1, 1, 3, 4, 5}));
  EXPECT_EQ(l.level1_groups(0), (V{0, 1, 2, 3, 4, 5}));   // the off-line slot stays alone
  EXPECT_EQ(l.level0_partial(), (std::vector<char>{0, 0, 0, 0, 0, 1}));
  EXPECT_EQ(l.partial_count(), 1);
  // duals: the spare slot holds none; the partial's bank holds U1's duals, its single U1
  EXPECT_EQ(l.singles(), (V{1, 2, 3, 4}));
  EXPECT_EQ(l.level1_partner(0), (V{-1, -1, 2, 3, 4, -1}));
  EXPECT_EQ(l.level1_single(4), 1);
  EXPECT_EQ(l.level1_partner(4), (V{-1, -1, -1, 2, 3, 4}));
  EXPECT_EQ(Levels::partial_of("U1:loss=0.5"), "U1");
  EXPECT_EQ(Levels::partial_of("U1+Z1"), "");
  EXPECT_EQ(Levels::partial_of("U1"), "");
  // a fixed K holds the same indices
  const HierarchyLevels<6> fixed(with_partial(small_bank()));
  EXPECT_EQ(V(fixed.level1(4).begin(), fixed.level1(4).end()), l.level1(4));
  EXPECT_EQ(V(fixed.level0_groups().begin(), fixed.level0_groups().end()), l.level0_groups());
}

TEST(HierarchyLevels, RefusesByName) {
  ModelBank mb = small_bank();
  mb.hypotheses.erase(mb.hypotheses.begin() + mb.find("U2+Z1"));
  expect_refused(mb, "no dual hypothesis 'U2+Z1' (nor 'Z1+U2') for the level-1 bank of U2");
  expect_refused(with_partial(small_bank(), "XX:loss=0.5"),
                 "partial hypothesis 'XX:loss=0.5' names no single-failure hypothesis of the bank ('XX')");
  try {
    HierarchyLevels<5> l(with_partial(small_bank()));
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("has 5 single-failure hypotheses (1 of them partial, e.g. "
                                         "'U1:loss=0.5'), this bank needs 4"),
              std::string::npos)
        << e.what();
  }
  ModelBank none_only = small_bank();
  none_only.hypotheses.resize(1);
  expect_refused(none_only, "no single-failure hypothesis");
  ModelBank bad = small_bank();
  bad.hypotheses[0].name = "N0";
  expect_refused(bad, "model bank: hypothesis 0 must be NONE");
}
