// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// The interposed rcutils clocks: rcutils' argument checks, monotonic, real time + the warp's
// offset; and a real warp in this process (horizon set before the first rmw_init).

#include <dlfcn.h>
#include <gtest/gtest.h>
#include <time.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "rcutils/error_handling.h"
#include "rcutils/time.h"
#include "rmw/rmw.h"

#include "api_fixture.hpp"
#include "detail/clock.hpp"

namespace
{

using TimeNowFn = rcutils_ret_t (*)(rcutils_time_point_value_t *);

// Settings of the middleware in this process: read once, at its first use.
const bool kEnvironment = []() {
  setenv("RMW_INTROSPECT_HORIZON_MS", "60000", 1);
  setenv("RMW_INTROSPECT_SETTLE_MS", "0", 1);
  setenv("RMW_INTROSPECT_AUTO_EXPORT", "0", 1);
  return true;
}();

// The library's own definition (not librcutils', which this executable also links).
TimeNowFn ours(const char * name)
{
  void * handle = dlopen(RMWI_LIBRARY_FILE, RTLD_NOW | RTLD_NOLOAD);
  EXPECT_NE(nullptr, handle) << dlerror();
  void * sym = handle != nullptr ? dlsym(handle, name) : nullptr;
  TimeNowFn fn = nullptr;
  static_assert(sizeof(fn) == sizeof(sym), "function pointer size");
  std::memcpy(&fn, &sym, sizeof(fn));
  return fn;
}

int64_t real_ns(clockid_t clock)
{
  struct timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

constexpr int64_t kSec = 1000000000;

}  // namespace

TEST(VirtualTimeNow, null_argument_is_invalid)
{
  for (const char * name : {"rcutils_steady_time_now", "rcutils_system_time_now"}) {
    TimeNowFn fn = ours(name);
    ASSERT_NE(nullptr, fn) << name;
    rcutils_reset_error();
    EXPECT_EQ(RCUTILS_RET_INVALID_ARGUMENT, fn(nullptr)) << name;
    EXPECT_TRUE(rcutils_error_is_set());
    rcutils_reset_error();
  }
  int64_t now = 0;
  EXPECT_EQ(
    RCUTILS_RET_INVALID_ARGUMENT, rmw_introspect::virtual_time_now(CLOCK_MONOTONIC, 0, nullptr));
  rcutils_reset_error();
  EXPECT_EQ(RCUTILS_RET_OK, rmw_introspect::virtual_time_now(CLOCK_MONOTONIC, 0, &now));
}

TEST(VirtualTimeNow, offset_is_added_to_both_clocks)
{
  for (clockid_t clock : {CLOCK_MONOTONIC, CLOCK_REALTIME}) {
    int64_t now = 0;
    const int64_t before = real_ns(clock);
    ASSERT_EQ(RCUTILS_RET_OK, rmw_introspect::virtual_time_now(clock, 5 * kSec, &now));
    const int64_t after = real_ns(clock);
    EXPECT_GE(now, before + 5 * kSec);
    EXPECT_LE(now, after + 5 * kSec);
  }
  int64_t now = 0;
  rcutils_reset_error();
  EXPECT_EQ(
    RCUTILS_RET_ERROR,
    rmw_introspect::virtual_time_now(CLOCK_MONOTONIC, INT64_MAX - 1, &now));  // overflow
  EXPECT_TRUE(rcutils_error_is_set());
  rcutils_reset_error();
}

TEST(VirtualTimeNow, offset_only_grows)
{
  rmw_introspect::VirtualClock clock;
  clock.advance(3 * kSec);
  clock.advance(-kSec);
  clock.advance(0);
  EXPECT_EQ(3 * kSec, clock.offset_ns());
}

TEST(VirtualTimeNow, monotonic)
{
  TimeNowFn steady = ours("rcutils_steady_time_now");
  ASSERT_NE(nullptr, steady);
  rcutils_time_point_value_t last = 0;
  for (int i = 0; i < 10000; ++i) {
    rcutils_time_point_value_t now = 0;
    ASSERT_EQ(RCUTILS_RET_OK, steady(&now));
    ASSERT_GE(now, last);
    last = now;
  }
}

using WarpInProcess = ApiFixture;

// With RMW_INTROSPECT_HORIZON_MS=60000 and SETTLE_MS=0: the first blocked wait settles the
// process; the warp then makes a 5 s wait with nothing ready return at once, and both
// interposed clocks run 5 s ahead of the real ones.
TEST_F(WarpInProcess, a_finite_wait_jumps_and_both_clocks_move)
{
  ASSERT_TRUE(kEnvironment);
  TimeNowFn steady = ours("rcutils_steady_time_now");
  TimeNowFn system = ours("rcutils_system_time_now");
  ASSERT_NE(nullptr, steady);
  ASSERT_NE(nullptr, system);
  rmw_time_t timeout{5, 0};
  const auto t0 = std::chrono::steady_clock::now();
  bool jumped = false;
  for (int i = 0; i < 3 && !jumped; ++i) {
    void * gcs_storage[1] = {guard_condition->data};
    rmw_guard_conditions_t gcs{1, gcs_storage};
    const auto start = std::chrono::steady_clock::now();
    EXPECT_EQ(
      RMW_RET_TIMEOUT, rmw_wait(nullptr, &gcs, nullptr, nullptr, nullptr, wait_set, &timeout));
    EXPECT_EQ(nullptr, gcs_storage[0]);  // cleared as a timeout does
    jumped = std::chrono::steady_clock::now() - start < std::chrono::seconds(4);
  }
  ASSERT_TRUE(jumped) << "no wait returned before its timeout";
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(20));
  rcutils_time_point_value_t v_steady = 0;
  rcutils_time_point_value_t v_system = 0;
  ASSERT_EQ(RCUTILS_RET_OK, steady(&v_steady));
  ASSERT_EQ(RCUTILS_RET_OK, system(&v_system));
  EXPECT_GE(v_steady - real_ns(CLOCK_MONOTONIC), 4 * kSec);
  EXPECT_GE(v_system - real_ns(CLOCK_REALTIME), 4 * kSec);
  // A poll never jumps; an infinite wait is not a jump either (not tried: it would block).
  const int64_t offset = v_steady - real_ns(CLOCK_MONOTONIC);
  rmw_time_t zero{0, 0};
  EXPECT_EQ(
    RMW_RET_TIMEOUT, rmw_wait(nullptr, nullptr, nullptr, nullptr, nullptr, wait_set, &zero));
  ASSERT_EQ(RCUTILS_RET_OK, steady(&v_steady));
  EXPECT_LT(v_steady - real_ns(CLOCK_MONOTONIC) - offset, kSec / 10);
}
