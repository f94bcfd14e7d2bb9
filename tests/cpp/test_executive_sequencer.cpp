// FrameSequencer: every frame index owes the bank one propagate, preceded by at most one
// update, whatever the wire does (duplicates, reordering, loss, rejected frames).
#include "executive/frame_sequencer.h"

#include <gtest/gtest.h>

using f16mmae::executive::FramePlan;
using f16mmae::executive::FrameSequencer;

namespace {

void expect_plan(const FramePlan& p, bool accept, long long catch_up) {
  EXPECT_EQ(p.accept, accept);
  EXPECT_EQ(p.catch_up, catch_up);
}

}  // namespace

TEST(FrameSequencer, InOrderFramesAreAllAppliedWithoutCatchUp) {
  FrameSequencer s;
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
  FrameSequencer s;
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
  FrameSequencer s;
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
  FrameSequencer s;
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
  FrameSequencer s;
  s.on_sensor(0);
  // command 0 lost: frame 0 was updated, propagated with the held command
  expect_plan(s.on_sensor(1), true, 1);
  EXPECT_EQ(s.take_stale_since_status(), 0);
  EXPECT_EQ(s.counters().commands_missed, 1);
  EXPECT_EQ(s.counters().frames_stale, 0);
}

TEST(FrameSequencer, CommandOfALostSensorFramePropagatesWithoutUpdate) {
  FrameSequencer s;
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
  FrameSequencer s;
  expect_plan(s.on_command(5), false, 0);
  EXPECT_EQ(s.counters().dropped_out_of_order, 1);
  expect_plan(s.on_sensor(7), true, 0);  // the first sensor frame starts the sequence
}

TEST(FrameSequencer, RejectedFramesAreCountedAndCaughtUpLater) {
  FrameSequencer s;
  s.on_sensor(0);
  s.on_command(0);
  s.on_rejected();  // sensor 1 had a NaN
  s.on_rejected();  // so did its command
  expect_plan(s.on_sensor(2), true, 1);
  EXPECT_EQ(s.counters().frames_rejected, 2);
  EXPECT_EQ(s.take_stale_since_status(), 1);
}

TEST(FrameSequencer, ResetStartsANewSequenceAndKeepsCounters) {
  FrameSequencer s;
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
