// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__RMW_API_HPP_
#define DETAIL__RMW_API_HPP_

// The differences between the rmw APIs of the distributions this middleware builds for, in one
// place. One source tree serves all of them: CMake passes rmw's package version as
// RMWI_RMW_VERSION (MAJOR * 10000 + MINOR * 100 + PATCH: Jazzy's rmw is 7.3.x, Kilted's 7.8.x),
// and code that differs asks the names below, never the version itself.
//
// The changes that matter here landed between Jazzy and Kilted (rolling, released in rmw 7.5.0
// and rmw_implementation 3.0): `rmw_init_options_t::localhost_only` was removed (ros2/rmw#376);
// `rmw_event_type_t` gained RMW_EVENT_INVALID as its *first* value with RMW_EVENT_TYPE_MAX as
// the sentinel (it used to end with RMW_EVENT_INVALID); and two functions that answered a NULL
// argument with RMW_RET_ERROR now answer RMW_RET_INVALID_ARGUMENT, as rmw.h always documented
// (Kilted's test_rmw_implementation expects it, and Kilted's rmw_fastrtps_cpp does it). The set
// of rmw_* functions an implementation exports is the same 95 in both
// (test/exported_symbols.txt).

#include "rmw/event.h"
#include "rmw/ret_types.h"

#ifndef RMWI_RMW_VERSION
#error "RMWI_RMW_VERSION is not defined: build with this package's CMakeLists.txt"
#endif

/// rmw_init_options_t has `localhost_only` (Jazzy and earlier).
#define RMWI_RMW_HAS_LOCALHOST_ONLY (RMWI_RMW_VERSION < 70500)

namespace rmw_introspect
{
/// What rmw_service_server_is_available and rmw_destroy_wait_set answer to a NULL argument:
/// RMW_RET_ERROR up to Jazzy (where rmw_fastrtps_cpp and test_rmw_implementation agree on it
/// against rmw.h), RMW_RET_INVALID_ARGUMENT from Kilted on.
constexpr rmw_ret_t kNullArgumentRetOfOldChecks =
  RMWI_RMW_VERSION >= 70500 ? RMW_RET_INVALID_ARGUMENT : RMW_RET_ERROR;

#if RMWI_RMW_VERSION >= 70500
/// One past the largest event type: the size of a table indexed by event type.
constexpr int kEventTypeEnd = RMW_EVENT_TYPE_MAX;
/// An event type an rmw_event_t may carry (not the INVALID marker, not the sentinel).
constexpr bool is_valid_event_type(rmw_event_type_t type)
{
  return type > RMW_EVENT_INVALID && type < RMW_EVENT_TYPE_MAX;
}
#else
constexpr int kEventTypeEnd = RMW_EVENT_INVALID;
constexpr bool is_valid_event_type(rmw_event_type_t type)
{
  return type >= 0 && type < RMW_EVENT_INVALID;
}
#endif
}  // namespace rmw_introspect

#endif  // DETAIL__RMW_API_HPP_
