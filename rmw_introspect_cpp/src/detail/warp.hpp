// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__WARP_HPP_
#define DETAIL__WARP_HPP_

#include <cstdint>
#include <functional>

#include "detail/capture_writer.hpp"
#include "detail/clock.hpp"

namespace rmw_introspect
{

/// The warp (docs/design.md, "Virtual time" and "Detected quiescence"): after the first settle,
/// finite waits with nothing ready jump virtual time (jump) until the node's virtual age would
/// pass the horizon or the real-time budget is spent; a steady periodic timer is fast-forwarded
/// to the horizon; a warp in which the process loops without ever waiting with a timeout
/// stalls. It moves the VirtualClock and keeps what the capture reports of it; the Session
/// decides when it starts and what ends it means (the final settle).
class Warp
{
public:
  struct Settings
  {
    int settle_ms = 10;
    int64_t horizon_ms = 0;
    int64_t budget_ms = 3000;
  };

  Warp(VirtualClock & virtual_clock, const Settings & settings);

  /// The session's time starts at `t0_ns` (real, on the session's clock).
  void set_origin(int64_t t0_ns) { t0_ns_ = t0_ns; }
  /// After the first settle, at `now`: true when the warp starts; false when the node's
  /// virtual age already reached the horizon (horizon_reached()).
  bool begin(int64_t now);
  /// Ends the warp at `now` (the final settle follows).
  void end(int64_t now) { end_ns_ = now; }

  /// A node or endpoint was created or destroyed: a timer that creates something is not
  /// fast-forwarded.
  void on_change();
  /// A poll and an activity call in the warp: the process runs a loop.
  void on_poll();
  void on_activity();

  enum class Jump {
    kJumped,  // virtual time was advanced to the target (or to the horizon)
    kPassed,  // virtual time is already past the target: no jump, but not quiet either
    kEnded,   // the budget is spent or the target is past the horizon: the warp is over
  };
  /// A wait with nothing ready at `now` would sleep until virtual time `target_ns`.
  Jump jump(int64_t now, int64_t target_ns);

  /// The warp's own deadlines at `now`: true when it is over (budget, horizon, or stalled).
  /// `any_blocked`: a thread is blocked in rmw_wait; `idle_polls_proven`: asked only when
  /// idle polls alone could stall the warp (no jump yet, a loop seen, a thread polling).
  /// Lowers `*look_at_ns` to the moment the monitor must look again.
  bool check(
    int64_t now, bool any_blocked, const std::function<bool()> & idle_polls_proven,
    int64_t * look_at_ns);

  /// The final settle was proven while a thread in its loop waited on the real clock until
  /// before the horizon (the warp cannot step it).
  void note_real_waits() { real_waits_ = true; }
  uint64_t jumps() const { return jumps_; }
  bool loop_seen() const { return loop_seen_; }
  bool stalled() const { return stalled_; }
  bool fast_forwarded() const { return fast_forwarded_; }
  /// The warp's part of a capture header at `now`.
  void fill_header(int64_t now, CaptureHeader * header) const;

private:
  VirtualClock & virtual_clock_;
  const Settings settings_;
  int64_t t0_ns_ = 0;
  int64_t start_ns_ = 0;
  int64_t end_ns_ = 0;
  // When a wait last had a timeout (a jump or a try), and whether the process ran a loop
  // meanwhile (polls, activity): the warp cannot advance a process that never waits with a
  // timeout, it stalls (stalled_) instead of running into its budget.
  int64_t last_timed_wait_ns_ = 0;
  bool loop_seen_ = false;
  bool stalled_ = false;
  // What the process did in the warp (a stalled warp's note says which loop it was).
  uint64_t polls_ = 0;
  uint64_t activity_ = 0;
  uint64_t jumps_ = 0;
  int64_t warp_ns_ = 0;
  // Fast-forward of a steady periodic timer (jump).
  int64_t last_target_ns_ = 0;
  int64_t last_step_ns_ = 0;
  uint64_t steady_jumps_ = 0;
  uint64_t odd_jumps_ = 0;
  bool fast_forwarded_ = false;
  bool horizon_reached_ = false;
  bool budget_exhausted_ = false;
  bool real_waits_ = false;
};

}  // namespace rmw_introspect

#endif  // DETAIL__WARP_HPP_
