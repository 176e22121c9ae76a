// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__RUNTIME_HPP_
#define DETAIL__RUNTIME_HPP_

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "detail/clock.hpp"
#include "detail/config.hpp"
#include "detail/graph_guards.hpp"
#include "detail/recorder.hpp"
#include "detail/session.hpp"
#include "detail/wait_hub.hpp"

namespace rmw_introspect
{

struct ContextImpl;

/// Everything this process's middleware keeps beyond the handles rcl holds: configuration,
/// recorder, session (settle) with its monitor thread, wait hub and graph guard conditions.
/// One object per process, reached through instance() by the rmw_* entry points.
///
/// Lock order: a thread holding one of these mutexes takes only those further down the list.
///   1. Runtime::write_mutex_    serializes capture writes (held while rendering one)
///   2. GraphGuards' mutex       trigger_all() triggers through the wait hub
///   3. WaitHub's mutex          rmw_wait registers a blocked thread with the session under it
///   4. Runtime::session_mutex_  the Session; the monitor thread sleeps on session_cv_
///   5. Recorder's mutex         a leaf: its change listener (-> session) runs after release
/// Per-entity mutexes (stored callbacks, a subscription's content filter) are leaves too.
class Runtime
{
public:
  /// The process-wide runtime, made on first use and never destroyed: atexit handlers, the
  /// monitor thread and waits still running in other threads use it while the process exits.
  static Runtime & instance();

  Runtime(const Runtime &) = delete;
  Runtime & operator=(const Runtime &) = delete;

  const Config & config() const {return config_;}
  Recorder & recorder() {return recorder_;}
  WaitHub & wait_hub() {return wait_hub_;}
  GraphGuards & graph_guards() {return graph_guards_;}

  /// Trigger the graph guard condition of every live node (a local graph change).
  void notify_graph_change();

  /// First rmw_init of the process: start the session and its monitor, register atexit.
  void on_init();
  /// A thread blocks in rmw_wait; returns the token for leave_wait.
  uint64_t enter_wait();
  void leave_wait(uint64_t token);
  /// rmw_shutdown: write a capture with state "shutdown".
  void on_shutdown();
  /// Normal process exit (atexit): write a capture with state "exit".
  void on_process_exit();

  /// True when destroying an entity now is teardown rather than behaviour: its context was
  /// shut down, the process is exiting (atexit ran), or the Python interpreter is finalizing.
  bool in_teardown(const ContextImpl * context);

private:
  Runtime();
  void on_change();
  void monitor_loop();
  /// Write the capture with `state` (no-op with AUTO_EXPORT=0 or before rmw_init; once the
  /// exit capture is being written, nothing else replaces it).
  void write_capture(const char * state);
  /// The settled capture is written: end the process when RMW_INTROSPECT_EXIT=1.
  void exit_if_asked(double time_to_settle_ms);

  const Config config_;
  const SteadyClock clock_;
  Recorder recorder_;
  WaitHub wait_hub_;
  GraphGuards graph_guards_;
  std::vector<std::string> argv_;  // read at rmw_init (immutable after)

  std::mutex write_mutex_;
  std::mutex session_mutex_;
  std::condition_variable session_cv_;
  Session session_;
};

}  // namespace rmw_introspect

#endif  // DETAIL__RUNTIME_HPP_
