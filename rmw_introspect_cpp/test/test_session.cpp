// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// The Session state machine on a manual clock and an injected main-thread state: settling (by
// wait, by activity), probing, progress snapshots, the warp (jumps, horizon, budget), the final
// settle, exit. Only the two tests of the real /proc main-thread state use a thread and a sleep.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "detail/session.hpp"
#include "detail/thread_census.hpp"

using rmw_introspect::CaptureHeader;
using rmw_introspect::Session;

namespace
{

constexpr int64_t kMs = 1000 * 1000;

class ManualClock : public rmw_introspect::Clock
{
public:
  int64_t now_ns() const override {return now;}
  void advance_ms(int64_t ms) {now += ms * kMs;}
  int64_t now = 1000 * kMs;
};

Session::Settings settings(int64_t horizon_ms = 0, int64_t budget_ms = 3000)
{
  Session::Settings s;
  s.settle_ms = 10;
  s.horizon_ms = horizon_ms;
  s.warp_budget_ms = budget_ms;
  return s;
}

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

// ------------------------------------------------------------------ probing (issue 10)
namespace
{
Session::Settings probe_settings(int64_t horizon_ms = 0)
{
  Session::Settings s = settings(horizon_ms);
  s.probe = true;
  s.answer_timeout_ms = 5000;
  return s;
}

class ProbeTest : public ::testing::Test
{
protected:
  // Settle once with a thread blocked in rmw_wait: the probing starts.
  void settle_into_probing()
  {
    session.start();
    session.on_change();
    session.on_wait_entered();
    token = session.enter_wait();
    clock.advance_ms(10);
    ASSERT_EQ(Session::Action::kStartProbe, session.poll().action);
    EXPECT_TRUE(session.probing());
    EXPECT_STREQ("probing", session.progress_state());
    EXPECT_STREQ("running", session.probe_state());
  }

  // The answering thread goes back to rmw_wait.
  void back_to_wait()
  {
    session.leave_wait(token);
    token = session.enter_wait();
  }

  ManualClock clock;
  rmw_introspect::VirtualClock virtual_clock;
  Session session{clock, virtual_clock, probe_settings()};
  uint64_t token = 0;
};
}  // namespace

TEST_F(ProbeTest, queries_follow_each_other_and_need_no_second_settle)
{
  settle_into_probing();
  EXPECT_EQ(Session::Action::kProbe, session.poll().action);
  session.probe_sent();
  Session::Step step = session.poll();
  EXPECT_EQ(Session::Action::kNone, step.action);
  ASSERT_TRUE(step.has_deadline);
  EXPECT_EQ(clock.now + 5000 * kMs, step.deadline_ns);  // the answer timeout
  clock.advance_ms(1);
  session.probe_answered(false);  // a query: the next request goes at once
  EXPECT_EQ(Session::Action::kProbe, session.poll().action);
  session.probe_sent();
  session.probe_answered(false);
  EXPECT_EQ(Session::Action::kProbe, session.poll().action);
  session.probe_done();
  // Reads run none of the node's code and nothing was created: the settle that started the
  // probing holds, the capture is settled at once.
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  EXPECT_FALSE(session.probing());
  EXPECT_STREQ("done", session.probe_state());
  CaptureHeader header;
  session.fill_header("settled", &header);
  EXPECT_DOUBLE_EQ(11.0, header.time_to_settle_ms);
  EXPECT_FALSE(header.ended_before_settle);
  session.leave_wait(token);
}

TEST_F(ProbeTest, an_entity_created_while_reading_needs_a_settle_at_the_end)
{
  settle_into_probing();
  EXPECT_EQ(Session::Action::kProbe, session.poll().action);
  session.probe_sent();
  clock.advance_ms(1);
  session.on_change();  // another thread of the node creates a publisher meanwhile
  session.probe_answered(false);
  EXPECT_EQ(Session::Action::kProbe, session.poll().action);
  session.probe_done();
  EXPECT_EQ(Session::Action::kNone, session.poll().action);
  back_to_wait();
  const Session::Step step = session.poll();
  EXPECT_EQ(Session::Action::kNone, step.action);
  EXPECT_EQ(clock.now + 10 * kMs, step.deadline_ns);
  clock.advance_ms(10);
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  CaptureHeader header;
  session.fill_header("settled", &header);
  EXPECT_DOUBLE_EQ(21.0, header.time_to_settle_ms);
  session.leave_wait(token);
}

TEST_F(ProbeTest, a_transition_is_followed_by_a_settle_with_its_new_entities)
{
  settle_into_probing();
  EXPECT_EQ(Session::Action::kProbe, session.poll().action);
  session.probe_sent();
  clock.advance_ms(2);
  session.on_change();  // on_configure creates a publisher
  session.probe_answered(true);
  EXPECT_EQ(Session::Action::kNone, session.poll().action);
  back_to_wait();
  clock.advance_ms(9);
  EXPECT_EQ(Session::Action::kNone, session.poll().action);
  clock.advance_ms(1);
  EXPECT_EQ(Session::Action::kProbe, session.poll().action);
  session.probe_done();
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);  // still quiet
  session.leave_wait(token);
}

TEST_F(ProbeTest, the_end_after_a_transition_waits_for_a_settle)
{
  settle_into_probing();
  EXPECT_EQ(Session::Action::kProbe, session.poll().action);
  session.probe_sent();
  session.probe_answered(true);  // on_activate ran the node's code
  back_to_wait();
  clock.advance_ms(10);
  EXPECT_EQ(Session::Action::kProbe, session.poll().action);
  session.probe_sent();
  session.probe_answered(false);  // parameters read again after driving
  EXPECT_EQ(Session::Action::kProbe, session.poll().action);
  session.probe_done();
  EXPECT_EQ(Session::Action::kNone, session.poll().action);
  back_to_wait();
  clock.advance_ms(10);
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  session.leave_wait(token);
}

TEST_F(ProbeTest, no_answer_in_time)
{
  settle_into_probing();
  EXPECT_EQ(Session::Action::kProbe, session.poll().action);
  session.probe_sent();
  clock.advance_ms(4999);
  EXPECT_EQ(Session::Action::kNone, session.poll().action);
  clock.advance_ms(1);
  EXPECT_EQ(Session::Action::kProbeTimeout, session.poll().action);
  // A late answer changes nothing; the next request waits for a settle.
  session.probe_answered(false);
  EXPECT_EQ(Session::Action::kNone, session.poll().action);
  back_to_wait();
  clock.advance_ms(10);
  EXPECT_EQ(Session::Action::kProbe, session.poll().action);
  session.probe_done();
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  session.leave_wait(token);
}

TEST_F(ProbeTest, progress_snapshots_while_probing_say_probing_and_exit_is_before_settle)
{
  settle_into_probing();
  EXPECT_EQ(Session::Action::kProbe, session.poll().action);
  session.probe_sent();
  session.on_change();
  clock.advance_ms(20);
  EXPECT_EQ(Session::Action::kWriteRunning, session.poll().action);
  EXPECT_STREQ("probing", session.progress_state());
  session.begin_exit();
  CaptureHeader header;
  session.fill_header("exit", &header);
  EXPECT_TRUE(header.has_ended);
  EXPECT_TRUE(header.ended_before_settle);
  EXPECT_TRUE(header.has_time_to_settle);  // settled once
  session.leave_wait(token);
}

namespace
{
class ManualMainThread : public rmw_introspect::MainThreadState
{
public:
  bool runnable() const override {return running;}
  bool running = false;
};

// A process that settles by activity (two publishes after its last creation) before any
// thread waited: the probing starts, waiting for a first wait.
void settle_by_activity_into_probing(Session & session, ManualClock & clock)
{
  session.start();
  session.on_change();
  session.on_activity();
  session.on_activity();
  clock.advance_ms(10);
  ASSERT_EQ(Session::Action::kStartProbe, session.poll().action);
}

// The process reaches its executor: it is asked at once, then settles with the probing done.
void expect_probed_once_it_waits(Session & session)
{
  session.on_wait_entered();
  const uint64_t token = session.enter_wait();
  EXPECT_EQ(Session::Action::kProbe, session.poll().action);
  session.probe_done();
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  EXPECT_STREQ("done", session.probe_state());
  session.leave_wait(token);
}
}  // namespace

TEST(SessionProbe, a_process_that_never_waited_is_not_probed)
{
  ManualClock clock;
  rmw_introspect::VirtualClock virtual_clock;
  Session session{clock, virtual_clock, probe_settings()};
  EXPECT_STREQ("pending", session.probe_state());
  ASSERT_NO_FATAL_FAILURE(settle_by_activity_into_probing(session, clock));
  Session::Step step = session.poll();
  EXPECT_EQ(Session::Action::kNone, step.action);
  EXPECT_EQ(clock.now + 250 * kMs, step.deadline_ns);  // time to start waiting
  session.on_activity();
  session.on_activity();
  clock.advance_ms(250);
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  EXPECT_STREQ("skipped", session.probe_state());
}

TEST(SessionProbe, a_runnable_main_thread_gets_more_time_to_start_waiting_up_to_2_s)
{
  ManualClock clock;
  rmw_introspect::VirtualClock virtual_clock;
  ManualMainThread main_thread;
  Session session{clock, virtual_clock, probe_settings(), &main_thread};
  ASSERT_NO_FATAL_FAILURE(settle_by_activity_into_probing(session, clock));
  main_thread.running = true;  // still importing and setting up, or waiting for a CPU
  clock.advance_ms(250);
  Session::Step step = session.poll();
  EXPECT_EQ(Session::Action::kNone, step.action);
  EXPECT_EQ(clock.now + 50 * kMs, step.deadline_ns);  // looked at again in 50 ms
  clock.advance_ms(50);
  EXPECT_EQ(Session::Action::kNone, session.poll().action);
  // it reaches its executor: probed as usual
  expect_probed_once_it_waits(session);
}

TEST(SessionProbe, a_main_thread_that_runs_without_ever_waiting_is_given_up_after_2_s)
{
  ManualClock clock;
  rmw_introspect::VirtualClock virtual_clock;
  ManualMainThread main_thread;
  main_thread.running = true;  // a loop that publishes without sleeping or spinning
  Session session{clock, virtual_clock, probe_settings(), &main_thread};
  ASSERT_NO_FATAL_FAILURE(settle_by_activity_into_probing(session, clock));
  const int64_t probing_since = clock.now;
  Session::Step step = session.poll();
  while (step.action == Session::Action::kNone && step.has_deadline) {
    ASSERT_LE(step.deadline_ns, probing_since + 2000 * kMs);
    clock.now = step.deadline_ns;
    session.on_activity();
    session.on_activity();
    step = session.poll();
  }
  EXPECT_EQ(Session::Action::kSettle, step.action);
  EXPECT_EQ(probing_since + 2000 * kMs, clock.now);
  EXPECT_STREQ("skipped", session.probe_state());
}

TEST(SessionProbe, a_sleeping_main_thread_is_given_up_after_250_ms)
{
  ManualClock clock;
  rmw_introspect::VirtualClock virtual_clock;
  ManualMainThread main_thread;  // sleeps between its publishes (an old-school loop)
  Session session{clock, virtual_clock, probe_settings(), &main_thread};
  ASSERT_NO_FATAL_FAILURE(settle_by_activity_into_probing(session, clock));
  clock.advance_ms(250);
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  EXPECT_STREQ("skipped", session.probe_state());
}

TEST(SessionProbe, the_proc_main_thread_state_of_a_running_test_is_runnable)
{
  // this test's own main thread is running while it asks
  EXPECT_TRUE(rmw_introspect::ProcMainThreadState().runnable());
}

TEST(SessionProbe, the_proc_main_thread_state_of_a_blocked_main_thread_is_not_runnable)
{
  bool runnable = true;
  std::thread asker([&runnable]() {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      runnable = rmw_introspect::ProcMainThreadState().runnable();
    });
  asker.join();  // the main thread is blocked in here while the other thread asks
  EXPECT_FALSE(runnable);
}

TEST(SessionProbe, an_executor_that_starts_waiting_after_an_activity_settle_is_probed)
{
  ManualClock clock;
  rmw_introspect::VirtualClock virtual_clock;
  Session session{clock, virtual_clock, probe_settings()};
  ASSERT_NO_FATAL_FAILURE(settle_by_activity_into_probing(session, clock));
  clock.advance_ms(5);
  // Quiet since the last change and a thread waiting: the settle rule holds, ask now.
  expect_probed_once_it_waits(session);
}

TEST(SessionProbe, off_without_the_setting)
{
  ManualClock clock;
  rmw_introspect::VirtualClock virtual_clock;
  Session session{clock, virtual_clock, settings()};
  EXPECT_STREQ("off", session.probe_state());
  session.start();
  session.on_wait_entered();
  const uint64_t token = session.enter_wait();
  clock.advance_ms(10);
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);
  EXPECT_STREQ("off", session.probe_state());
  session.leave_wait(token);
}

TEST(SessionProbe, the_warp_comes_after_the_probing)
{
  ManualClock clock;
  rmw_introspect::VirtualClock virtual_clock;
  Session session{clock, virtual_clock, probe_settings(10000)};
  session.start();
  session.on_wait_entered();
  uint64_t token = session.enter_wait();
  clock.advance_ms(10);
  ASSERT_EQ(Session::Action::kStartProbe, session.poll().action);
  EXPECT_FALSE(session.try_jump(session.virtual_now_ns() + 1000 * kMs));  // no warp yet
  ASSERT_EQ(Session::Action::kProbe, session.poll().action);
  session.probe_done();
  ASSERT_EQ(Session::Action::kStartWarp, session.poll().action);
  EXPECT_TRUE(session.warping());
  EXPECT_STREQ("warping", session.progress_state());
  EXPECT_STREQ("done", session.probe_state());
  EXPECT_TRUE(session.try_jump(session.virtual_now_ns() + 1000 * kMs));
  session.leave_wait(token);
}

// ------------------------------------------------------------------ detected quiescence

namespace
{

class FakeCensus : public rmw_introspect::ThreadCensus
{
public:
  bool others_blocked(
    const std::vector<pid_t> & known, int64_t until_ns, std::string * culprit) const override
  {
    ++calls;
    last_known = known;
    last_until = until_ns;
    if (!blocked && culprit != nullptr) {
      *culprit = "thread 7 is not blocked (clock_nanosleep)";
    }
    return blocked;
  }
  bool blocked = true;
  mutable int calls = 0;
  mutable std::vector<pid_t> last_known;
  mutable int64_t last_until = 0;
};

Session::Settings idle_settings(int settle_ms = 100, int64_t horizon_ms = 0)
{
  Session::Settings s = settings(horizon_ms);
  s.settle_ms = settle_ms;
  s.detect_idle = true;
  return s;
}

class IdleTest : public ::testing::Test
{
protected:
  // poll(), answering its census requests and writing progress snapshots as the monitor does.
  Session::Step poll(Session & session)
  {
    for (;;) {
      const Session::Step step = session.poll();
      if (step.action == Session::Action::kWriteRunning) {
        continue;
      }
      if (step.action != Session::Action::kCheckIdle) {
        return step;
      }
      const Session::CensusRequest request = session.census_request();
      std::string culprit;
      const bool idle = census.others_blocked(request.known, request.until_ns, &culprit);
      session.census_done(request.version, idle, culprit);
    }
  }
  ManualClock clock;
  rmw_introspect::VirtualClock virtual_clock;
  FakeCensus census;
};

}  // namespace

TEST_F(IdleTest, a_blocked_wait_with_every_other_thread_blocked_settles_at_once)
{
  Session session{clock, virtual_clock, idle_settings()};
  session.start();
  session.set_monitor_tid(99);
  session.on_change();
  session.enter_wait(42, -1);
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);  // no quiet window waited for
  EXPECT_EQ((std::vector<pid_t>{99, 42}), census.last_known);
  EXPECT_EQ(clock.now + 100 * kMs, census.last_until);  // where the quiet window would end
  CaptureHeader header;
  session.fill_header("settled", &header);
  EXPECT_EQ("wait", header.settled_by);
  EXPECT_TRUE(header.idle_detect);
  EXPECT_EQ(1u, header.idle_settles);
  EXPECT_EQ(0u, header.window_settles);
  EXPECT_DOUBLE_EQ(0.0, header.time_to_settle_ms);
}

TEST_F(IdleTest, another_thread_not_blocked_falls_back_to_the_quiet_window)
{
  census.blocked = false;  // say, a time.sleep loop
  Session session{clock, virtual_clock, idle_settings()};
  session.start();
  session.on_change();
  session.enter_wait(42, -1);
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  EXPECT_EQ(1, census.calls);
  EXPECT_EQ("thread 7 is not blocked (clock_nanosleep)", session.not_idle_reason());
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  EXPECT_EQ(1, census.calls);  // nothing changed: not asked again at once ...
  clock.advance_ms(5);
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  EXPECT_EQ(2, census.calls);  // ... but a little later
  clock.advance_ms(94);
  EXPECT_NE(Session::Action::kSettle, poll(session).action);
  clock.advance_ms(1);
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);
  CaptureHeader header;
  session.fill_header("settled", &header);
  EXPECT_EQ(0u, header.idle_settles);
  EXPECT_EQ(1u, header.window_settles);
}

TEST_F(IdleTest, an_answer_for_an_older_state_is_dropped)
{
  Session session{clock, virtual_clock, idle_settings()};
  session.start();
  session.on_change();
  session.enter_wait(42, -1);
  ASSERT_EQ(Session::Action::kCheckIdle, session.poll().action);
  const Session::CensusRequest request = session.census_request();
  session.on_activity();  // a thread ran while the census read the threads
  session.census_done(request.version, true, "");
  EXPECT_EQ(Session::Action::kCheckIdle, session.poll().action);  // asked again
}

TEST_F(IdleTest, no_thread_in_rmw_wait_proves_nothing)
{
  Session session{clock, virtual_clock, idle_settings()};
  session.start();
  session.on_change();
  session.on_activity();
  session.on_activity();
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  EXPECT_EQ(0, census.calls);  // not even asked
}

TEST_F(IdleTest, a_deadline_inside_the_quiet_window_is_waited_for)
{
  Session session{clock, virtual_clock, idle_settings()};
  session.start();
  session.on_change();
  // A timer due 50 ms from now: its callback may create something the window would see.
  uint64_t token = session.enter_wait(42, clock.now + 50 * kMs);
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  EXPECT_EQ(0, census.calls);
  clock.advance_ms(50);
  session.leave_wait(token);  // the timer fires, creates nothing, the executor waits again
  token = session.enter_wait(42, clock.now + 1000 * kMs);  // next one after the window
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);
  CaptureHeader header;
  session.fill_header("settled", &header);
  EXPECT_DOUBLE_EQ(50.0, header.time_to_settle_ms);
  EXPECT_EQ(1u, header.idle_settles);
}

TEST_F(IdleTest, a_woken_waiter_proves_nothing_until_it_blocks_again)
{
  Session session{clock, virtual_clock, idle_settings()};
  session.start();
  session.on_change();
  const uint64_t token = session.enter_wait(42, -1);
  session.on_wake();  // a guard condition was triggered: the waiter runs again
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  EXPECT_EQ(0, census.calls);
  session.leave_wait(token);
  session.enter_wait(42, -1);  // it found nothing and went back to sleep
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);
}

TEST_F(IdleTest, off_it_is_the_quiet_window_alone)
{
  Session::Settings off = idle_settings();
  off.detect_idle = false;
  Session session{clock, virtual_clock, off};
  session.start();
  session.on_change();
  session.enter_wait(42, -1);
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  EXPECT_EQ(0, census.calls);
  clock.advance_ms(100);
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);
  CaptureHeader header;
  session.fill_header("settled", &header);
  EXPECT_FALSE(header.idle_detect);
  EXPECT_EQ(1u, header.window_settles);
}

TEST_F(IdleTest, the_settle_after_the_warp_is_detected_too)
{
  Session session{clock, virtual_clock, idle_settings(100, 10000)};
  session.start();
  session.on_change();
  uint64_t token = session.enter_wait(42, clock.now + 1000 * kMs);
  EXPECT_EQ(Session::Action::kStartWarp, poll(session).action);
  session.on_wake();  // the warp wakes every waiter
  session.leave_wait(token);
  for (int i = 0; i < 10; ++i) {
    EXPECT_TRUE(session.try_jump(session.virtual_now_ns() + 1000 * kMs));
  }
  EXPECT_FALSE(session.try_jump(session.virtual_now_ns() + 1000 * kMs));  // past the horizon
  token = session.enter_wait(42, clock.now + 1000 * kMs);
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);
  CaptureHeader header;
  session.fill_header("settled", &header);
  EXPECT_EQ(2u, header.idle_settles);
  EXPECT_EQ(0u, header.window_settles);
  EXPECT_TRUE(header.horizon_reached);
}

TEST(ThreadCensus, reads_what_a_thread_waits_in)
{
  using rmw_introspect::parse_syscall;
  // futex(FUTEX_WAIT_BITSET | PRIVATE | CLOCK_REALTIME, no timeout): a lock, a queue
  auto wait = parse_syscall("202 0x7f227c000ba0 0x189 0x0 0x0 0x0 0xffffffff 0x7f 0x7f");
  EXPECT_TRUE(wait.blocked);
  EXPECT_FALSE(wait.has_deadline);
  EXPECT_EQ(0x7f227c000ba0u, wait.futex);
  // the same with an absolute timeout (a timed condition wait, the GIL): until a deadline
  wait = parse_syscall("202 0x7f2278000ba0 0x89 0x0 0x7f22822d99f0 0x0 0xffffffff 0x7f 0x7f");
  EXPECT_TRUE(wait.blocked);
  EXPECT_TRUE(wait.has_deadline);
  EXPECT_EQ(CLOCK_MONOTONIC, wait.clock);
  EXPECT_EQ(0x7f22822d99f0u, wait.timespec_address);
  EXPECT_EQ(CLOCK_REALTIME, parse_syscall("202 0x1 0x189 0x0 0x7f 0x0 0xffffffff 0x7f 0x7f").clock);
  // FUTEX_WAIT with a relative timeout: when it started is unknown
  EXPECT_FALSE(parse_syscall("202 0x1 0x80 0x0 0x7f 0x0 0x0 0x7f 0x7f").blocked);
  EXPECT_TRUE(parse_syscall("202 0x1 0x80 0x0 0x0 0x0 0x0 0x7f 0x7f").blocked);
  // time.sleep: clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME); a relative one is not
  wait = parse_syscall("230 0x1 0x1 0x7f2282adaab0 0x0 0x0 0x7f 0x7f 0x7f");
  EXPECT_TRUE(wait.blocked && wait.has_deadline);
  EXPECT_EQ("clock_nanosleep", wait.name);
  EXPECT_FALSE(parse_syscall("230 0x1 0x0 0x7f2282adaab0 0x0 0x0 0x7f 0x7f 0x7f").blocked);
  // futex wake, read, running, in no syscall
  EXPECT_FALSE(parse_syscall("202 0x7f227c000ba0 0x81 0x1 0x0 0x0 0x0 0x7f 0x7f").blocked);
  EXPECT_FALSE(parse_syscall("0 0x3 0x560b915c9250 0x2000 0x0 0x0 0x0 0x7f 0x7f").blocked);
  EXPECT_EQ("running", parse_syscall("running").name);
  EXPECT_FALSE(parse_syscall("running").blocked);
  EXPECT_FALSE(parse_syscall("-1 0x7ffd 0x7f").blocked);
  EXPECT_FALSE(parse_syscall("").blocked);
  // pause, sigsuspend; sigtimedwait with and without a timeout
  EXPECT_TRUE(parse_syscall("34 0x0 0x0 0x0 0x0 0x0 0x0 0x7f 0x7f").blocked);
  EXPECT_TRUE(parse_syscall("130 0x7ffd 0x8 0x0 0x0 0x0 0x0 0x7f 0x7f").blocked);
  EXPECT_TRUE(parse_syscall("128 0x7ffd 0x0 0x0 0x8 0x0 0x0 0x7f 0x7f").blocked);
  EXPECT_FALSE(parse_syscall("128 0x7ffd 0x0 0x7ffe 0x8 0x0 0x0 0x7f 0x7f").blocked);
}

TEST(ThreadCensus, sleeping_threads_count_by_their_deadline_and_waiting_ones_are_blocked)
{
  rmw_introspect::ProcThreadCensus census;
  std::mutex mutex;
  std::condition_variable cv;
  bool go = false;
  std::atomic<pid_t> tid{0};
  std::thread waiter([&]() {
      tid = rmw_introspect::current_tid();
      std::unique_lock<std::mutex> lock(mutex);
      cv.wait(lock, [&]() {return go;});
    });
  while (tid.load() == 0) {
    std::this_thread::yield();
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const std::vector<pid_t> me{rmw_introspect::current_tid()};
  const int64_t now = std::chrono::duration_cast<std::chrono::nanoseconds>(
    std::chrono::steady_clock::now().time_since_epoch()).count();
  EXPECT_TRUE(census.others_blocked(me, now + 1000 * kMs, nullptr));
  // a mutex the asker holds (the middleware's own): not blocked for ever
  census.set_busy_futexes({reinterpret_cast<uintptr_t>(mutex.native_handle())});
  std::unique_lock<std::mutex> held(mutex);
  std::atomic<bool> locked{false};
  std::thread blocked_on_mutex([&]() {std::lock_guard<std::mutex> lock(mutex); locked = true;});
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  std::string culprit;
  EXPECT_FALSE(census.others_blocked(me, now + 1000 * kMs, &culprit));
  EXPECT_NE(std::string::npos, culprit.find("the middleware's lock")) << culprit;
  held.unlock();
  blocked_on_mutex.join();
  census.set_busy_futexes({});
  // a thread sleeping 10 s: blocked until after a window ending in 1 s, not in 20 s
  std::mutex sleep_mutex;
  std::condition_variable sleep_cv;
  bool stop = false;
  std::thread sleeper([&]() {
      std::unique_lock<std::mutex> lock(sleep_mutex);
      sleep_cv.wait_for(lock, std::chrono::seconds(10), [&]() {return stop;});
    });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_TRUE(census.others_blocked(me, now + 1000 * kMs, &culprit)) << culprit;
  EXPECT_FALSE(census.others_blocked(me, now + 20000 * kMs, &culprit));
  EXPECT_NE(std::string::npos, culprit.find("wakes by itself")) << culprit;
  {
    std::lock_guard<std::mutex> lock(sleep_mutex);
    stop = true;
  }
  sleep_cv.notify_all();
  sleeper.join();
  // a thread that keeps running: not blocked
  std::atomic<bool> spin{true};
  std::thread spinner([&]() {
      while (spin.load()) {
      }
    });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_FALSE(census.others_blocked(me, now + 1000 * kMs, &culprit));
  EXPECT_NE(std::string::npos, culprit.find("not blocked")) << culprit;
  spin = false;
  spinner.join();
  {
    std::lock_guard<std::mutex> lock(mutex);
    go = true;
  }
  cv.notify_all();
  waiter.join();
  EXPECT_TRUE(locked.load());
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

// Idle pollers (docs/design.md, "Detected quiescence"): a thread that polls rmw_wait back to back
// and finds nothing ready.
namespace
{
// `count` polls of thread `tid` that find nothing, `gap_us` apart; `sleeps`: the thread sleeps
// between them (a voluntary context switch each), else it is at most preempted.
void idle_polls(
  Session & session, ManualClock & clock, int count, int64_t gap_us, pid_t tid = 42,
  bool sleeps = false)
{
  static uint64_t switches = 0;
  for (int i = 0; i < count; ++i) {
    clock.now += gap_us * 1000;
    switches += sleeps ? 1 : 0;
    session.on_poll(tid, true, switches);
  }
}

// Start, and settle by 10 ms of idle polls into the warp.
#define poll_into_the_warp(session) \
  do { \
    (session).start(); \
    (session).on_change(); \
    idle_polls((session), clock, 101, 100); \
    ASSERT_EQ(Session::Action::kStartWarp, poll(session).action); \
  } while (false)

CaptureHeader header_of(const Session & session, const char * state = "settled")
{
  CaptureHeader header;
  session.fill_header(state, &header);
  return header;
}
}  // namespace

TEST_F(IdleTest, back_to_back_polls_that_find_nothing_for_10_ms_settle_as_idle)
{
  Session session{clock, virtual_clock, idle_settings()};
  session.start();
  session.set_monitor_tid(99);
  session.on_change();
  idle_polls(session, clock, 91, 100);  // 9 ms from the first poll to the last
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  EXPECT_EQ(0, census.calls);
  idle_polls(session, clock, 10, 100);  // 10 ms
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);
  EXPECT_EQ((std::vector<pid_t>{99, 42}), census.last_known);  // the poller is not read
  const CaptureHeader header = header_of(session);
  EXPECT_EQ("poll", header.settled_by);
  EXPECT_EQ(1u, header.idle_settles);
  EXPECT_EQ(0u, header.window_settles);
  EXPECT_NEAR(10.0, header.time_to_settle_ms, 0.2);
}

TEST_F(IdleTest, many_polls_in_less_than_10_ms_prove_nothing)
{
  Session session{clock, virtual_clock, idle_settings()};
  session.start();
  session.on_change();
  idle_polls(session, clock, 2000, 4);  // 8 ms: a bounded loop of polls, say, then ...
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  session.on_change();  // ... it creates its publisher: the next run starts from there
  idle_polls(session, clock, 2000, 4);
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  EXPECT_EQ(0, census.calls);
}

TEST_F(IdleTest, a_poller_that_pauses_between_polls_is_not_proven_idle)
{
  // publish; sleep_for(10 ms); spin_some without the publish: every gap starts a new run.
  Session session{clock, virtual_clock, idle_settings()};
  session.start();
  session.on_change();
  idle_polls(session, clock, 16, 6000, 42, true);  // 96 ms
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  EXPECT_EQ(0, census.calls);
  idle_polls(session, clock, 1, 6000, 42, true);  // the quiet window (100 ms) decides
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);
  const CaptureHeader header = header_of(session);
  EXPECT_EQ(0u, header.idle_settles);
  EXPECT_EQ(1u, header.window_settles);  // settled_by poll, after the quiet window
}

TEST_F(IdleTest, a_poller_preempted_on_a_busy_machine_is_still_polling_back_to_back)
{
  Session session{clock, virtual_clock, idle_settings()};
  session.start();
  session.on_change();
  idle_polls(session, clock, 20, 100);
  idle_polls(session, clock, 1, 9000);  // 9 ms without the CPU, but it never slept or blocked
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);
}

TEST_F(IdleTest, activity_or_a_ready_poll_starts_the_run_again)
{
  Session session{clock, virtual_clock, idle_settings()};
  session.start();
  session.on_change();
  idle_polls(session, clock, 60, 100);
  session.on_activity();  // a loop that publishes is not idle
  idle_polls(session, clock, 60, 100);
  session.on_poll(42, false);  // something was ready: it has work
  idle_polls(session, clock, 60, 100);
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  EXPECT_EQ(0, census.calls);
  idle_polls(session, clock, 41, 100);  // 10 ms of this run
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);
}

TEST_F(IdleTest, a_poller_with_another_thread_not_blocked_falls_back_to_the_quiet_window)
{
  census.blocked = false;
  Session session{clock, virtual_clock, idle_settings()};
  session.start();
  session.on_change();
  idle_polls(session, clock, 200, 100);
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  EXPECT_EQ(1, census.calls);
  idle_polls(session, clock, 800, 100);
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);
  const CaptureHeader header = header_of(session);
  EXPECT_EQ(0u, header.idle_settles);
}

TEST_F(IdleTest, idle_polls_stall_the_warp_before_any_jump_and_the_unchanged_capture_is_final)
{
  Session session{clock, virtual_clock, idle_settings(100, 10000)};
  poll_into_the_warp(session);
  idle_polls(session, clock, 90, 100);  // nothing to jump to: a poll is no wait with a timeout
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  idle_polls(session, clock, 11, 100);
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);
  const CaptureHeader header = header_of(session);
  EXPECT_TRUE(header.warp_stalled);
  EXPECT_EQ(0u, header.jumps);
  EXPECT_NEAR(20.0, header.elapsed_ms, 0.2);  // not a quiet window in sight
  EXPECT_EQ(101u, header.warp_polls);
}

TEST_F(IdleTest, a_poller_that_creates_in_the_warp_settles_after_10_ms_more_of_idle_polls)
{
  Session session{clock, virtual_clock, idle_settings(100, 10000)};
  poll_into_the_warp(session);
  idle_polls(session, clock, 50, 100);
  session.on_change();  // a bounded loop of polls ended and created its publisher
  idle_polls(session, clock, 100, 100);
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  idle_polls(session, clock, 1, 100);  // 10 ms of polls since: the warp stalls, and the
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);  // same proof ends the settle
  const CaptureHeader header = header_of(session);
  EXPECT_TRUE(header.warp_stalled);
  EXPECT_EQ(2u, header.idle_settles);
  EXPECT_EQ(0u, header.window_settles);
}

TEST_F(IdleTest, after_jumps_idle_polls_leave_the_warp_to_its_stall_rule)
{
  // A timer due in real time on a busy machine makes rcl poll until it has caught up.
  Session session{clock, virtual_clock, idle_settings(100, 10000)};
  session.start();
  session.on_change();
  session.enter_wait(42, clock.now + 1000 * kMs);
  EXPECT_EQ(Session::Action::kStartWarp, poll(session).action);
  session.on_wake();
  EXPECT_TRUE(session.try_jump(session.virtual_now_ns() + 1000 * kMs));
  idle_polls(session, clock, 400, 100, 43);
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  EXPECT_TRUE(session.warping());
}

TEST_F(IdleTest, before_the_warp_a_deadline_inside_the_window_does_not_hold_the_settle)
{
  // A 1 kHz timer: the warp jumps to its next deadline anyway, so the settle is taken now.
  Session session{clock, virtual_clock, idle_settings(100, 10000)};
  session.start();
  session.on_change();
  session.enter_wait(42, clock.now + 1 * kMs);
  EXPECT_EQ(Session::Action::kStartWarp, poll(session).action);
  const CaptureHeader header = header_of(session, "warping");
  EXPECT_EQ(1u, header.idle_settles);
}

TEST_F(IdleTest, after_the_horizon_a_deadline_past_it_does_not_hold_the_final_settle)
{
  Session session{clock, virtual_clock, idle_settings(100, 10000)};
  session.start();
  session.on_change();
  uint64_t token = session.enter_wait(42, clock.now + 1 * kMs);
  EXPECT_EQ(Session::Action::kStartWarp, poll(session).action);
  session.on_wake();
  session.leave_wait(token);
  int jumps = 0;
  while (session.try_jump(session.virtual_now_ns() + 1 * kMs) && jumps < 20000) {
    clock.now += 50 * 1000;  // the callback
    ++jumps;
  }
  EXPECT_LT(jumps, 200);  // fast-forwarded
  // The timer's next deadlines are real milliseconds away, all past the 10 s horizon.
  token = session.enter_wait(42, clock.now + 1 * kMs);
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);
  const CaptureHeader header = header_of(session);
  EXPECT_TRUE(header.horizon_reached);
  EXPECT_EQ(2u, header.idle_settles);
  EXPECT_EQ(0u, header.window_settles);
}

TEST_F(IdleTest, a_deadline_inside_the_window_still_holds_the_final_settle_of_a_warp_out_of_budget)
{
  Session::Settings s = idle_settings(100, 10000);
  s.warp_budget_ms = 5;
  Session session{clock, virtual_clock, s};
  session.start();
  session.on_change();
  session.enter_wait(42, clock.now + 1000 * kMs);
  EXPECT_EQ(Session::Action::kStartWarp, poll(session).action);
  clock.advance_ms(6);
  EXPECT_FALSE(session.try_jump(session.virtual_now_ns() + 1 * kMs));  // budget spent
  session.enter_wait(43, clock.now + 1 * kMs);  // due long before the horizon
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
}

TEST_F(IdleTest, a_pollers_own_triggers_keep_the_census_answer_and_another_threads_do_not)
{
  Session session{clock, virtual_clock, idle_settings()};
  session.start();
  session.on_change();
  idle_polls(session, clock, 101, 100);
  ASSERT_EQ(Session::Action::kCheckIdle, session.poll().action);
  Session::CensusRequest request = session.census_request();
  session.on_wake(42);  // spin_once(node) adds and removes the node: its own triggers
  session.census_done(request.version, true, "");
  EXPECT_EQ(Session::Action::kSettle, session.poll().action);

  Session other{clock, virtual_clock, idle_settings()};
  other.start();
  other.on_change();
  idle_polls(other, clock, 101, 100);
  ASSERT_EQ(Session::Action::kCheckIdle, other.poll().action);
  request = other.census_request();
  other.on_wake(7);  // another thread triggered something: the poller may have work now
  other.census_done(request.version, true, "");
  EXPECT_EQ(Session::Action::kCheckIdle, other.poll().action);  // asked again
}

TEST_F(IdleTest, a_poller_preempted_when_the_monitor_looks_is_looked_at_again_soon)
{
  Session session{clock, virtual_clock, idle_settings(1000)};
  session.start();
  session.on_change();
  clock.advance_ms(25);
  EXPECT_EQ(Session::Action::kWriteRunning, session.poll().action);  // (its deadline is past)
  idle_polls(session, clock, 101, 100);  // announced: the monitor is woken ...
  clock.advance_ms(6);  // ... but by then the poller has been off the CPU for 6 ms
  Session::Step step = poll(session);
  EXPECT_EQ(Session::Action::kNone, step.action);
  ASSERT_TRUE(step.has_deadline);
  EXPECT_LE(step.deadline_ns, clock.now + 5 * kMs);  // not the quiet window's end, 1 s away
  clock.now += 5 * kMs;
  idle_polls(session, clock, 1, 100);  // it polls again (it never slept)
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);
}

// ------------------------------------------------------------------ sleeps (src/sleep.cpp)

namespace
{
Session::Settings sleep_settings(int64_t horizon_ms = 10000)
{
  Session::Settings s = idle_settings(100, horizon_ms);
  s.virtual_sleeps = true;
  return s;
}
}  // namespace

TEST_F(IdleTest, a_thread_that_used_ros_and_sleeps_is_in_its_loop_and_settles_before_the_warp)
{
  // `while rclpy.ok(): publish(); time.sleep(0.5)`: the first sleep after the publish.
  Session session{clock, virtual_clock, sleep_settings()};
  session.start();
  session.set_monitor_tid(99);
  session.on_change();
  clock.advance_ms(1);
  session.on_activity(42);
  const uint64_t token = session.enter_sleep(42, clock.now + 500 * kMs);
  EXPECT_EQ(Session::Action::kStartWarp, poll(session).action);  // no quiet window
  EXPECT_EQ((std::vector<pid_t>{99, 42}), census.last_known);
  EXPECT_EQ("sleep", header_of(session, "warping").settled_by);
  session.leave_sleep(token);
}

TEST_F(IdleTest, a_sleeper_that_did_not_use_ros_since_the_last_change_proves_nothing)
{
  // A driver that logs while it waits for its device, then creates its publisher (item 7):
  // its sleeps are not a loop's.
  Session session{clock, virtual_clock, sleep_settings()};
  session.start();
  session.on_activity(42);
  session.on_change();  // created after the activity
  session.on_activity(43);  // another thread's
  session.enter_sleep(42, clock.now + 500 * kMs);
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  EXPECT_EQ(0, census.calls);
}

TEST_F(IdleTest, without_virtual_time_or_with_sleeps_off_a_sleeper_proves_nothing)
{
  for (const bool sleeps_on : {true, false}) {
    Session::Settings s = sleep_settings(sleeps_on ? 0 : 10000);
    s.virtual_sleeps = sleeps_on;
    Session session{clock, virtual_clock, s};
    session.start();
    session.on_change();
    session.on_activity(42);
    session.enter_sleep(42, clock.now + 500 * kMs);
    EXPECT_EQ(Session::Action::kNone, poll(session).action) << "sleeps on: " << sleeps_on;
    EXPECT_EQ(0, census.calls);
  }
}

TEST_F(IdleTest, a_sleep_that_ends_inside_the_window_holds_the_settle_only_without_a_warp_to_come)
{
  Session session{clock, virtual_clock, sleep_settings()};
  session.start();
  session.on_change();
  session.on_activity(42);
  uint64_t token = session.enter_sleep(42, clock.now + 10 * kMs);
  // Before the warp, the warp steps the sleep next: taken now.
  EXPECT_EQ(Session::Action::kStartWarp, poll(session).action);
  // In the warp, a sleep from before it proves nothing: it is about to come back and jump.
  EXPECT_NE(Session::Action::kSettle, poll(session).action);
  session.leave_sleep(token);
  int jumps = 0;
  while (session.try_jump(session.virtual_now_ns() + 10 * kMs) && jumps < 20000) {
    clock.now += 100 * 1000;  // the loop's publish
    session.on_activity(42);
    ++jumps;
  }
  EXPECT_LT(jumps, 200);  // fast-forwarded like a timer
  // Past the horizon the sleep is real; its end lies beyond what the capture covers.
  session.on_activity(42);
  token = session.enter_sleep(42, clock.now + 10 * kMs);
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);
  const CaptureHeader header = header_of(session);
  EXPECT_TRUE(header.horizon_reached);
  EXPECT_EQ(2u, header.idle_settles);
  EXPECT_EQ("sleep", header.settled_by);
  session.leave_sleep(token);
}

TEST_F(IdleTest, a_sleep_loop_is_not_kept_waiting_for_an_executor_that_cannot_start_before_it_wakes)
{
  // No thread ever waited: the probing waits a grace for an executor to start spinning, unless
  // every thread is asleep in its loop (or blocked) until after the grace.
  for (const int64_t sleep_ms : {500, 100}) {
    Session::Settings s = sleep_settings();
    s.probe = true;
    Session session{clock, virtual_clock, s};
    session.start();
    session.on_change();
    session.on_activity(42);
    session.enter_sleep(42, clock.now + sleep_ms * kMs);
    EXPECT_EQ(Session::Action::kStartProbe, poll(session).action);
    const Session::Step step = poll(session);
    if (sleep_ms == 500) {
      EXPECT_EQ(Session::Action::kStartWarp, step.action);
      EXPECT_STREQ("skipped", session.probe_state());
    } else {
      EXPECT_EQ(Session::Action::kNone, step.action);  // it may start to spin when it wakes
      EXPECT_EQ(clock.now + 250 * kMs, step.deadline_ns);
      // It wakes, publishes and sleeps again, and no thread waited: its loop went round, the
      // grace ends 20 ms later instead of 250 ms after the settle.
      clock.advance_ms(100);
      session.on_activity(42);
      session.enter_sleep(42, clock.now + sleep_ms * kMs);
      const Session::Step again = poll(session);
      EXPECT_EQ(Session::Action::kNone, again.action);
      EXPECT_EQ(clock.now + 20 * kMs, again.deadline_ns);
      clock.advance_ms(20);
      EXPECT_EQ(Session::Action::kStartWarp, poll(session).action);
      EXPECT_STREQ("skipped", session.probe_state());
    }
  }
}
