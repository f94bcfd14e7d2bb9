// FrameSequencer: every frame index owes the bank one propagate, preceded by at most one
// update, whatever the wire does (duplicates, reordering, loss, rejected frames).
#include "executive/frame_sequencer.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>

using f16mmae::executive::Fate;
using f16mmae::executive::FramePlan;
using f16mmae::executive::FrameSequencer;

namespace {

void expect_plan(const FramePlan& p, bool accept, long long catch_up) {
  EXPECT_EQ(p.apply, accept);
  EXPECT_EQ(p.catch_up, catch_up);
}

}  // namespace

TEST(FrameSequencer, InOrderFramesAreAllAppliedWithoutCatchUp) {
  FrameSequencer s(64);
  for (long long i = 100; i < 110; ++i) {
    expect_plan(s.on_sensor(i), true, 0);
    EXPECT_EQ(s.take_stale_since_status(), 0);
    expect_plan(s.on_command(i), true, 0);
  }
  const auto& c = s.counters();
  EXPECT_EQ(c.frames_updated, 10);
  EXPECT_EQ(c.frames_stale, 0);
  EXPECT_EQ(c.commands_missed, 0);
  EXPECT_EQ(c.frames_dropped(), 0);
  EXPECT_EQ(s.pending_frame(), 110);
}

TEST(FrameSequencer, DuplicatesAreDroppedAndCounted) {
  FrameSequencer s(64);
  expect_plan(s.on_sensor(0), true, 0);
  expect_plan(s.on_sensor(0), false, 0);  // repeated before its command
  expect_plan(s.on_command(0), true, 0);
  expect_plan(s.on_command(0), false, 0);
  expect_plan(s.on_sensor(0), false, 0);  // repeated after its command
  EXPECT_EQ(s.counters().dropped_duplicate, 3);
  EXPECT_EQ(s.counters().dropped_out_of_order, 0);
  EXPECT_EQ(s.counters().frames_updated, 1);
}

TEST(FrameSequencer, LateFramesAreDroppedAsOutOfOrder) {
  FrameSequencer s(64);
  for (long long i = 0; i < 4; ++i) {
    s.on_sensor(i);
    s.on_command(i);
  }
  expect_plan(s.on_sensor(1), false, 0);
  expect_plan(s.on_command(2), false, 0);
  EXPECT_EQ(s.counters().dropped_out_of_order, 2);
  EXPECT_EQ(s.counters().dropped_duplicate, 0);
}

TEST(FrameSequencer, LostSensorFramesArePropagatedWithTheHeldCommandAndMarkedStale) {
  FrameSequencer s(64);
  s.on_sensor(0);
  s.on_command(0);
  // sensor frames 1 and 2 (and their commands) lost
  expect_plan(s.on_sensor(3), true, 2);
  EXPECT_EQ(s.take_stale_since_status(), 2);
  EXPECT_EQ(s.take_stale_since_status(), 0);
  EXPECT_EQ(s.counters().frames_stale, 2);
  EXPECT_EQ(s.counters().commands_missed, 2);
  expect_plan(s.on_command(3), true, 0);
}

TEST(FrameSequencer, MissedCommandAfterAnUpdateIsNotStale) {
  FrameSequencer s(64);
  s.on_sensor(0);
  // command 0 lost: frame 0 was updated, propagated with the held command
  expect_plan(s.on_sensor(1), true, 1);
  EXPECT_EQ(s.take_stale_since_status(), 0);
  EXPECT_EQ(s.counters().commands_missed, 1);
  EXPECT_EQ(s.counters().frames_stale, 0);
}

TEST(FrameSequencer, CommandOfALostSensorFramePropagatesWithoutUpdate) {
  FrameSequencer s(64);
  s.on_sensor(0);
  s.on_command(0);
  expect_plan(s.on_command(1), true, 0);  // sensor 1 lost, its command arrived
  expect_plan(s.on_command(3), true, 1);  // sensor 2, command 2, sensor 3 lost
  EXPECT_EQ(s.counters().frames_stale, 3);
  EXPECT_EQ(s.counters().commands_missed, 1);
  EXPECT_EQ(s.take_stale_since_status(), 3);
  expect_plan(s.on_sensor(3), false, 0);  // too late: frame 3 already propagated
  expect_plan(s.on_sensor(4), true, 0);
}

TEST(FrameSequencer, CommandsBeforeTheFirstSensorFrameAreDropped) {
  FrameSequencer s(64);
  expect_plan(s.on_command(5), false, 0);
  EXPECT_EQ(s.counters().dropped_out_of_order, 1);
  expect_plan(s.on_sensor(7), true, 0);  // the first sensor frame starts the sequence
}

TEST(FrameSequencer, RejectedFramesAreCountedAndCaughtUpLater) {
  FrameSequencer s(64);
  s.on_sensor(0);
  s.on_command(0);
  s.on_rejected();  // sensor 1 had a NaN
  s.on_rejected();  // so did its command
  expect_plan(s.on_sensor(2), true, 1);
  EXPECT_EQ(s.counters().frames_rejected, 2);
  EXPECT_EQ(s.take_stale_since_status(), 1);
}

TEST(FrameSequencer, ResetStartsANewSequenceAndKeepsCounters) {
  FrameSequencer s(64);
  for (long long i = 0; i < 5; ++i) {
    s.on_sensor(i);
    s.on_command(i);
  }
  s.reset();
  EXPECT_FALSE(s.started());
  expect_plan(s.on_sensor(0), true, 0);
  EXPECT_EQ(s.counters().frames_updated, 6);
  EXPECT_EQ(s.counters().frames_dropped(), 0);
}

// Bounded catch-up: a gap of exactly L frames is caught up; L + 1 re-synchronises.
TEST(FrameSequencer, AGapOfExactlyTheLimitIsCaughtUpOneMoreResynchronises) {
  FrameSequencer s(64);
  s.on_sensor(0);
  s.on_command(0);  // pending frame 1
  expect_plan(s.on_sensor(1 + 64), true, 64);
  EXPECT_EQ(s.counters().frames_resynchronised, 0);
  s.on_command(65);  // pending frame 66
  const FramePlan p = s.on_sensor(66 + 65);
  EXPECT_EQ(p.fate, Fate::resynchronised);
  EXPECT_TRUE(p.restart);
  EXPECT_TRUE(p.apply);
  EXPECT_EQ(p.catch_up, 0);
  EXPECT_EQ(s.counters().frames_resynchronised, 1);
  EXPECT_EQ(s.take_stale_since_status(), 0);
  // the new sequence runs on from the resynchronised frame
  expect_plan(s.on_command(131), true, 0);
  expect_plan(s.on_sensor(132), true, 0);
}

TEST(FrameSequencer, WildCountersResynchroniseInConstantTimeAndTheTrafficIsPickedUpAgain) {
  for (const std::int64_t wild : {std::int64_t{10000000}, std::int64_t{1} << 62, FrameSequencer::kMaxFrame}) {
    FrameSequencer s(64);
    for (long long i = 0; i < 5; ++i) {
      s.on_sensor(i);
      s.on_command(i);
    }
    EXPECT_EQ(s.on_sensor(wild).fate, Fate::resynchronised) << wild;
    // the original traffic resumes: more than L behind the wild counter, it resynchronises back
    EXPECT_EQ(s.on_command(5).fate, Fate::resynchronised) << wild;
    expect_plan(s.on_sensor(6), true, 0);
    expect_plan(s.on_command(6), true, 0);
    EXPECT_EQ(s.counters().frames_resynchronised, 2);
    EXPECT_EQ(s.counters().commands_missed, 0);
    EXPECT_EQ(s.counters().frames_stale, 0);
  }
}

TEST(FrameSequencer, AWildCommandResynchronisesAndTheNextSensorFrameStarts) {
  FrameSequencer s(64);
  s.on_sensor(0);
  const FramePlan p = s.on_command(1LL << 62);
  EXPECT_EQ(p.fate, Fate::resynchronised);
  EXPECT_TRUE(p.restart);
  EXPECT_FALSE(p.apply);
  EXPECT_FALSE(s.started());
  expect_plan(s.on_sensor(1), true, 0);
}

TEST(FrameSequencer, CountersOutsideTheValidRangeAreRejected) {
  FrameSequencer s(64);
  EXPECT_EQ(s.on_sensor(-1).fate, Fate::rejected);
  EXPECT_EQ(s.on_sensor(INT64_MAX).fate, Fate::rejected);
  EXPECT_EQ(s.on_command(-5).fate, Fate::rejected);
  EXPECT_EQ(s.counters().frames_rejected, 3);
  EXPECT_FALSE(s.started());
  // the largest valid counter runs without overflow
  EXPECT_EQ(s.on_sensor(FrameSequencer::kMaxFrame).fate, Fate::used);
  EXPECT_EQ(s.on_command(FrameSequencer::kMaxFrame).fate, Fate::used);
}

TEST(FrameSequencer, RefusesANonPositiveLimit) {
  EXPECT_THROW(FrameSequencer(0), std::invalid_argument);
}
