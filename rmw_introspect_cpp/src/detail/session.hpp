// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__SESSION_HPP_
#define DETAIL__SESSION_HPP_

#include <cstdint>

#include "detail/capture_writer.hpp"
#include "detail/clock.hpp"

namespace rmw_introspect
{

/// When the capture of this process settles and what is written when: a state machine with
/// no thread and no lock of its own, on an injected clock (unit-tested without a process).
/// The Runtime serializes every call and runs the monitor thread that acts on poll().
///
/// Settled = no node/endpoint change for settle_ms AND a thread is blocked in rmw_wait
/// that entered it after the last change. A "running" progress snapshot is due 20 ms after
/// every burst of changes.
class Session
{
public:
  Session(const Clock & clock, int settle_ms);

  /// First rmw_init of the process: the session's time starts. False when already started.
  bool start();
  bool started() const {return started_;}

  /// A node or endpoint was created or destroyed.
  void on_change();
  /// A thread enters rmw_wait (a blocking one); returns the token for leave_wait.
  uint64_t enter_wait();
  void leave_wait(uint64_t token);

  enum class Action
  {
    kNone,          // nothing to do before `deadline_ns` (or the next input, without one)
    kWriteRunning,  // write a "running" progress snapshot now
    kSettle,        // the process settled: write "settled" now
  };
  struct Step
  {
    Action action = Action::kNone;
    bool has_deadline = false;
    int64_t deadline_ns = 0;  // on the session's clock
  };
  /// What the monitor has to do now; the write it asks for is counted as done.
  Step poll();

  /// A capture is being written out of turn (rmw_shutdown, process exit).
  void note_written() {written_generation_ = generation_;}

  /// The process-exit capture is being written: nothing may replace it.
  void begin_exit() {exiting_ = true;}
  bool exiting() const {return exiting_;}

  /// The session's part of a capture header (times, settle) for a write with `state`.
  void fill_header(CaptureHeader * header) const;

private:
  const Clock & clock_;
  const int64_t settle_ns_;
  bool started_ = false;
  bool exiting_ = false;
  int64_t t0_ns_ = 0;
  int64_t last_change_ns_ = 0;
  uint64_t generation_ = 0;       // bumped on every change
  uint64_t waiters_current_ = 0;  // threads in rmw_wait that entered at generation_
  uint64_t written_generation_ = UINT64_MAX;   // last generation written at all
  uint64_t settled_generation_ = UINT64_MAX;   // last generation written as settled
  bool has_settled_ = false;
  int64_t time_to_settle_ns_ = 0;
};

}  // namespace rmw_introspect

#endif  // DETAIL__SESSION_HPP_
