// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/warp.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>

namespace rmw_introspect
{

namespace
{
constexpr int64_t kNsPerMs = 1000 * 1000;
// The warp of a process that made jumps stalls after this long without a wait with a timeout.
constexpr int64_t kStallAfterJumpsNs = 500 * 1000 * 1000;
// Fast-forward (docs/design.md, "Fast-forward of a steady periodic timer"): after this many jumps
// in a row to equally spaced deadlines with no entity created or destroyed, the next jump goes
// straight to the horizon. Two steps count as equal within half the longer one, at least
// kSteadyToleranceNs: a jump's target is the wait's timeout added to the real clock read a
// moment after rcl read it, so it carries the time the process ran in between (a busy machine:
// up to a millisecond and more), while two timers of different periods alternate their steps.
constexpr uint64_t kSteadyJumpsBeforeHorizon = 100;
constexpr int64_t kSteadyToleranceNs = 200 * 1000;
// Steps unlike the reference step forgiven before it is replaced (plus one per ten steady jumps).
constexpr uint64_t kOddJumpsForgiven = 10;
}  // namespace

Warp::Warp(VirtualClock & virtual_clock, const Settings & settings)
: virtual_clock_(virtual_clock), settings_(settings)
{
}

bool Warp::begin(int64_t now)
{
  if (now + virtual_clock_.offset_ns() - t0_ns_ < settings_.horizon_ms * kNsPerMs) {
    start_ns_ = now;
    last_timed_wait_ns_ = now;
    return true;
  }
  horizon_reached_ = true;  // settling took longer than the horizon
  return false;
}

void Warp::on_change()
{
  steady_jumps_ = 0;  // a timer that creates something is not fast-forwarded
  odd_jumps_ = 0;
}

void Warp::on_poll()
{
  loop_seen_ = true;
  ++polls_;
}

void Warp::on_activity()
{
  loop_seen_ = true;
  ++activity_;
}

Warp::Jump Warp::jump(int64_t now, int64_t target_ns)
{
  last_timed_wait_ns_ = now;
  if (now - start_ns_ >= settings_.budget_ms * kNsPerMs) {
    budget_exhausted_ = true;
    return Jump::kEnded;
  }
  const int64_t virtual_now = now + virtual_clock_.offset_ns();
  if (target_ns <= virtual_now) {
    // Another thread's jump, or real time on a busy machine, already took virtual time past
    // it: no jump, but timers still drive the process, so it is not quiet either.
    return Jump::kPassed;
  }
  if (target_ns - t0_ns_ > settings_.horizon_ms * kNsPerMs) {
    horizon_reached_ = true;
    return Jump::kEnded;
  }
  // A periodic timer that fired again and again and created nothing: jump to the horizon
  // at once (rcl then runs its callback once for the missed periods; see kSteadyJumpsBeforeHorizon).
  // Steps are compared with a reference step; a few outliers (the process preempted before its
  // wait on a busy machine) are forgiven, a steady run of other steps becomes the reference.
  const int64_t step = last_target_ns_ != 0 ? target_ns - last_target_ns_ : 0;
  last_target_ns_ = target_ns;
  if (step > 0 && last_step_ns_ > 0 &&
      std::llabs(step - last_step_ns_) <=
        std::max(kSteadyToleranceNs, std::max(step, last_step_ns_) / 2))
  {
    ++steady_jumps_;
  } else if (step > 0 &&
             (last_step_ns_ <= 0 || ++odd_jumps_ > kOddJumpsForgiven + steady_jumps_ / 10))
  {
    last_step_ns_ = step;  // another timer (or none steady): start over with this step
    steady_jumps_ = 0;
    odd_jumps_ = 0;
  }
  if (steady_jumps_ >= kSteadyJumpsBeforeHorizon) {
    const int64_t horizon_target = t0_ns_ + settings_.horizon_ms * kNsPerMs;
    if (horizon_target > target_ns) {
      target_ns = horizon_target;
      fast_forwarded_ = true;
    }
  }
  const int64_t delta = target_ns - virtual_now;
  virtual_clock_.advance(delta);
  ++jumps_;
  warp_ns_ += delta;
  return Jump::kJumped;
}

bool Warp::check(
  int64_t now, bool any_blocked, const std::function<bool()> & idle_polls_proven,
  int64_t * look_at_ns)
{
  const int64_t budget_end = start_ns_ + settings_.budget_ms * kNsPerMs;
  // Real time also ages the node: the real moment its virtual age reaches the horizon.
  const int64_t horizon_at = t0_ns_ + settings_.horizon_ms * kNsPerMs - virtual_clock_.offset_ns();
  if (now >= budget_end) {
    budget_exhausted_ = true;
    return true;
  }
  if (now >= horizon_at) {
    horizon_reached_ = true;
    return true;
  }
  *look_at_ns = std::min(*look_at_ns, std::min(budget_end, horizon_at));
  // No wait with a timeout for a while the process ran a loop (polls, activity): a loop
  // that polls or sleeps on its own clock, with nothing to jump to. Before any jump that
  // is settle_ms; after jumps (timers) kStallAfterJumpsNs at least: a timer due in real
  // time on a busy machine makes rcl poll (timeout 0) until it has caught up.
  const int64_t quiet_ns = static_cast<int64_t>(settings_.settle_ms) * kNsPerMs;
  const int64_t stall_at =
    last_timed_wait_ns_ + (jumps_ == 0 ? quiet_ns : std::max(quiet_ns, kStallAfterJumpsNs));
  if (!any_blocked && now >= stall_at && loop_seen_) {
    stalled_ = true;
    return true;
  }
  if (jumps_ == 0 && loop_seen_ && idle_polls_proven()) {
    // Every thread polls with nothing ready, or is blocked, and nothing changes: nothing
    // to jump to, proven without waiting for the stall window.
    stalled_ = true;
    return true;
  }
  if (!any_blocked) {
    // (looked at again a window later when nothing ran yet)
    *look_at_ns = std::min(*look_at_ns, std::max(stall_at, now + quiet_ns));
  }
  return false;
}

void Warp::fill_header(int64_t now, CaptureHeader * header) const
{
  header->jumps = jumps_;
  header->warp_ms = ns_to_ms(warp_ns_);
  header->horizon_reached = horizon_reached_;
  header->warp_budget_exhausted = budget_exhausted_;
  header->warp_stalled = stalled_;
  header->warp_real_waits = real_waits_ && !horizon_reached_;
  const bool warped = start_ns_ != 0;
  header->warp_real_ms = warped ? ns_to_ms((end_ns_ != 0 ? end_ns_ : now) - start_ns_) : 0.0;
  header->warp_polls = polls_;
  header->warp_activity = activity_;
}

}  // namespace rmw_introspect
