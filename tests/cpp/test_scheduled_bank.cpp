// A scheduled HierarchicalBank (bank_schedule.h, scheduled_filters.h) on F-16-sized synthetic
// banks designed at four grid nodes (different plants and trims): at a node the filters and
// trims are that node's bit for bit; at a cell midpoint every matrix is the hand-computed
// mean of the corners'; the bilinear weights at a quarter point are hand-computed; nearest
// switching keeps its node within the hysteresis; a schedule change keeps probabilities,
// declarations and the level and moves the states bumplessly; outside the grid is clamped and
// counted; an uncovered corner splits the cell, its half taking the nearest node's filters and
// the covered triangle's plane for the trims (or the node's, plane_trims off), a cell keeping one
// corner its neighbours' planes, a cut cell's linear trims in the lift coordinate; the trim offset adds to the
// scheduled trim; nothing allocates per frame; the scheduled-bank file round-trips and refuses
// corruption naming the field.
#include "bankfile/schedule_file.h"
#include "f16mmae/hierarchical_bank.h"

#include "allocation_counter.h"
#include "synthetic_models.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <utility>

using namespace f16mmae;

namespace {

using Z = F16HierarchicalBank::ZVector;
using U = F16HierarchicalBank::UVector;
using X = F16HierarchicalBank::XVector;

// Node (i, j) of a 2 x 2 grid Mach {0.4, 0.6} x {10,000, 20,000} ft: its own plant and trims.
test::Plant node_plant(int i, int j) { return test::random_plant(13, 5, 7, 100u + 10u * i + j, 1e-3, 1e-3); }
ModelBank node_bank(int i, int j) {
  Eigen::VectorXd u_trim = Eigen::VectorXd::Constant(5, 0.01 * (1 + i + 2 * j)), z_trim(7);
  z_trim << 400.0 + 100.0 * i - 20.0 * j, 0.1 - 0.02 * i + 0.01 * j, 0.0, 1.0, 0.0, 0.0, 0.0;
  ModelBank b = test::make_bank(node_plant(i, j), test::kF16Actuators, test::kF16Sensors, u_trim, z_trim);
  b.mach = i == 0 ? 0.4 : 0.6;
  b.alt_ft = j == 0 ? 10000.0 : 20000.0;
  return b;
}
Eigen::VectorXd node_x_trim(int i, int j) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(13);
  const ModelBank b = node_bank(i, j);
  x(0) = b.z_trim(0);
  x(1) = b.z_trim(1);
  x(3) = b.z_trim(1);
  x.tail(5) = b.u_trim;
  return x;
}

// The schedule; `skip` names a node left out ((-1, -1): all four covered).
BankSchedule make_schedule(int skip_i = -1, int skip_j = -1) {
  BankSchedule s;
  s.mach = {0.4, 0.6};
  s.alt_ft = {10000.0, 20000.0};
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      if (i == skip_i && j == skip_j) continue;
      ScheduleNode n;
      n.i_mach = i;
      n.i_alt = j;
      n.bank = node_bank(i, j);
      n.x_trim = node_x_trim(i, j);
      s.nodes.push_back(n);
    }
  s.metadata = "{}";
  return s;
}

// A schedule on the grid mach x alt, node_bank(0, 0)'s plant at every node but those where
// uncovered(i, j), each node's trims set by trims(z_trim, mach, alt_ft).
template <class Uncovered, class Trims>
BankSchedule grid_schedule(const std::vector<double>& mach, const std::vector<double>& alt, Uncovered uncovered,
                           Trims trims) {
  BankSchedule s;
  s.mach = mach;
  s.alt_ft = alt;
  for (int j = 0; j < static_cast<int>(alt.size()); ++j)
    for (int i = 0; i < static_cast<int>(mach.size()); ++i) {
      if (uncovered(i, j)) continue;
      ScheduleNode n;
      n.i_mach = i;
      n.i_alt = j;
      n.bank = node_bank(0, 0);
      n.bank.mach = mach[static_cast<std::size_t>(i)];
      n.bank.alt_ft = alt[static_cast<std::size_t>(j)];
      trims(n.bank.z_trim, n.bank.mach, n.bank.alt_ft);
      n.x_trim = node_x_trim(0, 0);
      s.nodes.push_back(n);
    }
  s.metadata = "{}";
  return s;
}
// The shipped schedule's low-speed corner on a 3 x 3 grid (Mach 0.3, 0.35, 0.4 x 25,000, 30,000,
// 35,000 ft): (0.3, 30,000 and 35,000 ft) and (0.35, 35,000 ft) do not trim.
bool corner_uncovered(int i, int j) { return (i == 0 && j >= 1) || (i == 1 && j == 2); }

ModelBank scheduled_bank(const BankSchedule& s) {
  ModelBank b = s.nodes[static_cast<std::size_t>(s.primary)].bank;
  b.schedule = std::make_shared<BankSchedule>(s);
  return b;
}

// No air-data low-pass unless a test asks for it: each schedule() call is where it says.
HierarchicalOptions options(ScheduleMode mode) {
  HierarchicalOptions o;
  o.schedule.mode = mode;
  o.schedule.air_data_time_constant_s = 0.0;
  return o;
}

// A short noisy flight in absolute signals around a trim.
struct Frames {
  std::vector<Z> z;
  std::vector<U> u;
};
Frames fly(const ModelBank& truth_bank, int node_i, int node_j, const std::vector<std::string>& failed_from_64,
           int frames, unsigned seed) {
  test::Truth truth(node_plant(node_i, node_j), test::kF16Actuators, test::kF16Sensors, seed);
  Frames f;
  for (int i = 0; i < frames; ++i) {
    const std::vector<std::string> failed = i >= 64 ? failed_from_64 : std::vector<std::string>{};
    f.z.push_back(truth.measure(failed) + truth_bank.z_trim);
    const Eigen::VectorXd u = test::dither(5, i, 64.0);
    f.u.push_back(u + truth_bank.u_trim);
    truth.advance(u, failed);
  }
  return f;
}

}  // namespace

TEST(ScheduledBank, AtANodeTheFiltersAndTrimsAreThatNodesBitForBit) {
  const BankSchedule s = make_schedule();
  F16HierarchicalBank hb(scheduled_bank(s), options(ScheduleMode::kInterpolate));
  hb.schedule(AirData{0.6, 20000.0});
  const ModelBank node = node_bank(1, 1);
  for (int k = 0; k < hb.size(); ++k) {
    const HypothesisModel& m = node.hypotheses[hb.online()[k]];
    const F16HypothesisFilter expected(F16FilterModel::from_matrices(m.phi, m.bd, m.h, m.k, m.a));
    const auto& got = hb.bank().hypothesis(k);
    EXPECT_TRUE(got.model().phi == expected.model().phi);
    EXPECT_TRUE(got.model().bd == expected.model().bd);
    EXPECT_TRUE(got.model().h == expected.model().h);
    EXPECT_TRUE(got.model().k == expected.model().k);
    EXPECT_TRUE(got.a_inverse() == expected.a_inverse());
    EXPECT_EQ(got.log_det_a(), expected.log_det_a());
  }
  EXPECT_TRUE(hb.u_trim() == U(node.u_trim));
  EXPECT_TRUE(hb.z_trim() == Z(node.z_trim));
  EXPECT_TRUE(Eigen::MatrixXd(hb.bank().h_output()) == node.h_output);

  // and a flight there gives the node bank's own probabilities, bit for bit
  F16HierarchicalBank alone(node);
  F16HierarchicalBank sched(scheduled_bank(s), options(ScheduleMode::kInterpolate));
  const Frames f = fly(node, 1, 1, {"PIT"}, 300, 7u);
  for (std::size_t i = 0; i < f.z.size(); ++i) {
    sched.schedule(AirData{0.6, 20000.0});
    alone.step(f.z[i], f.u[i]);
    sched.step(f.z[i], f.u[i]);
    ASSERT_TRUE(alone.probabilities() == sched.probabilities()) << "frame " << i;
  }
  EXPECT_EQ(alone.declarations().size(), sched.declarations().size());
}

TEST(ScheduledBank, AtACellMidpointEveryMatrixIsTheMeanOfTheCorners) {
  const BankSchedule s = make_schedule();
  F16HierarchicalBank hb(scheduled_bank(s), options(ScheduleMode::kInterpolate));
  hb.schedule(AirData{0.5, 15000.0});
  const ModelBank b00 = node_bank(0, 0), b10 = node_bank(1, 0), b01 = node_bank(0, 1), b11 = node_bank(1, 1);
  for (int k = 0; k < hb.size(); ++k) {
    const int h = hb.online()[k];
    auto mean = [&](auto get) -> Eigen::MatrixXd {
      return 0.25 * get(b00.hypotheses[h]) + 0.25 * get(b10.hypotheses[h]) + 0.25 * get(b01.hypotheses[h]) +
             0.25 * get(b11.hypotheses[h]);
    };
    const auto& got = hb.bank().hypothesis(k);
    EXPECT_LT((Eigen::MatrixXd(got.model().phi) - mean([](const HypothesisModel& m) { return m.phi; })).norm(), 1e-14);
    EXPECT_LT((Eigen::MatrixXd(got.model().bd) - mean([](const HypothesisModel& m) { return m.bd; })).norm(), 1e-14);
    EXPECT_LT((Eigen::MatrixXd(got.model().k) - mean([](const HypothesisModel& m) { return m.k; })).norm(), 1e-14);
    EXPECT_LT((Eigen::MatrixXd(got.model().h) - mean([](const HypothesisModel& m) { return m.h; })).norm(), 1e-14);
    const Eigen::MatrixXd a_inv_mean = mean([](const HypothesisModel& m) -> Eigen::MatrixXd { return m.a.inverse(); });
    EXPECT_LT((Eigen::MatrixXd(got.a_inverse()) - a_inv_mean).norm(), 1e-9 * a_inv_mean.norm());
    const double logdet = 0.25 * (std::log(b00.hypotheses[h].a.determinant()) + std::log(b10.hypotheses[h].a.determinant()) +
                                  std::log(b01.hypotheses[h].a.determinant()) + std::log(b11.hypotheses[h].a.determinant()));
    EXPECT_NEAR(got.log_det_a(), logdet, 1e-9 * std::abs(logdet));
  }
  const Eigen::MatrixXd h_mid = 0.25 * (b00.h_output + b10.h_output + b01.h_output + b11.h_output);
  EXPECT_LT((Eigen::MatrixXd(hb.bank().h_output()) - h_mid).norm(), 1e-14);
  const Eigen::VectorXd z_mid = 0.25 * (b00.z_trim + b10.z_trim + b01.z_trim + b11.z_trim);
  EXPECT_LT((Eigen::VectorXd(hb.z_trim()) - z_mid).norm(), 1e-12);
}

TEST(ScheduledBank, BilinearWeightsAtAQuarterPointAreHandComputed) {
  const BankSchedule s = make_schedule();
  F16HierarchicalBank hb(scheduled_bank(s), options(ScheduleMode::kInterpolate));
  hb.schedule(AirData{0.45, 15000.0});  // a = 0.25, b = 0.5
  const auto& w = hb.scheduled().weights();
  EXPECT_DOUBLE_EQ(w[0], 0.375);
  EXPECT_DOUBLE_EQ(w[1], 0.125);
  EXPECT_DOUBLE_EQ(w[2], 0.375);
  EXPECT_DOUBLE_EQ(w[3], 0.125);
  // u_trim of node (i, j) is 0.01 (1 + i + 2 j): 0.375*0.01 + 0.125*0.02 + 0.375*0.03 + 0.125*0.04 = 0.0225
  for (int j = 0; j < 5; ++j) EXPECT_NEAR(hb.u_trim()(j), 0.0225, 1e-15);
}

TEST(ScheduledBank, TheScheduleFollowsTheAirDataThroughItsLowPass) {
  const BankSchedule s = make_schedule();
  HierarchicalOptions o = options(ScheduleMode::kInterpolate);
  o.schedule.air_data_time_constant_s = 2.0;
  F16HierarchicalBank hb(scheduled_bank(s), o);
  hb.schedule(AirData{0.4, 10000.0});  // the first value after a reset is taken as it is
  EXPECT_EQ(hb.scheduled().filtered_air_data().mach, 0.4);
  hb.schedule(AirData{0.6, 20000.0});  // then the running mean: (0.4 + 0.6) / 2
  EXPECT_NEAR(hb.scheduled().filtered_air_data().mach, 0.5, 1e-15);
  EXPECT_NEAR(hb.scheduled().filtered_air_data().pressure_altitude_ft, 15000.0, 1e-9);
  // the trims are the bilinear blend at the filtered point: u_trim of node (i, j) is 0.01 (1 + i + 2 j)
  const double a = 0.5, b = 0.5;
  const double u = 0.01 * ((1 - a) * (1 - b) * 1 + a * (1 - b) * 2 + (1 - a) * b * 3 + a * b * 4);
  EXPECT_NEAR(hb.u_trim()(0), u, 1e-15);
  // the mean of every selection while 1/n > alpha = 1 - exp(-1/128) (n <= 128 here)
  const double alpha = 1.0 - std::exp(-1.0 / (64.0 * 2.0));  // frame period 1/64 s, tau 2 s
  double sum = 1.0;
  for (int n = 3; n <= 128; ++n) {
    const double m = 0.4 + 0.001 * (n % 7);
    sum += m;
    hb.schedule(AirData{m, 20000.0});
  }
  EXPECT_NEAR(hb.scheduled().filtered_air_data().mach, sum / 128.0, 1e-14);
  ASSERT_GT(1.0 / 128.0, alpha);  // n = 128 is the last running-mean step
  ASSERT_LT(1.0 / 129.0, alpha);
  // after it, the low-pass: a filter moves 1 - 1/e of a step in tau
  hb.reset();
  for (int i = 0; i < 200; ++i) hb.schedule(AirData{0.4, 20000.0});
  for (int i = 0; i < 128; ++i) hb.schedule(AirData{0.6, 20000.0});
  EXPECT_NEAR(hb.scheduled().filtered_air_data().mach, 0.6 - 0.2 * std::exp(-1.0), 1e-12);
  hb.reset();
  hb.schedule(AirData{0.6, 20000.0});
  EXPECT_EQ(hb.scheduled().filtered_air_data().mach, 0.6);
}

TEST(ScheduledBank, TrimsAreInterpolatedToThirdOrderOnFourNodes) {
  // Mach axis 0.3 0.4 0.5 0.6 at one altitude; every trim entry of node i is f(M_i) = 1/M_i^2
  BankSchedule s;
  s.mach = {0.3, 0.4, 0.5, 0.6};
  s.alt_ft = {20000.0};
  for (int i = 0; i < 4; ++i) {
    ScheduleNode n;
    n.i_mach = i;
    n.bank = node_bank(0, 0);
    const double f = 1.0 / (s.mach[i] * s.mach[i]);
    n.bank.u_trim.setConstant(f);
    n.bank.z_trim.setConstant(f);
    n.x_trim = Eigen::VectorXd::Constant(13, f);
    s.nodes.push_back(n);
  }
  s.primary = 1;
  F16HierarchicalBank hb(scheduled_bank(s), options(ScheduleMode::kInterpolate));
  hb.schedule(AirData{0.45, 20000.0});
  // Lagrange weights at 0.45 on 0.3 0.4 0.5 0.6: -1/16, 9/16, 9/16, -1/16
  const double cubic = -0.0625 / 0.09 + 0.5625 / 0.16 + 0.5625 / 0.25 - 0.0625 / 0.36;
  EXPECT_NEAR(hb.u_trim()(0), cubic, 1e-12);
  EXPECT_NEAR(hb.z_trim()(3), cubic, 1e-12);
  EXPECT_NEAR(hb.scheduled().x_trim()(5), cubic, 1e-12);
  EXPECT_NEAR(cubic, 1.0 / (0.45 * 0.45), 0.05);  // 0.04 off; linear would be 0.19 off
  hb.schedule(AirData{0.5, 20000.0});  // at a node: the node's trim exactly
  EXPECT_EQ(hb.u_trim()(0), 1.0 / (0.5 * 0.5));
  HierarchicalOptions linear = options(ScheduleMode::kInterpolate);
  linear.schedule.cubic_trims = false;
  F16HierarchicalBank hl(scheduled_bank(s), linear);
  hl.schedule(AirData{0.45, 20000.0});
  EXPECT_NEAR(hl.u_trim()(0), 0.5 / 0.16 + 0.5 / 0.25, 1e-12);
}

TEST(ScheduledBank, NearestSwitchesOnlyPastTheHysteresis) {
  const BankSchedule s = make_schedule();
  HierarchicalOptions o = options(ScheduleMode::kNearest);
  o.schedule.hysteresis_cells = 0.1;
  F16HierarchicalBank hb(scheduled_bank(s), o);
  auto node_mach = [&] { return s.mach[hb.scheduled().axes().nodes[hb.scheduled().corners()[0]].i_mach]; };
  hb.schedule(AirData{0.4, 10000.0});
  EXPECT_EQ(node_mach(), 0.4);
  hb.schedule(AirData{0.5 + 0.2 * 0.04, 10000.0});  // s = 0.54: 0.08 nearer node 1, inside the margin
  EXPECT_EQ(node_mach(), 0.4);
  hb.schedule(AirData{0.5 + 0.2 * 0.06, 10000.0});  // s = 0.56: 0.12 nearer
  EXPECT_EQ(node_mach(), 0.6);
  hb.schedule(AirData{0.5 - 0.2 * 0.04, 10000.0});  // back to s = 0.46: stays
  EXPECT_EQ(node_mach(), 0.6);
  hb.schedule(AirData{0.5 - 0.2 * 0.06, 10000.0});
  EXPECT_EQ(node_mach(), 0.4);
  EXPECT_EQ(hb.scheduled().switches(), 2);
  EXPECT_TRUE(hb.z_trim() == Z(node_bank(0, 0).z_trim));
}

TEST(ScheduledBank, AHandoverKeepsProbabilitiesDeclarationsLevelAndTheAbsoluteState) {
  for (const ScheduleMode mode : {ScheduleMode::kNearest, ScheduleMode::kInterpolate}) {
    const BankSchedule s = make_schedule();
    F16HierarchicalBank hb(scheduled_bank(s), options(mode));
    const ModelBank node = node_bank(0, 0);
    const Frames f = fly(node, 0, 0, {"PIT"}, 320, 5u);
    for (std::size_t i = 0; i < f.z.size(); ++i) {
      hb.schedule(AirData{0.4, 10000.0});
      hb.step(f.z[i], f.u[i]);
    }
    ASSERT_EQ(hb.level(), 1);
    const auto p = hb.probabilities();
    const auto names = hb.online_names();
    const auto declared = hb.declarations().size();
    const X x_trim_before = hb.scheduled().x_trim();
    std::vector<X> absolute;
    for (int k = 0; k < hb.size(); ++k) absolute.push_back(X(hb.bank().prior(k)) + x_trim_before);
    hb.schedule(AirData{0.6, 20000.0});
    EXPECT_FALSE(hb.scheduled().x_trim() == x_trim_before);
    EXPECT_TRUE(hb.probabilities() == p);
    EXPECT_EQ(hb.level(), 1);
    EXPECT_EQ(hb.online_names(), names);
    EXPECT_EQ(hb.declarations().size(), declared);
    EXPECT_EQ(hb.name(hb.current_hypothesis()), "PIT");
    for (int k = 0; k < hb.size(); ++k)
      EXPECT_LT((X(hb.bank().prior(k)) + hb.scheduled().x_trim() - absolute[k]).norm(), 1e-9) << "filter " << k;
  }
}

TEST(ScheduledBank, OutsideTheGridIsClampedAndAnUncoveredCornerSplitsTheCellOrFallsBackToTheNearestNode) {
  const BankSchedule s = make_schedule();
  F16HierarchicalBank hb(scheduled_bank(s), options(ScheduleMode::kInterpolate));
  hb.schedule(AirData{0.9, 40000.0});
  EXPECT_EQ(hb.scheduled().outside_frames(), 1);
  EXPECT_TRUE(hb.z_trim() == Z(node_bank(1, 1).z_trim));
  hb.schedule(AirData{0.5, 15000.0});
  EXPECT_EQ(hb.scheduled().outside_frames(), 1);

  const BankSchedule holed = make_schedule(1, 1);  // (0.6, 20,000 ft) does not trim
  HierarchicalOptions nearest_trims = options(ScheduleMode::kInterpolate);
  nearest_trims.schedule.plane_trims = false;
  nearest_trims.schedule.lift_trims = false;   // the triangle's trims in (Mach, altitude): by hand below
  F16HierarchicalBank h2(scheduled_bank(holed), nearest_trims);
  h2.schedule(AirData{0.58, 18000.0});  // s, t = 0.9, 0.8: nearest covered (0.6, 10,000 ft), 0.81 cells
  EXPECT_EQ(h2.scheduled().fallback_frames(), 1);
  EXPECT_TRUE(h2.z_trim() == Z(node_bank(1, 0).z_trim));
  // s, t = 0.05: the hole would weigh 0.0025 bilinearly; the point lies in the triangle of the
  // three covered corners (a + b <= 1): weights 1 - a - b, a, b on (0,0), (1,0), (0,1).
  h2.schedule(AirData{0.41, 10500.0});
  EXPECT_EQ(h2.scheduled().fallback_frames(), 1);
  const Z by_hand = 0.9 * Z(node_bank(0, 0).z_trim) + 0.05 * Z(node_bank(1, 0).z_trim) + 0.05 * Z(node_bank(0, 1).z_trim);
  EXPECT_LT((h2.z_trim() - by_hand).norm(), 1e-12 * by_hand.norm());
  const auto& w = h2.scheduled().weights();
  EXPECT_NEAR(w[0], 0.9, 1e-12);
  EXPECT_NEAR(w[1], 0.05, 1e-12);
  EXPECT_NEAR(w[2], 0.05, 1e-12);
  EXPECT_EQ(w[3], 0.0);
  h2.schedule(AirData{0.41, 10000.0});  // on the lower edge: the hole has weight 0
  EXPECT_EQ(h2.scheduled().fallback_frames(), 1);
  h2.schedule(AirData{0.52, 15000.0});  // s, t = 0.6, 0.5: beyond the diagonal, the nearest node
  EXPECT_EQ(h2.scheduled().fallback_frames(), 2);
  EXPECT_TRUE(h2.z_trim() == Z(node_bank(1, 0).z_trim));
}

// The synthetic nodes' trims are affine in the cell coordinates (node_bank: z_trim(VEL) =
// 400 + 100 i - 20 j, AOA 0.1 - 0.02 i + 0.01 j, u_trim 0.01 (1 + i + 2 j)), so the covered
// triangle's plane, extrapolated into the missing corner's half, is that affine function exactly.
TEST(ScheduledBank, TheMissingCornersHalfTakesTheCoveredTrianglesPlaneAndTheNearestNodesFilters) {
  const BankSchedule holed = make_schedule(1, 1);  // (0.6, 20,000 ft) does not trim
  HierarchicalOptions grid_plane = options(ScheduleMode::kInterpolate);
  grid_plane.schedule.lift_trims = false;   // the plane in (Mach, altitude); in the lift coordinate: below
  F16HierarchicalBank hb(scheduled_bank(holed), grid_plane);
  ASSERT_TRUE(hb.options().schedule.plane_trims);   // the default
  const auto affine_z = [](double a, double b) {
    Z z = Z::Zero();
    z << 400.0 + 100.0 * a - 20.0 * b, 0.1 - 0.02 * a + 0.01 * b, 0.0, 1.0, 0.0, 0.0, 0.0;
    return z;
  };
  hb.schedule(AirData{0.58, 18000.0});  // s, t = 0.9, 0.8: plane weights -0.7, 0.9, 0.8 on (0,0), (1,0), (0,1)
  EXPECT_EQ(hb.scheduled().fallback_frames(), 1);
  EXPECT_LT((hb.z_trim() - affine_z(0.9, 0.8)).norm(), 1e-9);
  EXPECT_NEAR(hb.u_trim()(0), 0.01 * (1 + 0.9 + 1.6), 1e-12);
  const Z by_hand = -0.7 * Z(node_bank(0, 0).z_trim) + 0.9 * Z(node_bank(1, 0).z_trim) + 0.8 * Z(node_bank(0, 1).z_trim);
  EXPECT_LT((hb.z_trim() - by_hand).norm(), 1e-12 * by_hand.norm());
  // the filters are the nearest covered node's, (0.6, 10,000 ft), as without the plane
  const auto& w = hb.scheduled().weights();
  EXPECT_EQ(w[0] + w[1] + w[2] + w[3], 1.0);
  for (int c = 0; c < 4; ++c)
    if (w[c] != 0.0) EXPECT_EQ(hb.scheduled().corners()[c], holed.node_index(1, 0, 0));
  // continuous across the diagonal a + b = 1 (the old fallback jumped to the node's trims)
  // (both sides the same affine function: s = 0.5 -/+ 1e-6 cells, t = 0.5)
  hb.schedule(AirData{0.5 - 2e-7, 15000.0});
  EXPECT_EQ(hb.scheduled().fallback_frames(), 1);
  EXPECT_LT((hb.z_trim() - affine_z(0.5 - 1e-6, 0.5)).norm(), 1e-9);
  hb.schedule(AirData{0.5 + 2e-7, 15000.0});
  EXPECT_EQ(hb.scheduled().fallback_frames(), 2);
  EXPECT_LT((hb.z_trim() - affine_z(0.5 + 1e-6, 0.5)).norm(), 1e-9);
}

// Row trims on a 6 x 3 grid (Mach 0.3, 0.35, 0.4, 0.5, 0.6, 0.7 x 20,000, 25,000, 30,000 ft)
// without (0.3, 30,000 ft), so near it no 4 x 3 stencil is covered: the nodes' trims are quadratic in
// Mach and linear in altitude, which each row's Lagrange blend (4 or 3 nodes) and the rows'
// blend reproduce exactly, where the bilinear triangle does not, away from the cut cell's diagonal.
TEST(ScheduledBank, RowTrimsFollowEachRowsOwnStencilWhereNoFullStencilIsCovered) {
  const std::vector<double> mach = {0.3, 0.35, 0.4, 0.5, 0.6, 0.7}, alt = {20000.0, 25000.0, 30000.0};
  const auto vel = [](double m, double h) { return 1000.0 * m - 300.0 * m * m + 0.001 * (h - 20000.0); };
  const auto aoa = [](double m, double h) { return 0.6 - 2.0 * m + 1.5 * m * m + 1e-6 * (h - 20000.0); };
  const BankSchedule s = grid_schedule(
      mach, alt, [](int i, int j) { return i == 0 && j == 2; },   // (0.3, 30,000 ft) does not trim
      [&](auto& z, double m, double h) { z(0) = vel(m, h), z(1) = aoa(m, h); });
  HierarchicalOptions rows = options(ScheduleMode::kInterpolate), linear = rows;
  rows.schedule.row_trims = true;
  linear.schedule.row_trims = false;
  F16HierarchicalBank hr(scheduled_bank(s), rows), hl(scheduled_bank(s), linear);
  for (const AirData a : {AirData{0.3453, 26582.0}, AirData{0.33, 22000.0}, AirData{0.45, 28000.0}}) {
    hr.schedule(a);
    hl.schedule(a);
    EXPECT_EQ(hr.scheduled().fallback_frames(), 0) << a.mach;   // the covered half or a covered cell
    EXPECT_NEAR(hr.z_trim()(0), vel(a.mach, a.pressure_altitude_ft), 1e-9) << a.mach;
    EXPECT_NEAR(hr.z_trim()(1), aoa(a.mach, a.pressure_altitude_ft), 1e-12) << a.mach;
  }
  // the bilinear triangle misses the curvature in Mach at (0.3453, 26,582 ft)
  hl.schedule(AirData{0.3453, 26582.0});
  EXPECT_GT(std::abs(hl.z_trim()(1) - aoa(0.3453, 26582.0)), 1e-4);
  // at a node, the node's trims
  hr.schedule(AirData{0.35, 25000.0});
  EXPECT_NEAR(hr.z_trim()(1), aoa(0.35, 25000.0), 1e-15);
  // near the cut cell's diagonal (a - b < 0.25 cells) they move to the triangle's linear trims,
  // which the missing half's plane continues: on it (a = b = 0.5) the linear trims, a quarter of
  // the way in (a - b = 0.125) half of each
  const AirData on{0.325, 27500.0}, half{0.33125, 27500.0};
  hr.schedule(on);
  hl.schedule(on);
  EXPECT_NEAR(hr.z_trim()(1), hl.z_trim()(1), 1e-15);
  EXPECT_GT(std::abs(hr.z_trim()(1) - aoa(on.mach, on.pressure_altitude_ft)), 1e-4);
  hr.schedule(half);
  hl.schedule(half);
  EXPECT_NEAR(hr.z_trim()(1), 0.5 * (hl.z_trim()(1) + aoa(half.mach, half.pressure_altitude_ft)), 1e-12);
  const AirData past{0.32499, 27500.0};   // just inside the missing half: the plane, 2e-4 cells on
  hr.schedule(past);
  hl.schedule(past);
  EXPECT_EQ(hr.scheduled().fallback_frames(), 1);
  EXPECT_EQ(hr.z_trim()(1), hl.z_trim()(1));
  const double plane_past = hl.z_trim()(1);
  hr.schedule(on);   // continuous across the diagonal: 2e-4 cells apart, about 0.05 rad a cell
  EXPECT_NEAR(hr.z_trim()(1), plane_past, 2e-5);
  // the row stencils kept from frame to frame give the trims a fresh choice gives, bit for bit,
  // over a path through every cell (on nodes, half cells and the diagonal too), where the rows'
  // stencils move with the Mach number
  F16HierarchicalBank path(scheduled_bank(s), rows);
  for (int i = 0; i <= 800; ++i) {
    const double x = i / 800.0;
    const AirData a{0.3 + 0.4 * x, 20000.0 + 10000.0 * std::fmod(4.0 * x, 1.0)};
    path.schedule(a);
    F16HierarchicalBank fresh(scheduled_bank(s), rows);
    fresh.schedule(a);
    ASSERT_TRUE(path.z_trim() == fresh.z_trim() && path.u_trim() == fresh.u_trim()) << a.mach << " " << a.pressure_altitude_ft;
  }
}

// A 3 x 3 grid (Mach 0.3, 0.35, 0.4 x 25,000, 30,000, 35,000 ft) missing the shipped schedule's
// three low-speed, high-altitude nodes, so the cell Mach 0.3-0.35, 30,000-35,000 ft keeps one
// corner: its trims are its two edge-adjacent cells' planes (the right cell's covered triangle, the
// lower cell's), extended to the point and blended by inverse distance. Trims affine in the grid
// are reproduced exactly; others meet each neighbour's trims on the shared edge; the filters stay
// the nearest node's; neighbour_trims off: the nearest node's trims.
TEST(ScheduledBank, ACellMissingThreeCornersTakesItsNeighboursPlanesForTheTrims) {
  const std::vector<double> mach = {0.3, 0.35, 0.4}, alt = {25000.0, 30000.0, 35000.0};
  const auto affine = [](double m, double h) { return 0.6 - 0.8 * m + 2e-6 * (h - 25000.0); };
  const auto curved = [](double m, double h) { return 0.02 / (m * m) + 1e-10 * (h - 25000.0) * (h - 25000.0); };
  const BankSchedule s = grid_schedule(mach, alt, corner_uncovered,
                                       [&](auto& z, double m, double h) { z(1) = affine(m, h), z(3) = curved(m, h); });
  HierarchicalOptions on = options(ScheduleMode::kInterpolate), off = on;
  ASSERT_TRUE(on.schedule.neighbour_trims);   // the default
  on.schedule.lift_trims = off.schedule.lift_trims = false;   // planes in (Mach, altitude): affine exactly
  off.schedule.neighbour_trims = false;
  F16HierarchicalBank hb(scheduled_bank(s), on), hn(scheduled_bank(s), off);
  const int kept = s.node_index(1, 1, 0);   // (0.35, 30,000 ft), the cell's one covered corner
  for (const AirData a : {AirData{0.34, 31000.0}, AirData{0.32, 34000.0}, AirData{0.345, 30200.0}}) {
    hb.schedule(a);
    hn.schedule(a);
    EXPECT_NEAR(hb.z_trim()(1), affine(a.mach, a.pressure_altitude_ft), 1e-12) << a.mach;
    EXPECT_EQ(hn.z_trim()(1), s.nodes[static_cast<std::size_t>(kept)].bank.z_trim(1)) << a.mach;
    for (int c = 0; c < 4; ++c)   // the filters: the nearest covered node's
      if (hb.scheduled().weights()[c] != 0.0) EXPECT_EQ(hb.scheduled().corners()[c], kept);
  }
  EXPECT_EQ(hb.scheduled().fallback_frames(), 3);
  // curved trims: continuous across the edge Mach 0.35 (into the right cell's missing half, its
  // plane) and across 30,000 ft (into the lower cell's missing half, its plane), and on 30,000 ft
  // itself the lower cell's plane
  const auto across = [&](AirData inside, AirData outside) {
    hb.schedule(inside);
    const double z_in = hb.z_trim()(3);
    hb.schedule(outside);
    EXPECT_NEAR(z_in, hb.z_trim()(3), 1e-6) << inside.mach << " " << inside.pressure_altitude_ft;
  };
  across(AirData{0.35 - 1e-9, 32000.0}, AirData{0.35, 32000.0});
  across(AirData{0.33, 30000.0 + 1e-6}, AirData{0.33, 30000.0 - 1e-6});
  hb.schedule(AirData{0.33, 30000.0});
  const double on_edge = hb.z_trim()(3);
  hb.schedule(AirData{0.33, 29999.999});
  EXPECT_NEAR(on_edge, hb.z_trim()(3), 1e-8);
  // without it the trims jump at the edge by the plane's distance from the node's
  hn.schedule(AirData{0.35 - 1e-9, 32000.0});
  const double node_side = hn.z_trim()(3);
  hn.schedule(AirData{0.35, 32000.0});
  EXPECT_GT(std::abs(node_side - hn.z_trim()(3)), 1e-3);
}

// Lift trims on the same 3 x 3 grid: where a cut cell's trims are linear (the covered triangle,
// the missing half's plane, the neighbours' planes; here everywhere in the cut cells, the third-order
// and row trims off) they are linear in the lift coordinate lambda = (delta M^2)^(-3/4) and
// altitude, the airspeed (VEL) in Mach and altitude: trims affine in those are reproduced exactly,
// which the planes in (Mach, altitude) are not; delta is the standard atmosphere's pressure ratio.
TEST(ScheduledBank, ACutCellsLinearTrimsAreLinearInTheLiftCoordinateAndTheAirspeedInMach) {
  const std::vector<double> mach = {0.3, 0.35, 0.4}, alt = {25000.0, 30000.0, 35000.0};
  const auto lambda = [](double m, double h) { return std::pow(std::pow(1.0 - h / 145442.16, 5.2558797) * m * m, -0.75); };
  const auto aoa = [&](double m, double h) { return 0.05 + 0.02 * lambda(m, h) + 1e-7 * (h - 25000.0); };
  const auto vel = [](double m, double h) { return 1000.0 * m - 0.003 * (h - 25000.0); };
  const BankSchedule s = grid_schedule(mach, alt, corner_uncovered,
                                       [&](auto& z, double m, double h) { z(0) = vel(m, h), z(1) = aoa(m, h); });
  HierarchicalOptions lift = options(ScheduleMode::kInterpolate), grid = lift;
  lift.schedule.cubic_trims = grid.schedule.cubic_trims = false;
  ASSERT_TRUE(lift.schedule.lift_trims);   // the default
  grid.schedule.lift_trims = false;
  F16HierarchicalBank hl(scheduled_bank(s), lift), hg(scheduled_bank(s), grid);
  // the covered half of (0.35-0.4, 30,000-35,000 ft), its missing half, the lower cut cell's missing
  // half, the cell missing three corners
  for (const AirData a : {AirData{0.39, 31000.0}, AirData{0.36, 34000.0}, AirData{0.31, 29000.0}, AirData{0.34, 31500.0}}) {
    hl.schedule(a);
    hg.schedule(a);
    EXPECT_NEAR(hl.z_trim()(1), aoa(a.mach, a.pressure_altitude_ft), 1e-9) << a.mach << " " << a.pressure_altitude_ft;
    EXPECT_NEAR(hl.z_trim()(0), vel(a.mach, a.pressure_altitude_ft), 1e-9) << a.mach << " " << a.pressure_altitude_ft;
    EXPECT_NEAR(hg.z_trim()(0), vel(a.mach, a.pressure_altitude_ft), 1e-9) << a.mach << " " << a.pressure_altitude_ft;
    EXPECT_GT(std::abs(hg.z_trim()(1) - aoa(a.mach, a.pressure_altitude_ft)), 1e-4) << a.mach;
  }
  // a covered cell keeps its bilinear trims
  hl.schedule(AirData{0.37, 27000.0});
  hg.schedule(AirData{0.37, 27000.0});
  EXPECT_TRUE(hl.z_trim() == hg.z_trim());
  // a Mach axis from 0 (lambda infinite at its nodes): the planes in (Mach, altitude), finite
  const BankSchedule zero = grid_schedule({0.0, 0.35, 0.4}, alt, corner_uncovered,
                                          [&](auto& z, double m, double h) { z(0) = vel(m, h); });
  F16HierarchicalBank zl(scheduled_bank(zero), lift), zg(scheduled_bank(zero), grid);
  for (const AirData a : {AirData{0.2, 29000.0}, AirData{0.1, 31000.0}, AirData{0.36, 34000.0}}) {
    zl.schedule(a);
    zg.schedule(a);
    EXPECT_TRUE(zl.z_trim().allFinite() && zl.u_trim().allFinite()) << a.mach;
    EXPECT_LT((zl.z_trim() - zg.z_trim()).norm(), 1e-9 * zg.z_trim().norm()) << a.mach;
  }
}

// Stabilator trims on the same 3 x 3 grid, alpha affine in the lift coordinate (so the lift trims
// reproduce it) and the stabilator a curve in alpha: past the diagonal by a quarter cell or more
// and in the cell missing three corners the stabilators' trims (LS, RS and their lag states) are
// the edge table's, a piecewise-linear interpolation in alpha of the nodes that are corners of a
// cell with an untrimmable corner (here all but (0.4, 25,000 ft)), computed here independently;
// on the diagonal they meet the covered half's, on Mach 0.35 the neighbour's; the other trims are
// those of stabilator_trims off, which keeps the plane's.
TEST(ScheduledBank, PastTheTrimmableEdgeTheStabilatorTrimsFollowTheEdgeNodesAlongAlpha) {
  const std::vector<double> mach = {0.3, 0.35, 0.4}, alt = {25000.0, 30000.0, 35000.0};
  const auto lambda = [](double m, double h) { return std::pow(std::pow(1.0 - h / 145442.16, 5.2558797) * m * m, -0.75); };
  const auto aoa = [&](double m, double h) { return 0.02 + 0.04 * lambda(m, h) + 1e-7 * (h - 25000.0); };
  const auto stab = [](double alpha) { return -0.03 - 2.0 * (alpha - 0.2) * (alpha - 0.2); };
  BankSchedule s = grid_schedule(mach, alt, corner_uncovered, [&](auto& z, double m, double h) { z(1) = aoa(m, h); });
  std::vector<std::pair<double, double>> table;   // the edge nodes' (alpha, stabilator)
  for (ScheduleNode& n : s.nodes) {
    n.bank.state_names = {"u_fps", "alpha_rad", "q_rad_s", "theta_rad", "beta_rad", "p_rad_s", "r_rad_s",
                          "phi_rad", "d_ls_rad", "d_rs_rad", "d_lf_rad", "d_rf_rad", "d_rud_rad"};
    const double alpha = n.bank.z_trim(1), st = stab(alpha);
    n.bank.u_trim(0) = n.bank.u_trim(1) = n.x_trim(8) = n.x_trim(9) = st;
    n.x_trim(1) = alpha;
    if (!(n.i_mach == 2 && n.i_alt == 0)) table.emplace_back(alpha, st);
  }
  std::sort(table.begin(), table.end());
  ASSERT_EQ(table.size(), 5u);
  const auto along = [&](double alpha) {   // linear between the table's nodes, extended past its ends
    std::size_t k = 0;
    while (k + 2 < table.size() && alpha > table[k + 1].first) ++k;
    const auto [a0, v0] = table[k];
    const auto [a1, v1] = table[k + 1];
    return v0 + (v1 - v0) * (alpha - a0) / (a1 - a0);
  };
  HierarchicalOptions on = options(ScheduleMode::kInterpolate), off = on;
  ASSERT_TRUE(on.schedule.stabilator_trims);   // the default
  off.schedule.stabilator_trims = false;
  F16HierarchicalBank hb(scheduled_bank(s), on), hp(scheduled_bank(s), off);
  // the missing halves of (0.35-0.4, 30,000-35,000 ft) and (0.3-0.35, 25,000-30,000 ft) a quarter
  // cell or more past the diagonal; the cell missing three corners
  for (const AirData a : {AirData{0.36, 34000.0}, AirData{0.37, 35000.0}, AirData{0.305, 29000.0},
                          AirData{0.32, 34000.0}, AirData{0.34, 31000.0}}) {
    hb.schedule(a);
    hp.schedule(a);
    const double alpha = aoa(a.mach, a.pressure_altitude_ft);
    ASSERT_NEAR(hb.z_trim()(1), alpha, 1e-9) << a.mach << " " << a.pressure_altitude_ft;
    for (int k : {0, 1}) EXPECT_NEAR(hb.u_trim()(k), along(alpha), 1e-8) << a.mach << " " << a.pressure_altitude_ft;
    for (int k : {8, 9})
      EXPECT_NEAR(hb.scheduled().x_trim()(k), along(alpha), 1e-8) << a.mach << " " << a.pressure_altitude_ft;
    EXPECT_GT(std::abs(hp.u_trim()(0) - along(alpha)), 1e-4) << a.mach;   // the plane's
    EXPECT_TRUE(hb.z_trim() == hp.z_trim());
    EXPECT_TRUE(hb.u_trim().tail(3) == hp.u_trim().tail(3));
    EXPECT_TRUE(hb.scheduled().x_trim().head(8) == hp.scheduled().x_trim().head(8));
  }
  // continuous across the diagonal of (0.35-0.4, 30,000-35,000 ft), a - b = 0 (the covered half's
  // linear trims there, the third-order and row trims blended to them), and across Mach 0.35 from
  // the cell missing three corners into that cell's missing half
  const auto across = [&](AirData inside, AirData outside) {
    hb.schedule(inside);
    const double u_in = hb.u_trim()(0), x_in = hb.scheduled().x_trim()(8);
    hb.schedule(outside);
    EXPECT_NEAR(u_in, hb.u_trim()(0), 1e-6) << inside.mach << " " << inside.pressure_altitude_ft;
    EXPECT_NEAR(x_in, hb.scheduled().x_trim()(8), 1e-6) << inside.mach << " " << inside.pressure_altitude_ft;
  };
  across(AirData{0.375, 32500.0 - 1e-4}, AirData{0.375, 32500.0 + 1e-4});
  // an eighth of a cell past that diagonal (a = 0.2, b = 0.325): half the plane's, half the table's
  hb.schedule(AirData{0.36, 31625.0});
  hp.schedule(AirData{0.36, 31625.0});
  EXPECT_NEAR(hb.u_trim()(0), 0.5 * hp.u_trim()(0) + 0.5 * along(aoa(0.36, 31625.0)), 1e-8);
  across(AirData{0.35 - 1e-9, 33000.0}, AirData{0.35, 33000.0});
  across(AirData{0.33, 30000.0 + 1e-6}, AirData{0.33, 30000.0 - 1e-6});
  // through the missing halves and the cell missing three corners without allocating
  const long long before = f16mmae::testing::allocation_count();
  for (int k = 0; k <= 200; ++k) hb.schedule(AirData{0.3 + 0.0005 * k, 28000.0 + 35.0 * k});
  EXPECT_EQ(f16mmae::testing::allocation_count() - before, 0);
  // a schedule without a state alpha_rad keeps the plane's
  BankSchedule plain = s;
  for (ScheduleNode& n : plain.nodes) n.bank.state_names[1] = "x1";
  F16HierarchicalBank hq(scheduled_bank(plain), on);
  hq.schedule(AirData{0.36, 34000.0});
  hp.schedule(AirData{0.36, 34000.0});
  EXPECT_TRUE(hq.u_trim() == hp.u_trim());
}

// gust_airspeed: with a state named u_g_fps the schedule follows M + u_g^ / c, u_g^ the blended
// prior estimate before the frame and c = VEL_trim / M_f of the trims in force (the air-data
// low-pass off: the schedule's Mach is that value exactly); the measured Mach itself before the
// first frame, with the option off, and on a bank without the state; no allocation.
TEST(ScheduledBank, GustAirspeedSchedulesOnTheMachLessTheEstimatedGust) {
  BankSchedule s = make_schedule();
  for (ScheduleNode& n : s.nodes) n.bank.state_names[2] = "u_g_fps";
  const Frames f = fly(node_bank(0, 0), 0, 0, {}, 200, 9u);
  for (const bool on : {true, false}) {
    HierarchicalOptions o = options(ScheduleMode::kInterpolate);
    o.schedule.gust_airspeed = on;
    F16HierarchicalBank hb(scheduled_bank(s), o);
    double largest = 0.0;
    const long long before = f16mmae::testing::allocation_count();
    for (std::size_t i = 0; i < f.z.size(); ++i) {
      const double m = 0.45 + 0.0002 * static_cast<double>(i % 5), h = 14000.0;
      double expected = m;
      if (on && i > 0) {
        const double c = hb.scheduled().z_trim()(0) / hb.scheduled().filtered_air_data().mach;
        expected = m + hb.blended_state()(2) / c;
      }
      hb.schedule(AirData{m, h});
      EXPECT_NEAR(hb.scheduled().filtered_air_data().mach, expected, 1e-15) << "frame " << i;
      EXPECT_EQ(hb.scheduled().filtered_air_data().pressure_altitude_ft, h);
      largest = std::max(largest, std::abs(expected - m));
      hb.step(f.z[i], f.u[i]);
    }
    EXPECT_EQ(f16mmae::testing::allocation_count() - before, 0);
    if (on) EXPECT_GT(largest, 1e-6);   // the gust estimate moved the schedule
  }
  // a bank without the state: the measured Mach
  HierarchicalOptions o = options(ScheduleMode::kInterpolate);
  o.schedule.gust_airspeed = true;
  F16HierarchicalBank plain(scheduled_bank(make_schedule()), o);
  for (std::size_t i = 0; i < 50; ++i) {
    plain.schedule(AirData{0.45, 14000.0});
    EXPECT_EQ(plain.scheduled().filtered_air_data().mach, 0.45);
    plain.step(f.z[i], f.u[i]);
  }
}

TEST(ScheduledBank, TheTrimOffsetAddsToTheScheduledTrim) {
  const BankSchedule s = make_schedule();
  F16HierarchicalBank hb(scheduled_bank(s), options(ScheduleMode::kInterpolate));
  EXPECT_TRUE(hb.u_trim_offset().isZero(0.0));
  hb.schedule(AirData{0.6, 10000.0});
  const U du = U::Constant(0.002);
  const Z dz = Z::LinSpaced(7, 1.0, 7.0);
  hb.set_trim_offset(du, dz);
  hb.schedule(AirData{0.4, 20000.0});
  EXPECT_TRUE(hb.z_trim() == Z(node_bank(0, 1).z_trim));  // the scheduled part
  EXPECT_TRUE(hb.u_trim() == U(node_bank(0, 1).u_trim));
  EXPECT_TRUE(hb.z_trim_offset() == dz);
  EXPECT_TRUE(hb.u_trim_offset() == du);
  EXPECT_TRUE(hb.z_hat() == Z(hb.z_hat_perturbation() + hb.z_trim() + dz));  // trim in force = scheduled + dz
}

// A failed sensor whose reading is uninformative (steady_state_filter.h: an unknown level b̂ it
// tracks) keeps its level of the ABSOLUTE reading across a change of the scheduled trim: VEL
// reads a constant (node (0,0)'s trim + noise, failed from frame 64); at frame 200 the air data
// moves to node (1,0), whose VEL trim is 100 ft/s higher. The VEL hypothesis' failed-channel term
// u_k = l_k + q_k / 2 - v_k (leading term stripped, no adaptation; v_k the footing, which is
// the node's, on NONE's variance of the reading given the others: filter_bank.h) must then be
// that of the same
// readings with the trim held at node (0,0) -- frame for frame -- and stay far above the
// level-jump branch ln eps + (1/2) ln(2 pi A_jj) - ln W that a level left behind would take.
TEST(ScheduledBank, AFailedSensorsLevelFollowsTheAbsoluteReadingAcrossATrimChange) {
  const double width = 1500.0, level_q = 1e-5, r_var = 1e-3, eps = 1e-3;
  BankSchedule s = make_schedule();
  for (auto& n : s.nodes)
    for (auto& h : n.bank.hypotheses)
      if (h.name == "VEL") {
        h.uninformative_width = Eigen::VectorXd::Zero(7);
        h.uninformative_level_q = Eigen::VectorXd::Zero(7);
        h.uninformative_width(0) = width;
        h.uninformative_level_q(0) = level_q;
      }
  HierarchicalOptions o = options(ScheduleMode::kNearest);
  o.declarer.dwell_s = 60.0;   // no declaration: the VEL filter stays on line at its index
  F16HierarchicalBank moved(scheduled_bank(s), o), held(scheduled_bank(s), o);
  const Frames f = fly(node_bank(0, 0), 0, 0, {"VEL"}, 260, 9u);
  const int vel = 1 + 5;   // NONE, five actuators, then VEL
  ASSERT_EQ(moved.name(vel), "VEL");
  F16HierarchicalBank blended(scheduled_bank(s), options(ScheduleMode::kInterpolate));
  blended.schedule(AirData{0.5, 15000.0});   // a blend of the nodes' filters keeps the channel uninformative
  EXPECT_TRUE(blended.bank().hypothesis(vel).has_uninformative());
  EXPECT_TRUE(held.bank().hypothesis(vel).has_uninformative());
  const double jump = std::log(eps) + 0.5 * std::log(2.0 * 3.14159265358979323846 * r_var) - std::log(width);
  auto u_term = [&](const F16HierarchicalBank& b) {   // less the footing of the node in force (filter_bank.h)
    // NONE's variance of the VEL residual given the other six: its Schur complement
    const auto& a0 = b.bank().hypothesis(0).model().a;
    const Eigen::Matrix<double, 6, 6> a_gg = a0.bottomRightCorner<6, 6>();
    const Eigen::Matrix<double, 6, 1> a_gj = a0.bottomLeftCorner<6, 1>();
    const double conditional = a0(0, 0) - a_gj.dot(a_gg.llt().solve(a_gj));
    const double footing = 0.5 * std::log(conditional / b.bank().hypothesis(vel).model().a(0, 0));
    return b.bank().log_likelihoods()(vel) + 0.5 * b.bank().quadratic_forms()(vel) - footing;
  };
  const long long before = f16mmae::testing::allocation_count();
  int compared = 0;
  for (std::size_t i = 0; i < f.z.size(); ++i) {
    moved.schedule(AirData{i >= 200 ? 0.6 : 0.4, 10000.0});
    held.schedule(AirData{0.4, 10000.0});
    moved.step(f.z[i], f.u[i]);
    held.step(f.z[i], f.u[i]);
    if (i < 70) continue;
    ASSERT_EQ(moved.level(), 0);
    EXPECT_NEAR(u_term(moved), u_term(held), 1e-9) << "frame " << i;
    EXPECT_NE(u_term(moved), 0.0) << "frame " << i;   // the channel is uninformative at every node
    EXPECT_GT(u_term(moved), jump + 5.0) << "frame " << i;
    ++compared;
  }
  EXPECT_EQ(f16mmae::testing::allocation_count() - before, 0);
  EXPECT_EQ(compared, 190);
  EXPECT_NEAR(moved.z_trim()(0) - held.z_trim()(0), 100.0, 1e-9);
}

// The running mean's length and the filtered air data against the rule written out with the
// gain max(alpha, 1/n) (the header's), bit for bit, at several time constants.
TEST(ScheduledBank, TheRunningMeansLengthIsTheLastNWithOneOverNAtLeastAlpha) {
  EXPECT_EQ(f16mmae::running_mean_length(1.0), 1);
  EXPECT_EQ(f16mmae::running_mean_length(0.5), 2);
  EXPECT_EQ(f16mmae::running_mean_length(0.3), 3);
  EXPECT_EQ(f16mmae::running_mean_length(1.0 - std::exp(-1.0 / 128.0)), 128);
  const BankSchedule s = make_schedule();
  for (const double tau : {0.0, 0.05, 0.5, 2.0, 30.0}) {
    HierarchicalOptions o = options(ScheduleMode::kInterpolate);
    o.schedule.air_data_time_constant_s = tau;
    F16HierarchicalBank hb(scheduled_bank(s), o);
    const double alpha = tau > 0.0 ? 1.0 - std::exp(-1.0 / (64.0 * tau)) : 1.0;
    double mach = 0.0;
    std::int64_t n = 0;
    for (int i = 0; i < 3000; ++i) {
      const double a = 0.45 + 0.05 * std::sin(0.37 * i) + 0.001 * (i % 11);
      if (n == 0) {
        mach = a;
        n = 1;
      } else {
        mach += std::max(alpha, 1.0 / static_cast<double>(n + 1)) * (a - mach);
        if (1.0 / static_cast<double>(n + 1) >= alpha) ++n;
      }
      hb.schedule(AirData{a, 15000.0});
      ASSERT_EQ(hb.scheduled().filtered_air_data().mach, mach) << "tau " << tau << " frame " << i;
    }
  }
}

TEST(ScheduledBank, ScheduledFramesAllocateNothing) {
  for (const ScheduleMode mode : {ScheduleMode::kNearest, ScheduleMode::kInterpolate}) {
    const BankSchedule s = make_schedule();
    F16HierarchicalBank hb(scheduled_bank(s), options(mode));
    const ModelBank node = node_bank(0, 0);
    const Frames f = fly(node, 0, 0, {"PIT"}, 320, 5u);
    const long long before = f16mmae::testing::allocation_count();
    for (std::size_t i = 0; i < f.z.size(); ++i) {
      const double x = static_cast<double>(i) / f.z.size();  // across the whole cell and back
      hb.schedule(AirData{0.4 + 0.2 * x, 10000.0 + 10000.0 * (1 - x)});
      hb.step(f.z[i], f.u[i]);
    }
    EXPECT_EQ(f16mmae::testing::allocation_count() - before, 0);
    EXPECT_GE(hb.declarations().size(), 1u);
    EXPECT_GT(hb.scheduled().switches() + hb.scheduled().blends(), 0);
  }
}

// Node floors 1e-9, 1e-3 (Mach 0.6, 10,000 ft), 1e-5, 1e-7 (nodes in grid order): the floor in
// force is a node's own bit for bit there, their geometric mean at the cell centre
// (10^(-24/4) = 1e-6) and at the quarter point (weights 9/16, 3/16, 3/16, 1/16:
// 10^-(9*9 + 3*3 + 5*3 + 7*1)/16 = 10^-7.0), the floor the next update applies; reset presumes
// NONE with the start node's floor; node_p_min off: the options' floor everywhere; no allocation.
TEST(ScheduledBank, NodeFloorsAreBlendedGeometricallyWithTheFilters) {
  BankSchedule s = make_schedule();
  const double floors[4] = {1e-9, 1e-3, 1e-5, 1e-7};
  for (std::size_t n = 0; n < 4; ++n) s.nodes[n].bank.estimator.p_min = floors[n];
  ASSERT_NO_THROW(s.validate());
  F16HierarchicalBank hb(scheduled_bank(s), options(ScheduleMode::kInterpolate));
  EXPECT_EQ(hb.bank().options().p_min, 1e-9);
  EXPECT_EQ(hb.bank().probabilities()(1), 1e-9);
  const Frames f = fly(node_bank(1, 0), 1, 0, {}, 40, 3u);
  const long long before = f16mmae::testing::allocation_count();
  hb.schedule(AirData{0.6, 10000.0});
  for (std::size_t i = 0; i < f.z.size(); ++i) hb.step(f.z[i], f.u[i]);
  EXPECT_EQ(hb.bank().options().p_min, 1e-3);
  EXPECT_GE(hb.bank().probabilities().minCoeff(), 1e-3 * (1 - 1e-12));
  hb.schedule(AirData{0.5, 15000.0});
  EXPECT_NEAR(std::log10(hb.bank().options().p_min), -6.0, 1e-12);
  hb.schedule(AirData{0.45, 12500.0});
  EXPECT_NEAR(std::log10(hb.bank().options().p_min), -112.0 / 16.0, 1e-12);
  EXPECT_EQ(f16mmae::testing::allocation_count() - before, 0);
  hb.reset();
  EXPECT_EQ(hb.bank().options().p_min, 1e-9);
  EXPECT_EQ(hb.bank().probabilities()(1), 1e-9);
  HierarchicalOptions off = options(ScheduleMode::kInterpolate);
  off.schedule.node_p_min = false;
  off.bank.p_min = 1e-4;
  F16HierarchicalBank one(scheduled_bank(s), off);
  one.schedule(AirData{0.6, 10000.0});
  EXPECT_EQ(one.bank().options().p_min, 1e-4);
}

// The rough-air floor (rough_air_floor.h) on node floors 1e-5 and calm-air references 0.5: the
// floor in force before each update is the one the air of the frames before gives,
// x = max(rho-bar, rho_L) / 0.5: a band far above the air leaves the node floor bit for bit, a
// band below it puts the rough-air floor in force, a band centred on the air blends them half and
// half (10^-7), read against the air ratio a run with the first band measured frame for frame
// (the filters' residuals, so the air, do not depend on the floor in a failure-free flight);
// reset() starts at the node floor; no allocation.
TEST(ScheduledBank, TheRoughAirFloorFollowsTheAirOfTheFramesBefore) {
  BankSchedule s = make_schedule();
  for (auto& node : s.nodes) {
    node.bank.estimator.p_min = 1e-5;
    node.calm_reference = 0.5;
  }
  ASSERT_NO_THROW(s.validate());
  const Frames f = fly(node_bank(0, 0), 0, 0, {}, 400, 11u);
  auto with_band = [&](double from, double to) {
    HierarchicalOptions o = options(ScheduleMode::kInterpolate);
    o.bank.adaptation.enabled = true;
    o.bank.adaptation.floor_time_constant_s = 5.0;   // rho_L in force from 160 frames on
    o.rough_floor.p_min = 1e-9;
    o.rough_floor.from = from;
    o.rough_floor.to = to;
    return o;
  };
  F16HierarchicalBank calm(scheduled_bank(s), with_band(100.0, 200.0));
  calm.schedule(AirData{0.4, 10000.0});
  std::vector<double> air;   // x before each frame's update
  for (std::size_t i = 0; i < f.z.size(); ++i) {
    air.push_back(calm.bank().adaptation().air_power_ratio() / 0.5);
    calm.step(f.z[i], f.u[i]);
    ASSERT_EQ(calm.bank().options().p_min, 1e-5) << "frame " << i;
  }
  ASSERT_TRUE(calm.declarations().empty());
  const double x = air.back();
  ASSERT_GT(x, 0.0);
  F16HierarchicalBank rough(scheduled_bank(s), with_band(0.0, 1e-3 * x));
  F16HierarchicalBank half(scheduled_bank(s), with_band(0.5 * x, 1.5 * x));
  rough.schedule(AirData{0.4, 10000.0});
  half.schedule(AirData{0.4, 10000.0});
  EXPECT_EQ(rough.bank().options().p_min, 1e-5);   // before the first update: no air measured, x = 0
  const RoughAirFloorOptions band = with_band(0.5 * x, 1.5 * x).rough_floor;
  const long long before = f16mmae::testing::allocation_count();
  for (std::size_t i = 0; i < f.z.size(); ++i) {
    rough.step(f.z[i], f.u[i]);
    half.step(f.z[i], f.u[i]);
    if (air[i] > 1e-3 * x) ASSERT_EQ(rough.bank().options().p_min, 1e-9) << "frame " << i;
    ASSERT_EQ(half.bank().options().p_min, RoughAirFloor::floor(band, 1e-5, air[i]))
        << "frame " << i;
  }
  EXPECT_EQ(f16mmae::testing::allocation_count() - before, 0);
  EXPECT_NEAR(std::log10(half.bank().options().p_min), -7.0, 1e-12);
  half.reset();
  EXPECT_EQ(half.bank().options().p_min, 1e-5);
  EXPECT_EQ(half.bank().probabilities()(1), 1e-5);
}

// Two layers on the trim alpha x_trim(1) = 0.1 - 0.02 i + 0.01 j (0.10, 0.08 / 0.11, 0.09 at the
// corners) switched at 0.095: every corner is covered in both layers (layer 1: x_trim(0) + 50),
// and each node carries an adaptation reference 0.5 + 0.1 n.
TEST(ScheduledBank, FlapLayersFollowTheLawOnTheTrimAlphaAndAllocateNothing) {
  BankSchedule s = make_schedule();
  s.switch_state = 1;
  s.switch_thresholds = {0.095};
  const std::size_t own = s.nodes.size();
  for (std::size_t n = 0; n < own; ++n) {
    ScheduleNode alt = s.nodes[n];
    alt.layer = 1;
    alt.x_trim(0) += 50.0;
    s.nodes.push_back(alt);
  }
  for (std::size_t n = 0; n < s.nodes.size(); ++n) s.nodes[n].adapt_reference = 0.5 + 0.1 * static_cast<double>(n);
  for (std::size_t n = 0; n < own; ++n)   // a node's own layer is the law at its alpha
    if (s.nodes[n].x_trim(1) > 0.095) std::swap(s.nodes[n].layer, s.nodes[n + own].layer);
  ASSERT_NO_THROW(s.validate());
  for (const ScheduleMode mode : {ScheduleMode::kNearest, ScheduleMode::kInterpolate}) {
    F16HierarchicalBank hb(scheduled_bank(s), options(mode));
    const Frames f = fly(node_bank(0, 0), 0, 0, {"PIT"}, 320, 5u);
    int changes = 0, last = -1;
    const long long before = f16mmae::testing::allocation_count();
    for (std::size_t i = 0; i < f.z.size(); ++i) {
      const double x = static_cast<double>(i) / f.z.size();  // Mach 0.4 -> 0.6 at 20,000 ft: alpha 0.11 -> 0.09
      hb.schedule(AirData{0.4 + 0.2 * x, 20000.0});
      const int layer = hb.scheduled().layer();
      changes += last >= 0 && layer != last;
      last = layer;
      hb.step(f.z[i], f.u[i]);
    }
    EXPECT_EQ(f16mmae::testing::allocation_count() - before, 0);
    EXPECT_EQ(changes, 1);   // alpha crosses 0.095 once, at Mach 0.55
    EXPECT_EQ(last, 0);
    hb.schedule(AirData{0.4, 20000.0});   // the node (0, 1): alpha 0.11, layer 1
    EXPECT_EQ(hb.scheduled().layer(), 1);
    const int n = s.node_index(0, 1, 1);
    if (mode == ScheduleMode::kNearest) {
      EXPECT_EQ(hb.scheduled().corners()[0], n);
      EXPECT_DOUBLE_EQ(hb.scheduled().adapt_reference(), s.nodes[static_cast<std::size_t>(n)].adapt_reference);
    }
    EXPECT_DOUBLE_EQ(hb.scheduled().x_trim()(0), s.nodes[static_cast<std::size_t>(n)].x_trim(0));
  }
}

TEST(ScheduleFile, RoundTripsAndRefusesCorruptionNamingTheField) {
  BankSchedule s = make_schedule(1, 1);
  s.primary = 1;
  const std::string path = ::testing::TempDir() + "/sched.f16sched";
  const std::string hash = save_schedule(s, path);
  const ModelBank loaded = load_bank(path);
  ASSERT_TRUE(loaded.schedule);
  EXPECT_EQ(loaded.content_hash, hash);
  EXPECT_EQ(loaded.schedule->nodes.size(), 3u);
  EXPECT_EQ(loaded.schedule->primary, 1);
  EXPECT_EQ(loaded.mach, 0.6);  // node 1 is (0.6, 10,000 ft)
  for (std::size_t n = 0; n < 3; ++n) {
    EXPECT_EQ(loaded.schedule->nodes[n].bank.content_hash, bank_content_hash(s.nodes[n].bank));
    EXPECT_TRUE(loaded.schedule->nodes[n].x_trim == s.nodes[n].x_trim);
  }
  // deterministic
  EXPECT_EQ(schedule_file_bytes(*loaded.schedule), schedule_file_bytes(s));

  std::ifstream in(path, std::ios::binary);
  std::vector<std::uint8_t> image((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto refused = [&](std::vector<std::uint8_t> bytes, const std::string& needle) {
    try {
      parse_schedule_file(bytes.data(), bytes.size(), "'x'");
      ADD_FAILURE() << "accepted; expected: " << needle;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  std::vector<std::uint8_t> flipped = image;
  flipped[image.size() / 2] ^= 1;
  refused(flipped, "content hash mismatch");
  refused(std::vector<std::uint8_t>(image.begin(), image.end() - 1), "truncated");
  std::vector<std::uint8_t> version = image;
  version[11] = 9;
  refused(version, "unsupported format version 9");
  refused(std::vector<std::uint8_t>(image.begin(), image.begin() + 30), "truncated");

  BankSchedule bad = s;
  bad.primary = 3;
  EXPECT_THROW(schedule_file_bytes(bad), std::invalid_argument);
  bad = s;
  bad.nodes[2].i_mach = 2;
  try {
    schedule_file_bytes(bad);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("nodes[2] at grid index (2, 1) is outside the 2 x 2 grid"), std::string::npos)
        << e.what();
  }
  bad = s;
  bad.alt_ft = {20000.0, 10000.0};
  EXPECT_THROW(schedule_file_bytes(bad), std::invalid_argument);
  bad = s;
  bad.nodes[1].x_trim.resize(3);
  EXPECT_THROW(schedule_file_bytes(bad), std::invalid_argument);
  std::remove(path.c_str());
}

// The start-up a schedule recommends (format 3): written as version 3 only when it is given,
// read back as the loaded bank's estimator.start_up_s; a schedule without one is written as
// version 2 and carries 0 (as every version-1 and version-2 file); out of range is refused
// naming the field, on writing and in a file image (its hash made valid).
TEST(ScheduleFile, TheRecommendedStartUpIsFormatThreeAndOlderFilesCarryNone) {
  BankSchedule s = make_schedule();
  const auto version_of = [](const std::vector<std::uint8_t>& image) {
    return (std::uint32_t{image[8]} << 24) | (std::uint32_t{image[9]} << 16) | (std::uint32_t{image[10]} << 8) |
           std::uint32_t{image[11]};
  };
  const std::vector<std::uint8_t> plain = schedule_file_bytes(s);
  EXPECT_EQ(version_of(plain), 2u);
  const ModelBank none = parse_schedule_file(plain.data(), plain.size(), "'plain'");
  EXPECT_EQ(none.estimator.start_up_s, 0.0);
  EXPECT_EQ(none.schedule->start_up_s, 0.0);

  s.start_up_s = 0.25;
  const std::vector<std::uint8_t> image = schedule_file_bytes(s);
  EXPECT_EQ(version_of(image), 3u);
  EXPECT_EQ(image.size(), plain.size() + 8);   // one double more
  const ModelBank loaded = parse_schedule_file(image.data(), image.size(), "'v3'");
  EXPECT_EQ(loaded.estimator.start_up_s, 0.25);
  EXPECT_EQ(loaded.schedule->start_up_s, 0.25);
  EXPECT_EQ(schedule_file_bytes(*loaded.schedule), image);   // deterministic
  // the schedule's start-up reaches the estimator as its option would
  HierarchicalOptions o = options(ScheduleMode::kInterpolate);
  o.bank.start_up_s = loaded.estimator.start_up_s;
  F16HierarchicalBank hb(loaded, o);
  const Frames f = fly(node_bank(0, 0), 0, 0, {}, 20, 4u);
  const auto p0 = hb.probabilities();
  for (int i = 0; i < 16; ++i) {   // round(0.25 s x 64 Hz) = 16 frames weigh nothing
    hb.schedule(AirData{0.4, 10000.0});
    hb.step(f.z[i], f.u[i]);
    ASSERT_TRUE(hb.probabilities() == p0) << "frame " << i;
  }

  s.start_up_s = -1.0;
  try {
    schedule_file_bytes(s);
    ADD_FAILURE() << "accepted start_up_s -1";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("start_up_s = -1 must be in [0, 3600] s"), std::string::npos) << e.what();
  }
  // a version-3 image whose start_up_s reads 7200 (payload re-hashed): refused naming it
  const std::size_t at = kBankFileHeaderSize + 4 + 8 * s.mach.size() + 4 + 8 * s.alt_ft.size() + 4 + 4 +
                         (s.metadata.size() + 1) + 4 + 4;
  std::vector<std::uint8_t> payload(image.begin() + static_cast<std::ptrdiff_t>(kBankFileHeaderSize), image.end());
  const double big = 7200.0;
  std::uint64_t bits;
  std::memcpy(&bits, &big, sizeof bits);
  for (int b = 0; b < 8; ++b)
    payload[at - kBankFileHeaderSize + static_cast<std::size_t>(b)] = static_cast<std::uint8_t>(bits >> (8 * (7 - b)));
  const std::vector<std::uint8_t> forged = hashed_file_image(kScheduleFileMagic, 3, payload);
  try {
    parse_schedule_file(forged.data(), forged.size(), "'forged'");
    ADD_FAILURE() << "accepted start_up_s 7200";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("start_up_s = 7200 must be in [0, 3600] s"), std::string::npos) << e.what();
  }
  std::vector<std::uint8_t> future = image;
  future[11] = 6;
  try {
    parse_schedule_file(future.data(), future.size(), "'future'");
    ADD_FAILURE() << "accepted version 6";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unsupported format version 6 (this build reads versions 1 to 5)"),
              std::string::npos) << e.what();
  }
}

// The nodes' calm-air reference (format 4): written as version 4 only when the nodes carry it,
// one double more per node, read back per node; blended with the filters in force (at a node,
// that node's; 1 without it); carried by every node or none, in (0, 100].
TEST(ScheduleFile, TheCalmAirReferenceIsFormatFourAndBlendedWithTheFilters) {
  BankSchedule s = make_schedule();
  s.start_up_s = 0.25;
  const std::vector<std::uint8_t> v3 = schedule_file_bytes(s);
  for (std::size_t n = 0; n < s.nodes.size(); ++n) s.nodes[n].calm_reference = 0.4 + 0.05 * static_cast<double>(n);
  const std::vector<std::uint8_t> image = schedule_file_bytes(s);
  EXPECT_EQ(image[11], 4);
  EXPECT_EQ(image.size(), v3.size() + 8 * s.nodes.size());
  const ModelBank loaded = parse_schedule_file(image.data(), image.size(), "'v4'");
  ASSERT_TRUE(loaded.schedule->has_calm_reference());
  for (std::size_t n = 0; n < s.nodes.size(); ++n)
    EXPECT_EQ(loaded.schedule->nodes[n].calm_reference, s.nodes[n].calm_reference);
  EXPECT_EQ(schedule_file_bytes(*loaded.schedule), image);   // deterministic
  EXPECT_FALSE(parse_schedule_file(v3.data(), v3.size(), "'v3'").schedule->has_calm_reference());
  F16HierarchicalBank hb(loaded, options(ScheduleMode::kNearest));
  for (std::size_t n = 0; n < s.nodes.size(); ++n) {
    const ScheduleNode& node = s.nodes[n];
    hb.schedule(AirData{s.mach[static_cast<std::size_t>(node.i_mach)], s.alt_ft[static_cast<std::size_t>(node.i_alt)]});
    EXPECT_DOUBLE_EQ(hb.scheduled().calm_reference(), node.calm_reference) << "node " << n;
  }
  F16HierarchicalBank without(parse_schedule_file(v3.data(), v3.size(), "'v3'"), options(ScheduleMode::kNearest));
  EXPECT_EQ(without.scheduled().calm_reference(), 1.0);
  s.nodes[1].calm_reference = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(s.validate(), std::invalid_argument);   // some nodes, not all
  s.nodes[1].calm_reference = 0.0;
  EXPECT_THROW(s.validate(), std::invalid_argument);   // outside (0, 100]
}

// The nodes' reference scale sigma (format 5): written as version 5 only when the nodes carry
// it, one double more per node than version 4, read back per node; blended with the filters in
// force (at a node, that node's; 1 without it) and handed to the turbulence adaptation as its
// power scale, the references left in force as they are (the node's, and the climb's while the
// air data climb); carried by every node or none, in (0, 100].
// The adaptation's lull floor (turbulence_adaptation.h) is held while the air data climb (the
// climb reference's phase, climb_reference.h) and released with the phase.
TEST(ScheduledBank, TheLullFloorIsHeldWhileClimbing) {
  const ModelBank mb = scheduled_bank(make_schedule());
  HierarchicalOptions o = options(ScheduleMode::kNearest);
  o.bank.adaptation.enabled = true;
  o.bank.adaptation.floor_time_constant_s = 60.0;
  o.climb_reference.reference = 0.6;
  o.climb_reference.hold_s = 0.0;
  F16HierarchicalBank hb(mb, o);
  const Frames f = fly(node_bank(0, 0), 0, 0, {}, 2048, 5u);
  const AirData at{0.4, 20000.0};
  hb.schedule(at);
  for (int i = 0; i < 8; ++i) {   // level flight
    hb.schedule(at);
    hb.step(f.z[static_cast<std::size_t>(i)], f.u[static_cast<std::size_t>(i)]);
    EXPECT_FALSE(hb.bank().adaptation().floor_held()) << "frame " << i;
  }
  int i = 8;
  for (; i < 256 && !hb.climb_reference().climbing(); ++i) {   // climbing at 128 ft/s
    hb.schedule(AirData{at.mach, at.pressure_altitude_ft + 2.0 * static_cast<double>(i - 7)});
    hb.step(f.z[static_cast<std::size_t>(i)], f.u[static_cast<std::size_t>(i)]);
  }
  ASSERT_TRUE(hb.climb_reference().climbing());
  hb.schedule(AirData{at.mach, at.pressure_altitude_ft + 2.0 * static_cast<double>(i - 7)});
  hb.step(f.z[static_cast<std::size_t>(i)], f.u[static_cast<std::size_t>(i)]);
  EXPECT_TRUE(hb.bank().adaptation().floor_held());
  const double top = at.pressure_altitude_ft + 2.0 * static_cast<double>(i - 7);
  for (++i; i < 2047 && hb.climb_reference().climbing(); ++i) {   // level again: the phase ends
    hb.schedule(AirData{at.mach, top});
    hb.step(f.z[static_cast<std::size_t>(i)], f.u[static_cast<std::size_t>(i)]);
  }
  ASSERT_FALSE(hb.climb_reference().climbing());
  hb.schedule(AirData{at.mach, top});
  hb.step(f.z[static_cast<std::size_t>(i)], f.u[static_cast<std::size_t>(i)]);
  EXPECT_FALSE(hb.bank().adaptation().floor_held());
  o.bank.adaptation.floor_time_constant_s = 0.0;   // off: never held
  F16HierarchicalBank off(mb, o);
  for (int j = 0; j < 64; ++j) {
    off.schedule(AirData{at.mach, at.pressure_altitude_ft + 2.0 * static_cast<double>(j)});
    off.step(f.z[static_cast<std::size_t>(j)], f.u[static_cast<std::size_t>(j)]);
    EXPECT_FALSE(off.bank().adaptation().floor_held());
  }
}

TEST(ScheduleFile, TheReferenceScaleIsFormatFiveAndTheAdaptationsPowerScale) {
  BankSchedule s = make_schedule();
  s.start_up_s = 0.25;
  for (std::size_t n = 0; n < s.nodes.size(); ++n) {
    s.nodes[n].calm_reference = 0.4;
    s.nodes[n].adapt_reference = 0.5 + 0.1 * static_cast<double>(n);
  }
  const std::vector<std::uint8_t> v4 = schedule_file_bytes(s);
  for (std::size_t n = 0; n < s.nodes.size(); ++n) s.nodes[n].reference_scale = 0.8 + 0.05 * static_cast<double>(n);
  const std::vector<std::uint8_t> image = schedule_file_bytes(s);
  EXPECT_EQ(v4[11], 4);
  EXPECT_EQ(image[11], 5);
  EXPECT_EQ(image.size(), v4.size() + 8 * s.nodes.size());
  const ModelBank loaded = parse_schedule_file(image.data(), image.size(), "'v5'");
  ASSERT_TRUE(loaded.schedule->has_reference_scale());
  for (std::size_t n = 0; n < s.nodes.size(); ++n)
    EXPECT_EQ(loaded.schedule->nodes[n].reference_scale, s.nodes[n].reference_scale);
  EXPECT_EQ(schedule_file_bytes(*loaded.schedule), image);   // deterministic
  EXPECT_FALSE(parse_schedule_file(v4.data(), v4.size(), "'v4'").schedule->has_reference_scale());
  HierarchicalOptions o = options(ScheduleMode::kNearest);
  o.bank.adaptation.enabled = true;
  o.climb_reference.reference = 0.6;
  o.climb_reference.hold_s = 0.0;
  F16HierarchicalBank hb(loaded, o), without(parse_schedule_file(v4.data(), v4.size(), "'v4'"), o);
  const Frames f = fly(node_bank(0, 0), 0, 0, {}, 256, 5u);
  for (std::size_t n = 0; n < s.nodes.size(); ++n) {
    const ScheduleNode& node = s.nodes[n];
    const AirData at{s.mach[static_cast<std::size_t>(node.i_mach)], s.alt_ft[static_cast<std::size_t>(node.i_alt)]};
    for (F16HierarchicalBank* b : {&hb, &without}) {
      b->reset();
      b->schedule(at);
      EXPECT_DOUBLE_EQ(b->bank().adaptation().scale(), 1.0);   // rho starts at sigma rho_0
      for (int i = 0; i < 8; ++i) {   // level flight at the node
        b->schedule(at);
        b->step(f.z[static_cast<std::size_t>(i)], f.u[static_cast<std::size_t>(i)]);
      }
    }
    EXPECT_DOUBLE_EQ(hb.scheduled().reference_scale(), node.reference_scale) << "node " << n;
    EXPECT_EQ(without.scheduled().reference_scale(), 1.0);
    EXPECT_DOUBLE_EQ(hb.bank().adaptation().power_scale(), node.reference_scale);
    EXPECT_DOUBLE_EQ(without.bank().adaptation().power_scale(), 1.0);
    EXPECT_FALSE(hb.climb_reference().climbing());
    EXPECT_DOUBLE_EQ(hb.bank().adaptation().options().reference, node.adapt_reference);
    for (int i = 8; i < 256 && !hb.climb_reference().climbing(); ++i) {   // climbing at 128 ft/s, Mach held
      hb.schedule(AirData{at.mach, at.pressure_altitude_ft + 2.0 * static_cast<double>(i - 7)});
      hb.step(f.z[static_cast<std::size_t>(i)], f.u[static_cast<std::size_t>(i)]);
    }
    ASSERT_TRUE(hb.climb_reference().climbing()) << "node " << n;
    EXPECT_DOUBLE_EQ(hb.bank().adaptation().options().reference, 0.6);
    EXPECT_DOUBLE_EQ(hb.bank().adaptation().power_scale(), node.reference_scale);
  }
  const auto refused = [&s](const std::string& expected) {
    try {
      s.validate();
      ADD_FAILURE() << "accepted: " << expected;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  s.nodes[1].reference_scale = std::numeric_limits<double>::quiet_NaN();
  refused(".reference_scale is missing but nodes[0]'s is given: every node carries one or none does");
  s.nodes[1].reference_scale = 0.0;
  refused(".reference_scale must be in (0, 100], got 0.000000");
  s.nodes[1].reference_scale = 0.9;
  s.nodes[1].adapt_reference = -0.5;
  refused(".adapt_reference must be in [0, 100], got -0.500000");
}
