// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__RUNTIME_HPP_
#define DETAIL__RUNTIME_HPP_

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "detail/capture_writer.hpp"
#include "detail/clock.hpp"
#include "detail/config.hpp"
#include "detail/delivery.hpp"
#include "detail/graph_guards.hpp"
#include "detail/injector.hpp"
#include "detail/probe_driver.hpp"
#include "detail/recorder.hpp"
#include "detail/session.hpp"
#include "detail/thread_census.hpp"
#include "detail/wait_hub.hpp"

namespace rmw_introspect
{

struct ContextImpl;

/// Everything this process's middleware keeps beyond the handles rcl holds: configuration,
/// recorder, session (settle) with its monitor thread, wait hub, graph guard conditions, and
/// the injector + probe driver that ask the nodes' own services after the first settle and
/// deliver the stimuli (RMW_INTROSPECT_STIMULI).
/// One object per process, reached through instance() by the rmw_* entry points.
///
/// Lock order: a thread holding one of these mutexes takes only those further down the list.
///   1. Runtime::write_mutex_    serializes capture writes (held while rendering one; guards
///                               capture_renderer_ and its cache of rendered types)
///   2. GraphGuards' mutex       trigger_all() triggers through the wait hub
///   3. Injector's mutex         release() makes a request ready through the wait hub; its
///                               answer listener (-> session) runs after release
///   4. WaitHub's mutex          rmw_wait registers a blocked thread with the session under it
///   5. Runtime::session_mutex_  the Session; the monitor thread sleeps on session_cv_
///   6. Recorder's mutex         a leaf: its change listener (-> session) runs after release
/// Per-entity mutexes (stored callbacks, a subscription's content filter) and stimuli_mutex_
/// are leaves too.
/// Delivery's mutex is taken with none of the above held and takes only per-entity ones (a
/// content filter, then an inbox or a matched status); the waiters are woken and the "new
/// data" callbacks called after it is released. rmw_wait reads readiness from atomics.
class Runtime
{
public:
  /// The process-wide runtime, made on first use and never destroyed: atexit handlers, the
  /// monitor thread and waits still running in other threads use it while the process exits.
  /// A process forked before its parent's rmw_init (a warm start server's child) makes its own
  /// on first use, so the configuration is read from the child's environment, after the fork.
  static Runtime & instance();
  /// The runtime when rmw_init reached it in this very process (not in a parent it was forked
  /// from), else null; never makes one (the interposed sleeps of any process ask it).
  static Runtime * started_instance();

  Runtime(const Runtime &) = delete;
  Runtime & operator=(const Runtime &) = delete;

  const Config & config() const { return config_; }
  const VirtualClock & virtual_clock() const { return virtual_clock_; }
  Recorder & recorder() { return recorder_; }
  WaitHub & wait_hub() { return wait_hub_; }
  GraphGuards & graph_guards() { return graph_guards_; }
  /// In-process delivery (RMW_INTROSPECT_DELIVERY=1): who receives what this process sends.
  Delivery & delivery() { return delivery_; }
  /// The middleware's own requests to the nodes' services (parameters, lifecycle).
  Injector & injector() { return injector_; }

  /// Trigger the graph guard condition of every live node (a local graph change).
  void notify_graph_change();

  /// First rmw_init of the process: start the session and its monitor, register atexit.
  void on_init();
  /// The blocking part of rmw_wait: until `ready()` (evaluated under the wait hub's lock)
  /// holds or `timeout_ns` passes (0: poll, negative: forever). In the warp, a finite wait
  /// with nothing ready jumps virtual time instead and returns at once. `work()`: whether
  /// anything is ready that the calling thread did not trigger itself (a poll that finds
  /// nothing is an idle poll: Session::on_poll).
  template<typename ReadyFn, typename WorkFn>
  void wait(ReadyFn ready, WorkFn work, int64_t timeout_ns);
  /// publish, take*, send_*, graph queries...: the process is in its loop (settle rule).
  void on_activity();

  /// Sleeps (detail/sleep.hpp): whether the warp steps this process's sleeps (virtual time
  /// and RMW_INTROSPECT_SLEEPS on).
  bool sleeps_stepped() const { return sleeps_stepped_; }
  /// In the warp: jump virtual time by `duration_ns` for the calling thread's sleep; true when
  /// the sleep is over (false: no warp, or it ended at the horizon or by its budget).
  bool jump_sleep(int64_t duration_ns);
  /// How often the warp started (0 or 1), and whether it is still to come.
  uint64_t warp_starts() const { return warp_starts_.load(); }
  bool warp_to_come() const { return sleeps_stepped_ && warp_starts_.load() == 0; }
  /// RAII registration of the calling thread's real sleep until `deadline_ns` (Session::enter_sleep).
  class Sleeping
  {
  public:
    Sleeping(Runtime & runtime, int64_t deadline_ns);
    ~Sleeping();
    Sleeping(const Sleeping &) = delete;
    Sleeping & operator=(const Sleeping &) = delete;

  private:
    Runtime & runtime_;
    uint64_t token_;
  };
  /// The process's virtual and real age now (creation times).
  CreationTime creation_time();
  /// rmw_shutdown: write a capture with state "shutdown".
  void on_shutdown();
  /// Normal process exit (atexit): write a capture with state "exit".
  void on_process_exit();

  /// True when destroying an entity now is teardown rather than behaviour: its context was
  /// shut down, the process is exiting (atexit ran), or the Python interpreter is finalizing.
  bool in_teardown(const ContextImpl * context);

private:
  /// RAII registration of a thread blocked in rmw_wait (settle rule).
  class BlockedWait
  {
  public:
    BlockedWait(Runtime & runtime, int64_t deadline_ns)
    : runtime_(runtime), token_(runtime.enter_wait(deadline_ns))
    {
    }
    ~BlockedWait() { runtime_.leave_wait(token_); }
    BlockedWait(const BlockedWait &) = delete;
    BlockedWait & operator=(const BlockedWait &) = delete;

  private:
    Runtime & runtime_;
    uint64_t token_;
  };

  Runtime();
  /// `deadline_ns`: real steady time the wait ends by itself (negative: never).
  uint64_t enter_wait(int64_t deadline_ns);
  void leave_wait(uint64_t token);
  void note_wait_entered();
  /// A poll (timeout 0, or a wait that found something ready at once; see Session::on_poll).
  void note_poll(bool found_nothing);
  /// In the warp and with nothing ready: jump virtual time to `target_ns` (see Session).
  template<typename ReadyFn>
  bool try_jump(ReadyFn & ready, int64_t target_ns);
  void on_change();
  /// The injector got the answer to the request in flight (or it failed).
  void on_probe_answer(bool changes_node);
  /// The monitor's kProbe / kProbeTimeout (no lock held).
  void probe_step();
  void probe_timeout();
  /// Copy what the stimuli came to for the captures (monitor thread).
  void publish_stimuli();
  void monitor_loop();
  /// The monitor's kCheckIdle: read the other threads with no lock held (`lock` is the
  /// session's, held on entry and on return).
  void check_idle(std::unique_lock<std::mutex> & lock);
  /// Write the capture with `state` (no-op with AUTO_EXPORT=0 or before rmw_init; once the
  /// exit capture is being written, nothing else replaces it).
  void write_capture(const char * state);
  /// The settled capture is written: end the process when RMW_INTROSPECT_EXIT=1.
  void exit_if_asked(double time_to_settle_ms);

  const Config config_;
  const SteadyClock clock_;
  const ProcMainThreadState main_thread_state_;
  ProcThreadCensus thread_census_;  // the monitor thread's only
  VirtualClock virtual_clock_;
  Recorder recorder_;
  WaitHub wait_hub_;
  Delivery delivery_;
  GraphGuards graph_guards_;
  Injector injector_;
  ProbeDriver probe_driver_;  // the monitor thread's only
  std::atomic<uint64_t> probe_requests_{0};
  std::atomic<uint64_t> probe_unanswered_{0};
  std::mutex stimuli_mutex_;  // a leaf: guards stimuli_
  std::vector<StimulusRecord> stimuli_;  // the ProbeDriver's, as last published
  std::vector<ComponentLoadRecord> component_loads_;  // the same (guarded by stimuli_mutex_)
  std::vector<std::string> argv_;  // read at rmw_init (immutable after)

  std::mutex write_mutex_;
  CaptureRenderer capture_renderer_;  // guarded by write_mutex_
  std::string output_path_;  // where captures go, chosen at the first write (write_mutex_)
  std::mutex session_mutex_;
  std::condition_variable session_cv_;
  Session session_;
  // Lock-free hints for rmw_wait (the Session under session_mutex_ decides).
  std::atomic<bool> ever_waited_{false};
  std::atomic<bool> warping_{false};
  std::atomic<uint64_t> warp_starts_{0};  // bumped under the wait hub's lock
  const bool sleeps_stepped_;
  pid_t init_pid_ = 0;  // the process whose rmw_init started the session (started_instance)
};

template<typename ReadyFn>
bool Runtime::try_jump(ReadyFn & ready, int64_t target_ns)
{
  if (wait_hub_.poll(ready)) {
    return false;  // ready: nothing to jump for
  }
  std::lock_guard<std::mutex> lock(session_mutex_);
  const bool jumped = session_.try_jump(target_ns);
  warping_.store(session_.warping());
  return jumped;
}

template<typename ReadyFn, typename WorkFn>
void Runtime::wait(ReadyFn ready, WorkFn work, int64_t timeout_ns)
{
  if (timeout_ns == 0) {
    // A poll: rmw_wait reads the guard conditions itself; a loop of polls is in its loop.
    note_poll(!wait_hub_.poll(work));
    return;
  }
  if (ready()) {
    // Returns without waiting, like a poll: a loop that triggers its own guard condition before
    // every wait (rclpy's spin_once(node) adds and removes the node, each a trigger) and runs a
    // task that awaits an answer that never comes waits this way forever (issue 24 item 5).
    note_poll(!work());
    return;
  }
  note_wait_entered();
  const int64_t start_ns = clock_.now_ns();
  const int64_t target_ns = start_ns + virtual_clock_.offset_ns() + timeout_ns;
  for (int64_t remaining = timeout_ns;;) {
    if (remaining > 0 && warping_.load() && try_jump(ready, target_ns)) {
      return;
    }
    // The start of the warp wakes every waiter: a finite wait re-enters to jump, an infinite
    // one re-registers as blocked after the warp began (the settle rule counts only those).
    const uint64_t warp_starts = warp_starts_.load();
    auto ready_or_warp = [&]() { return ready() || warp_starts_.load() != warp_starts; };
    const int64_t deadline_ns = remaining < 0 ? -1 : clock_.now_ns() + remaining;
    wait_hub_.wait(ready_or_warp, remaining, [this, deadline_ns]() -> BlockedWait {
      return BlockedWait(*this, deadline_ns);
    });
    if (warp_starts_.load() == warp_starts || ready()) {
      return;
    }
    if (remaining > 0) {
      remaining = timeout_ns - (clock_.now_ns() - start_ns);
      if (remaining <= 0) {
        return;
      }
    }
  }
}

}  // namespace rmw_introspect

#endif  // DETAIL__RUNTIME_HPP_
