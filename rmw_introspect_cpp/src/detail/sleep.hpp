// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__SLEEP_HPP_
#define DETAIL__SLEEP_HPP_

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

}  // namespace rmw_introspect

#endif  // DETAIL__SLEEP_HPP_
