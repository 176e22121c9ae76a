// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// The warp (detail/warp.hpp) through the Session that composes it, on a manual clock: jumps,
// horizon, budget, fast-forward, stall, the final settle.

#include <gtest/gtest.h>

#include <cstdint>

#include "detail/session.hpp"
#include "detail/warp.hpp"
#include "session_fixture.hpp"

using namespace session_test;  // NOLINT(build/namespaces): the fixture's names

class WarpTest : public ::testing::Test
{
protected:
  // Settle once (by wait) and enter the warp.
  void settle_and_start_warp()
  {
    session.start();
    session.on_change();
    token = session.enter_wait();
    clock.advance_ms(10);
    ASSERT_EQ(Session::Action::kStartWarp, session.poll().action);
    ASSERT_TRUE(session.warping());
    EXPECT_STREQ("warping", session.progress_state());
  }
  // A wait with `timeout_ms` entered now.
  bool wait_ms(int64_t timeout_ms)
  {
    return session.try_jump(session.virtual_now_ns() + timeout_ms * kMs);
  }

  ManualClock clock;
  rmw_introspect::VirtualClock virtual_clock;
  Session session{clock, virtual_clock, settings(10000, 3000)};
  uint64_t token = 0;
};

TEST_F(WarpTest, first_settle_starts_the_warp_and_needs_a_new_quiet_period)
{
  settle_and_start_warp();
  // The waiter of the first settle does not end the warp: the warp start breaks the quiet.
  clock.advance_ms(100);
  EXPECT_EQ(Session::Action::kNone, session.poll().action);
  session.leave_wait(token);  // stale
  session.enter_wait();
  const Session::Step step = session.poll();
  EXPECT_EQ(Session::Action::kSettle, step.action);  // quiet since the warp start
  EXPECT_FALSE(session.warping());
  EXPECT_STREQ("running", session.progress_state());
}

TEST_F(WarpTest, jumps_are_counted_and_move_both_clocks)
{
  settle_and_start_warp();
  const int64_t before = session.virtual_now_ns();
  EXPECT_TRUE(wait_ms(3000));
  EXPECT_EQ(3000 * kMs, virtual_clock.offset_ns());
  EXPECT_EQ(before + 3000 * kMs, session.virtual_now_ns());
  EXPECT_TRUE(wait_ms(500));
  CaptureHeader header;
  session.fill_header("warping", &header);
  EXPECT_EQ(2u, header.jumps);
  EXPECT_DOUBLE_EQ(3500.0, header.warp_ms);
  EXPECT_DOUBLE_EQ(3510.0, header.virtual_elapsed_ms);  // 10 ms real + 3.5 s jumped
  EXPECT_DOUBLE_EQ(10.0, header.real_elapsed_ms);
  EXPECT_EQ(10000, header.horizon_ms);
  EXPECT_DOUBLE_EQ(3510.0, session.virtual_age_ms());
  EXPECT_DOUBLE_EQ(10.0, session.real_age_ms());
}

TEST_F(WarpTest, a_target_already_passed_returns_without_a_jump)
{
  settle_and_start_warp();
  // Two threads entered their waits at the same virtual time: 1 s and 2 s timeouts.
  const int64_t entry = session.virtual_now_ns();
  EXPECT_TRUE(session.try_jump(entry + 2000 * kMs));
  EXPECT_TRUE(session.try_jump(entry + 1000 * kMs));  // already past: no second jump
  EXPECT_EQ(2000 * kMs, virtual_clock.offset_ns());
  CaptureHeader header;
  session.fill_header("warping", &header);
  EXPECT_EQ(1u, header.jumps);
  // Still driven by timers: not quiet, the warp goes on.
  session.enter_wait();
  clock.advance_ms(5);
  EXPECT_TRUE(session.try_jump(session.virtual_now_ns() - kMs));
  clock.advance_ms(9);
  EXPECT_EQ(Session::Action::kNone, session.poll().action);
  EXPECT_TRUE(session.warping());
}

TEST_F(WarpTest, polls_in_the_warp_are_not_quiet)
{
  settle_and_start_warp();
  // Timers kept due by real time alone: polls and callbacks that publish, no jump.
  for (int i = 0; i < 20; ++i) {
    session.on_wait_entered();
    session.on_activity();
    session.on_activity();
    clock.advance_ms(5);
    EXPECT_EQ(Session::Action::kNone, session.poll().action) << i;
  }
  EXPECT_TRUE(session.warping());
  // An old-school loop (no wait at all) does settle by activity in the warp.
  clock.advance_ms(10);
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
}

TEST_F(WarpTest, horizon_clamps_the_warp)
{
  settle_and_start_warp();
  for (int i = 0; i < 9; ++i) {
    EXPECT_TRUE(wait_ms(1000)) << i;
  }
  // Virtual age 9.01 s: one more second would pass the 10 s horizon: no jump, warp over.
  EXPECT_FALSE(wait_ms(1000));
  EXPECT_FALSE(session.warping());
  EXPECT_FALSE(wait_ms(1));  // over for good
  CaptureHeader header;
  session.fill_header("warping", &header);
  EXPECT_TRUE(header.horizon_reached);
  EXPECT_FALSE(header.warp_budget_exhausted);
  EXPECT_EQ(9u, header.jumps);
  EXPECT_LE(header.virtual_elapsed_ms, 10000.0);
  // Final settle: a thread blocked after the last jump, settle_ms of quiet.
  session.enter_wait();
  EXPECT_EQ(Session::Action::kNone, session.poll().action);
  clock.advance_ms(10);
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
}

TEST_F(WarpTest, a_1khz_timer_is_stepped_through_100_ticks_then_fast_forwarded_to_the_10s_horizon)
{
  settle_and_start_warp();
  int jumps = 0;
  while (wait_ms(1)) {
    ++jumps;
    clock.now += 100 * 1000;  // 100 us of real time per timer callback
  }
  EXPECT_TRUE(session.fast_forwarded());
  EXPECT_GE(jumps, 100);  // not 10 000: the steady timer is fast-forwarded
  EXPECT_LE(jumps, 110);
  CaptureHeader header;
  session.fill_header("warping", &header);
  EXPECT_TRUE(header.horizon_reached);
  EXPECT_EQ(static_cast<uint64_t>(jumps), header.jumps);
}

TEST_F(WarpTest, budget_stops_the_warp)
{
  settle_and_start_warp();
  EXPECT_TRUE(wait_ms(1));
  clock.advance_ms(3000);  // the warp's real-time budget is spent
  EXPECT_FALSE(wait_ms(1));
  EXPECT_FALSE(session.warping());
  CaptureHeader header;
  session.fill_header("warping", &header);
  EXPECT_TRUE(header.warp_budget_exhausted);
  EXPECT_FALSE(header.horizon_reached);
}

TEST_F(WarpTest, budget_deadline_ends_a_warp_without_jumps)
{
  settle_and_start_warp();
  const Session::Step step = session.poll();
  ASSERT_TRUE(step.has_deadline);
  EXPECT_EQ(clock.now + 3000 * kMs, step.deadline_ns);
  clock.advance_ms(3000);
  EXPECT_EQ(Session::Action::kNone, session.poll().action);
  EXPECT_FALSE(session.warping());
}

TEST_F(WarpTest, a_jump_breaks_the_quiet_and_creations_in_the_warp_are_snapshots)
{
  settle_and_start_warp();
  EXPECT_TRUE(wait_ms(3000));
  session.on_change();  // the timer created a publisher
  session.enter_wait();
  clock.advance_ms(5);
  EXPECT_EQ(Session::Action::kNone, session.poll().action);
  clock.advance_ms(5);
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);  // final
  CaptureHeader header;
  session.fill_header("settled", &header);
  EXPECT_FALSE(header.horizon_reached);
  EXPECT_EQ(1u, header.jumps);
  EXPECT_DOUBLE_EQ(20.0, header.time_to_settle_ms);
}

TEST_F(WarpTest, progress_snapshots_in_the_warp_say_warping)
{
  settle_and_start_warp();
  session.on_change();
  clock.advance_ms(20);
  EXPECT_EQ(Session::Action::kWriteRunning, session.poll().action);
  EXPECT_STREQ("warping", session.progress_state());
}

TEST_F(WarpTest, ended_says_whether_the_final_settle_came)
{
  settle_and_start_warp();
  CaptureHeader header;
  session.fill_header("exit", &header);
  EXPECT_TRUE(header.has_ended);
  EXPECT_TRUE(header.ended_before_settle);  // exited during the warp
  session.fill_header("warping", &header);
  EXPECT_FALSE(header.has_ended);
  session.enter_wait();
  clock.advance_ms(10);
  ASSERT_EQ(Session::Action::kSettle, session.poll().action);
  session.fill_header("shutdown", &header);
  EXPECT_TRUE(header.has_ended);
  EXPECT_FALSE(header.ended_before_settle);
}

TEST(SessionHorizon, settling_past_the_horizon_skips_the_warp)
{
  ManualClock clock;
  rmw_introspect::VirtualClock virtual_clock;
  Session session{clock, virtual_clock, settings(100, 3000)};
  session.start();
  clock.advance_ms(200);
  session.enter_wait();
  clock.advance_ms(10);
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  CaptureHeader header;
  session.fill_header("settled", &header);
  EXPECT_TRUE(header.horizon_reached);
  EXPECT_EQ(0u, header.jumps);
}

TEST_F(WarpTest, a_warp_that_sees_only_polls_stalls_and_says_so)
{
  settle_and_start_warp();
  session.leave_wait(token);  // the executor only polls from now on
  for (int i = 0; i < 4; ++i) {
    session.on_poll();
    clock.advance_ms(2);
    EXPECT_EQ(Session::Action::kNone, session.poll().action) << i;
  }
  EXPECT_TRUE(session.warping());
  clock.advance_ms(2);  // settle_ms (10) without a wait with a timeout
  session.on_poll();
  // stalled before any jump with nothing changed since the first settle: that settle holds
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  EXPECT_FALSE(session.warping());
  CaptureHeader header;
  session.fill_header("settled", &header);
  EXPECT_TRUE(header.warp_stalled);
  EXPECT_FALSE(header.warp_budget_exhausted);
  EXPECT_FALSE(header.horizon_reached);
  EXPECT_EQ("wait", header.settled_by);  // the first settle's
  // what the warp saw, for the note that says which loop it was
  EXPECT_EQ(5u, header.warp_polls);
  EXPECT_EQ(0u, header.warp_activity);
  EXPECT_DOUBLE_EQ(10.0, header.warp_real_ms);
}

TEST_F(WarpTest, a_stalled_warp_in_which_an_entity_changed_settles_again)
{
  settle_and_start_warp();
  session.leave_wait(token);
  session.on_change();  // created in the warp (real time: a sleep loop that goes on)
  for (int i = 0; i < 5; ++i) {
    session.on_poll();
    session.on_activity();
    clock.advance_ms(3);
    session.poll();
  }
  EXPECT_FALSE(session.warping());  // stalled
  EXPECT_NE(Session::Action::kSettle, session.poll().action);  // a final settle of its own
  session.on_poll();
  session.on_poll();
  clock.advance_ms(10);
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  CaptureHeader header;
  session.fill_header("settled", &header);
  EXPECT_TRUE(header.warp_stalled);
  EXPECT_EQ("poll", header.settled_by);
  EXPECT_LT(0u, header.warp_activity);  // those before the stall
}

TEST_F(WarpTest, a_warp_with_jumps_stalls_only_after_half_a_second_of_polls)
{
  settle_and_start_warp();
  session.leave_wait(token);
  EXPECT_TRUE(wait_ms(1));  // a timer: one jump
  for (int i = 0; i < 40; ++i) {  // 400 ms of polls: a timer due in real time, rcl catching up
    session.on_poll();
    session.on_activity();
    clock.advance_ms(10);
    session.poll();
    ASSERT_TRUE(session.warping()) << i;
  }
  clock.advance_ms(100);
  session.on_poll();
  session.poll();
  EXPECT_FALSE(session.warping());
}

TEST_F(WarpTest, a_steady_periodic_timer_that_creates_nothing_is_fast_forwarded_to_the_horizon)
{
  settle_and_start_warp();
  // A 1 ms timer: each wait's deadline 1 ms after the previous one, give or take the real time
  // the process ran before it waited (up to 0.4 ms here).
  const int64_t start = session.virtual_now_ns();
  // 100 equal steps after the first two deadlines
  for (int i = 1; i <= 101; ++i) {
    EXPECT_TRUE(session.try_jump(start + i * kMs + (i % 3) * 200 * 1000));
    EXPECT_FALSE(session.fast_forwarded()) << i;
  }
  EXPECT_TRUE(session.try_jump(start + 102 * kMs));
  EXPECT_TRUE(session.fast_forwarded());
  EXPECT_DOUBLE_EQ(10000.0, session.virtual_age_ms());  // at the horizon
  EXPECT_FALSE(session.try_jump(session.virtual_now_ns() + kMs));  // past it: the warp ends
  EXPECT_FALSE(session.warping());
}

TEST_F(WarpTest, a_timer_that_creates_something_or_uneven_deadlines_are_stepped_through)
{
  settle_and_start_warp();
  int64_t target = session.virtual_now_ns();
  for (int i = 1; i <= 300; ++i) {
    target += (i % 2 == 0 ? 1 : 3) * kMs;  // two timers: uneven steps
    EXPECT_TRUE(session.try_jump(target));
  }
  EXPECT_FALSE(session.fast_forwarded());
  for (int i = 1; i <= 300; ++i) {
    target += kMs;
    if (i % 50 == 0) {
      session.on_change();  // the callback created something
    }
    EXPECT_TRUE(session.try_jump(target));
  }
  EXPECT_FALSE(session.fast_forwarded());
  EXPECT_TRUE(session.warping());
}

TEST_F(WarpTest, a_few_late_waits_of_a_preempted_process_do_not_stop_the_fast_forward)
{
  settle_and_start_warp();
  const int64_t start = session.virtual_now_ns();
  int64_t late = 0;
  for (int i = 1; i <= 300 && !session.fast_forwarded(); ++i) {
    late = (i % 20 == 0) ? 6 * kMs : 0;  // every 20th wait entered 6 ms late
    EXPECT_TRUE(session.try_jump(start + i * kMs + late));
  }
  EXPECT_TRUE(session.fast_forwarded());
}

// ------------------------------------------------------------------ the Warp on its own

TEST(Warp, jumps_move_the_virtual_clock_up_to_the_horizon)
{
  rmw_introspect::VirtualClock virtual_clock;
  rmw_introspect::Warp warp(virtual_clock, {10, 1000, 3000});
  warp.set_origin(0);
  ASSERT_TRUE(warp.begin(0));
  EXPECT_EQ(rmw_introspect::Warp::Jump::kJumped, warp.jump(0, 100 * kMs));
  EXPECT_EQ(100 * kMs, virtual_clock.offset_ns());
  EXPECT_EQ(rmw_introspect::Warp::Jump::kPassed, warp.jump(0, 50 * kMs));
  EXPECT_EQ(rmw_introspect::Warp::Jump::kEnded, warp.jump(0, 1001 * kMs));
  EXPECT_EQ(100 * kMs, virtual_clock.offset_ns());
  CaptureHeader header;
  warp.fill_header(0, &header);
  EXPECT_EQ(1u, header.jumps);
  EXPECT_DOUBLE_EQ(100.0, header.warp_ms);
  EXPECT_TRUE(header.horizon_reached);
  EXPECT_FALSE(header.warp_budget_exhausted);
}

TEST(Warp, does_not_begin_past_the_horizon)
{
  rmw_introspect::VirtualClock virtual_clock;
  rmw_introspect::Warp warp(virtual_clock, {10, 1000, 3000});
  warp.set_origin(0);
  EXPECT_FALSE(warp.begin(1000 * kMs));
  CaptureHeader header;
  warp.fill_header(1000 * kMs, &header);
  EXPECT_TRUE(header.horizon_reached);
  EXPECT_DOUBLE_EQ(0.0, header.warp_real_ms);
}

TEST(Warp, check_ends_it_at_the_budget_and_stalls_a_loop_that_never_waits_with_a_timeout)
{
  rmw_introspect::VirtualClock virtual_clock;
  const auto never = []() { return false; };
  rmw_introspect::Warp spent(virtual_clock, {10, 10000, 3000});
  spent.set_origin(0);
  ASSERT_TRUE(spent.begin(kMs));
  int64_t look_at = INT64_MAX;
  EXPECT_FALSE(spent.check(2 * kMs, true, never, &look_at));
  EXPECT_EQ(3001 * kMs, look_at);  // the budget's end (the horizon is later)
  EXPECT_TRUE(spent.check(3001 * kMs, true, never, &look_at));
  CaptureHeader header;
  spent.fill_header(3001 * kMs, &header);
  EXPECT_TRUE(header.warp_budget_exhausted);
  EXPECT_FALSE(header.warp_stalled);

  rmw_introspect::Warp looping(virtual_clock, {10, 10000, 3000});
  looping.set_origin(0);
  ASSERT_TRUE(looping.begin(kMs));
  looping.on_poll();
  looping.on_activity();
  look_at = INT64_MAX;
  EXPECT_FALSE(looping.check(5 * kMs, false, never, &look_at));
  EXPECT_EQ(15 * kMs, look_at);  // a window later
  EXPECT_TRUE(looping.check(11 * kMs, false, never, &look_at));  // settle_ms without a timed wait
  EXPECT_TRUE(looping.stalled());
  looping.fill_header(11 * kMs, &header);
  EXPECT_EQ(1u, header.warp_polls);
  EXPECT_EQ(1u, header.warp_activity);
  EXPECT_DOUBLE_EQ(10.0, header.warp_real_ms);
}
