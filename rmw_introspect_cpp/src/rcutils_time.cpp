// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// The virtual clock: rcl reads time through these two rcutils functions (undefined in librcl,
// defined in librcutils, no -Bsymbolic), so the preloaded middleware's definitions are what
// rcl timers and the ROS clock see. Real time + the warp's offset (0 until the warp starts).
// Not rmw functions: exported deliberately (exports.map, test/exported_symbols.txt).

#include <time.h>

#include "rcutils/time.h"

#include "detail/clock.hpp"
#include "detail/runtime.hpp"

extern "C" {

rcutils_ret_t rcutils_steady_time_now(rcutils_time_point_value_t * now)
{
  return rmw_introspect::virtual_time_now(
    CLOCK_MONOTONIC, rmw_introspect::Runtime::instance().virtual_clock().offset_ns(), now);
}

rcutils_ret_t rcutils_system_time_now(rcutils_time_point_value_t * now)
{
  return rmw_introspect::virtual_time_now(
    CLOCK_REALTIME, rmw_introspect::Runtime::instance().virtual_clock().offset_ns(), now);
}

}  // extern "C"
