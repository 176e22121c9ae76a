// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__SLEEP_HPP_
#define DETAIL__SLEEP_HPP_

#include <time.h>

#include <cstdint>

namespace rmw_introspect
{

/// The process's sleeps on virtual time (docs/design.md, "Sleeps"). The interposed nanosleep,
/// clock_nanosleep, usleep and sleep (src/sleep.cpp) come here. In a process whose session
/// started (rmw_init) with virtual time and RMW_INTROSPECT_SLEEPS on, a sleep in the warp jumps
/// virtual time by its duration and returns at once, like a wait with nothing ready; a sleep
/// before the warp sleeps for real, registered with the session (a thread that used ROS and
/// sleeps is in its loop), and comes back to jump the rest when the warp starts. Anywhere else
/// (no session, a child forked after rmw_init, another clock, horizon 0) the real function runs.

/// Whether this process's sleeps go through the session at all (the cheap check first).
bool sleeps_virtual();

/// Sleep `duration_ns` (> 0) of the calling thread as described above. Returns 0 or the error
/// of the real sleep (EINTR: a signal handler ran; `*unslept_ns` is what was left).
int virtual_sleep(int64_t duration_ns, int64_t * unslept_ns);

/// The real clock_nanosleep of the C library (the next definition after ours), for sleeps the
/// middleware does not step and for the middleware's own (a watchdog must sleep for real).
int real_clock_nanosleep(
  clockid_t clock, int flags, const struct timespec * request, struct timespec * remain);

/// The middleware's own real sleep of `duration_ns` (EINTR resumed).
void real_sleep_ns(int64_t duration_ns);

/// `ns` (>= 0) as a timespec.
struct timespec timespec_from_ns(int64_t ns);

}  // namespace rmw_introspect

#endif  // DETAIL__SLEEP_HPP_
