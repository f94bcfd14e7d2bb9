// parse_daemon_args: defaults, LCM URL resolution, and errors that name the bad value.
#include "daemon/daemon_config.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

using f16mmae::daemon::daemon_flag_names;
using f16mmae::daemon::daemon_usage;
using f16mmae::daemon::parse_daemon_args;

TEST(DaemonConfig, DefaultsFollowLcmConventions) {
  auto r = parse_daemon_args({"--bank", "b.f16bank"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.bank_path, "b.f16bank");
  EXPECT_EQ(r.config.lcm_url, "udpm://239.255.76.67:7667?ttl=0");
  EXPECT_EQ(r.config.rate_hz, 64.0);
  EXPECT_EQ(r.config.channels().sensors, "F16_SENSORS");
  EXPECT_EQ(r.config.channels().status, "MMAE_STATUS");
  r = parse_daemon_args({"--bank", "b"}, "memq://");
  EXPECT_EQ(r.config.lcm_url, "memq://");  // $LCM_DEFAULT_URL
  r = parse_daemon_args({"--bank", "b", "--lcm-url", "udpm://239.255.76.68:7668?ttl=0"}, "memq://");
  EXPECT_EQ(r.config.lcm_url, "udpm://239.255.76.68:7668?ttl=0");  // the option wins
}

TEST(DaemonConfig, OptionsWithSpaceOrEquals) {
  auto r = parse_daemon_args({"--bank=x", "--channel-prefix", "SIM1_", "--rate-hz=64", "--max-frames", "10", "--quiet"},
                             nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.channels().commands, "SIM1_F16_COMMANDS");
  EXPECT_EQ(r.config.channels().reset, "SIM1_MMAE_RESET");
  EXPECT_EQ(r.config.max_frames, 10);
  EXPECT_TRUE(r.config.quiet);
}

TEST(DaemonConfig, ErrorsNameTheBadValue) {
  auto r = parse_daemon_args({}, nullptr);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--bank FILE is required"), std::string::npos);
  r = parse_daemon_args({"--bank", "b", "--rate-hz", "fast"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("'fast'"), std::string::npos);
  r = parse_daemon_args({"--bank", "b", "--rate-hz", "0"}, nullptr);
  EXPECT_FALSE(r.ok);
  r = parse_daemon_args({"--bank", "b", "--max-frames", "-1"}, nullptr);
  EXPECT_NE(r.message.find("'-1'"), std::string::npos);
  r = parse_daemon_args({"--bank", "b", "--verbose"}, nullptr);
  EXPECT_NE(r.message.find("'--verbose'"), std::string::npos);
  EXPECT_NE(r.message.find("valid options"), std::string::npos);
  r = parse_daemon_args({"--bank", "b", "--realtime", "100"}, nullptr);
  EXPECT_NE(r.message.find("from 1 to 99, got '100'"), std::string::npos);
  r = parse_daemon_args({"--bank", "b", "--realtime", "80"}, nullptr);
  EXPECT_TRUE(r.ok);
  EXPECT_EQ(r.config.realtime_priority, 80);
  r = parse_daemon_args({"--bank"}, nullptr);
  EXPECT_NE(r.message.find("--bank needs a value"), std::string::npos);
}

TEST(DaemonConfig, HelpExitsZero) {
  auto r = parse_daemon_args({"--bank", "b", "--help"}, nullptr);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.message.find("usage: mmae-daemon"), std::string::npos);
}

TEST(DaemonConfig, EstimatorOverrides) {
  auto r = parse_daemon_args({"--bank", "b", "--p-min", "1e-9", "--threshold=0.95", "--dwell-s", "0.5"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(*r.config.p_min, 1e-9);
  EXPECT_EQ(*r.config.threshold, 0.95);
  EXPECT_EQ(*r.config.dwell_s, 0.5);
  EXPECT_FALSE(parse_daemon_args({"--bank", "b"}, nullptr).config.p_min.has_value());
  r = parse_daemon_args({"--bank", "b", "--p-min", "-1"}, nullptr);
  EXPECT_NE(r.message.find("--p-min must be a probability in [0, 1/13), got '-1'"), std::string::npos);
}

TEST(DaemonConfig, EvidenceDwell) {
  EXPECT_FALSE(parse_daemon_args({"--bank", "b"}, nullptr).config.dwell_nats.has_value());   // off
  auto r = parse_daemon_args({"--bank", "b", "--dwell-nats", "48"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(*r.config.dwell_nats, 48.0);
  r = parse_daemon_args({"--bank", "b", "--dwell-nats=-3"}, nullptr);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("--dwell-nats must be a number of nats in [0, 1e+06] (0: the dwell alone), got '-3'"),
            std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--dwell-nats", "nan"}, nullptr);
  EXPECT_FALSE(r.ok);
}

TEST(DaemonConfig, SetTemperingMargin) {
  EXPECT_FALSE(parse_daemon_args({"--bank", "b"}, nullptr).config.set_tempering_margin);   // off
  auto r = parse_daemon_args({"--bank", "b", "--turbulence-banks", "--set-tempering", "0.15", "--set-tempering-margin"},
                             nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(r.config.set_tempering_margin);
  r = parse_daemon_args({"--bank", "b", "--turbulence-banks", "--set-tempering-margin"}, nullptr);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("--set-tempering-margin applies with --set-tempering only"), std::string::npos) << r.message;
  // the margin's reference by name, upper-cased; only with the margin
  EXPECT_TRUE(parse_daemon_args({"--bank", "b"}, nullptr).config.set_tempering_margin_over.empty());
  r = parse_daemon_args({"--bank", "b", "--turbulence-banks", "--set-tempering", "0.15", "--set-tempering-margin",
                         "--set-tempering-margin-over", "ls,RS"},
                        nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.set_tempering_margin_over, (std::vector<std::string>{"LS", "RS"}));
  r = parse_daemon_args({"--bank", "b", "--turbulence-banks", "--set-tempering", "0.15", "--set-tempering-margin",
                         "--set-tempering-margin-over", "LS,"},
                        nullptr);
  EXPECT_NE(r.message.find("must be hypothesis names separated by commas"), std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--turbulence-banks", "--set-tempering", "0.15", "--set-tempering-margin-over",
                         "LS,RS"},
                        nullptr);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("--set-tempering-margin-over applies with --set-tempering-margin only"), std::string::npos)
      << r.message;
}

TEST(DaemonConfig, AdaptRunningStart) {
  EXPECT_FALSE(parse_daemon_args({"--bank", "b", "--adapt-turbulence"}, nullptr).config.estimator.bank.adaptation.running_start);
  auto r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-running-start"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(r.config.estimator.bank.adaptation.running_start);
  r = parse_daemon_args({"--bank", "b", "--adapt-running-start"}, nullptr);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("--adapt-running-start applies with --adapt-turbulence only"), std::string::npos) << r.message;
}

TEST(DaemonConfig, RoughAirFloor) {
  const f16mmae::RoughAirFloorOptions off = parse_daemon_args({"--bank", "b"}, nullptr).config.estimator.rough_floor;
  EXPECT_FALSE(off.enabled());
  EXPECT_EQ(off.from, 1.3);
  EXPECT_EQ(off.to, 1.5);
  auto r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--rough-p-min", "1e-9", "--rough-p-min-from", "1.2",
                              "--rough-p-min-to=1.6"},
                             nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.rough_floor.p_min, 1e-9);
  EXPECT_EQ(r.config.estimator.rough_floor.from, 1.2);
  EXPECT_EQ(r.config.estimator.rough_floor.to, 1.6);
  r = parse_daemon_args({"--bank", "b", "--rough-p-min", "1e-9"}, nullptr);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("--rough-p-min applies with --adapt-turbulence only"), std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--rough-p-min-to", "1.6"}, nullptr);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("--rough-p-min-to applies with --rough-p-min only"), std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--rough-p-min", "1e-9", "--rough-p-min-from", "1.6"},
                        nullptr);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("--rough-p-min-from 1.6 must lie below --rough-p-min-to 1.5 (the band the floor moves "
                           "across)"),
            std::string::npos)
      << r.message;
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--rough-p-min", "0.08"}, nullptr);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("--rough-p-min must be a probability in [0, 1/13)"), std::string::npos) << r.message;
}

TEST(DaemonConfig, SetTemperingDwell) {
  EXPECT_EQ(parse_daemon_args({"--bank", "b"}, nullptr).config.estimator.spare_dwell_s, 0.0);   // off
  auto r = parse_daemon_args({"--bank", "b", "--turbulence-banks", "--set-tempering", "0.15", "--set-tempering-dwell",
                              "0.0625"},
                             nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.spare_dwell_s, 0.0625);
  r = parse_daemon_args({"--bank", "b", "--turbulence-banks", "--set-tempering", "0.15", "--set-tempering-dwell", "-1"},
                        nullptr);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("--set-tempering-dwell must be a time in seconds in"), std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--turbulence-banks", "--set-tempering-dwell", "0.0625"}, nullptr);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("--set-tempering-dwell applies with --set-tempering only"), std::string::npos) << r.message;
}

TEST(DaemonConfig, ManeuverMachRate) {
  EXPECT_EQ(parse_daemon_args({"--bank", "b"}, nullptr).config.estimator.maneuver_dwell.mach_per_s,
            f16mmae::AirDataRates::kMachPerS);   // the core's
  auto r = parse_daemon_args({"--bank", "b", "--maneuver-mach-rate", "0.003"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.maneuver_dwell.mach_per_s, 0.003);
  r = parse_daemon_args({"--bank", "b", "--maneuver-mach-rate=1"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.maneuver_dwell.mach_per_s, 1.0);
  for (const char* bad : {"0", "-0.001", "1.5", "nan", "fast"}) {
    r = parse_daemon_args({"--bank", "b", "--maneuver-mach-rate", bad}, nullptr);
    EXPECT_FALSE(r.ok) << bad;
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.message.find(std::string("--maneuver-mach-rate must be a Mach rate per second, > 0 and <= 1, got '") +
                             bad + "'"),
              std::string::npos)
        << r.message;
  }
  EXPECT_NE(f16mmae::daemon::daemon_usage().find("--maneuver-mach-rate MACH_PER_S"), std::string::npos);
}

TEST(DaemonConfig, ManeuverClimbRate) {   // one gate for the maneuver dwell and the climb reference
  const auto defaults = parse_daemon_args({"--bank", "b"}, nullptr).config.estimator;
  EXPECT_EQ(defaults.maneuver_dwell.climb_ft_s, f16mmae::AirDataRates::kClimbFtS);   // the core's
  EXPECT_EQ(defaults.climb_reference.climb_ft_s, f16mmae::AirDataRates::kClimbFtS);
  auto r = parse_daemon_args({"--bank", "b", "--maneuver-climb-rate", "20"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.maneuver_dwell.climb_ft_s, 20.0);
  EXPECT_EQ(r.config.estimator.climb_reference.climb_ft_s, 20.0);
  for (const char* bad : {"0", "-5", "1000.5", "nan", "steep"}) {
    r = parse_daemon_args({"--bank", "b", "--maneuver-climb-rate", bad}, nullptr);
    EXPECT_FALSE(r.ok) << bad;
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.message.find(std::string("--maneuver-climb-rate must be a climb rate in ft/s, > 0 and <= 1000, got '") +
                             bad + "'"),
              std::string::npos)
        << r.message;
  }
  EXPECT_NE(f16mmae::daemon::daemon_usage().find("--maneuver-climb-rate FT_S"), std::string::npos);
}

TEST(DaemonConfig, EvidenceDwellPerHypothesis) {
  EXPECT_TRUE(parse_daemon_args({"--bank", "b"}, nullptr).config.dwell_nats_table_path.empty());   // off
  auto r = parse_daemon_args({"--bank", "b", "--dwell-nats-per-hypothesis", "t.txt"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.dwell_nats_table_path, "t.txt");
  r = parse_daemon_args({"--bank", "b", "--dwell-nats-per-hypothesis="}, nullptr);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("--dwell-nats-per-hypothesis needs a table file name"), std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--dwell-nats-per-hypothesis", "LS=32,RS=32"}, nullptr);   // inline
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.dwell_nats_table_path, "LS=32,RS=32");
  EXPECT_FALSE(r.config.estimator.evidence_dwell_in_phases);   // off unless given
  r = parse_daemon_args({"--bank", "b", "--evidence-dwell-in-phases"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(r.config.estimator.evidence_dwell_in_phases);
}

TEST(DaemonConfig, OnLineEstimatorOptions) {
  auto r = parse_daemon_args({"--bank", "b"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_FALSE(r.config.estimator.bank.adaptation.enabled);
  EXPECT_EQ(r.config.estimator.trim.time_constant_s, 0.0);
  EXPECT_EQ(r.config.estimator.trim.freeze_probability, f16mmae::TrimTrackingOptions{}.freeze_probability);
  EXPECT_FALSE(r.config.estimator.schedule.mode == f16mmae::ScheduleMode::kNearest);
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--trim-tracking", "30", "--trim-freeze-probability=0.2",
                         "--schedule-mode", "nearest"},
                        nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(r.config.estimator.bank.adaptation.enabled);
  EXPECT_EQ(r.config.estimator.trim.time_constant_s, 30.0);
  EXPECT_EQ(r.config.estimator.trim.freeze_probability, 0.2);
  EXPECT_TRUE(r.config.estimator.schedule.mode == f16mmae::ScheduleMode::kNearest);
  r = parse_daemon_args({"--bank", "b", "--trim-tracking", "0"}, nullptr);   // 0: off (a scheduled bank's default is 30)
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.trim.time_constant_s, 0.0);
  for (const char* bad : {"-1", "nan", "1e7", "slow"}) {
    r = parse_daemon_args({"--bank", "b", "--trim-tracking", bad}, nullptr);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.message.find(std::string("'") + bad + "'"), std::string::npos) << r.message;
  }
  for (const char* bad : {"0", "1.5", "x"}) {
    r = parse_daemon_args({"--bank", "b", "--trim-tracking", "30", "--trim-freeze-probability", bad}, nullptr);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.message.find("(0, 1]"), std::string::npos) << r.message;
  }
  r = parse_daemon_args({"--bank", "b", "--trim-freeze-probability", "0.2"}, nullptr);
  EXPECT_NE(r.message.find("applies with --trim-tracking only"), std::string::npos) << r.message;
  EXPECT_EQ(r.config.estimator.trim.steady_g, 0.0);   // steady tracking: off unless given
  r = parse_daemon_args({"--bank", "b", "--trim-tracking", "30", "--trim-tracking-steady", "0.1"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.trim.steady_g, 0.1);
  for (const char* bad : {"0", "-0.1", "10.5", "inf", "steady"}) {
    r = parse_daemon_args({"--bank", "b", "--trim-tracking", "30", "--trim-tracking-steady", bad}, nullptr);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.message.find(std::string("'") + bad + "'"), std::string::npos) << r.message;
    EXPECT_NE(r.message.find("> 0 and <= 10"), std::string::npos) << r.message;
  }
  r = parse_daemon_args({"--bank", "b", "--trim-tracking", "30", "--trim-tracking-steady", "0.1"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_FALSE(r.config.estimator.trim.load_factor);   // load-factor scaling: the core's (off) unless given
  r = parse_daemon_args({"--bank", "b", "--trim-tracking", "30", "--trim-tracking-steady", "0.1",
                         "--trim-tracking-load-factor", "on"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(r.config.estimator.trim.load_factor);
  r = parse_daemon_args({"--bank", "b", "--trim-tracking", "30", "--trim-tracking-steady", "0.1",
                         "--trim-tracking-load-factor", "yes"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--trim-tracking-load-factor must be 'on' or 'off', got 'yes'"), std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--trim-tracking", "30", "--trim-tracking-load-factor", "on"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--trim-tracking-load-factor applies with --trim-tracking-steady only"), std::string::npos)
      << r.message;
  // the steady tracking's air-data gate and measurements (in process: trim_steady_air_data and
  // trim_steady_measurements, loop/estimator_options.py)
  r = parse_daemon_args({"--bank", "b", "--trim-tracking", "30", "--trim-tracking-steady", "0.1"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.trim.steady_measurements, std::vector<std::string>{"AOA"});
  EXPECT_EQ(r.config.estimator.trim.steady_climb_ft_s, f16mmae::AirDataRates::kClimbFtS);
  r = parse_daemon_args({"--bank", "b", "--trim-tracking", "30", "--trim-tracking-steady", "0.1",
                         "--trim-tracking-steady-air-data", "off", "--trim-tracking-steady-measurements", "aoa,VEL,Az"},
                        nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(std::isinf(r.config.estimator.trim.steady_climb_ft_s));
  EXPECT_TRUE(std::isinf(r.config.estimator.trim.steady_mach_per_s));
  EXPECT_EQ(r.config.estimator.trim.steady_measurements, (std::vector<std::string>{"AOA", "VEL", "AZ"}));
  r = parse_daemon_args({"--bank", "b", "--trim-tracking", "30", "--trim-tracking-steady", "0.1",
                         "--trim-tracking-steady-air-data", "off", "--trim-tracking-steady-air-data", "on"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.trim.steady_mach_per_s, f16mmae::AirDataRates::kMachPerS);
  for (const char* bad : {"AOA,AOA", "AOA,", "", "ALT", "AOA;VEL"}) {
    r = parse_daemon_args({"--bank", "b", "--trim-tracking", "30", "--trim-tracking-steady", "0.1",
                           "--trim-tracking-steady-measurements", bad}, nullptr);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.message.find("--trim-tracking-steady-measurements must name measurements"), std::string::npos)
        << r.message;
  }
  r = parse_daemon_args({"--bank", "b", "--trim-tracking", "30", "--trim-tracking-steady", "0.1",
                         "--trim-tracking-steady-air-data", "no"}, nullptr);
  EXPECT_NE(r.message.find("--trim-tracking-steady-air-data must be 'on' or 'off', got 'no'"), std::string::npos)
      << r.message;
  for (const auto& [flag, value] : std::vector<std::pair<std::string, std::string>>{
           {"--trim-tracking-steady-air-data", "off"}, {"--trim-tracking-steady-measurements", "AOA"}}) {
    r = parse_daemon_args({"--bank", "b", "--trim-tracking", "30", flag, value}, nullptr);
    EXPECT_EQ(r.exit_code, 2) << flag;
    EXPECT_NE(r.message.find(std::string(flag) + " applies with --trim-tracking-steady only"), std::string::npos)
        << r.message;
  }
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-reference-climb", "0.6",
                         "--adapt-reference-climb-hold=30"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.climb_reference.reference, 0.6);
  EXPECT_EQ(r.config.estimator.climb_reference.hold_s, 30.0);
  EXPECT_EQ(r.config.estimator.climb_reference.dwell_s, 0.0);   // the climb dwell: the dwell unless given
  for (const char* bad : {"-0.1", "101", "nan", "x"}) {
    r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-reference-climb", bad}, nullptr);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.message.find("[0, 100], got '" + std::string(bad) + "'"), std::string::npos) << r.message;
  }
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-reference-climb", "0.6",
                         "--adapt-reference-climb-hold", "-1"}, nullptr);
  EXPECT_NE(r.message.find("[0, 3600], got '-1'"), std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-reference-climb", "0.6",
                         "--adapt-reference-climb-dwell", "1.5"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.climb_reference.dwell_s, 1.5);
  for (const char* bad : {"-0.1", "60.5", "nan", "long"}) {
    r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-reference-climb", "0.6",
                           "--adapt-reference-climb-dwell", bad}, nullptr);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.message.find("--adapt-reference-climb-dwell must be a time in seconds in [0, 60] (0: the dwell), "
                             "got '" + std::string(bad) + "'"), std::string::npos) << r.message;
  }
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-reference-climb-dwell=1.5"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--adapt-reference-climb-dwell applies with --adapt-reference-climb only"),
            std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--adapt-reference-climb", "0.6"}, nullptr);
  EXPECT_NE(r.message.find("--adapt-reference-climb applies with --adapt-turbulence only"), std::string::npos)
      << r.message;
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-reference-climb-hold", "5"}, nullptr);
  EXPECT_NE(r.message.find("--adapt-reference-climb-hold applies with --adapt-reference-climb only"),
            std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--trim-tracking-steady", "0.1"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--trim-tracking-steady applies with --trim-tracking only"), std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-reference=0.76"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.bank.adaptation.reference, 0.76);
  EXPECT_FALSE(r.config.estimator.bank.adaptation.own_channels);   // rho over all channels unless given
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-own-channels"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(r.config.estimator.bank.adaptation.own_channels);
  r = parse_daemon_args({"--bank", "b", "--adapt-own-channels"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--adapt-own-channels applies with --adapt-turbulence only"), std::string::npos)
      << r.message;
  EXPECT_TRUE(r.config.adapt_counted_channel.empty());
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-own-channels", "--adapt-counted-channel", "VEL"},
                        nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.adapt_counted_channel, "vel");
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-own-channels", "--adapt-counted-channel=air"},
                        nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--adapt-counted-channel must name a measurement (vel, aoa, pit, az, rol, yaw, ay), "
                           "got 'air'"), std::string::npos) << r.message;
  EXPECT_TRUE(r.config.adapt_excluded_channel.empty());
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-excluded-channel", "AOA"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.adapt_excluded_channel, "aoa");
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-excluded-channel=air"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--adapt-excluded-channel must name a measurement (vel, aoa, pit, az, rol, yaw, ay), "
                           "got 'air'"), std::string::npos) << r.message;
  // the level channels scaled at every level and their s_0 (filter_bank.h), with the adaptation only
  EXPECT_TRUE(r.config.adapt_level_scale_channel.empty());
  EXPECT_EQ(r.config.estimator.bank.adaptation.level_scale_from, 1.0);
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-level-scale-channel", "VEL",
                         "--adapt-level-scale-from", "8"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.adapt_level_scale_channel, "vel");
  EXPECT_EQ(r.config.estimator.bank.adaptation.level_scale_from, 8.0);
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-level-scale-channel", "none"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(r.config.adapt_level_scale_channel.empty());   // none: no channel
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-level-scale-channel", "air"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("must name a measurement (vel, aoa, pit, az, rol, yaw, ay) or none, got 'air'"),
            std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-level-scale-from", "0.5"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--adapt-level-scale-from must be a scale in [1, 1000]"), std::string::npos) << r.message;
  // the adaptation's lull floor (turbulence_adaptation.h), with the adaptation only
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.bank.adaptation.floor_time_constant_s, 0.0);
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-floor", "60"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.bank.adaptation.floor_time_constant_s, 60.0);
  for (const char* bad : {"-1", "2", "3601", "nan"}) {   // below the 5-s averaging time too, as the core refuses
    r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-floor", bad}, nullptr);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.message.find("--adapt-floor must be 0 (off) or a time in [5, 3600] s (at least the adaptation's "
                             "averaging time)"),
              std::string::npos)
        << r.message;
  }
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-floor", "5"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  r = parse_daemon_args({"--bank", "b", "--adapt-floor", "30"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--adapt-floor applies with --adapt-turbulence only"), std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--adapt-level-scale-channel", "vel"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--adapt-level-scale-channel applies with --adapt-turbulence only"), std::string::npos)
      << r.message;
  // the calm-air complete model's bounds (calm_air_complete.h), with the adaptation only
  EXPECT_TRUE(r.config.estimator.calm_complete.rho.empty());
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--calm-complete", "VEL=1,AZ=0.5"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.calm_complete.rho, (std::map<std::string, double>{{"AZ", 0.5}, {"VEL", 1.0}}));
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--calm-complete", "VEL=101"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("VEL's bound must lie in [0, 100] (0: off), got 101"), std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--calm-complete", "VEL=1"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--calm-complete applies with --adapt-turbulence only"), std::string::npos) << r.message;
  // its measure (residual_whiteness.h) and the whiteness' bound, with the bounds only
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--calm-complete", "VEL=1"}, nullptr);
  EXPECT_EQ(r.config.estimator.calm_complete.measure, f16mmae::CalmMeasure::kPowerRatio);
  EXPECT_EQ(r.config.estimator.calm_complete.whiteness_bound, 0.78);
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--calm-complete", "VEL=1", "--calm-measure", "either",
                         "--calm-whiteness-bound", "0.7"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.calm_complete.measure, f16mmae::CalmMeasure::kEither);
  EXPECT_EQ(r.config.estimator.calm_complete.whiteness_bound, 0.7);
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--calm-complete", "VEL=1", "--calm-measure", "white"},
                        nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--calm-measure must be 'power', 'whiteness' or 'either', got 'white'"), std::string::npos)
      << r.message;
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--calm-measure", "whiteness"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--calm-measure applies with --calm-complete only"), std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--calm-complete", "VEL=1", "--calm-whiteness-bound",
                         "0.7"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--calm-whiteness-bound applies with --calm-measure only"), std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--calm-complete", "VEL=1", "--calm-measure", "whiteness",
                         "--calm-whiteness-bound", "0"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--calm-whiteness-bound must be a bound in (0, 100]"), std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--adapt-excluded-channel", "aoa"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--adapt-excluded-channel applies with --adapt-turbulence only"), std::string::npos)
      << r.message;
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-counted-channel", "vel"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--adapt-counted-channel applies with --adapt-own-channels only"), std::string::npos)
      << r.message;
  for (const char* bad : {"-0.1", "101", "nan", "high"}) {
    r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--adapt-reference", bad}, nullptr);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.message.find(std::string("[0, 100], got '") + bad + "'"), std::string::npos) << r.message;
  }
  r = parse_daemon_args({"--bank", "b", "--adapt-reference", "0.76"}, nullptr);
  EXPECT_NE(r.message.find("applies with --adapt-turbulence only"), std::string::npos) << r.message;
  r = parse_daemon_args({"--bank", "b", "--schedule-mode", "linear"}, nullptr);
  EXPECT_NE(r.message.find("'interpolate' or 'nearest', got 'linear'"), std::string::npos) << r.message;
}

TEST(DaemonConfig, AirDataTimeConstant) {
  // unset: the core's default (scheduled_filters.h); 0 (no low-pass) to 60 s; anything else refused
  auto r = parse_daemon_args({"--bank", "b"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.schedule.air_data_time_constant_s, f16mmae::ScheduleOptions{}.air_data_time_constant_s);
  for (const auto& [text, tau] : {std::pair<const char*, double>{"0.5", 0.5}, {"0", 0.0}, {"60", 60.0}}) {
    r = parse_daemon_args({"--bank", "b", std::string("--air-data-time-constant=") + text}, nullptr);
    ASSERT_TRUE(r.ok) << r.message;
    EXPECT_EQ(r.config.estimator.schedule.air_data_time_constant_s, tau) << text;
  }
  for (const char* bad : {"-0.1", "60.5", "nan", "inf", "fast", ""}) {
    r = parse_daemon_args({"--bank", "b", "--air-data-time-constant", bad}, nullptr);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.message.find(std::string("--air-data-time-constant must be a time constant in seconds in [0, 60] "
                                         "(0: no low-pass), got '") + bad + "'"),
              std::string::npos)
        << r.message;
  }
}

TEST(DaemonConfig, ManeuverModelOptions) {
  auto r = parse_daemon_args({"--bank", "b", "--maneuver-kinematics", "--maneuver-tempering", "0.1",
                              "--actuator-rate-limits", "1,1,1.5,1.5,2", "--actuator-position-limits=0.4,0.4,0.3,0.3,0.5"},
                             nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(r.config.estimator.maneuver.kinematics);
  EXPECT_EQ(r.config.estimator.maneuver.tempering_g, 0.1);
  EXPECT_EQ(r.config.estimator.actuators.rate_limit_rad_s, (std::vector<double>{1, 1, 1.5, 1.5, 2}));
  EXPECT_EQ(r.config.estimator.actuators.position_limit_rad, (std::vector<double>{0.4, 0.4, 0.3, 0.3, 0.5}));
  for (const char* bad : {"-0.1", "x", "1e3"}) {
    r = parse_daemon_args({"--bank", "b", "--maneuver-tempering", bad}, nullptr);
    EXPECT_NE(r.message.find(std::string("got '") + bad + "'"), std::string::npos) << r.message;
  }
  r = parse_daemon_args({"--bank", "b", "--maneuver-tempering", "0"}, nullptr);   // 0: off (a scheduled
  ASSERT_TRUE(r.ok) << r.message;                                               // default turned off)
  EXPECT_EQ(r.config.estimator.maneuver.tempering_g, 0.0);
  EXPECT_FALSE(r.config.estimator.maneuver.tempering());
  for (const char* bad : {"1,,2", "1,x", "", "1,-2", "1,"}) {
    r = parse_daemon_args({"--bank", "b", "--actuator-rate-limits", bad, "--actuator-position-limits", "1"}, nullptr);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.message.find("positive numbers separated by commas"), std::string::npos) << r.message;
  }
  r = parse_daemon_args({"--bank", "b", "--actuator-rate-limits", "1,2"}, nullptr);
  EXPECT_NE(r.message.find("go together"), std::string::npos) << r.message;
  // a throttle bank's sixth input has no actuator: "inf" (actuator_limits.h)
  r = parse_daemon_args({"--bank", "b", "--actuator-rate-limits", "1,1,1.5,1.5,2,inf",
                         "--actuator-position-limits", "0.4,0.4,0.3,0.3,0.5,inf"},
                        nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(std::isinf(r.config.estimator.actuators.rate_limit_rad_s.at(5)) && r.config.estimator.actuators.rate_limit_rad_s[5] > 0);
  EXPECT_TRUE(std::isinf(r.config.estimator.actuators.position_limit_rad.at(5)));
  for (const char* bad : {"1,-inf", "1,nan", "1,infinity"}) {
    r = parse_daemon_args({"--bank", "b", "--actuator-rate-limits", bad, "--actuator-position-limits", "1"}, nullptr);
    EXPECT_EQ(r.exit_code, 2) << bad;
  }
}

TEST(DaemonConfig, ManeuverTrimOptions) {
  auto r = parse_daemon_args({"--bank", "b"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;   // unset: the core's (off)
  EXPECT_FALSE(r.config.estimator.maneuver_trim.enabled);
  EXPECT_EQ(r.config.estimator.maneuver_trim.time_constant_s, f16mmae::ManeuverTrimOptions{}.time_constant_s);
  r = parse_daemon_args({"--bank", "b", "--maneuver-trim", "--maneuver-trim-time-constant=0.25",
                         "--maneuver-trim-accel", "off"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(r.config.estimator.maneuver_trim.enabled);
  EXPECT_EQ(r.config.estimator.maneuver_trim.time_constant_s, 0.25);
  EXPECT_FALSE(r.config.estimator.maneuver_trim.accel);
  EXPECT_FALSE(r.config.estimator.maneuver_trim.inertial);
  r = parse_daemon_args({"--bank", "b", "--maneuver-trim", "--maneuver-trim-rates", "inertial",
                         "--maneuver-trim-blend", "3"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(r.config.estimator.maneuver_trim.inertial);
  EXPECT_EQ(r.config.estimator.maneuver_trim.inertial_path.blend_time_constant_s, 3.0);
  r = parse_daemon_args({"--bank", "b", "--maneuver-trim", "--maneuver-trim-accel-airspeed", "1.5"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.maneuver_trim.accel_airspeed_rad_s, 1.5);
  const std::vector<std::pair<std::vector<std::string>, std::string>> refused = {
      {{"--maneuver-trim-time-constant", "0.5"}, "--maneuver-trim-time-constant applies with --maneuver-trim only"},
      {{"--maneuver-trim", "--maneuver-trim-time-constant", "0.01"},
       "--maneuver-trim-time-constant must be a time constant in seconds in [0.05, 60], got '0.01'"},
      {{"--maneuver-trim", "--maneuver-trim-time-constant", "x"}, "--maneuver-trim-time-constant must be"},
      {{"--maneuver-trim-accel", "off"}, "--maneuver-trim-accel applies with --maneuver-trim only"},
      {{"--maneuver-trim", "--maneuver-trim-accel", "no"}, "--maneuver-trim-accel must be 'on' or 'off', got 'no'"},
      {{"--maneuver-trim-rates", "inertial"}, "--maneuver-trim-rates applies with --maneuver-trim only"},
      {{"--maneuver-trim-accel-airspeed", "1"},
       "--maneuver-trim-accel-airspeed applies with --maneuver-trim and the air data's rates only"},
      {{"--maneuver-trim", "--maneuver-trim-accel-airspeed", "0.01"},
       "--maneuver-trim-accel-airspeed must be a natural frequency in rad/s in [0.05, 20], got '0.01'"},
      {{"--maneuver-trim", "--maneuver-trim-accel-airspeed", "inf"}, "--maneuver-trim-accel-airspeed must be"},
      {{"--maneuver-trim", "--maneuver-trim-rates", "inertial", "--maneuver-trim-accel-airspeed", "1"},
       "--maneuver-trim-accel-airspeed applies with --maneuver-trim and the air data's rates only"},
      {{"--maneuver-trim", "--maneuver-trim-rates", "gyro"}, "--maneuver-trim-rates must be 'air' or 'inertial', got 'gyro'"},
      {{"--maneuver-trim-blend", "2"}, "--maneuver-trim-blend applies with --maneuver-trim only"},
      {{"--maneuver-trim", "--maneuver-trim-blend", "0"},
       "--maneuver-trim-blend must be a time constant in seconds in [0.05, 600], got '0'"},
  };
  for (const auto& [extra, message] : refused) {
    std::vector<std::string> args{"--bank", "b"};
    args.insert(args.end(), extra.begin(), extra.end());
    r = parse_daemon_args(args, nullptr);
    EXPECT_FALSE(r.ok) << message;
    EXPECT_NE(r.message.find(message), std::string::npos) << r.message;
    EXPECT_EQ(r.exit_code, 2) << message;
  }
}

TEST(DaemonConfig, ManeuverDwellAndLevelOneOptions) {
  auto r = parse_daemon_args({"--bank", "b"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;   // unset: the core's defaults
  const f16mmae::HierarchicalOptions& e = r.config.estimator;
  EXPECT_FALSE(e.maneuver_dwell.dwell_s || e.maneuver_dwell.has_reference() || e.level1_p_min || e.level1_dwell_s ||
               e.bank.adaptation.channel_weight || e.maneuver.tempering_deadband_g || e.maneuver.tempering_alpha_deg ||
               e.maneuver.tempering_alpha_deadband_deg || e.maneuver.tempering_alpha_trim_deg ||
               e.maneuver.tempering_added_g ||
               e.maneuver.tempering_added_deadband_g || e.maneuver.tempering_added_spread || e.rate_gates_gust_scaled ||
               e.declare_components || e.bank.fresh_floor_levels ||
               e.level1_allowance || e.partial_p_min);
  EXPECT_TRUE(e.departure.enabled);
  r = parse_daemon_args({"--bank", "b", "--adapt-turbulence", "--maneuver-dwell", "1.5", "--maneuver-dwell-hold=30",
                         "--maneuver-dwell-g", "0.08", "--maneuver-dwell-time-constant", "1", "--maneuver-reference",
                         "0.65", "--maneuver-tempering", "0.1", "--maneuver-tempering-deadband", "0.05",
                         "--level1-p-min", "1e-4", "--level1-dwell-s", "0.5", "--departure-hold", "off",
                         "--adapt-channel-weight", "0.5", "--declare-components", "--fresh-floor-levels",
                         "--level1-allowance", "0.1",
                         "--partial-p-min=0.002", "--maneuver-tempering-alpha", "1",
                         "--maneuver-tempering-alpha-deadband", "0.75", "--maneuver-tempering-alpha-trim", "9",
                         "--maneuver-tempering-added", "0.1",
                         "--maneuver-tempering-added-deadband", "0.05", "--maneuver-tempering-added-spread", "3",
                         "--maneuver-rate-gust-scaled"},
                        nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.estimator.maneuver.tempering_alpha_deg, 1.0);
  EXPECT_EQ(r.config.estimator.maneuver.tempering_alpha_deadband_deg, 0.75);
  EXPECT_EQ(r.config.estimator.maneuver.tempering_alpha_trim_deg, 9.0);
  EXPECT_EQ(r.config.estimator.maneuver.tempering_added_g, 0.1);
  EXPECT_EQ(r.config.estimator.maneuver.tempering_added_deadband_g, 0.05);
  EXPECT_EQ(r.config.estimator.maneuver.tempering_added_spread, 3.0);
  EXPECT_TRUE(r.config.estimator.rate_gates_gust_scaled);
  EXPECT_TRUE(r.config.estimator.declare_components);
  EXPECT_TRUE(r.config.estimator.bank.fresh_floor_levels);
  EXPECT_EQ(r.config.estimator.maneuver_dwell.dwell_s, 1.5);
  EXPECT_EQ(r.config.estimator.maneuver_dwell.hold_s, 30.0);
  EXPECT_EQ(r.config.estimator.maneuver_dwell.g, 0.08);
  EXPECT_EQ(r.config.estimator.maneuver_dwell.time_constant_s, 1.0);
  EXPECT_EQ(r.config.estimator.maneuver_dwell.reference, 0.65);
  EXPECT_EQ(r.config.estimator.maneuver.tempering_deadband_g, 0.05);
  EXPECT_EQ(r.config.estimator.level1_p_min, 1e-4);
  EXPECT_EQ(r.config.estimator.level1_dwell_s, 0.5);
  EXPECT_EQ(r.config.estimator.level1_allowance, 0.1);
  EXPECT_EQ(r.config.estimator.partial_p_min, 0.002);
  EXPECT_FALSE(r.config.estimator.departure.enabled);
  EXPECT_EQ(r.config.estimator.bank.adaptation.channel_weight, 0.5);
  const std::vector<std::pair<std::vector<std::string>, std::string>> refused = {
      {{"--maneuver-dwell", "61"}, "--maneuver-dwell must be a time in seconds in [0, 60] (0: the dwell), got '61'"},
      {{"--maneuver-dwell", "x"}, "--maneuver-dwell must be a time in seconds"},
      {{"--maneuver-dwell", "1", "--maneuver-dwell-hold", "-1"}, "--maneuver-dwell-hold must be a time in seconds in [0, 3600]"},
      {{"--maneuver-dwell", "1", "--maneuver-dwell-g", "0"}, "--maneuver-dwell-g must be a load factor in g, > 0 and <= 10"},
      {{"--maneuver-dwell", "1", "--maneuver-dwell-time-constant", "61"}, "--maneuver-dwell-time-constant must be"},
      {{"--maneuver-dwell-hold", "30"}, "--maneuver-dwell-hold applies with --maneuver-dwell S > 0 only"},
      {{"--maneuver-dwell", "0", "--maneuver-dwell-g", "0.1"}, "--maneuver-dwell-g applies with --maneuver-dwell S > 0 only"},
      {{"--maneuver-reference", "0.65"}, "--maneuver-reference applies with --adapt-turbulence only"},
      {{"--adapt-turbulence", "--maneuver-reference", "101"}, "--maneuver-reference must be a power ratio in [0, 100]"},
      {{"--maneuver-tempering-deadband", "0.05"}, "--maneuver-tempering-deadband applies with --maneuver-tempering only"},
      {{"--maneuver-tempering", "0.1", "--maneuver-tempering-deadband", "11"}, "--maneuver-tempering-deadband must be"},
      {{"--maneuver-tempering-alpha", "1", "--maneuver-tempering-deadband", "0.05"},
       "--maneuver-tempering-deadband applies with --maneuver-tempering only"},
      {{"--maneuver-tempering-alpha-deadband", "0.75"}, "--maneuver-tempering-alpha-deadband applies with --maneuver-tempering-alpha only"},
      {{"--maneuver-tempering-alpha-trim", "9"}, "--maneuver-tempering-alpha-trim applies with --maneuver-tempering-alpha only"},
      {{"--maneuver-tempering-alpha", "1", "--maneuver-tempering-alpha-trim", "nan"},
       "--maneuver-tempering-alpha-trim must be an angle in deg in [0, 90]"},
      {{"--maneuver-tempering-alpha", "91"}, "--maneuver-tempering-alpha must be an angle in deg in [0, 90] (0: off), got '91'"},
      {{"--maneuver-tempering-added-deadband", "0.05"}, "--maneuver-tempering-added-deadband applies with --maneuver-tempering-added only"},
      {{"--maneuver-tempering-added", "101"}, "--maneuver-tempering-added must be a load factor in g in [0, 100] (0: off), got '101'"},
      {{"--maneuver-tempering-added-spread", "3"}, "--maneuver-tempering-added-spread applies with --maneuver-tempering-added only"},
      {{"--maneuver-tempering-added", "0.03", "--maneuver-tempering-added-spread", "-1"},
       "--maneuver-tempering-added-spread must be a factor in [0, 100], got '-1'"},
      {{"--maneuver-rate-gust-scaled"}, "--maneuver-rate-gust-scaled applies with --adapt-turbulence only"},
      {{"--maneuver-tempering-alpha", "1", "--maneuver-tempering-alpha-deadband", "-1"},
       "--maneuver-tempering-alpha-deadband must be an angle in deg in [0, 90]"},
      {{"--level1-p-min", "0.01"}, "--level1-p-min must be a probability in [0, (1 - 0.9)/12)"},
      {{"--level1-dwell-s", "-0.5"}, "--level1-dwell-s must be a time in seconds in [0, 60]"},
      {{"--level1-allowance", "6"}, "--level1-allowance must be a number of nats a frame in [0, 5], got '6'"},
      {{"--partial-p-min", "nan"}, "--partial-p-min must be a probability in [0, 0.1], got 'nan'"},
      {{"--departure-hold", "yes"}, "--departure-hold must be 'on' or 'off', got 'yes'"},
      {{"--adapt-channel-weight", "1.5"}, "--adapt-channel-weight must be a weight in [0, 1], got '1.5'"},
  };
  for (const auto& [args, message] : refused) {
    std::vector<std::string> a{"--bank", "b"};
    a.insert(a.end(), args.begin(), args.end());
    r = parse_daemon_args(a, nullptr);
    EXPECT_FALSE(r.ok) << message;
    EXPECT_EQ(r.exit_code, 2) << message;
    EXPECT_NE(r.message.find(message), std::string::npos) << r.message;
  }
}

TEST(DaemonConfig, WarmUpLead) {
  auto r = parse_daemon_args({"--bank", "b"}, nullptr);
  EXPECT_EQ(r.config.warm_lead_us, 500.0);  // on by default
  r = parse_daemon_args({"--bank", "b", "--warm-lead-us", "0"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.warm_lead_us, 0.0);  // off
  r = parse_daemon_args({"--bank", "b", "--warm-lead-us=250"}, nullptr);
  EXPECT_EQ(r.config.warm_lead_us, 250.0);
  r = parse_daemon_args({"--bank", "b", "--warm-lead-us", "-5"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--warm-lead-us must be a number of microseconds >= 0"), std::string::npos);
  EXPECT_NE(r.message.find("'-5'"), std::string::npos);
  r = parse_daemon_args({"--bank", "b", "--warm-lead-us", "20000"}, nullptr);  // > 15625 us at 64 Hz
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("shorter than a frame period (15625 us"), std::string::npos) << r.message;
}

TEST(DaemonConfig, ReWarmInterval) {
  auto r = parse_daemon_args({"--bank", "b"}, nullptr);
  EXPECT_EQ(r.config.rewarm_us, 100.0);  // on by default
  r = parse_daemon_args({"--bank", "b", "--rewarm-us=0"}, nullptr);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.config.rewarm_us, 0.0);  // one warm-up per frame
  r = parse_daemon_args({"--bank", "b", "--rewarm-us", "fast"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--rewarm-us must be a number of microseconds >= 0 (0: one warm-up per frame), got "
                           "'fast'"),
            std::string::npos)
      << r.message;
  r = parse_daemon_args({"--bank", "b", "--rewarm-us", "16000"}, nullptr);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.message.find("--rewarm-us 16000 must be shorter than a frame period"), std::string::npos) << r.message;
}

TEST(DaemonConfig, EveryFlagOfTheTableIsInTheUsageAndParsed) {
  const std::vector<std::string> names = daemon_flag_names();
  ASSERT_GE(names.size(), 60u);
  const std::string usage = daemon_usage();
  const std::string synopsis = usage.substr(0, usage.find("\n\n"));
  for (const std::string& name : names) {
    // once in the synopsis (--bank unbracketed, --help too), once at the start of a help line
    if (name != "--bank") {
      const std::size_t at = synopsis.find("[" + name);
      ASSERT_NE(at, std::string::npos) << name;
      const char next = synopsis.at(at + 1 + name.size());
      EXPECT_TRUE(next == ']' || next == ' ' || next == '\n') << name;
    }
    EXPECT_NE(usage.find("\n  " + name + " "), std::string::npos) << name;
    if (name == "--help") continue;
    // a flag the parser does not know would be an unknown argument; a value flag without its value
    // is refused naming it, a switch given a value too
    auto r = parse_daemon_args({"--bank", "b", name}, nullptr);
    EXPECT_EQ(r.message.find("unknown argument"), std::string::npos) << name << ": " << r.message;
    if (!r.ok) EXPECT_NE(r.message.find(name + " "), std::string::npos) << r.message;
    r = parse_daemon_args({"--bank", "b", name + "=x"}, nullptr);
    EXPECT_FALSE(r.ok && name != "--channel-prefix" && name != "--bank-public-key" && name != "--auth-key" &&
                 name != "--dwell-nats-per-hypothesis" && name != "--lcm-url" && name != "--bank")
        << name;
  }
  auto r = parse_daemon_args({"--bank", "b", "--quiet=yes"}, nullptr);
  EXPECT_NE(r.message.find("--quiet takes no value, got 'yes'"), std::string::npos) << r.message;
  // the requirement of a row names the flag and what it needs
  r = parse_daemon_args({"--bank", "b", "--turbulence-banks", "--set-tempering-rho", "2"}, nullptr);
  EXPECT_NE(r.message.find("--set-tempering-rho applies with --set-tempering only"), std::string::npos) << r.message;
}
