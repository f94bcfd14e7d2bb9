// The cache warm-up of mmae-daemon: WarmUpSchedule's timing, and that Executive::warm_up and
// the core's warm_cache change nothing (statuses byte for byte, bank outputs bit for bit)
// and allocate nothing.
#include "executive/executive.h"
#include "daemon/warm_up_schedule.h"
#include "allocation_counter.h"
#include "test_executive_bank.h"

#include "bankfile/bank_file.h"
#include "f16mmae/hierarchical_bank.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <vector>

using namespace f16mmae;
using namespace f16mmae::daemon;
using namespace f16mmae::executive;
using namespace std::chrono_literals;

namespace {

lcmt_sensor_frame sensor(long long i, const ModelBank& b) {
  lcmt_sensor_frame f{};
  f.utime = i * 15625;
  f.frame = i;
  for (int j = 0; j < 7; ++j) {
    f.z[j] = b.z_trim(j) + 0.05 * std::sin(0.3 * i + j) + (i >= 40 && j == 1 ? 0.4 : 0.0);
    f.valid[j] = 1;
  }
  return f;
}
lcmt_command_frame command(long long i, const ModelBank& b) {
  lcmt_command_frame f{};
  f.utime = i * 15625;
  f.frame = i;
  for (int j = 0; j < 5; ++j) f.u_rad[j] = b.u_trim(j) + 0.01 * std::cos(0.2 * i + j);
  return f;
}
std::vector<std::uint8_t> encoded(const Executive& ex) {
  return {ex.encoded_status(), ex.encoded_status() + ex.encoded_status_size()};
}

}  // namespace

TEST(WarmUpSchedule, WakesOneLeadBeforeTheNextExpectedFrame) {
  WarmUpSchedule s(64.0, 500us);
  EXPECT_TRUE(s.enabled());
  EXPECT_FALSE(s.due());  // nothing before the first frame
  const auto t = WarmUpSchedule::Clock::time_point{} + 10s;
  s.on_frame(t);
  ASSERT_TRUE(s.due());
  EXPECT_EQ(std::chrono::duration_cast<std::chrono::microseconds>(*s.due() - t).count(), 15625 - 500);
  s.done(*s.due());
  EXPECT_FALSE(s.due());  // one warm-up per frame: a late frame gets none until it comes
  s.on_frame(t + 16ms);
  EXPECT_EQ(std::chrono::duration_cast<std::chrono::microseconds>(*s.due() - t).count(), 16000 + 15625 - 500);
}

TEST(WarmUpSchedule, ReWarmsEveryIntervalUntilTheFrameOrOneLeadPastItsDueTime) {
  using std::chrono::duration_cast;
  using std::chrono::microseconds;
  WarmUpSchedule s(64.0, 500us, 100us);
  const auto t = WarmUpSchedule::Clock::time_point{} + 10s;
  s.on_frame(t);
  std::vector<long long> at;  // the warm-ups of one window, us after t
  while (s.due()) {
    const auto now = *s.due();
    at.push_back(duration_cast<microseconds>(now - t).count());
    s.done(now);
  }
  // from 500 us before the frame is due (15625 us) to less than 500 us after it
  const std::vector<long long> expected = {15125, 15225, 15325, 15425, 15525, 15625, 15725, 15825, 15925, 16025};
  EXPECT_EQ(at, expected);
  // the frame comes (early, here): the window closes and the next one opens a period later
  s.on_frame(t + 15300us);
  EXPECT_EQ(duration_cast<microseconds>(*s.due() - t).count(), 15300 + 15125);
  // a warm-up that ran late (a busy host) counts the interval from when it ran
  s.done(t + 15300us + 15300us);
  EXPECT_EQ(duration_cast<microseconds>(*s.due() - t).count(), 30700);
}

TEST(WarmUpSchedule, ALeadOfZeroOrAWholePeriodIsOff) {
  for (auto lead : {0us, 15625us, 20000us}) {
    WarmUpSchedule s(64.0, lead);
    EXPECT_FALSE(s.enabled());
    s.on_frame(WarmUpSchedule::Clock::now());
    EXPECT_FALSE(s.due());
  }
}

// The rehearsal flies an executive of its own and the touches only read: with a warm-up before
// every frame, every status is the same, byte for byte, as without -- through a declaration,
// a level switch and a reset -- and nothing is allocated.
TEST(ExecutiveWarmUp, ChangesNoStatusAndAllocatesNothing) {
  const ModelBank b = load_bank(F16MMAE_SOURCE_DIR "/python/harness/f16mmae/data/nominal_tuned.f16bank");
  Executive plain(b), warmed(b);
  int level1_frames = 0;
  long long allocations = 0;
  for (long long i = 0; i < 300; ++i) {
    const auto s = sensor(i, b);
    const auto c = command(i, b);
    const long long before = f16mmae::testing::allocation_count();
    if (i == 200) {
      plain.on_reset();
      warmed.on_reset();
    }
    warmed.warm_up();
    warmed.warm_up();  // twice: the rehearsal's own state never leaks into the real one
    const Fate sent = warmed.on_sensor(s);
    allocations += f16mmae::testing::allocation_count() - before;
    ASSERT_EQ(plain.on_sensor(s), sent);
    ASSERT_EQ(encoded(plain).size(), encoded(warmed).size());
    // the step time differs by design; everything before it in the message must not
    lcmt_mmae_status a = plain.status(), w = warmed.status();
    a.step_time_ns = w.step_time_ns = 0;
    std::vector<std::uint8_t> ea(a.getEncodedSize()), ew(w.getEncodedSize());
    a.encode(ea.data(), 0, static_cast<int>(ea.size()));
    w.encode(ew.data(), 0, static_cast<int>(ew.size()));
    ASSERT_EQ(ea, ew) << "frame " << i;
    level1_frames += plain.status().bank_level == 1;
    const long long before_command = f16mmae::testing::allocation_count();
    const Fate applied = warmed.on_command(c);
    allocations += f16mmae::testing::allocation_count() - before_command;
    ASSERT_EQ(plain.on_command(c), applied);
  }
  EXPECT_EQ(allocations, 0);
  EXPECT_GT(level1_frames, 0) << "the sequence should reach the level-1 bank";
  EXPECT_EQ(warmed.warm_ups(), 600);
  EXPECT_EQ(plain.warm_ups(), 0);
}

TEST(CoreWarmCache, ReadsOnly) {
  const ModelBank b = test_support::synthetic_bank();
  F16HierarchicalBank plain(b), warmed(b);
  for (long long i = 0; i < 100; ++i) {
    F16HierarchicalBank::ZVector z = b.z_trim;
    for (int j = 0; j < 7; ++j) z(j) += 0.05 * std::sin(0.3 * i + j) + (i >= 30 && j == 2 ? 0.3 : 0.0);
    const F16HierarchicalBank::UVector u = b.u_trim;
    warmed.warm_cache();
    EXPECT_EQ(plain.update(z), warmed.update(z));
    plain.propagate(u);
    warmed.propagate(u);
    ASSERT_EQ(plain.probabilities(), warmed.probabilities()) << "frame " << i;
    ASSERT_EQ(plain.z_hat(), warmed.z_hat());
  }
}
