// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/clock.hpp"

#include <chrono>

namespace rmw_introspect
{

int64_t SteadyClock::now_ns() const
{
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
    std::chrono::steady_clock::now().time_since_epoch()).count();
}

double ns_to_ms(int64_t ns)
{
  return static_cast<double>(ns) / 1e6;
}

}  // namespace rmw_introspect
