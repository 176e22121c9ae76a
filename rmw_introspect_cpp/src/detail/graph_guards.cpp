// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/graph_guards.hpp"

namespace rmw_introspect
{

void GraphGuards::add(GuardCondition * gc)
{
  std::lock_guard<std::mutex> lock(mutex_);
  guards_.insert(gc);
}

void GraphGuards::remove(GuardCondition * gc)
{
  std::lock_guard<std::mutex> lock(mutex_);
  guards_.erase(gc);
}

void GraphGuards::trigger_all(WaitHub & hub)
{
  std::lock_guard<std::mutex> lock(mutex_);
  for (GuardCondition * gc : guards_) {
    hub.trigger(gc);
  }
}

}  // namespace rmw_introspect
