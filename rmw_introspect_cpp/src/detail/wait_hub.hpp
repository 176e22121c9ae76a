// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__WAIT_HUB_HPP_
#define DETAIL__WAIT_HUB_HPP_

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>

namespace rmw_introspect
{

/// A guard condition: a trigger is remembered until a wait consumes it.
struct GuardCondition
{
  std::atomic<bool> triggered{false};
};

/// The one mutex + condition variable every rmw_wait sleeps on. Triggering any guard
/// condition (or shutting a context down) wakes all waiters, which re-check their own sets.
class WaitHub
{
public:
  void trigger(GuardCondition * gc);
  /// Run `change` under the hub's lock, then wake every waiter (a context shutdown).
  void update_and_wake(const std::function<void()> & change);

  /// Evaluate `ready()` under the hub's lock.
  template<typename ReadyFn>
  bool poll(ReadyFn & ready)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return ready();
  }

  /// Block until `ready()` (evaluated under the hub's lock) holds or `timeout_ns` passes
  /// (0: poll, negative: forever). `make_guard()` is called under the lock just before the
  /// first sleep and its result destroyed, still under the lock, after the last one (the
  /// settle bookkeeping of a blocked thread). Returns whether `ready()` holds.
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
    [[maybe_unused]] auto guard = make_guard();
    if (timeout_ns < 0) {
      cv_.wait(lock, ready);
      return true;
    }
    return cv_.wait_for(lock, std::chrono::nanoseconds(timeout_ns), ready);
  }

private:
  std::mutex mutex_;
  std::condition_variable cv_;
};

}  // namespace rmw_introspect

#endif  // DETAIL__WAIT_HUB_HPP_
