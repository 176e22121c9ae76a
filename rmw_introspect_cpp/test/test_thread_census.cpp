// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// The thread census (detail/thread_census.hpp) the idle proof asks: what a thread waits in, read
// from its syscall line; and the real census of /proc on threads of this process.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "detail/thread_census.hpp"
#include "session_fixture.hpp"

using session_test::kMs;

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
    cv.wait(lock, [&]() { return go; });
  });
  while (tid.load() == 0) {
    std::this_thread::yield();
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const std::vector<pid_t> me{rmw_introspect::current_tid()};
  const int64_t now = std::chrono::duration_cast<std::chrono::nanoseconds>(
                        std::chrono::steady_clock::now().time_since_epoch())
                        .count();
  EXPECT_TRUE(census.others_blocked(me, now + 1000 * kMs, nullptr));
  // a mutex the asker holds (the middleware's own): not blocked for ever
  census.set_busy_futexes({reinterpret_cast<uintptr_t>(mutex.native_handle())});
  std::unique_lock<std::mutex> held(mutex);
  std::atomic<bool> locked{false};
  std::thread blocked_on_mutex([&]() {
    std::lock_guard<std::mutex> lock(mutex);
    locked = true;
  });
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
  std::atomic<pid_t> sleeper_tid{0};
  std::thread sleeper([&]() {
    sleeper_tid = rmw_introspect::current_tid();
    std::unique_lock<std::mutex> lock(sleep_mutex);
    sleep_cv.wait_for(lock, std::chrono::seconds(10), [&]() { return stop; });
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_TRUE(census.others_blocked(me, now + 1000 * kMs, &culprit)) << culprit;
  EXPECT_FALSE(census.others_blocked(me, now + 20000 * kMs, &culprit));
  EXPECT_NE(std::string::npos, culprit.find("wakes by itself")) << culprit;
  // ... unless it is a thread of the program's that is still setting up (issue 50 item 1):
  // then not blocked, and said with when it wakes
  const std::vector<pid_t> settling{sleeper_tid.load()};
  rmw_introspect::SettingUp setting_up;
  EXPECT_FALSE(census.others_blocked(me, now + 1000 * kMs, &culprit, &settling, &setting_up));
  EXPECT_NE(std::string::npos, culprit.find("still setting up")) << culprit;
  EXPECT_EQ(sleeper_tid.load(), setting_up.tid);
  EXPECT_GE(setting_up.wakes_at_ns, now + 9000 * kMs);
  EXPECT_LE(setting_up.wakes_at_ns, now + 11000 * kMs);
  const std::vector<pid_t> others{me[0] + 100000};  // another thread's: it counts as before
  EXPECT_TRUE(census.others_blocked(me, now + 1000 * kMs, &culprit, &others, &setting_up));
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
