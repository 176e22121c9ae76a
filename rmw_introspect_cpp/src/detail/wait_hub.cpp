// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/wait_hub.hpp"

namespace rmw_introspect
{

void WaitHub::trigger(GuardCondition * gc, pid_t by)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    gc->triggered_by.store(by);
    gc->triggered.store(true);
    if (wake_listener_) {
      wake_listener_(by);
    }
  }
  cv_.notify_all();
}

void WaitHub::update_and_wake(const std::function<void()> & change)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    change();
    if (wake_listener_) {
      wake_listener_(0);
    }
  }
  cv_.notify_all();
}

}  // namespace rmw_introspect
