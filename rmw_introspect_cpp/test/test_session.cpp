// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// The Session state machine on a manual clock: settling (by wait, by activity, by polls),
// progress snapshots, exit. Its parts have test files of their own, in the same binary:
// test_idle_proof.cpp (detected quiescence), test_warp.cpp (the warp), test_probing.cpp.

#include <gtest/gtest.h>

#include <cstdint>

#include "detail/session.hpp"
#include "session_fixture.hpp"

using namespace session_test;  // NOLINT(build/namespaces): the fixture's names

namespace
{

class SessionTest : public ::testing::Test
{
protected:
  ManualClock clock;
  rmw_introspect::VirtualClock virtual_clock;
  Session session{clock, virtual_clock, settings()};
};

}  // namespace

TEST_F(SessionTest, nothing_happens_before_start)
{
  EXPECT_FALSE(session.started());
  session.on_change();
  session.enter_wait();
  clock.advance_ms(100);
  EXPECT_EQ(Session::Action::kNone, session.poll().action);
  EXPECT_TRUE(session.start());
  EXPECT_FALSE(session.start());
}

TEST_F(SessionTest, settles_after_quiet_with_a_thread_waiting)
{
  session.start();
  session.on_change();
  const uint64_t token = session.enter_wait();
  clock.advance_ms(5);
  Session::Step step = session.poll();
  EXPECT_EQ(Session::Action::kNone, step.action);
  ASSERT_TRUE(step.has_deadline);
  EXPECT_EQ(clock.now + 5 * kMs, step.deadline_ns);  // 10 ms after the change
  clock.advance_ms(5);
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  CaptureHeader header;
  session.fill_header("settled", &header);
  EXPECT_TRUE(header.has_time_to_settle);
  EXPECT_DOUBLE_EQ(10.0, header.time_to_settle_ms);
  EXPECT_EQ(10, header.settle_ms);
  // Settled once per generation: nothing more to do, no deadline.
  step = session.poll();
  EXPECT_EQ(Session::Action::kNone, step.action);
  EXPECT_FALSE(step.has_deadline);
  session.leave_wait(token);
}

TEST_F(SessionTest, no_settle_without_a_waiter_only_a_running_snapshot)
{
  session.start();
  session.on_change();
  clock.advance_ms(19);
  Session::Step step = session.poll();
  EXPECT_EQ(Session::Action::kNone, step.action);
  EXPECT_EQ(clock.now + 1 * kMs, step.deadline_ns);
  clock.advance_ms(1);
  EXPECT_EQ(Session::Action::kWriteRunning, session.poll().action);
  clock.advance_ms(10000);
  step = session.poll();
  EXPECT_EQ(Session::Action::kNone, step.action);
  EXPECT_FALSE(step.has_deadline);
  CaptureHeader header;
  session.fill_header("settled", &header);
  EXPECT_FALSE(header.has_time_to_settle);
  EXPECT_DOUBLE_EQ(10020.0, header.elapsed_ms);
}

TEST_F(SessionTest, a_waiter_from_before_the_last_change_does_not_count)
{
  session.start();
  const uint64_t old = session.enter_wait();
  clock.advance_ms(1);
  session.on_change();  // the old waiter no longer counts
  clock.advance_ms(50);
  EXPECT_EQ(Session::Action::kWriteRunning, session.poll().action);
  EXPECT_EQ(Session::Action::kNone, session.poll().action);
  session.leave_wait(old);  // a stale token changes nothing
  const uint64_t fresh = session.enter_wait();
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  session.leave_wait(fresh);
}

TEST_F(SessionTest, resettles_after_a_later_change)
{
  session.start();
  session.enter_wait();
  clock.advance_ms(10);
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  clock.advance_ms(500);
  session.on_change();
  session.enter_wait();
  clock.advance_ms(10);
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  CaptureHeader header;
  session.fill_header("settled", &header);
  EXPECT_DOUBLE_EQ(520.0, header.time_to_settle_ms);
}

TEST_F(SessionTest, exiting_stops_everything)
{
  session.start();
  session.on_change();
  session.begin_exit();
  EXPECT_TRUE(session.exiting());
  clock.advance_ms(100);
  session.enter_wait();
  EXPECT_EQ(Session::Action::kNone, session.poll().action);
}

TEST_F(SessionTest, settles_by_activity_without_any_wait)
{
  session.start();
  session.on_change();
  EXPECT_FALSE(session.on_activity());
  clock.advance_ms(50);
  // One call is not a loop yet: a progress snapshot only.
  EXPECT_EQ(Session::Action::kWriteRunning, session.poll().action);
  EXPECT_EQ(Session::Action::kNone, session.poll().action);
  EXPECT_TRUE(session.on_activity());  // the second: the monitor looks again
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  CaptureHeader header;
  session.fill_header("settled", &header);
  EXPECT_EQ("activity", header.settled_by);
  EXPECT_FALSE(header.ever_waited);
  EXPECT_EQ(2u, header.activity_calls);
}

TEST_F(SessionTest, activity_before_the_last_change_does_not_count)
{
  session.start();
  session.on_activity();
  session.on_activity();
  clock.advance_ms(1);
  session.on_change();
  session.on_activity();
  clock.advance_ms(50);
  EXPECT_EQ(Session::Action::kWriteRunning, session.poll().action);
  EXPECT_EQ(Session::Action::kNone, session.poll().action);
}

TEST_F(SessionTest, settled_by_wait_is_reported)
{
  session.start();
  session.on_wait_entered();
  session.enter_wait();
  clock.advance_ms(10);
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  CaptureHeader header;
  session.fill_header("settled", &header);
  EXPECT_EQ("wait", header.settled_by);
  EXPECT_TRUE(header.ever_waited);
  EXPECT_FALSE(header.has_ended);
  EXPECT_EQ(0, header.horizon_ms);
  EXPECT_EQ(0u, header.jumps);
}

TEST_F(SessionTest, no_warp_with_horizon_0)
{
  session.start();
  session.enter_wait();
  clock.advance_ms(10);
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  EXPECT_FALSE(session.warping());
  EXPECT_FALSE(session.try_jump(session.virtual_now_ns() + 1000 * kMs));
  EXPECT_EQ(0, virtual_clock.offset_ns());
}

// ------------------------------------------------------------------ polling loops

TEST_F(SessionTest, a_loop_of_polls_settles_like_one_of_activity)
{
  session.start();
  session.on_change();
  session.on_poll();
  EXPECT_TRUE(session.on_poll());  // the second one: the monitor looks again
  clock.advance_ms(10);
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  CaptureHeader header;
  session.fill_header("settled", &header);
  EXPECT_EQ("poll", header.settled_by);
  EXPECT_EQ(2u, header.polls);
  EXPECT_TRUE(header.ever_waited);
}
