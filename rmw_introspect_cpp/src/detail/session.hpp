// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__SESSION_HPP_
#define DETAIL__SESSION_HPP_

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include "detail/config.hpp"

namespace rmw_introspect
{

/// Settle detection, progress snapshots and capture writing for this process.
///
/// Settled = no node/endpoint change for settle_ms AND a thread is blocked in rmw_wait
/// that entered it after the last change. A small monitor thread (sleeping on a condition
/// variable, no polling) does the timing; it never keeps the process alive.
class Session
{
public:
  static Session & instance();

  /// First rmw_init of the process: start the clock and the monitor, register atexit.
  void on_init();
  /// A node or endpoint was created or destroyed (recorder listener).
  void on_change();
  /// A thread enters rmw_wait; returns the token for leave_wait.
  uint64_t enter_wait();
  void leave_wait(uint64_t token);
  /// rmw_shutdown: write a capture with state "shutdown".
  void on_shutdown();
  /// Normal process exit (atexit): write a capture with state "exit".
  void on_process_exit();

  /// True once the process-exit capture is being written.
  bool exiting();

  /// Write the capture now with `state` (no-op with AUTO_EXPORT=0 or before rmw_init).
  void write_capture(const char * state);

private:
  Session();
  void monitor_loop();
  void settle_locked(std::unique_lock<std::mutex> & lock);
  void write_capture_unlocked(const char * state, double time_to_settle_ms, bool has_settle);

  using Clock = std::chrono::steady_clock;

  const Config & config_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool initialized_ = false;
  bool exiting_ = false;
  Clock::time_point t0_{};
  Clock::time_point last_change_{};
  uint64_t generation_ = 0;       // bumped on every change
  uint64_t waiters_current_ = 0;  // threads in rmw_wait that entered at generation_
  uint64_t written_generation_ = UINT64_MAX;   // last generation written at all
  uint64_t settled_generation_ = UINT64_MAX;   // last generation written as settled
  bool has_settled_ = false;
  double time_to_settle_ms_ = 0.0;
  std::mutex write_mutex_;
};

}  // namespace rmw_introspect

#endif  // DETAIL__SESSION_HPP_
