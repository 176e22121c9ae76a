// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__THREAD_CENSUS_HPP_
#define DETAIL__THREAD_CENSUS_HPP_

#include <sys/types.h>

#include <cstdint>
#include <string>
#include <vector>

namespace rmw_introspect
{

/// A thread that waits until a deadline past the quiet window without having used ROS since
/// the last change (issue 50 item 1): it is still setting up (rclcpp's Rate::sleep before the
/// program creates the rest), and what it does when it wakes is not known.
struct SettingUp
{
  pid_t tid = 0;
  int64_t wakes_at_ns = -1;  // CLOCK_MONOTONIC; -1: no such thread was found
  /// The earliest deadline of a wait counted as blocked of a thread of `looping` (a thread in
  /// its loop that waits on the real clock: Rate::sleep); -1: none.
  int64_t loop_wait_ns = -1;
};

/// Whether every thread of the process but some is blocked in a wait that nothing but another
/// thread of the process (or a deadline not before a given time) can end: docs/design.md,
/// "Detected quiescence", condition 2. An interface so that the unit tests inject it.
class ThreadCensus
{
public:
  virtual ~ThreadCensus() = default;
  /// True when every thread not in `known` is blocked until woken, or until a deadline at or
  /// after `until_ns` (CLOCK_MONOTONIC); false when one is not, or when it cannot be told
  /// (then `*culprit`, if given, says which thread and why). A thread of `settling` (it made
  /// the program's ROS calls, but none since the last change) in a wait with a deadline is
  /// still setting up, not in a loop: the answer is false, and `*setting_up` says which and
  /// until when. Other threads' waits with a deadline (a library's periodic worker that never
  /// calls ROS, such as spdlog's flusher) count as before; of those, the earliest deadline of a
  /// thread of `looping` is said in `setting_up->loop_wait_ns`.
  virtual bool others_blocked(
    const std::vector<pid_t> & known, int64_t until_ns, std::string * culprit,
    const std::vector<pid_t> * settling = nullptr, SettingUp * setting_up = nullptr,
    const std::vector<pid_t> * looping = nullptr) const = 0;
};

/// Reads /proc/self/task/<tid>/{syscall,stat,schedstat} twice (x86_64 syscall numbers;
/// elsewhere never proven): the first pass reads what each thread waits in, the second that
/// none of them ran or became runnable meanwhile (a consistent picture, not one thread at a
/// time). A thread blocked on one of `busy_futexes` (the middleware's own mutexes, held by the
/// thread asking) waits for the asker, not for ever: it is not counted as blocked.
class ProcThreadCensus final : public ThreadCensus
{
public:
  void set_busy_futexes(std::vector<uintptr_t> addresses) { busy_futexes_ = std::move(addresses); }
  bool others_blocked(
    const std::vector<pid_t> & known, int64_t until_ns, std::string * culprit,
    const std::vector<pid_t> * settling = nullptr, SettingUp * setting_up = nullptr,
    const std::vector<pid_t> * looping = nullptr) const override;

private:
  std::vector<uintptr_t> busy_futexes_;
};

/// What one line of /proc/<pid>/task/<tid>/syscall says about the thread.
struct SyscallWait
{
  bool blocked = false;       // in a wait that only a wake or its deadline ends
  bool has_deadline = false;  // ... which has a deadline; `timespec_address` points at it
  clockid_t clock = 0;        // the deadline's clock (CLOCK_MONOTONIC or CLOCK_REALTIME)
  uintptr_t timespec_address = 0;
  uintptr_t futex = 0;        // the futex word of a futex wait (0: not one)
  std::string name;           // the syscall, for people ("futex", "clock_nanosleep", "running")
};

/// Parse one line ("running", "-1 sp pc", or the number and six arguments in hex, then sp and
/// pc): untimed futex waits, pause, sigsuspend, untimed sigtimedwait are blocked; futex
/// waits with an absolute timeout (FUTEX_WAIT_BITSET, the PI locks) and clock_nanosleep with
/// TIMER_ABSTIME are blocked with a deadline; anything else (a relative timeout, a file
/// descriptor, running) is not. Public for the unit tests.
SyscallWait parse_syscall(const std::string & syscall_line);

/// The calling thread's id (gettid).
pid_t current_tid();

}  // namespace rmw_introspect

#endif  // DETAIL__THREAD_CENSUS_HPP_
