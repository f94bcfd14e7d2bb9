// Executive: the daemon's frame handling against the core bank driven directly with
// perturbations from trim (docs/INTERFACES.md), for in-order frames, a gap (propagate with
// the held command, no update), rejected frames; and no allocation on the per-frame path.
#include "executive/executive.h"
#include "allocation_counter.h"
#include "test_executive_bank.h"

#include "bankfile/bank_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

using namespace f16mmae;
using namespace f16mmae::executive;

namespace {

lcmt_sensor_frame sensor(long long i, const Eigen::VectorXd& z) {
  lcmt_sensor_frame f{};
  f.utime = i * 15625;
  f.frame = i;
  for (int j = 0; j < 7; ++j) {
    f.z[j] = z(j);
    f.valid[j] = 1;
  }
  return f;
}
// u: the five surface commands, and the throttle command when it has six (else NaN, as a
// sender without one).
lcmt_command_frame command(long long i, const Eigen::VectorXd& u) {
  lcmt_command_frame f{};
  f.utime = i * 15625;
  f.frame = i;
  for (int j = 0; j < 5; ++j) f.u_rad[j] = u(j);
  f.throttle = u.size() == 6 ? u(5) : std::numeric_limits<double>::quiet_NaN();
  return f;
}
// Deterministic absolute signals near trim with a failure-like bias on AOA from frame 20.
Eigen::VectorXd z_at(const ModelBank& b, long long i) {
  Eigen::VectorXd z = b.z_trim;
  for (int j = 0; j < 7; ++j) z(j) += 0.05 * std::sin(0.3 * i + j);
  if (i >= 20) z(1) += 0.4;
  return z;
}
Eigen::VectorXd u_at(const ModelBank& b, long long i) {
  Eigen::VectorXd u = b.u_trim;
  for (int j = 0; j < 5; ++j) u(j) += 0.01 * std::cos(0.2 * i + j);
  if (u.size() == 6) u(5) += 0.02 * std::sin(0.1 * i);  // a throttle dither
  return u;
}
F16FilterBank reference_bank(const ModelBank& b) {
  std::vector<F16FilterBank::Model> models;
  for (int k = 0; k < 13; ++k) {
    const auto& h = b.hypotheses[k];
    models.push_back(F16FilterBank::Model::from_matrices(h.phi, h.bd, h.h, h.k, h.a));
  }
  F16FilterBank bank(models);
  bank.set_h_output(b.h_output);
  return bank;
}
// Frames 0 .. n-1 of the deterministic signals, in order.
void fly(Executive& ex, const ModelBank& b, long long n) {
  for (long long i = 0; i < n; ++i) {
    ex.on_sensor(sensor(i, z_at(b, i)));
    ex.on_command(command(i, u_at(b, i)));
  }
}
void expect_same(const Executive& ex, const F16FilterBank& ref, const ModelBank& b) {
  const auto& st = ex.status();
  ASSERT_EQ(st.num_hypotheses, 13);
  for (int k = 0; k < 13; ++k) {
    EXPECT_EQ(st.hypothesis_names[k], b.hypotheses[k].name);
    EXPECT_NEAR(st.probabilities[k], ref.probabilities()(k), 1e-12) << "hypothesis " << k;
  }
  for (int j = 0; j < 7; ++j) EXPECT_NEAR(st.z_hat[j], ref.z_hat()(j) + b.z_trim(j), 1e-9);
  EXPECT_EQ(st.turbulence_member, -1) << "one bank: no turbulence set's member";
  EXPECT_TRUE(std::isnan(st.turbulence_power_ratio));
}

}  // namespace

TEST(Executive, InOrderFramesMatchTheCoreBankOnPerturbations) {
  const ModelBank b = test_support::synthetic_bank();
  Executive ex(b);
  F16FilterBank ref = reference_bank(b);
  for (long long i = 0; i < 60; ++i) {
    ASSERT_EQ(ex.on_sensor(sensor(i, z_at(b, i))), Fate::used);
    ref.update((z_at(b, i) - b.z_trim).eval());
    expect_same(ex, ref, b);
    EXPECT_EQ(ex.status().frame, i);
    EXPECT_FALSE(ex.status().stale);
    ASSERT_EQ(ex.on_command(command(i, u_at(b, i))), Fate::used);
    ref.propagate((u_at(b, i) - b.u_trim).eval());
  }
  // the signals moved the probabilities away from NONE presumed (1 - 12 p_min)
  EXPECT_GT(std::abs(ex.status().probabilities[0] - 0.988), 1e-3);
  double sum = 0.0;
  for (double p : ex.status().probabilities) sum += p;
  EXPECT_NEAR(sum, 1.0, 1e-12);
  EXPECT_EQ(ex.counters().frames_updated, 60);
  EXPECT_GT(ex.encoded_status_size(), 0);
  lcmt_mmae_status decoded;
  ASSERT_EQ(decoded.decode(ex.encoded_status(), 0, ex.encoded_status_size()), ex.encoded_status_size());
  EXPECT_EQ(decoded.frame, 59);
  EXPECT_EQ(decoded.hypothesis_names[7], "AOA");
  EXPECT_EQ(decoded.probabilities[7], ex.status().probabilities[7]);
}

TEST(Executive, AGapPropagatesWithTheHeldCommandWithoutUpdateAndMarksStale) {
  const ModelBank b = test_support::synthetic_bank();
  Executive ex(b);
  F16FilterBank ref = reference_bank(b);
  for (long long i = 0; i < 10; ++i) {
    ex.on_sensor(sensor(i, z_at(b, i)));
    ref.update((z_at(b, i) - b.z_trim).eval());
    ex.on_command(command(i, u_at(b, i)));
    ref.propagate((u_at(b, i) - b.u_trim).eval());
  }
  // frames 10, 11, 12 lost on the wire; the held command is u_9
  for (int k = 0; k < 3; ++k) ref.propagate((u_at(b, 9) - b.u_trim).eval());
  ASSERT_EQ(ex.on_sensor(sensor(13, z_at(b, 13))), Fate::used);
  ref.update((z_at(b, 13) - b.z_trim).eval());
  expect_same(ex, ref, b);
  EXPECT_TRUE(ex.status().stale);
  EXPECT_EQ(ex.status().frames_without_update, 3);
  EXPECT_EQ(ex.status().frames_stale, 3);
  EXPECT_EQ(ex.status().commands_missed, 3);
  ex.on_command(command(13, u_at(b, 13)));
  ASSERT_EQ(ex.on_sensor(sensor(14, z_at(b, 14))), Fate::used);
  EXPECT_FALSE(ex.status().stale);
}

TEST(Executive, NonFiniteOrInvalidFramesAreRejectedAndChangeNothing) {
  const ModelBank b = test_support::synthetic_bank();
  Executive ex(b);
  ASSERT_EQ(ex.on_sensor(sensor(0, z_at(b, 0))), Fate::used);
  const std::vector<double> before(ex.status().probabilities.begin(), ex.status().probabilities.end());
  auto bad = sensor(0, z_at(b, 0));
  bad.z[2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(ex.on_sensor(bad), Fate::rejected);
  bad = sensor(0, z_at(b, 0));
  bad.z[0] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(ex.on_sensor(bad), Fate::rejected);
  bad = sensor(1, z_at(b, 1));
  bad.valid[4] = 0;
  EXPECT_EQ(ex.on_sensor(bad), Fate::rejected);
  auto cmd = command(0, u_at(b, 0));
  cmd.u_rad[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(ex.on_command(cmd), Fate::rejected);
  EXPECT_EQ(ex.counters().frames_rejected, 4);
  EXPECT_EQ(ex.counters().frames_updated, 1);
  for (int k = 0; k < 13; ++k) EXPECT_EQ(ex.status().probabilities[k], before[k]);
  EXPECT_EQ(ex.on_command(command(0, u_at(b, 0))), Fate::used);
}

TEST(Executive, ResetReturnsToTheInitialBank) {
  const ModelBank b = test_support::synthetic_bank();
  Executive ex(b), fresh(b);
  fly(ex, b, 30);
  ex.on_reset();
  ASSERT_EQ(ex.on_sensor(sensor(0, z_at(b, 0))), Fate::used);
  ASSERT_EQ(fresh.on_sensor(sensor(0, z_at(b, 0))), Fate::used);
  for (int k = 0; k < 13; ++k) EXPECT_EQ(ex.status().probabilities[k], fresh.status().probabilities[k]);
}

TEST(Executive, ThePerFramePathAllocatesNothing) {
  const ModelBank b = test_support::synthetic_bank();
  Executive ex(b);
  std::vector<lcmt_sensor_frame> sensors;
  std::vector<lcmt_command_frame> commands;
  for (long long i = 0; i < 200; ++i) {
    sensors.push_back(sensor(i, z_at(b, i)));
    commands.push_back(command(i, u_at(b, i)));
  }
  sensors[50].z[3] = std::numeric_limits<double>::quiet_NaN();  // rejected
  const long long before = f16mmae::testing::allocation_count();
  for (std::size_t i = 0; i < sensors.size(); ++i) {
    if (i == 120) continue;  // a gap
    ex.on_sensor(sensors[i]);
    ex.on_sensor(sensors[i]);  // a duplicate
    ex.on_command(commands[i]);
  }
  EXPECT_EQ(f16mmae::testing::allocation_count() - before, 0);
  EXPECT_EQ(ex.counters().frames_updated, 198);
  EXPECT_EQ(ex.counters().dropped_duplicate, 198);
  EXPECT_EQ(ex.update_stats().count(), 198);
  EXPECT_GT(ex.update_stats().max_ns(), 0);
  EXPECT_NE(ex.summary().find("198 updated"), std::string::npos);
}

TEST(Executive, TheShippedBankRunsAllocationFreeAndHoldsNoneAtTrim) {
  const ModelBank b = load_bank(F16MMAE_SOURCE_DIR "/python/harness/f16mmae/data/nominal_tuned.f16bank");
  Executive ex(b);
  EXPECT_EQ(ex.status().bank_hash, b.content_hash);
  std::vector<lcmt_sensor_frame> sensors;
  std::vector<lcmt_command_frame> commands;
  for (long long i = 0; i < 256; ++i) {
    Eigen::VectorXd z = b.z_trim;
    for (int j = 0; j < 7; ++j) z(j) += 1e-4 * std::sin(0.7 * i + j);  // well inside the noise
    sensors.push_back(sensor(i, z));
    commands.push_back(command(i, b.u_trim));
  }
  const long long before = f16mmae::testing::allocation_count();
  for (std::size_t i = 0; i < sensors.size(); ++i) {
    ASSERT_EQ(ex.on_sensor(sensors[i]), Fate::used);
    ASSERT_EQ(ex.on_command(commands[i]), Fate::used);
  }
  EXPECT_EQ(f16mmae::testing::allocation_count() - before, 0);
  EXPECT_EQ(ex.status().bank_level, 0);
  EXPECT_EQ(ex.status().declared, "NONE");
  EXPECT_EQ(ex.status().hypothesis_names[0], "NONE");
  EXPECT_GT(ex.status().probabilities[0], 0.9);
  for (int j = 0; j < 7; ++j) EXPECT_NEAR(ex.status().z_hat[j], b.z_trim(j), 1e-2 * (1.0 + std::abs(b.z_trim(j))));
}

// A frame more than one second of frames ahead restarts the estimator from the stale state
// (what a fresh executive starts with) at that frame, in constant time: the 2^62 jump of a
// forged frame costs no more than one frame, and the statuses say so.
TEST(Executive, AJumpBeyondOneSecondOfFramesResynchronisesFromTheStaleState) {
  const ModelBank b = test_support::synthetic_bank();
  ASSERT_EQ(b.frame_rate_hz, 64.0);
  for (const long long jump : {65LL, 10000000LL, 1LL << 62}) {
    Executive ex(b);
    EXPECT_EQ(ex.max_gap_frames(), 64);
    fly(ex, b, 30);  // the AOA bias moves it away from the initial state
    const long long n = 30 + jump;  // pending frame 30: 30 + 64 would still be caught up
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_EQ(ex.on_sensor(sensor(n, z_at(b, 30))), Fate::resynchronised);
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(100));
    Executive fresh(b);
    ASSERT_EQ(fresh.on_sensor(sensor(n, z_at(b, 30))), Fate::used);
    for (int k = 0; k < 13; ++k) EXPECT_EQ(ex.status().probabilities[k], fresh.status().probabilities[k]);
    for (int j = 0; j < 7; ++j) EXPECT_EQ(ex.status().z_hat[j], fresh.status().z_hat[j]);
    EXPECT_TRUE(ex.status().resynchronised);
    EXPECT_FALSE(ex.status().stale);
    EXPECT_EQ(ex.status().frame, n);
    EXPECT_EQ(ex.status().frames_resynchronised, 1);
    EXPECT_EQ(ex.counters().commands_missed, 0);
    // the flight goes on from there
    ASSERT_EQ(ex.on_command(command(n, u_at(b, 30))), Fate::used);
    ASSERT_EQ(ex.on_sensor(sensor(n + 1, z_at(b, 31))), Fate::used);
    EXPECT_FALSE(ex.status().resynchronised);
  }
}

TEST(Executive, AGapOfExactlyOneSecondIsStillCaughtUp) {
  const ModelBank b = test_support::synthetic_bank();
  Executive ex(b);
  F16FilterBank ref = reference_bank(b);
  ex.on_sensor(sensor(0, z_at(b, 0)));
  ref.update((z_at(b, 0) - b.z_trim).eval());
  ex.on_command(command(0, u_at(b, 0)));
  ref.propagate((u_at(b, 0) - b.u_trim).eval());
  for (int k = 0; k < 64; ++k) ref.propagate((u_at(b, 0) - b.u_trim).eval());
  ASSERT_EQ(ex.on_sensor(sensor(65, z_at(b, 65))), Fate::used);
  ref.update((z_at(b, 65) - b.z_trim).eval());
  expect_same(ex, ref, b);
  EXPECT_EQ(ex.status().frames_without_update, 64);
  EXPECT_FALSE(ex.status().resynchronised);
}

TEST(Executive, AWildCommandRestartsTheEstimatorWithoutApplyingIt) {
  const ModelBank b = test_support::synthetic_bank();
  Executive ex(b), fresh(b);
  fly(ex, b, 30);
  ASSERT_EQ(ex.on_command(command(1LL << 62, u_at(b, 0))), Fate::resynchronised);
  ASSERT_EQ(ex.on_sensor(sensor(30, z_at(b, 30))), Fate::used);
  ASSERT_EQ(fresh.on_sensor(sensor(30, z_at(b, 30))), Fate::used);
  for (int k = 0; k < 13; ++k) EXPECT_EQ(ex.status().probabilities[k], fresh.status().probabilities[k]);
}

TEST(Executive, AirDataIsScheduledAndANonFiniteValueIsCountedNotRejected) {
  const ModelBank b = test_support::synthetic_bank();
  Executive ex(b);
  auto s = sensor(0, z_at(b, 0));
  s.mach = 0.42;
  s.pressure_altitude_ft = 21000.0;
  ASSERT_EQ(ex.on_sensor(s), Fate::used);
  EXPECT_EQ(ex.estimator().air_data().mach, 0.42);
  EXPECT_EQ(ex.estimator().air_data().pressure_altitude_ft, 21000.0);
  ASSERT_EQ(ex.on_command(command(0, u_at(b, 0))), Fate::used);
  s = sensor(1, z_at(b, 1));
  s.mach = std::numeric_limits<double>::quiet_NaN();
  s.pressure_altitude_ft = 21500.0;
  EXPECT_EQ(ex.on_sensor(s), Fate::used);  // the measurements are applied all the same
  EXPECT_EQ(ex.counters().frames_updated, 2);
  EXPECT_EQ(ex.air_data_rejected(), 1);
  EXPECT_EQ(ex.status().air_data_rejected, 1);
  EXPECT_EQ(ex.estimator().air_data().mach, 0.42);  // frozen at the last usable value
  EXPECT_EQ(ex.estimator().air_data().pressure_altitude_ft, 21000.0);
  EXPECT_NE(ex.summary().find("1 air data rejected"), std::string::npos) << ex.summary();
  ex.on_reset();  // a new flight: the bank returns to its design condition; the count stays
  EXPECT_EQ(ex.estimator().air_data().mach, b.mach);
  EXPECT_EQ(ex.air_data_rejected(), 1);
}

namespace {

// The executive on bank b equals the fixed-size core bank Ref stepped directly: the same
// probabilities, z_hat, level and declarations bit for bit, and its frames allocate nothing.
// A bias on AOA from frame 20 makes the bank declare and switch to level 1.
template <class Ref>
void expect_runs_as_the_core_bank(const ModelBank& b) {
  Executive ex(b);
  Ref ref(b);
  std::vector<lcmt_sensor_frame> sensors;
  std::vector<lcmt_command_frame> commands;
  std::vector<Eigen::VectorXd> z(120);
  for (long long i = 0; i < 120; ++i) {
    z[i] = z_at(b, i);
    if (i >= 20) z[i](1) += 3.0;  // a bias this bank declares (the deterministic signals' 0.4 it does not)
    sensors.push_back(sensor(i, z[i]));
    commands.push_back(command(i, u_at(b, i)));
  }
  std::vector<std::string> declared;
  bool saw_level1 = false;
  long long allocations = 0;
  for (long long i = 0; i < 120; ++i) {
    const long long before = f16mmae::testing::allocation_count();
    ASSERT_EQ(ex.on_sensor(sensors[i]), Fate::used);
    allocations += f16mmae::testing::allocation_count() - before;
    const int d = ref.update(z[i]);
    if (d >= 0) declared.push_back(ref.name(d));
    const auto& st = ex.status();
    ASSERT_EQ(st.bank_level, ref.level()) << "frame " << i;
    saw_level1 = saw_level1 || ref.level() == 1;
    EXPECT_EQ(st.declaration, d < 0 ? "" : ref.name(d)) << "frame " << i;
    for (int k = 0; k < 13; ++k) {
      ASSERT_EQ(st.hypothesis_names[k], ref.name(ref.online()[k]));
      ASSERT_EQ(st.probabilities[k], ref.probabilities()(k)) << "frame " << i << " hypothesis " << k;
    }
    const Eigen::Matrix<double, 7, 1> z_hat = ref.z_hat();
    for (int j = 0; j < 7; ++j) ASSERT_EQ(st.z_hat[j], z_hat(j));
    const long long before_command = f16mmae::testing::allocation_count();
    ASSERT_EQ(ex.on_command(commands[i]), Fate::used);
    allocations += f16mmae::testing::allocation_count() - before_command;
    ref.propagate(u_at(b, i));
  }
  EXPECT_EQ(allocations, 0);
  // the synthetic models pick VEL: which one does not matter here
  ASSERT_FALSE(declared.empty());
  EXPECT_TRUE(saw_level1);
  EXPECT_EQ(ex.status().declared, ref.name(ref.current_hypothesis()));
}

// The probabilities after n frames of the deterministic signals, with the commands' throttle
// replaced by `throttle` (NaN: none sent) when it is not empty.
std::vector<double> probabilities_after(const ModelBank& b, long long n, const std::vector<double>& throttle = {}) {
  Executive ex(b);
  for (long long i = 0; i < n; ++i) {
    ex.on_sensor(sensor(i, z_at(b, i)));
    lcmt_command_frame c = command(i, u_at(b, i));
    if (!throttle.empty()) c.throttle = throttle[i % throttle.size()];
    EXPECT_EQ(ex.on_command(c), Fate::used) << "frame " << i;
  }
  return {ex.status().probabilities.begin(), ex.status().probabilities.end()};
}

}  // namespace

// A bank of 19 states (the filters with the six Dryden gust states) runs in the executive as
// F16GustHierarchicalBank stepped directly.
TEST(Executive, AGustStateBankRunsAsTheNineteenStateCoreBank) {
  const ModelBank b = test_support::synthetic_bank(19);
  ASSERT_EQ(b.nx(), 19);
  EXPECT_EQ(Executive(b).estimator().nx(), 19);
  EXPECT_EQ(Executive(b).estimator().states(), "19 states (gust)");
  expect_runs_as_the_core_bank<F16GustHierarchicalBank>(b);
}

// A bank with the throttle as its sixth input runs in the executive as
// F16ThrottleHierarchicalBank stepped directly with (u_rad, throttle) of each command frame.
TEST(Executive, AThrottleBankRunsAsTheSixInputCoreBankOnTheCommandFramesThrottle) {
  const ModelBank b = test_support::synthetic_bank(13, 6);
  ASSERT_EQ(b.nu(), 6);
  Executive ex(b);
  EXPECT_EQ(ex.estimator().nu(), 6);
  EXPECT_TRUE(ex.estimator().models_throttle());
  EXPECT_EQ(ex.estimator().states(), "13 states, 6 inputs (throttle)");
  EXPECT_EQ(ex.estimator().u_trim()(5), 0.25);  // the held command starts at the trim throttle
  expect_runs_as_the_core_bank<F16ThrottleHierarchicalBank>(b);
  // the throttle reaches the filters: held at its trim, the probabilities are others
  const std::vector<double> dithered = probabilities_after(b, 40), held = probabilities_after(b, 40, {0.25});
  double differ = 0.0;
  for (std::size_t k = 0; k < held.size(); ++k) differ = std::max(differ, std::abs(dithered[k] - held[k]));
  EXPECT_GT(differ, 1e-6);
}

// A bank of 19 states with the throttle as its sixth input (the scheduled default since its
// revision 15) runs as F16GustThrottleHierarchicalBank stepped directly.
TEST(Executive, AGustStateThrottleBankRunsAsTheNineteenStateSixInputCoreBank) {
  const ModelBank b = test_support::synthetic_bank(19, 6);
  ASSERT_EQ(b.nx(), 19);
  ASSERT_EQ(b.nu(), 6);
  Executive ex(b);
  EXPECT_TRUE(ex.estimator().models_throttle());
  EXPECT_EQ(ex.estimator().states(), "19 states (gust), 6 inputs (throttle)");
  expect_runs_as_the_core_bank<F16GustThrottleHierarchicalBank>(b);
}

TEST(Executive, ANonFiniteThrottleRejectsTheFrameOfAThrottleBankOnly) {
  const ModelBank six = test_support::synthetic_bank(13, 6), five = test_support::synthetic_bank();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Executive ex(six);
  ASSERT_EQ(ex.on_sensor(sensor(0, z_at(six, 0))), Fate::used);
  lcmt_command_frame c = command(0, u_at(six, 0));
  c.throttle = nan;
  EXPECT_EQ(ex.on_command(c), Fate::rejected);
  c.throttle = std::numeric_limits<double>::infinity();
  EXPECT_EQ(ex.on_command(c), Fate::rejected);
  EXPECT_EQ(ex.counters().frames_rejected, 2);
  EXPECT_EQ(ex.on_command(command(0, u_at(six, 0))), Fate::used);
  // a 5-input bank ignores the throttle: none (NaN), or any value, gives the same flight
  const std::vector<double> none = probabilities_after(five, 40);
  EXPECT_EQ(probabilities_after(five, 40, {nan}), none);
  EXPECT_EQ(probabilities_after(five, 40, {0.9, 0.1}), none);
}

TEST(Executive, ABankOfAnotherStateSizeIsRefusedNamingTheSizesItRuns) {
  const ModelBank b = test_support::synthetic_bank(15);
  try {
    Executive ex(b);
    FAIL() << "a 15-state bank was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("(13, 5, 7), (19, 5, 7) with the gust states, (13, 6, 7) with the throttle input or (19, 6, 7) with both"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("this bank has (15, 5, 7)"), std::string::npos) << what;
  }
}

TEST(Executive, OneAdaptedBanksStatusCarriesTheAdaptationsMeasuredPowerRatio) {
  // the closed loop's adaptive dither over LCM reads it (member -1): frame by frame the status's
  // rho is the core bank's TurbulenceAdaptation::measured_power_ratio() flown with the same options
  const ModelBank b = test_support::synthetic_bank();
  HierarchicalOptions o;
  o.bank.adaptation.enabled = true;
  Executive ex(b, o);
  F16HierarchicalBank direct(b, o);
  for (long long i = 0; i < 40; ++i) {
    ASSERT_EQ(ex.on_sensor(sensor(i, z_at(b, i))), Fate::used);
    direct.update(z_at(b, i));
    EXPECT_EQ(ex.status().turbulence_member, -1);
    ASSERT_EQ(ex.status().turbulence_power_ratio, direct.bank().adaptation().measured_power_ratio()) << "frame " << i;
    ASSERT_EQ(ex.on_command(command(i, u_at(b, i))), Fate::used);
    direct.propagate(u_at(b, i));
  }
  EXPECT_GT(ex.status().turbulence_power_ratio, 0.0);
}
