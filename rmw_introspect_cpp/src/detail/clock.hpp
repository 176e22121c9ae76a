// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__CLOCK_HPP_
#define DETAIL__CLOCK_HPP_

#include <cstdint>

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

/// Nanoseconds as milliseconds with a fraction (what the capture reports).
double ns_to_ms(int64_t ns);

}  // namespace rmw_introspect

#endif  // DETAIL__CLOCK_HPP_
