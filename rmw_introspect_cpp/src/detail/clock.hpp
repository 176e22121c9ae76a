// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__CLOCK_HPP_
#define DETAIL__CLOCK_HPP_

#include <time.h>

#include <atomic>
#include <cstdint>

#include "rcutils/types/rcutils_ret.h"

namespace rmw_introspect
{

/// Real monotonic time in nanoseconds: the clock the middleware's own timing (settle,
/// progress snapshots) runs on. An interface so that the unit tests inject a manual clock.
class Clock
{
public:
  virtual ~Clock() = default;
  virtual int64_t now_ns() const = 0;
};

/// std::chrono::steady_clock (CLOCK_MONOTONIC).
class SteadyClock final : public Clock
{
public:
  int64_t now_ns() const override;
};

/// Whether the process's main thread is runnable right now: running, or ready and waiting for
/// a CPU (a process still working towards its first rmw_wait, or one starved on a busy
/// machine), as opposed to blocked or sleeping. An interface so that the unit tests inject it.
class MainThreadState
{
public:
  virtual ~MainThreadState() = default;
  virtual bool runnable() const = 0;
};

/// The state field of /proc/self/stat (the thread group leader): R.
class ProcMainThreadState final : public MainThreadState
{
public:
  bool runnable() const override;
};

/// The process-wide offset of virtual time: what the warp has added to the real clocks.
/// Steady and system time are shifted together; the offset only ever grows, so virtual
/// steady time stays monotonic. Read without a lock by every rcutils time call.
class VirtualClock
{
public:
  int64_t offset_ns() const { return offset_ns_.load(std::memory_order_acquire); }
  /// Add `ns` (> 0) to the offset; anything else is ignored.
  void advance(int64_t ns);

private:
  std::atomic<int64_t> offset_ns_{0};
};

/// What the interposed rcutils_{steady,system}_time_now return: `clock` (CLOCK_MONOTONIC or
/// CLOCK_REALTIME) + `offset_ns`, with rcutils' own checks (NULL -> INVALID_ARGUMENT,
/// overflow -> ERROR, each with an rcutils error message).
rcutils_ret_t virtual_time_now(clockid_t clock, int64_t offset_ns, int64_t * now);

/// Nanoseconds as milliseconds with a fraction (what the capture reports).
double ns_to_ms(int64_t ns);

}  // namespace rmw_introspect

#endif  // DETAIL__CLOCK_HPP_
