// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__WAIT_HUB_HPP_
#define DETAIL__WAIT_HUB_HPP_

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <utility>

#include <sys/types.h>

namespace rmw_introspect
{

/// A guard condition: a trigger is remembered until a wait consumes it.
struct GuardCondition
{
  std::atomic<bool> triggered{false};
  /// The thread of the latest trigger (0: the middleware's own, a graph change): a trigger of
  /// the polling thread itself is no work for it (detected quiescence, idle pollers).
  std::atomic<pid_t> triggered_by{0};
};

/// The one mutex + condition variable every rmw_wait sleeps on. Triggering any guard
/// condition (or shutting a context down) wakes all waiters, which re-check their own sets.
class WaitHub
{
public:
  /// `by`: the triggering thread (0: none of the program's).
  void trigger(GuardCondition * gc, pid_t by = 0);
  /// Run `change` under the hub's lock, then wake every waiter (a context shutdown).
  void update_and_wake(const std::function<void()> & change);

  /// Evaluate `ready()` under the hub's lock.
  template<typename ReadyFn>
  bool poll(ReadyFn & ready)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return ready();
  }

  /// The futex word of the hub's mutex (a thread blocked on it is not idle: ThreadCensus).
  uintptr_t lock_address() { return reinterpret_cast<uintptr_t>(mutex_.native_handle()); }

  /// Called under the hub's lock whenever the waiters are woken (trigger, update_and_wake),
  /// with the triggering thread (0: none of the program's): a blocked registration no longer
  /// proves anything (detected quiescence).
  void set_wake_listener(std::function<void(pid_t)> listener)
  {
    wake_listener_ = std::move(listener);
  }

  /// Block until `ready()` (evaluated under the hub's lock) holds or `timeout_ns` passes
  /// (0: poll, negative: forever). `make_guard()` is called under the lock before every sleep
  /// and its result destroyed, still under the lock, after it (the settle bookkeeping of a
  /// blocked thread: a thread woken for nothing registers again). Returns whether `ready()`
  /// holds.
  template<typename ReadyFn, typename MakeGuardFn>
  bool wait(ReadyFn ready, int64_t timeout_ns, MakeGuardFn make_guard)
  {
    std::unique_lock<std::mutex> lock(mutex_);
    if (ready()) {
      return true;
    }
    if (timeout_ns == 0) {
      return false;
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::nanoseconds(timeout_ns);
    for (;;) {
      {
        [[maybe_unused]] auto guard = make_guard();
        if (timeout_ns < 0) {
          cv_.wait(lock);
        } else if (cv_.wait_until(lock, deadline) == std::cv_status::timeout) {
          return ready();
        }
      }
      if (ready()) {
        return true;
      }
    }
  }

private:
  std::mutex mutex_;
  std::condition_variable cv_;
  std::function<void(pid_t)> wake_listener_;
};

}  // namespace rmw_introspect

#endif  // DETAIL__WAIT_HUB_HPP_
