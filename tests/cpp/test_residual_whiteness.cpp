// The residual whiteness (cpp/f16mmae/residual_whiteness.h): W̄ against the header's sums
// computed here by hand, its limits (alternating, constant and white residuals), the start it
// leaves out, skipped non-finite residuals, carry_over and no allocation per update; the
// calm-air rule read by it (calm_air_complete.h) and a hierarchical bank's wiring.
#include "f16mmae/calm_air_complete.h"
#include "f16mmae/hierarchical_bank.h"
#include "f16mmae/residual_whiteness.h"

#include "allocation_counter.h"
#include "synthetic_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

using namespace f16mmae;
using namespace f16mmae::test;

namespace {

constexpr int kB = ResidualWhiteness::kBlockUpdates;

// W̄ of the header over the residual rows `r` (updates × channels), channels `channels`, with S
// updates left out and the low-pass' gain `alpha` after `length` blocks: the sums written out.
double by_hand(const std::vector<std::vector<double>>& r, const std::vector<int>& channels, int start, double alpha,
               long long length) {
  std::vector<double> u(channels.size(), 0.0), v(channels.size(), 0.0);
  long long blocks = 0;
  for (std::size_t first = static_cast<std::size_t>(start); first + kB <= r.size(); first += kB) {
    ++blocks;
    const double a = blocks <= length ? 1.0 / static_cast<double>(blocks) : alpha;
    for (std::size_t c = 0; c < channels.size(); ++c) {
      double sum = 0.0, sq = 0.0;
      for (int i = 0; i < kB; ++i) {
        const double x = r[first + static_cast<std::size_t>(i)][static_cast<std::size_t>(channels[c])];
        sum += x;
        sq += x * x;
      }
      u[c] += a * (kB * (sum / kB) * (sum / kB) - u[c]);
      v[c] += a * (sq / kB - v[c]);
    }
  }
  double w = 0.0;
  for (std::size_t c = 0; c < channels.size(); ++c) w += u[c] / v[c];
  return w / static_cast<double>(channels.size());
}

}  // namespace

TEST(ResidualWhiteness, IsTheHeadersBlockPowersAveragedAsWrittenOutByHand) {
  // 8 Hz: S = 8 updates; tau = 2 s: alpha = 1 - exp(-8/16), a mean over the first blocks then the low-pass
  const double rate = 8.0, tau = 2.0;
  const double alpha = 1.0 - std::exp(-kB / (tau * rate));
  ResidualWhiteness w;
  w.configure(0b101u, 3, tau, rate);
  std::mt19937 g(5);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::vector<std::vector<double>> rows;
  for (int i = 0; i < 8 + 40 * kB + 3; ++i) {   // three updates of a block not yet complete
    Eigen::Vector3d r(n01(g) + 0.3 * (i % 5), 100.0 * n01(g), -2.0 * n01(g) * (1.0 + 0.01 * i));
    rows.push_back({r(0), r(1), r(2)});
    w.observe(r);
    if (i < 8 + kB - 1) EXPECT_TRUE(std::isnan(w.value())) << "update " << i;   // the start, then the first block
  }
  EXPECT_NEAR(w.value(), by_hand(rows, {0, 2}, 8, alpha, running_mean_length(alpha)), 1e-12);
}

TEST(ResidualWhiteness, ReadsAlternatingResidualsAsZeroAConstantAsTheBlockAndWhiteNoiseAsOne) {
  const auto feed = [](auto residual, int n) {
    ResidualWhiteness w;
    w.configure(0b1u, 1, 5.0, 64.0);
    for (int i = 0; i < n; ++i) w.observe(Eigen::Matrix<double, 1, 1>(residual(i)));
    return w.value();
  };
  EXPECT_DOUBLE_EQ(feed([](int i) { return i % 2 ? 1.0 : -1.0; }, 64 + 80), 0.0);   // blocks of 8 sum to 0
  EXPECT_DOUBLE_EQ(feed([](int) { return 0.25; }, 64 + 80), static_cast<double>(kB));
  std::mt19937 g(11);
  std::normal_distribution<double> n01(0.0, 1.0);
  EXPECT_NEAR(feed([&](int) { return n01(g); }, 64 + 8 * 3000), 1.0, 0.15);
  // a zero channel counts as white; a NaN residual is skipped, its block waits
  ResidualWhiteness w;
  w.configure(0b11u, 2, 5.0, 64.0);
  for (int i = 0; i < 64 + 7; ++i) w.observe(Eigen::Vector2d(i % 2 ? 1.0 : -1.0, 0.0));
  EXPECT_TRUE(std::isnan(w.value()));
  w.observe(Eigen::Vector2d(std::nan(""), 0.0));
  EXPECT_TRUE(std::isnan(w.value()));
  w.observe(Eigen::Vector2d(1.0, 0.0));
  EXPECT_DOUBLE_EQ(w.value(), 0.5);   // (0 + 1) / 2
  ResidualWhiteness other;
  other.configure(0b11u, 2, 5.0, 64.0);
  other.carry_over(w);
  EXPECT_DOUBLE_EQ(other.value(), 0.5);
  w.reset();
  EXPECT_TRUE(std::isnan(w.value()));
  EXPECT_THROW(w.configure(0u, 2, 5.0, 64.0), std::invalid_argument);
  EXPECT_THROW(w.configure(0b100u, 2, 5.0, 64.0), std::invalid_argument);
  EXPECT_THROW(w.configure(0b1u, 2, 0.0, 64.0), std::invalid_argument);
}

TEST(ResidualWhiteness, ObservesWithoutAllocating) {
  ResidualWhiteness w;
  w.configure(0b1011011u, 7, 5.0, 64.0);
  Eigen::Matrix<double, 7, 1> r;
  std::mt19937 g(3);
  std::normal_distribution<double> n01(0.0, 1.0);
  const long long before = f16mmae::testing::allocation_count();
  double sum = 0.0;
  for (int i = 0; i < 2000; ++i) {
    for (int j = 0; j < 7; ++j) r(j) = n01(g);
    w.observe(r);
    sum += std::isnan(w.value()) ? 0.0 : w.value();
  }
  EXPECT_EQ(f16mmae::testing::allocation_count() - before, 0);
  EXPECT_GT(sum, 0.0);
}

TEST(ResidualWhiteness, TheCalmAirRuleReadsItAgainstItsBoundOrWithThePowerRatioHeldAlike) {
  const std::vector<std::string> sensors{"VEL", "AOA", "PIT"};
  CalmAirCompleteOptions o;
  o.rho = {{"VEL", 0.5}, {"PIT", 2.0}};
  o.measure = CalmMeasure::kWhiteness;
  o.whiteness_bound = 0.6;
  o.whiteness_channels = {"AOA"};
  CalmAirComplete c(o, sensors, 1.0, 8.0);   // S = 8 updates
  int k = 0;   // the updates so far: the alternation runs on across the calls
  const auto feed = [&](CalmAirComplete& rule, double aoa, int n, double rho_bar = 0.0, bool decide = true) {
    for (int i = 0; i < n; ++i, ++k) {
      rule.observe_residual(Eigen::Vector3d(5.0, (k % 2 ? 1.0 : -1.0) + aoa, 0.0));
      rule.observe(rho_bar, decide);
    }
  };
  feed(c, 0.0, 8 + kB - 1);
  EXPECT_TRUE(std::isnan(c.whiteness()));
  EXPECT_EQ(c.calm(), 0b101u);   // the start's calm, held until the first block
  feed(c, 0.0, 1);
  EXPECT_DOUBLE_EQ(c.whiteness(), 0.0);
  EXPECT_EQ(c.calm(), 0b101u);   // W-bar 0 < 0.6: every bounded channel, whatever its rho
  feed(c, 3.0, 40 * kB);   // a steady offset: the block power far above the mean power's share
  EXPECT_GT(c.whiteness(), 0.6);
  EXPECT_EQ(c.calm(), 0u);   // rho-bar 0 plays no part
  k = 0;
  c.reset();
  EXPECT_EQ(c.calm(), 0b101u);
  EXPECT_TRUE(std::isnan(c.whiteness()));
  // either: calm by W-bar, or per channel by rho-bar against rho_j c; held while a failure rises
  o.measure = CalmMeasure::kEither;
  CalmAirComplete e(o, sensors, 1.0, 8.0);
  feed(e, 0.0, 4, 1.0);   // no W-bar yet: rho-bar 1 against 0.5 and 2
  EXPECT_EQ(e.calm(), 0b100u);
  feed(e, 3.0, 8 + 40 * kB, 1.0);
  EXPECT_GT(e.whiteness(), 0.6);
  EXPECT_EQ(e.calm(), 0b100u);
  feed(e, 3.0, 8, 3.0);
  EXPECT_EQ(e.calm(), 0u);
  feed(e, 0.0, 8 * 400, 0.1, false);
  EXPECT_LT(e.whiteness(), 0.6);   // W-bar goes on averaging
  EXPECT_EQ(e.calm(), 0u);         // the decision held
  feed(e, 0.0, 1, 3.0);
  EXPECT_EQ(e.calm(), 0b101u);
  EXPECT_STREQ(calm_measure_name(parse_calm_measure("either")), "either");
  EXPECT_THROW(parse_calm_measure("white"), std::invalid_argument);
  o.whiteness_bound = 0.0;
  EXPECT_THROW(CalmAirComplete(o, sensors), std::invalid_argument);
  o.whiteness_bound = 0.6;
  o.whiteness_channels = {"AZ"};
  try {
    CalmAirComplete(o, sensors);
    ADD_FAILURE() << "accepted AZ";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "calm-air complete: 'AZ' is not a measurement of the bank; it has VEL, AOA, PIT");
  }
  o.whiteness_channels = {};
  EXPECT_THROW(CalmAirComplete(o, sensors), std::invalid_argument);
  EXPECT_TRUE(std::isnan(CalmAirComplete(CalmAirCompleteOptions{}, sensors).whiteness()));
}

TEST(ResidualWhiteness, AHierarchicalBankFeedsItThePresumedFiltersResiduals) {
  // the synthetic bank, its calm-air rule read by whiteness on Z1 and Z3: the bank's W̄ is a
  // ResidualWhiteness fed filter 0's residuals, every frame, bit for bit
  const std::vector<std::string> act{"U1", "U2"}, sen{"Z1", "Z2", "Z3"};
  const Plant plant = random_plant(3, 2, 3, 21u);
  const ModelBank mb = make_bank(plant, act, sen, Eigen::Vector2d(0.1, -0.2), Eigen::Vector3d(10.0, 1.0, -3.0));
  HierarchicalOptions o;
  o.bank.adaptation.enabled = true;
  o.bank.adaptation.time_constant_s = 2.0;
  o.declarer.dwell_s = 30.0;   // no declaration: level 0 throughout
  o.calm_complete.rho = {{"Z1", 1.0}};
  o.calm_complete.measure = CalmMeasure::kWhiteness;
  o.calm_complete.whiteness_bound = 0.9;
  o.calm_complete.whiteness_channels = {"Z1", "Z3"};
  using Bank = HierarchicalBank<Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic>;
  Bank bank(mb, o);
  ResidualWhiteness mine;
  mine.configure(0b101u, 3, 2.0, mb.frame_rate_hz);
  Truth truth(plant, act, sen, 4u);
  int calm_frames = 0;
  for (int i = 0; i < 400; ++i) {
    const Eigen::VectorXd z = truth.measure({}) + mb.z_trim;
    const Eigen::VectorXd u = dither(2, i, mb.frame_rate_hz);
    bank.step(z, u + mb.u_trim);
    truth.advance(u, {});
    mine.observe(bank.bank().residual(0));
    if (std::isnan(mine.value()))
      EXPECT_TRUE(std::isnan(bank.calm_whiteness())) << "frame " << i;
    else
      EXPECT_EQ(bank.calm_whiteness(), mine.value()) << "frame " << i;
    EXPECT_EQ(bank.bank().complete_channels(), std::isnan(mine.value()) || mine.value() < 0.9 ? 1u : 0u) << i;
    calm_frames += static_cast<int>(bank.bank().complete_channels());
  }
  EXPECT_GT(calm_frames, 0);     // the start's calm
  EXPECT_LT(calm_frames, 400);   // then read rough: the rule changed the channels
  EXPECT_FALSE(std::isnan(bank.calm_whiteness()));
}
