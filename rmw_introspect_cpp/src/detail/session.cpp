// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/session.hpp"

namespace rmw_introspect
{

namespace
{
// Delay after the last change before a "running" progress snapshot is written.
constexpr int64_t kSnapshotDelayNs = 20 * 1000 * 1000;
constexpr int64_t kNsPerMs = 1000 * 1000;
}  // namespace

Session::Session(const Clock & clock, int settle_ms)
: clock_(clock), settle_ns_(static_cast<int64_t>(settle_ms) * kNsPerMs)
{
}

bool Session::start()
{
  if (started_) {
    return false;
  }
  started_ = true;
  t0_ns_ = clock_.now_ns();
  last_change_ns_ = t0_ns_;
  return true;
}

void Session::on_change()
{
  ++generation_;
  last_change_ns_ = clock_.now_ns();
  waiters_current_ = 0;
}

uint64_t Session::enter_wait()
{
  ++waiters_current_;
  return generation_;
}

void Session::leave_wait(uint64_t token)
{
  if (token == generation_ && waiters_current_ > 0) {
    --waiters_current_;
  }
}

Session::Step Session::poll()
{
  Step step;
  if (!started_ || exiting_) {
    return step;
  }
  const int64_t now = clock_.now_ns();
  if (settled_generation_ != generation_ && waiters_current_ > 0) {
    const int64_t settle_at = last_change_ns_ + settle_ns_;
    if (now >= settle_at) {
      settled_generation_ = generation_;
      written_generation_ = generation_;
      has_settled_ = true;
      time_to_settle_ns_ = now - t0_ns_;
      step.action = Action::kSettle;
      return step;
    }
    step.has_deadline = true;
    step.deadline_ns = settle_at;
  }
  if (written_generation_ != generation_) {
    const int64_t snapshot_at = last_change_ns_ + kSnapshotDelayNs;
    if (now >= snapshot_at) {
      written_generation_ = generation_;
      step.action = Action::kWriteRunning;
      step.has_deadline = false;
      return step;
    }
    if (!step.has_deadline || snapshot_at < step.deadline_ns) {
      step.has_deadline = true;
      step.deadline_ns = snapshot_at;
    }
  }
  return step;
}

void Session::fill_header(CaptureHeader * header) const
{
  header->settle_ms = static_cast<int>(settle_ns_ / kNsPerMs);
  header->has_time_to_settle = has_settled_;
  header->time_to_settle_ms = ns_to_ms(time_to_settle_ns_);
  header->elapsed_ms = ns_to_ms(clock_.now_ns() - t0_ns_);
}

}  // namespace rmw_introspect
