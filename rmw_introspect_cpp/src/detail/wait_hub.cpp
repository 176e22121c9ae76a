// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/wait_hub.hpp"

namespace rmw_introspect
{

WaitHub & WaitHub::instance()
{
  static WaitHub * hub = new WaitHub();  // leaked: waits may still run during exit
  return *hub;
}

void WaitHub::trigger(GuardCondition * gc)
{
  {
    std::lock_guard<std::mutex> lock(mutex);
    gc->triggered.store(true);
  }
  cv.notify_all();
}

}  // namespace rmw_introspect
