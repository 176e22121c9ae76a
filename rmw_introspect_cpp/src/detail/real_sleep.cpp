// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/real_sleep.hpp"

#include <dlfcn.h>
#include <errno.h>

#include <cstdint>

namespace rmw_introspect
{

namespace
{
constexpr int64_t kNsPerSecond = 1000 * 1000 * 1000;

using ClockNanosleepFn = int (*)(clockid_t, int, const struct timespec *, struct timespec *);

ClockNanosleepFn next_clock_nanosleep()
{
  static const auto next = reinterpret_cast<ClockNanosleepFn>(dlsym(RTLD_NEXT, "clock_nanosleep"));
  return next;
}
}  // namespace

int64_t monotonic_now_ns()
{
  struct timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<int64_t>(now.tv_sec) * kNsPerSecond + now.tv_nsec;
}

int real_sleep_until(int64_t until_ns)
{
  const struct timespec until = timespec_from_ns(until_ns);
  return real_clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &until, nullptr);
}

struct timespec timespec_from_ns(int64_t ns)
{
  struct timespec ts{};
  ts.tv_sec = static_cast<time_t>(ns / kNsPerSecond);
  ts.tv_nsec = static_cast<long>(ns % kNsPerSecond);
  return ts;
}

int real_clock_nanosleep(
  clockid_t clock, int flags, const struct timespec * request, struct timespec * remain)
{
  const ClockNanosleepFn next = next_clock_nanosleep();
  if (next == nullptr) {
    return ENOSYS;  // no C library after us: cannot happen in a dynamically linked process
  }
  return next(clock, flags, request, remain);
}

void real_sleep_ns(int64_t duration_ns)
{
  const int64_t until = monotonic_now_ns() + duration_ns;
  while (real_sleep_until(until) == EINTR) {
  }
}

}  // namespace rmw_introspect
