// bank_estimator_settings: the bank's recommended estimator settings from its metadata JSON,
// the same rule as f16mmae.closedloop.bank_estimator_settings.
#include "daemon/bank_settings.h"

#include <gtest/gtest.h>

using f16mmae::daemon::bank_estimator_settings;

TEST(BankSettings, ReadsTheTopLevelEstimatorObjectOnly) {
  const auto s = bank_estimator_settings(
      R"({"command":"f16mmae design","design_version":1,"estimator":{"dwell_s":0.25,"p_min":1e-09,)"
      R"("threshold":0.9},"model":{"mixing":[[0.5,-0.5],[1,true,null,"x\"y"]]},)"
      R"("tuning":{"estimator":{"dwell_s":9,"p_min":0.2,"threshold":0.6}}})");
  ASSERT_TRUE(s.p_min && s.threshold && s.dwell_s);
  EXPECT_EQ(*s.p_min, 1e-09);
  EXPECT_EQ(*s.threshold, 0.9);
  EXPECT_EQ(*s.dwell_s, 0.25);
  const auto o = s.apply({});
  EXPECT_EQ(o.bank.p_min, 1e-09);
  EXPECT_EQ(o.declarer.threshold, 0.9);
}

TEST(BankSettings, MissingKeysKeepTheCoreDefaults) {
  const auto s = bank_estimator_settings(R"({"estimator": {"threshold": 0.95, "other": [1, 2]}})");
  EXPECT_FALSE(s.p_min.has_value());
  EXPECT_EQ(*s.threshold, 0.95);
  const f16mmae::HierarchicalOptions defaults;
  EXPECT_EQ(s.apply({}).bank.p_min, defaults.bank.p_min);
}

TEST(BankSettings, NoJsonObjectRecommendsNothing) {
  for (const char* text : {"", "   ", "not json", "[1,2]", R"({"estimator": 3})", R"({"estimator": {"p_min": 1e-3})",
                           R"({"a": 1} trailing)"}) {
    const auto s = bank_estimator_settings(text);
    EXPECT_FALSE(s.p_min || s.threshold || s.dwell_s) << text;
  }
}

TEST(BankSettings, ANonNumericSettingIsAnError) {
  EXPECT_THROW(bank_estimator_settings(R"({"estimator": {"p_min": "small"}})"), std::invalid_argument);
}
