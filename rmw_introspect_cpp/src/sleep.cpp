// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// The process's sleeps on virtual time: Python's time.sleep (clock_nanosleep), C++'s
// std::this_thread::sleep_for (nanosleep), usleep and sleep reach these definitions first
// (the middleware is preloaded), so the warp steps a `publish; sleep` loop like a timer
// (detail/sleep.hpp). Only relative sleeps and absolute ones on CLOCK_MONOTONIC and
// CLOCK_REALTIME are stepped; anything else, and every call in a process without a session,
// goes to the C library unchanged. Not rmw functions: exported deliberately (exports.map,
// test/exported_symbols.txt).

#include <errno.h>
#include <time.h>
#include <unistd.h>

#include <cstdint>

#include "detail/real_sleep.hpp"
#include "detail/sleep.hpp"

namespace
{
constexpr int64_t kNsPerSecond = 1000 * 1000 * 1000;

bool valid(const struct timespec * ts)
{
  return ts != nullptr && ts->tv_sec >= 0 && ts->tv_nsec >= 0 && ts->tv_nsec < kNsPerSecond;
}

int64_t to_ns(const struct timespec & ts)
{
  // A sleep of more than 100 years saturates (it never ends within a capture either way), so
  // that a deadline (now + duration) cannot overflow.
  constexpr int64_t kMaxSeconds = 100LL * 365 * 24 * 3600;
  const int64_t seconds = ts.tv_sec > kMaxSeconds ? kMaxSeconds : static_cast<int64_t>(ts.tv_sec);
  return seconds * kNsPerSecond + ts.tv_nsec;
}

// The relative duration of a clock_nanosleep request, or false when it is not stepped.
bool stepped_duration(clockid_t clock, int flags, const struct timespec * request, int64_t * ns)
{
  if ((clock != CLOCK_MONOTONIC && clock != CLOCK_REALTIME) || !valid(request) ||
      !rmw_introspect::sleeps_virtual())
  {
    return false;
  }
  *ns = to_ns(*request);
  if ((flags & TIMER_ABSTIME) != 0) {
    struct timespec now{};
    if (clock_gettime(clock, &now) != 0) {
      return false;
    }
    *ns -= to_ns(now);
  }
  return *ns > 0;
}
}  // namespace

// The library is built with hidden visibility; these four are the C library's names, declared
// there without an export attribute.
#define RMWI_INTERPOSED extern "C" __attribute__((visibility("default")))

RMWI_INTERPOSED int clock_nanosleep(
  clockid_t clock, int flags, const struct timespec * request, struct timespec * remain)
{
  int64_t duration_ns = 0;
  if (!stepped_duration(clock, flags, request, &duration_ns)) {
    return rmw_introspect::real_clock_nanosleep(clock, flags, request, remain);
  }
  int64_t unslept_ns = 0;
  const int rc = rmw_introspect::virtual_sleep(duration_ns, &unslept_ns);
  if (rc == EINTR && remain != nullptr && (flags & TIMER_ABSTIME) == 0) {
    *remain = rmw_introspect::timespec_from_ns(unslept_ns);
  }
  return rc;
}

RMWI_INTERPOSED int nanosleep(const struct timespec * request, struct timespec * remain)
{
  const int rc = clock_nanosleep(CLOCK_REALTIME, 0, request, remain);  // as the C library's
  if (rc != 0) {
    errno = rc;
    return -1;
  }
  return 0;
}

RMWI_INTERPOSED int usleep(useconds_t microseconds)
{
  const struct timespec request =
    rmw_introspect::timespec_from_ns(static_cast<int64_t>(microseconds) * 1000);
  return nanosleep(&request, nullptr);
}

RMWI_INTERPOSED unsigned int sleep(unsigned int seconds)
{
  struct timespec request{};
  request.tv_sec = static_cast<time_t>(seconds);
  struct timespec remain{};
  if (nanosleep(&request, &remain) != 0) {
    return static_cast<unsigned int>(remain.tv_sec + (remain.tv_nsec > 0 ? 1 : 0));
  }
  return 0;
}
