// SensorReconfiguration: the "reconfigure" feedback takes the estimate exactly on the
// channels of the sensors a hypothesis names, and raw z everywhere else.
#include "f16mmae/sensor_reconfiguration.h"
#include "allocation_counter.h"
#include "test_executive_bank.h"

#include <gtest/gtest.h>

#include <array>

using namespace f16mmae;

TEST(SensorReconfiguration, ReplacesExactlyTheFailedSensorsOfEachHypothesis) {
  const ModelBank b = test_support::synthetic_bank();
  const SensorReconfiguration r(b);
  ASSERT_EQ(r.hypothesis_count(), 79);
  const std::array<double, 7> z = {1, 2, 3, 4, 5, 6, 7}, z_hat = {-1, -2, -3, -4, -5, -6, -7};
  // hypothesis -> which of VEL AOA PIT AZ ROL YAW AY take z_hat (written out by hand)
  const std::vector<std::pair<std::string, std::array<int, 7>>> cases = {
      {"NONE", {0, 0, 0, 0, 0, 0, 0}},    {"LS", {0, 0, 0, 0, 0, 0, 0}},     {"RUD", {0, 0, 0, 0, 0, 0, 0}},
      {"VEL", {1, 0, 0, 0, 0, 0, 0}},     {"AY", {0, 0, 0, 0, 0, 0, 1}},     {"LF+AOA", {0, 1, 0, 0, 0, 0, 0}},
      {"AZ+AY", {0, 0, 0, 1, 0, 0, 1}},   {"LS+RS", {0, 0, 0, 0, 0, 0, 0}},  {"PIT+ROL", {0, 0, 1, 0, 1, 0, 0}}};
  for (const auto& [name, failed] : cases) {
    const int k = r.index(name);
    std::array<double, 7> out{};
    const long long before = f16mmae::testing::allocation_count();
    r.apply(k, z.data(), z_hat.data(), out.data());
    EXPECT_EQ(f16mmae::testing::allocation_count() - before, 0);
    for (int j = 0; j < 7; ++j) {
      EXPECT_EQ(r.failed(k, j), failed[j] == 1) << name << " sensor " << j;
      EXPECT_EQ(out[j], failed[j] ? z_hat[j] : z[j]) << name << " sensor " << j;
    }
  }
  EXPECT_THROW(r.index("FLAP"), std::invalid_argument);
}

TEST(SensorReconfiguration, AHypothesisNamingAnUnknownComponentIsRefused) {
  ModelBank b = test_support::synthetic_bank();
  b.hypotheses[1].name = "LS+GEAR";
  try {
    SensorReconfiguration r(b);
    FAIL() << "accepted a hypothesis naming GEAR";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'LS+GEAR' names 'GEAR'"), std::string::npos) << e.what();
  }
}

TEST(SensorReconfiguration, APartialFailureIsItsComponent) {
  ModelBank b = test_support::synthetic_bank();
  b.hypotheses[1].name = "LS:loss=0.5";   // a partial-loss hypothesis (f16mmae design --partial-loss)
  b.hypotheses[2].name = "VEL:bias=1";     // a sensor's: the channel of VEL
  const SensorReconfiguration r(b);
  for (int j = 0; j < 7; ++j) EXPECT_FALSE(r.failed(r.index("LS:loss=0.5"), j)) << "sensor " << j;
  for (int j = 0; j < 7; ++j) EXPECT_EQ(r.failed(r.index("VEL:bias=1"), j), j == 0) << "sensor " << j;
  b.hypotheses[1].name = "GEAR:loss=0.5";
  EXPECT_THROW(SensorReconfiguration{b}, std::invalid_argument);
}
