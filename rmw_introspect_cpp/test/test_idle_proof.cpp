// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Detected quiescence (detail/idle_proof.hpp): the IdleProof on its own, and through the
// Session that composes it, on a manual clock and a fake thread census: blocked waits, idle
// pollers, sleepers.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "detail/idle_proof.hpp"
#include "detail/session.hpp"
#include "detail/thread_census.hpp"
#include "session_fixture.hpp"

using namespace session_test;  // NOLINT(build/namespaces): the fixture's names

namespace
{

class FakeCensus : public rmw_introspect::ThreadCensus
{
public:
  bool others_blocked(
    const std::vector<pid_t> & known, int64_t until_ns, std::string * culprit,
    const std::vector<pid_t> * settling, rmw_introspect::SettingUp * setting_up,
    const std::vector<pid_t> * looping) const override
  {
    ++calls;
    last_known = known;
    last_until = until_ns;
    last_settling = settling != nullptr ? *settling : std::vector<pid_t>();
    // A thread of the program's in a wait with a deadline (Rate::sleep): still setting up
    // unless it used ROS since the last change.
    if (waiting_tid != 0 && settling != nullptr &&
        std::find(settling->begin(), settling->end(), waiting_tid) != settling->end())
    {
      if (setting_up != nullptr) {
        *setting_up = rmw_introspect::SettingUp{waiting_tid, waiting_until};
      }
      return false;
    }
    if (!blocked && culprit != nullptr) {
      *culprit = "thread 7 is not blocked (clock_nanosleep)";
    }
    if (blocked && loop_tid != 0 && setting_up != nullptr && looping != nullptr &&
        std::find(looping->begin(), looping->end(), loop_tid) != looping->end())
    {
      setting_up->loop_wait_ns = loop_until;  // its Rate::sleep, counted: it is in its loop
    }
    return blocked;
  }
  pid_t loop_tid = 0;  // a thread in its loop waiting on the real clock, until:
  int64_t loop_until = 0;
  bool blocked = true;
  pid_t waiting_tid = 0;  // a thread in a wait with a deadline past the window, until:
  int64_t waiting_until = 0;
  mutable std::vector<pid_t> last_settling;
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
      rmw_introspect::SettingUp setting_up;
      const bool idle = census.others_blocked(
        request.known, request.until_ns, &culprit, &request.settling, &setting_up,
        &request.looping);
      session.census_done(request.version, idle, culprit, setting_up);
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
#define poll_into_the_warp(session)                               \
  do {                                                            \
    (session).start();                                            \
    (session).on_change();                                        \
    idle_polls((session), clock, 101, 100);                       \
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

// Issue 50 item 1: a thread parked in rmw_wait (rclcpp's sim-time clock thread, a
// TransformListener's spin thread, a multi-threaded executor) does not make a thread of the
// program that is still setting up (it made ROS calls, none since the last change) and waits
// with a deadline look idle: the settle waits until it wakes, the quiet window too.
TEST_F(IdleTest, a_thread_parked_in_rmw_wait_does_not_make_one_still_setting_up_idle)
{
  Session session{clock, virtual_clock, sleep_settings()};
  session.start();
  session.set_monitor_tid(99);
  session.on_change(7);  // the main thread creates its node
  session.enter_wait(42, -1);  // the clock thread, parked from the start
  census.waiting_tid = 7;  // the main thread in Rate::sleep() (a timed wait the census reads)
  census.waiting_until = clock.now + 500 * kMs;
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  EXPECT_EQ((std::vector<pid_t>{7}), census.last_settling);
  clock.advance_ms(20);  // (the progress snapshot)
  Session::Step step = poll(session);
  EXPECT_EQ(Session::Action::kNone, step.action);
  ASSERT_TRUE(step.has_deadline);
  EXPECT_EQ(clock.now + 480 * kMs, step.deadline_ns);  // looked at when it wakes, not before
  EXPECT_EQ(1, census.calls);  // and not read again meanwhile
  clock.advance_ms(130);  // past the quiet window: it does not settle either
  step = poll(session);
  EXPECT_EQ(Session::Action::kNone, step.action);
  EXPECT_EQ(clock.now + 350 * kMs, step.deadline_ns);
  clock.advance_ms(350);  // it wakes, declares its parameters, creates and spins
  census.waiting_tid = 0;
  session.on_change(7);
  session.enter_wait(7, -1);
  EXPECT_EQ(Session::Action::kStartWarp, poll(session).action);
  EXPECT_EQ(1u, header_of(session, "warping").idle_settles);
}

TEST_F(IdleTest, a_sleep_before_the_program_used_ros_again_holds_the_settle_until_it_ends)
{
  // The rclpy form: a second node spun in a thread, the main thread in time.sleep(0.5) before
  // it declares a parameter and creates a publisher (an interposed sleep, not a census read).
  Session session{clock, virtual_clock, sleep_settings()};
  session.start();
  session.set_monitor_tid(99);
  session.on_change(7);
  session.enter_wait(42, -1);
  const uint64_t token = session.enter_sleep(7, clock.now + 500 * kMs);
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  clock.advance_ms(20);  // (the progress snapshot)
  const Session::Step step = poll(session);
  EXPECT_EQ(Session::Action::kNone, step.action);
  EXPECT_EQ(clock.now + 580 * kMs, step.deadline_ns);
  EXPECT_EQ(0, census.calls);
  clock.advance_ms(180);
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  clock.advance_ms(300);
  session.leave_sleep(token);
  session.on_change(7);
  session.enter_wait(7, -1);
  EXPECT_EQ(Session::Action::kStartWarp, poll(session).action);
}

TEST_F(IdleTest, a_thread_that_waits_again_with_nothing_created_is_a_loop_and_holds_once)
{
  // A loop that only waits on its own clock (Rate::sleep; spin_some): held for its first wait,
  // then the rule before issue 50 (here: the quiet window, by the parked thread's wait).
  Session session{clock, virtual_clock, sleep_settings()};
  session.start();
  session.set_monitor_tid(99);
  session.on_change(7);
  session.enter_wait(42, -1);
  census.waiting_tid = 7;
  census.waiting_until = clock.now + 500 * kMs;
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  clock.advance_ms(500);
  census.waiting_until = clock.now + 500 * kMs;  // the next wait, nothing created meanwhile
  EXPECT_EQ(Session::Action::kNone, poll(session).action);  // (a window after the first wake)
  clock.advance_ms(100);
  EXPECT_EQ(Session::Action::kStartWarp, poll(session).action);
  const CaptureHeader header = header_of(session, "warping");
  EXPECT_EQ(1u, header.window_settles);
  EXPECT_EQ("wait", header.settled_by);
}

TEST_F(IdleTest, a_wait_of_a_thread_that_never_made_ros_calls_counts_as_before)
{
  // A library's periodic worker (spdlog's flusher: a 5 s timed wait) never calls ROS: its wait
  // past the window is counted as blocked, as before issue 50.
  Session session{clock, virtual_clock, sleep_settings()};
  session.start();
  session.set_monitor_tid(99);
  session.on_change(7);
  session.enter_wait(7, -1);
  census.waiting_tid = 8;
  census.waiting_until = clock.now + 5000 * kMs;
  EXPECT_EQ(Session::Action::kStartWarp, poll(session).action);
  EXPECT_TRUE(census.last_settling.empty());
}

TEST_F(IdleTest, without_virtual_time_a_thread_setting_up_leaves_the_settle_to_the_window)
{
  // Horizon 0: the quiet window is all the time the process gets; it is not held.
  Session session{clock, virtual_clock, idle_settings()};
  session.start();
  session.on_change(7);
  session.enter_wait(42, -1);
  census.waiting_tid = 7;
  census.waiting_until = clock.now + 500 * kMs;
  EXPECT_EQ(Session::Action::kNone, poll(session).action);
  clock.advance_ms(100);
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);
}

TEST_F(IdleTest, a_warp_the_proof_ends_while_a_loop_waits_on_the_real_clock_says_so)
{
  // diagnostic_updater's example after its set-up: Rate::sleep(); publish; spin_some. The warp
  // cannot step the Rate's timed wait: the final settle is proven at once, far short of the
  // horizon, and the capture says why (warp_real_waits).
  Session session{clock, virtual_clock, sleep_settings()};
  session.start();
  session.set_monitor_tid(99);
  session.on_change(7);
  session.enter_wait(42, -1);  // the clock thread
  session.on_activity(7);  // its publish: in its loop
  census.loop_tid = 7;
  census.loop_until = clock.now + 500 * kMs;
  EXPECT_EQ(Session::Action::kStartWarp, poll(session).action);
  EXPECT_EQ(Session::Action::kSettle, poll(session).action);
  CaptureHeader header = header_of(session);
  EXPECT_TRUE(header.warp_real_waits);
  EXPECT_FALSE(header.horizon_reached || header.warp_stalled || header.warp_budget_exhausted);
  // A thread that waits past the horizon: nothing the capture covers is lost, no note.
  Session later{clock, virtual_clock, sleep_settings()};
  later.start();
  later.set_monitor_tid(99);
  later.on_change(7);
  later.enter_wait(42, -1);
  later.on_activity(7);
  census.loop_until = clock.now + 20000 * kMs;
  EXPECT_EQ(Session::Action::kStartWarp, poll(later).action);
  EXPECT_EQ(Session::Action::kSettle, poll(later).action);
  EXPECT_FALSE(header_of(later).warp_real_waits);
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

// ------------------------------------------------------------------ the IdleProof on its own

namespace
{
rmw_introspect::IdleProof::Moment moment_at(int64_t now_ns, int64_t window_end_ns)
{
  rmw_introspect::IdleProof::Moment moment;
  moment.now_ns = now_ns;
  moment.window_end_ns = window_end_ns;
  return moment;
}
}  // namespace

TEST(IdleProof, a_blocked_wait_is_idle_once_the_census_says_every_other_thread_is_blocked)
{
  rmw_introspect::IdleProof proof({100, true, false});
  proof.set_monitor_tid(99);
  proof.enter_wait(7, -1, 0);
  const auto moment = moment_at(0, 100 * kMs);
  EXPECT_FALSE(proof.provably_idle(moment));  // not before the census
  int64_t recheck = INT64_MAX;
  ASSERT_TRUE(proof.look_done(0, &recheck));  // a census is wanted
  const auto & request = proof.census_request();
  EXPECT_EQ((std::vector<pid_t>{99, 7}), request.known);
  EXPECT_EQ(100 * kMs, request.until_ns);
  proof.census_done(request.version, true, "", 0);
  proof.look_begins();
  EXPECT_TRUE(proof.provably_idle(moment));
  EXPECT_STREQ("wait", proof.proven_by());
  EXPECT_FALSE(proof.look_done(0, &recheck));
  // A wake: the waiter proves nothing until it has looked at its wait set and blocked again.
  proof.on_wake(0);
  EXPECT_FALSE(proof.provably_idle(moment));
}

TEST(IdleProof, a_census_that_found_a_thread_running_is_rechecked_5_ms_later)
{
  rmw_introspect::IdleProof proof({100, true, false});
  proof.enter_wait(7, -1, 0);
  EXPECT_FALSE(proof.provably_idle(moment_at(0, 100 * kMs)));
  int64_t recheck = INT64_MAX;
  ASSERT_TRUE(proof.look_done(0, &recheck));
  proof.census_done(proof.census_request().version, false, "thread 8 is not blocked", 0);
  EXPECT_EQ("thread 8 is not blocked", proof.not_idle_reason());
  proof.look_begins();
  EXPECT_FALSE(proof.provably_idle(moment_at(kMs, 100 * kMs)));  // the answer still holds
  EXPECT_FALSE(proof.look_done(kMs, &recheck));
  EXPECT_EQ(5 * kMs, recheck);
}

TEST(IdleProof, a_deadline_inside_the_window_holds_the_proof_unless_it_is_past_the_limit)
{
  rmw_introspect::IdleProof proof({100, true, false});
  proof.enter_wait(7, 50 * kMs, 0);  // a timer due in 50 ms
  auto moment = moment_at(0, 100 * kMs);
  EXPECT_FALSE(proof.provably_idle(moment));
  int64_t recheck = INT64_MAX;
  EXPECT_FALSE(proof.look_done(0, &recheck));  // no census: the timer comes first
  moment.deadlines_until_ns = INT64_MIN;  // the warp to come jumps to it
  EXPECT_FALSE(proof.provably_idle(moment));
  EXPECT_TRUE(proof.look_done(0, &recheck));
}

TEST(IdleProof, off_it_proves_nothing_and_leaving_a_wait_gives_its_quiet_epoch)
{
  rmw_introspect::IdleProof proof({100, false, false});
  const uint64_t token = proof.enter_wait(7, -1, 3);
  EXPECT_FALSE(proof.provably_idle(moment_at(0, 100 * kMs)));
  int64_t recheck = INT64_MAX;
  EXPECT_FALSE(proof.look_done(0, &recheck));
  EXPECT_EQ(INT64_MAX, recheck);
  uint64_t quiet_epoch = 0;
  ASSERT_TRUE(proof.leave_wait(token, &quiet_epoch));
  EXPECT_EQ(3u, quiet_epoch);
  EXPECT_FALSE(proof.leave_wait(token, &quiet_epoch));
  EXPECT_FALSE(proof.any_blocked());
}

TEST(IdleProof, a_sleeper_counts_when_it_used_ros_in_the_generation_and_sleeps_can_be_stepped)
{
  rmw_introspect::IdleProof proof({100, true, true});
  proof.enter_sleep(7, 500 * kMs);
  auto moment = moment_at(0, 100 * kMs);
  moment.generation = 2;
  EXPECT_FALSE(proof.sleepers_count(moment));  // no activity call yet
  proof.on_activity(7, 1);
  EXPECT_FALSE(proof.sleepers_count(moment));  // ... in an older generation
  proof.on_activity(7, 2);
  EXPECT_TRUE(proof.sleepers_count(moment));
  EXPECT_EQ(500 * kMs, proof.first_counted_wake(moment));
  moment.warping = true;  // about to come back and jump
  EXPECT_FALSE(proof.sleepers_count(moment));
  EXPECT_EQ(INT64_MAX, proof.first_counted_wake(moment));
}
