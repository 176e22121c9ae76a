// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// The probing's pace (detail/probing.hpp) through the Session that composes it, on a manual
// clock and an injected main-thread state. Only the two tests of the real /proc main-thread
// state use a thread and a sleep.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "detail/probing.hpp"
#include "detail/session.hpp"
#include "session_fixture.hpp"

using namespace session_test;  // NOLINT(build/namespaces): the fixture's names

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
  bool runnable() const override { return running; }
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

// ------------------------------------------------------------------ the Probing on its own

TEST(Probing, one_request_at_a_time_and_a_timeout_asks_for_a_settle)
{
  using Next = rmw_introspect::Probing::Next;
  rmw_introspect::Probing probing(5000, nullptr);
  probing.begin(0, true, std::nullopt);
  int64_t look_at = INT64_MAX;
  EXPECT_EQ(Next::kSend, probing.next(0, true, true, &look_at));
  probing.sent(kMs);
  EXPECT_EQ(Next::kWait, probing.next(2 * kMs, true, true, &look_at));
  EXPECT_EQ(5001 * kMs, look_at);
  EXPECT_EQ(Next::kTimeout, probing.next(5001 * kMs, true, true, &look_at));
  EXPECT_FALSE(probing.answered(false));  // late
  EXPECT_EQ(Next::kSendAfterSettle, probing.next(5001 * kMs, true, true, &look_at));
  probing.done();
  EXPECT_EQ(Next::kEndAfterSettle, probing.next(5001 * kMs, true, true, &look_at));
  EXPECT_STREQ("done", probing.outcome());
}

TEST(Probing, reads_alone_need_no_settle_at_the_end)
{
  using Next = rmw_introspect::Probing::Next;
  rmw_introspect::Probing probing(5000, nullptr);
  probing.begin(0, true, std::nullopt);
  int64_t look_at = INT64_MAX;
  probing.sent(0);
  EXPECT_TRUE(probing.answered(false));
  EXPECT_EQ(Next::kSend, probing.next(0, true, true, &look_at));
  probing.done();
  EXPECT_EQ(Next::kEnd, probing.next(0, true, true, &look_at));
  EXPECT_EQ(Next::kEndAfterSettle, probing.next(0, true, false, &look_at));  // a creation
}

TEST(Probing, a_process_that_never_waits_is_skipped_after_the_grace)
{
  using Next = rmw_introspect::Probing::Next;
  rmw_introspect::Probing probing(5000, nullptr);
  probing.begin(0, false, std::nullopt);
  int64_t look_at = INT64_MAX;
  EXPECT_EQ(Next::kWait, probing.next(0, false, true, &look_at));
  EXPECT_EQ(250 * kMs, look_at);
  EXPECT_EQ(Next::kEnd, probing.next(250 * kMs, false, true, &look_at));
  EXPECT_STREQ("skipped", probing.outcome());
}

TEST(Probing, a_sleep_loop_that_goes_round_again_ends_the_grace_20_ms_later)
{
  using Next = rmw_introspect::Probing::Next;
  rmw_introspect::Probing probing(5000, nullptr);
  probing.begin(0, false, 100 * kMs);  // its sleeper wakes before the grace ends
  int64_t look_at = INT64_MAX;
  EXPECT_EQ(Next::kWait, probing.next(0, false, true, &look_at));
  EXPECT_EQ(250 * kMs, look_at);
  probing.sleep_loop_again(100 * kMs);
  look_at = INT64_MAX;
  EXPECT_EQ(Next::kWait, probing.next(100 * kMs, false, true, &look_at));
  EXPECT_EQ(120 * kMs, look_at);
  // A sleeper that wakes only after the grace: nothing can start to wait before, no grace.
  rmw_introspect::Probing late(5000, nullptr);
  late.begin(0, false, 300 * kMs);
  EXPECT_EQ(Next::kEnd, late.next(0, false, true, &look_at));
  EXPECT_STREQ("skipped", late.outcome());
}
