// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__WAIT_HUB_HPP_
#define DETAIL__WAIT_HUB_HPP_

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>

namespace rmw_introspect
{

/// A guard condition: a trigger is remembered until a wait consumes it.
struct GuardCondition
{
  std::atomic<bool> triggered{false};
};

/// The one mutex + condition variable every rmw_wait sleeps on. Triggering any guard
/// condition wakes all waiters, which re-check their own sets.
class WaitHub
{
public:
  static WaitHub & instance();

  void trigger(GuardCondition * gc);

  std::mutex mutex;
  std::condition_variable cv;
};

}  // namespace rmw_introspect

#endif  // DETAIL__WAIT_HUB_HPP_
