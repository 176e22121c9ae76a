// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/sleep.hpp"

#include <errno.h>

#include <algorithm>
#include <cstdint>

#include "detail/real_sleep.hpp"
#include "detail/runtime.hpp"

namespace rmw_introspect
{

namespace
{
// A sleep that began before the warp wakes this often to see whether the warp started (a
// nanosleep cannot be woken by another thread without a signal): the warp then steps it from
// the next slice on instead of after its real end (a 0.5 s sleep of a publish loop).
constexpr int64_t kSliceNs = 2 * 1000 * 1000;
}  // namespace

bool sleeps_virtual()
{
  const Runtime * runtime = Runtime::started_instance();
  return runtime != nullptr && runtime->sleeps_stepped();
}

int virtual_sleep(int64_t duration_ns, int64_t * unslept_ns)
{
  Runtime * runtime = Runtime::started_instance();
  const int64_t deadline_ns = monotonic_now_ns() + duration_ns;
  if (runtime == nullptr || !runtime->sleeps_stepped()) {
    const int rc = real_sleep_until(deadline_ns);
    *unslept_ns = rc == 0 ? 0 : std::max<int64_t>(0, deadline_ns - monotonic_now_ns());
    return rc;
  }
  *unslept_ns = 0;
  if (runtime->jump_sleep(duration_ns)) {
    return 0;
  }
  const Runtime::Sleeping sleeping(*runtime, deadline_ns);
  for (;;) {
    const int64_t now = monotonic_now_ns();
    if (now >= deadline_ns) {
      return 0;
    }
    const uint64_t warp_starts = runtime->warp_starts();
    const bool warp_to_come = runtime->warp_to_come();
    const int rc =
      real_sleep_until(warp_to_come ? std::min(deadline_ns, now + kSliceNs) : deadline_ns);
    if (rc != 0) {
      *unslept_ns = std::max<int64_t>(0, deadline_ns - monotonic_now_ns());
      return rc;
    }
    if (runtime->warp_starts() != warp_starts &&
        runtime->jump_sleep(deadline_ns - monotonic_now_ns()))
    {
      return 0;
    }
  }
}

}  // namespace rmw_introspect
