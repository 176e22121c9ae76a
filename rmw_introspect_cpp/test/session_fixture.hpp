// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// What the Session's tests share (test_session.cpp, test_idle_proof.cpp, test_warp.cpp,
// test_probing.cpp; one binary): a manual clock and the settings they start from.
#ifndef SESSION_FIXTURE_HPP_
#define SESSION_FIXTURE_HPP_

#include <cstdint>

#include "detail/clock.hpp"
#include "detail/session.hpp"

namespace session_test
{

using rmw_introspect::CaptureHeader;
using rmw_introspect::Session;

constexpr int64_t kMs = 1000 * 1000;

class ManualClock : public rmw_introspect::Clock
{
public:
  int64_t now_ns() const override { return now; }
  void advance_ms(int64_t ms) { now += ms * kMs; }
  int64_t now = 1000 * kMs;
};

inline Session::Settings settings(int64_t horizon_ms = 0, int64_t budget_ms = 3000)
{
  Session::Settings s;
  s.settle_ms = 10;
  s.horizon_ms = horizon_ms;
  s.warp_budget_ms = budget_ms;
  return s;
}

}  // namespace session_test

#endif  // SESSION_FIXTURE_HPP_
