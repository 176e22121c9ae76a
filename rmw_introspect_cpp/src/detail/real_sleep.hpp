// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__REAL_SLEEP_HPP_
#define DETAIL__REAL_SLEEP_HPP_

#include <time.h>

#include <cstdint>

namespace rmw_introspect
{

/// Real sleeps, past the interposed ones (sleep.hpp, src/sleep.cpp): for the sleeps the
/// middleware does not step and for the middleware's own (a watchdog must sleep for real).

/// The real clock_nanosleep of the C library (the next definition after ours).
int real_clock_nanosleep(
  clockid_t clock, int flags, const struct timespec * request, struct timespec * remain);

/// Sleep for real until CLOCK_MONOTONIC reaches `until_ns`: 0, or the error (EINTR).
int real_sleep_until(int64_t until_ns);

/// The middleware's own real sleep of `duration_ns` (EINTR resumed).
void real_sleep_ns(int64_t duration_ns);

/// CLOCK_MONOTONIC now, in nanoseconds.
int64_t monotonic_now_ns();

/// `ns` (>= 0) as a timespec.
struct timespec timespec_from_ns(int64_t ns);

}  // namespace rmw_introspect

#endif  // DETAIL__REAL_SLEEP_HPP_
