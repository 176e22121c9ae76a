// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/clock.hpp"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <limits>

#include "rcutils/error_handling.h"

namespace rmw_introspect
{

int64_t SteadyClock::now_ns() const
{
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
           std::chrono::steady_clock::now().time_since_epoch())
    .count();
}

bool ProcMainThreadState::runnable() const
{
  // "pid (comm) S ...": comm may hold spaces and parentheses, the state follows the last ')'.
  std::FILE * stat = std::fopen("/proc/self/stat", "re");
  if (stat == nullptr) {
    return false;
  }
  char buffer[512];
  const size_t read = std::fread(buffer, 1, sizeof(buffer) - 1, stat);
  std::fclose(stat);
  buffer[read] = '\0';
  const char * close = std::strrchr(buffer, ')');
  return close != nullptr && close[1] == ' ' && close[2] == 'R';
}

void VirtualClock::advance(int64_t ns)
{
  if (ns > 0) {
    offset_ns_.fetch_add(ns, std::memory_order_acq_rel);
  }
}

rcutils_ret_t virtual_time_now(clockid_t clock, int64_t offset_ns, int64_t * now)
{
  RCUTILS_CHECK_ARGUMENT_FOR_NULL(now, RCUTILS_RET_INVALID_ARGUMENT);
  struct timespec ts{};
  if (clock_gettime(clock, &ts) != 0) {
    RCUTILS_SET_ERROR_MSG("clock_gettime failed");
    return RCUTILS_RET_ERROR;
  }
  constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
  const int64_t sec = static_cast<int64_t>(ts.tv_sec);
  if (sec < 0 || sec > (kMax - ts.tv_nsec - offset_ns) / 1000000000) {
    RCUTILS_SET_ERROR_MSG("overflow detected");
    return RCUTILS_RET_ERROR;
  }
  *now = sec * 1000000000 + static_cast<int64_t>(ts.tv_nsec) + offset_ns;
  return RCUTILS_RET_OK;
}

double ns_to_ms(int64_t ns)
{
  return static_cast<double>(ns) / 1e6;
}

}  // namespace rmw_introspect
