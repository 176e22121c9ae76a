// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__SESSION_HPP_
#define DETAIL__SESSION_HPP_

#include <sys/types.h>

#include <cstdint>
#include <string>

#include "detail/capture_writer.hpp"
#include "detail/clock.hpp"
#include "detail/idle_proof.hpp"
#include "detail/probing.hpp"
#include "detail/warp.hpp"

namespace rmw_introspect
{

/// When the capture of this process settles, when virtual time is warped and what is written
/// when: a state machine with no thread and no lock of its own, on an injected real clock
/// (unit-tested without a process). The Runtime serializes every call and runs the monitor
/// thread that acts on poll(). Phases (see docs/notes vt-spec):
///
/// 1. settling: settled when no node/endpoint changed for settle_ms AND either a thread is
///    blocked in rmw_wait that entered it after the last change ("wait"), or at least two
///    activity calls (publish, take, graph queries, ...) came after it ("activity").
///    With Settings::detect_idle, every settle (this one, after each transition or stimulus,
///    after the warp) ends at once when the process is provably idle (docs/design.md,
///    "Detected quiescence"): a thread blocked in rmw_wait and not woken since, every other
///    thread blocked until woken (the ThreadCensus), and no deadline of a blocked wait inside
///    the rest of the quiet window (before the warp, or past the horizon after it, a deadline
///    does not count). A thread that polls back to back and finds nothing for 10 ms (an idle
///    poller, on_poll) counts like a blocked one, and so does a thread asleep in an interposed
///    sleep after using ROS (enter_sleep), until its sleep's end. The quiet window is the
///    fallback.
/// 1b. probing (Settings::probe): a "probing" snapshot
///    is written, then the middleware asks the nodes' own services, one request at a time
///    (the Runtime's ProbeDriver): kProbe = send the next request now; the answer (or no
///    answer within answer_timeout_ms: kProbeTimeout) breaks the quiet; a request that
///    changes the node (a lifecycle transition) is followed by a settle (the rule of 1)
///    before the next one, a query by the next request at once. When nothing is left to ask,
///    the process settles once more if an answer ran the node's code (a transition, a
///    stimulus), a request timed out or an entity was created meanwhile, and goes on as after
///    1. A process that settled by activity and never entered rmw_wait gets 250 ms to start
///    waiting, longer (up to 2 s) while its main thread is runnable (still setting up, or
///    waiting for a CPU on a busy machine), then the probing is skipped (nothing could take a
///    request).
/// 2. With horizon 0 that settle is final. Otherwise a "warping" snapshot is written and
///    finite waits with nothing ready jump virtual time (try_jump) until the node's virtual
///    age would pass the horizon or the real-time budget is spent.
/// 3. final settle: the same rule as 1, where a jump also counts as a change. Then the
///    final "settled" capture is written.
/// A "running" (before the first settle) or "warping" progress snapshot is due 20 ms after
/// every burst of entity changes.
/// The Session keeps the phases, the generations of entity changes and the quiet rule; it
/// composes the parts it hands the rest to: the IdleProof (idle_proof.hpp: blocked waits,
/// sleepers, idle pollers, the census), the Warp (warp.hpp: jumps, fast-forward, budget,
/// stall) and the Probing (probing.hpp: the pace of the requests).
class Session
{
public:
  struct Settings
  {
    int settle_ms = 10;
    int64_t horizon_ms = 0;
    int64_t warp_budget_ms = 3000;
    bool probe = false;               // ask the nodes' services after the first settle
    int64_t answer_timeout_ms = 5000;  // real time a node has to answer one request
    bool detect_idle = false;         // settle at once when provably idle (RMW_INTROSPECT_IDLE)
    bool virtual_sleeps = false;  // the warp jumps the process's sleeps (RMW_INTROSPECT_SLEEPS)
  };

  /// `main_thread`: whether the main thread is runnable (null: taken as never; unit tests).
  Session(
    const Clock & clock, VirtualClock & virtual_clock, const Settings & settings,
    const MainThreadState * main_thread = nullptr);

  /// First rmw_init of the process: the session's time starts. False when already started.
  bool start();
  bool started() const { return started_; }

  /// A node or endpoint was created or destroyed, by thread `tid` (0: not known).
  void on_change(pid_t tid = 0);
  /// A thread enters rmw_wait (any wait, a poll included). In the warp this breaks the quiet:
  /// a process that keeps entering waits that jump or poll is still driven by its timers
  /// (on a busy machine real time alone can keep its short timers due).
  void on_wait_entered();
  /// Thread `tid` polled rmw_wait (timeout 0, or a wait that found something ready as it
  /// entered): a wait entry (on_wait_entered), and, like an activity call, a sign of a loop
  /// (spin_some, spin_once(timeout_sec=0)): at least two after the last change settle the
  /// process once it was quiet for settle_ms (settled_by "poll"). `found_nothing`: nothing of
  /// its wait set was ready; back-to-back polls that find nothing can prove the thread idle
  /// (docs/design.md, "Detected quiescence", idle pollers). True when the monitor should look
  /// again.
  /// `voluntary_switches`: how often the thread has blocked or slept so far (getrusage): a gap
  /// between two polls in which it did is a pause of its own (a sleep), not a preemption.
  bool on_poll(pid_t tid = 0, bool found_nothing = false, uint64_t voluntary_switches = 0);
  /// Whether the warp jumped straight to the horizon (a steady periodic timer; try_jump).
  bool fast_forwarded() const { return warp_.fast_forwarded(); }
  /// Thread `tid` blocks in rmw_wait until real time `deadline_ns` (negative: no deadline);
  /// returns the token for leave_wait. Called under the wait hub's lock, after the thread
  /// found nothing ready.
  uint64_t enter_wait(pid_t tid = 0, int64_t deadline_ns = -1);
  void leave_wait(uint64_t token);
  /// The wait hub woke its waiters (a trigger, a request, a delivery, a shutdown): a blocked
  /// wait proves nothing until its thread has looked again and blocked again. `by`: the
  /// triggering thread (0: none of the program's); an idle poller's own trigger (rclpy's
  /// spin_once(node) before every wait) keeps what a census found.
  void on_wake(pid_t by = 0) { idle_.on_wake(by); }
  /// The middleware's own monitor thread (left out of the census).
  void set_monitor_tid(pid_t tid) { idle_.set_monitor_tid(tid); }

  /// What kCheckIdle asks: are the threads not in `known` blocked until woken, or until
  /// `until_ns` (the end of the quiet window) at least? Answered for `version` only.
  using CensusRequest = IdleProof::CensusRequest;
  const CensusRequest & census_request() const { return idle_.census_request(); }
  /// The answer to census_request() (read with no lock held: anything that happened meanwhile
  /// changed the version, and the answer is dropped). `culprit`: why not, for people.
  /// `setting_up`: a thread still setting up that the census found (it may hold the settle).
  void census_done(
    uint64_t version, bool idle, const std::string & culprit,
    const SettingUp & setting_up = SettingUp())
  {
    idle_.census_done(version, idle, culprit, clock_.now_ns(), setting_up);
  }
  /// Why the latest census found the process not idle ("" when it did, or none ran).
  const std::string & not_idle_reason() const { return idle_.not_idle_reason(); }
  /// publish, take*, send_request/response, take_request/response, graph queries, counts of
  /// matched endpoints, server_is_available, by thread `tid`. True when the monitor should
  /// look again.
  bool on_activity(pid_t tid = 0);

  /// Thread `tid` sleeps (an interposed nanosleep, clock_nanosleep, usleep or sleep: src/sleep.cpp)
  /// until real time `deadline_ns`; returns the token for leave_sleep. A sleeper that used ROS
  /// (an activity call) since the last change is in its loop, and with virtual sleeps the warp
  /// steps it: it counts like a blocked wait with that deadline (docs/design.md, "Sleeps").
  uint64_t enter_sleep(pid_t tid, int64_t deadline_ns);
  void leave_sleep(uint64_t token) { idle_.leave_sleep(token); }

  /// In the warp: a wait with nothing ready would sleep until virtual time `target_ns` (the
  /// virtual time at its entry + its timeout). True: virtual time is now past it (jumped, or
  /// already past), the wait returns a timeout at once; either breaks the quiet of the final
  /// settle. False: wait for real (no warp, horizon reached, budget spent).
  bool try_jump(int64_t target_ns);
  bool warping() const { return phase_ == Phase::kWarping; }
  /// Virtual now on the steady clock (real monotonic + offset).
  int64_t virtual_now_ns() const { return clock_.now_ns() + virtual_clock_.offset_ns(); }

  enum class Action {
    kNone,  // nothing to do before `deadline_ns` (or the next input, without one)
    kWriteRunning,  // write a progress snapshot now (progress_state())
    kStartWarp,  // settled once: write "warping" now and wake the waiters to jump
    kSettle,  // settled for good: write "settled" now
    kStartProbe,  // settled once: write "probing" now (then kProbe follows)
    kProbe,  // send the next request now: then probe_sent(), or probe_done()
    kProbeTimeout,  // the request in flight got no answer in time (then kProbe follows)
    kCheckIdle,  // every thread in rmw_wait is blocked: read the other threads
    // (census_request(), a ThreadCensus, then census_done())
  };
  struct Step
  {
    Action action = Action::kNone;
    bool has_deadline = false;
    int64_t deadline_ns = 0;  // on the session's clock
  };
  /// What the monitor has to do now; the write it asks for is counted as done.
  Step poll();
  /// "running" before the first settle and after the final one, "probing" or "warping" in
  /// between.
  const char * progress_state() const;

  /// Probing: a request is about to reach the node (call it before the node can see it).
  void probe_sent() { probing_.sent(clock_.now_ns()); }
  /// Probing: the answer to the request in flight came. `settle_first`: the node changed
  /// (a transition); it must settle again before the next request.
  void probe_answered(bool settle_first);
  /// Probing: nothing (more) to ask.
  void probe_done() { probing_.done(); }
  bool probing() const { return phase_ == Phase::kProbing; }
  /// "off" (nothing to ask), "pending" (not settled yet), "running", "done", "skipped"
  /// (no thread entered rmw_wait in time after the settle: no executor to ask).
  const char * probe_state() const;

  /// A capture is being written out of turn (rmw_shutdown, process exit).
  void note_written() { written_generation_ = generation_; }

  /// The process-exit capture is being written: nothing may replace it.
  void begin_exit() { exiting_ = true; }
  bool exiting() const { return exiting_; }

  /// The session's part of a capture header for a write with `state` (times, settle, warp;
  /// `ended` for "exit" and "shutdown").
  void fill_header(const char * state, CaptureHeader * header) const;

  /// Real and virtual age now, for the creation times of entities.
  double real_age_ms() const { return ns_to_ms(clock_.now_ns() - t0_ns_); }
  double virtual_age_ms() const { return ns_to_ms(virtual_now_ns() - t0_ns_); }

private:
  enum class Phase { kSettling, kProbing, kWarping, kFinalSettling, kDone };

  /// A change for the quiet rule: entity change, jump, warp start. `voids_polls`: false for the
  /// polls of the warp (they break its quiet but are what an idle poller does).
  void break_quiet(int64_t now, bool voids_polls = true);
  /// What the idle proof needs to know of the session at `now`.
  IdleProof::Moment moment(int64_t now) const;
  void end_warp(int64_t now);
  /// The warp stalled without a jump and nothing changed since the first settle (poll()).
  bool stalled_unchanged() const;
  /// A settle is written now (time to settle, generations).
  void mark_settled(int64_t now);
  /// The first settle, at `now`, starts the probing.
  void start_probing(int64_t now, Step * step);
  /// After the first settle (and the probing): start the warp or settle for good.
  void after_first_settle(int64_t now, Step * step);
  /// poll() in the probing phase: true when `step` has an action.
  bool poll_probing(int64_t now, Step * step);
  /// The settle rule at `now`: true when settled; else may set `deadline`.
  bool quiet_settled(int64_t now, bool * has_deadline, int64_t * deadline);
  /// Detected quiescence at `now` (see the class comment).
  bool provably_idle(int64_t now);
  /// The latest settle was proven by sleepers alone (settled_by "sleep").
  bool settled_by_sleep() const;

  const Clock & clock_;
  VirtualClock & virtual_clock_;
  const Settings settings_;
  IdleProof idle_;
  Warp warp_;
  Probing probing_;
  Phase phase_ = Phase::kSettling;
  bool started_ = false;
  bool exiting_ = false;
  int64_t t0_ns_ = 0;
  // Entity changes: progress snapshots and settles are per generation.
  uint64_t generation_ = 0;
  int64_t last_change_ns_ = 0;
  uint64_t written_generation_ = UINT64_MAX;  // last generation written at all
  uint64_t settled_generation_ = UINT64_MAX;  // last generation written as settled
  // The quiet rule: entity changes and jumps.
  uint64_t quiet_epoch_ = 0;
  int64_t quiet_since_ns_ = 0;
  uint64_t waiters_current_ = 0;  // threads in rmw_wait that entered in quiet_epoch_
  uint64_t activity_current_ = 0;  // activity calls in quiet_epoch_
  uint64_t polls_current_ = 0;  // polls in quiet_epoch_
  uint64_t polls_ = 0;  // ... in all
  // Reported.
  uint64_t idle_settles_ = 0;  // settles that ended by detection
  uint64_t window_settles_ = 0;  // settles that ended by the quiet window (or activity)
  bool has_settled_ = false;
  int64_t time_to_settle_ns_ = 0;
  const char * settled_by_ = nullptr;
  bool ever_waited_ = false;
  uint64_t activity_calls_ = 0;
};

}  // namespace rmw_introspect

#endif  // DETAIL__SESSION_HPP_
