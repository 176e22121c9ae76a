// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__IDLE_PROOF_HPP_
#define DETAIL__IDLE_PROOF_HPP_

#include <sys/types.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "detail/thread_census.hpp"
#include "detail/thread_marks.hpp"

namespace rmw_introspect
{

/// Detected quiescence (docs/design.md, "Detected quiescence"): whether the process is provably
/// idle now, so that a settle may end before its quiet window. The evidence: threads blocked in
/// rmw_wait and not woken since (blocked waits), threads asleep in an interposed sleep in their
/// loop (sleepers), threads that poll back to back and find nothing (idle pollers), and what a
/// ThreadCensus (thread_census.hpp) reads of every other thread. No clock, no thread, no lock of
/// its own: the Session feeds it and asks it (provably_idle), the monitor answers its census
/// requests.
class IdleProof
{
public:
  struct Settings
  {
    int settle_ms = 10;
    bool detect_idle = false;  // off: provably_idle() is always false
    bool sleeps_count = false;  // a sleep can be stepped (virtual sleeps and a horizon)
  };

  /// What the Session knows at the moment of a proof.
  struct Moment
  {
    int64_t now_ns = 0;
    /// The end of the quiet window: nothing may happen before it.
    int64_t window_end_ns = 0;
    /// The generation of entity changes (a sleeper that used ROS since is in its loop).
    uint64_t generation = 0;
    bool warping = false;
    /// A deadline after this (real time) does not hold the settle: INT64_MAX without a warp,
    /// INT64_MIN with the warp to come (it jumps to it next), past the horizon after it.
    int64_t deadlines_until_ns = INT64_MAX;
    /// False in a warp after jumps (the stall rule decides) or before its loop was seen.
    bool pollers_prove = true;
    /// A thread still setting up (asleep, or in a wait with a deadline, without having used ROS
    /// since the last change) holds the settle until it wakes when it wakes at or before this
    /// (real time): the moment the node's virtual age reaches the horizon. INT64_MIN: never
    /// (no virtual time: the quiet window is all the time the process gets).
    int64_t hold_limit_ns = INT64_MIN;
  };

  explicit IdleProof(const Settings & settings);

  /// Something happened (a change, a jump, an activity call): every poll run starts again and
  /// a census answer is stale.
  void new_epoch();
  /// Thread `tid` polled at `now` (see Session::on_poll). True when its run of polls that found
  /// nothing became long enough just now and the monitor should look.
  bool on_poll(pid_t tid, int64_t now, bool found_nothing, uint64_t voluntary_switches);
  /// Thread `tid` blocks in rmw_wait until `deadline_ns` (negative: none), in quiet epoch
  /// `quiet_epoch` of the Session; returns the token for leave_wait.
  uint64_t enter_wait(pid_t tid, int64_t deadline_ns, uint64_t quiet_epoch);
  /// False for an unknown token; else `*quiet_epoch` is the one the wait entered in.
  bool leave_wait(uint64_t token, uint64_t * quiet_epoch);
  uint64_t enter_sleep(pid_t tid, int64_t deadline_ns);
  void leave_sleep(uint64_t token);
  /// Thread `tid` made an activity call in generation `generation` (0: no thread known).
  void on_activity(pid_t tid, uint64_t generation);
  /// Thread `tid` made one of the program's ROS calls (created or destroyed something, polled,
  /// waited, used ROS): a thread of the program's, not a library's worker that never calls ROS.
  void on_ros_call(pid_t tid);
  /// See Session::on_wake.
  void on_wake(pid_t by);
  void set_monitor_tid(pid_t tid) { monitor_tid_ = tid; }

  /// Thread `tid` made an activity call in generation `generation`.
  bool used_ros_in(pid_t tid, uint64_t generation) const;
  bool any_blocked() const { return !blocked_.empty(); }
  bool any_polling() const { return !poll_runs_.empty(); }
  /// Whether a sleeper counts like a blocked wait (used ROS since the last change, a sleep the
  /// warp can step, not in the warp).
  bool sleepers_count(const Moment & moment) const;
  /// The earliest end of a sleep that counts (INT64_MAX: none).
  int64_t first_counted_wake(const Moment & moment) const;

  /// The proof at `moment`; may leave a census request (look_done).
  bool provably_idle(const Moment & moment);
  /// What the latest proof rested on: "poll" (idle pollers), "sleep" (sleepers alone), "wait".
  const char * proven_by() const;

  /// Before a look of the monitor (Session::poll): no census wanted, no recheck yet.
  void look_begins();
  /// After it: true when a census is wanted now; lowers `*recheck_ns` to when to look again.
  bool look_done(int64_t now, int64_t * recheck_ns);

  /// What kCheckIdle asks (Session::census_request): are the threads not in `known` blocked
  /// until woken, or until `until_ns` (the end of the quiet window) at least? Answered for
  /// `version` only.
  /// `settling`: the threads that made ROS calls, but none since the last change; a wait with a
  /// deadline of one of them is set-up, not a loop's (ThreadCensus::others_blocked).
  struct CensusRequest
  {
    uint64_t version = 0;
    std::vector<pid_t> known;
    int64_t until_ns = 0;
    std::vector<pid_t> settling;
    std::vector<pid_t> looping;  // threads of the program that used ROS since the last change
  };
  const CensusRequest & census_request() const { return census_request_; }
  /// The answer to census_request(), at `now` (see Session::census_done). `setting_up`: the
  /// thread still setting up the census found, if any: it may hold the settle (holding).
  void census_done(
    uint64_t version, bool idle, const std::string & culprit, int64_t now,
    const SettingUp & setting_up = SettingUp());
  const std::string & not_idle_reason() const { return not_idle_reason_; }

  /// Whether a thread still setting up holds the settle at `now` (issue 50 item 1): neither the
  /// proof nor the quiet window may take it before `*until_ns`, a quiet window after that
  /// thread wakes.
  bool holding(int64_t now, int64_t * until_ns) const;
  /// The earliest deadline on the real clock of a thread in its loop that the latest census
  /// counted as blocked (-1: none): the warp does not step it (a Rate::sleep loop).
  int64_t loop_wait_ns() const { return answer_idle_ ? loop_wait_ns_ : -1; }

private:
  /// A thread's run of back-to-back polls that found nothing ready, in one poll epoch.
  struct PollRun
  {
    uint64_t epoch = 0;
    int64_t since_ns = 0;
    int64_t last_ns = 0;
    uint64_t polls = 0;
    uint64_t voluntary_switches = 0;
    bool announced = false;  // the monitor was woken when it became long enough
  };

  struct BlockedWait
  {
    pid_t tid = 0;
    int64_t deadline_ns = -1;
    uint64_t quiet_epoch = 0;
    uint64_t wake_epoch = 0;
  };

  /// A thread in an interposed sleep (enter_sleep).
  struct Sleeper
  {
    pid_t tid = 0;
    int64_t deadline_ns = 0;
  };

  /// How long a run of polls must last to prove its thread idle.
  int64_t long_enough_ns() const;
  /// The threads that polled back to back with nothing ready for long enough (`*proven`), or
  /// false when one still polls but not yet for long enough.
  /// A poller that was proven long enough but had not polled for a moment (preempted) is
  /// looked at again soon (`poller_recheck_`): nothing else would wake the monitor for it.
  bool idle_pollers(int64_t now, std::vector<pid_t> * proven);
  bool sleeper_counts(const Sleeper & sleeper, const Moment & moment) const;
  /// Whether a deadline inside the rest of the quiet window keeps the settle from being proven.
  static bool deadline_matters(int64_t deadline_ns, const Moment & moment);
  /// A thread still setting up, `tid`, waits until `wakes_at_ns`: hold the settle until then
  /// when it wakes before the limit, once per thread and wait in a generation (a thread that
  /// wakes and waits again with nothing created meanwhile is a loop, not set-up). True when
  /// the settle is held for it.
  bool hold_for(pid_t tid, int64_t wakes_at_ns, uint64_t generation, int64_t limit_ns, int64_t now);
  /// Asks the monitor for a census of the threads not in the proof.
  void want_census(
    const Moment & moment, const std::vector<pid_t> & pollers, const std::vector<pid_t> & asleep);

  const Settings settings_;
  // The threads blocked in rmw_wait now, by token.
  std::map<uint64_t, BlockedWait> blocked_;
  uint64_t next_wait_token_ = 0;
  uint64_t wake_epoch_ = 0;
  // Sleeps: the threads asleep now, by token, and the generation of each thread's latest
  // activity call (a sleeper counts when it used ROS since the last change).
  std::map<uint64_t, Sleeper> sleepers_;
  uint64_t next_sleep_token_ = 0;
  ThreadMarks activity_generation_;  // fixed storage: on_activity never allocates
  ThreadMarks ros_threads_;  // on_ros_call, all in "generation" 1
  /// Whether `tid` made ROS calls, but none since the last change (`generation`): still setting up
  /// when it waits with a deadline.
  bool settling(pid_t tid, uint64_t generation) const;
  // Idle pollers: each polling thread's current run; a new epoch starts every run again.
  std::map<pid_t, PollRun> poll_runs_;
  uint64_t poll_epoch_ = 0;
  bool poller_recheck_ = false;
  pid_t monitor_tid_ = 0;
  bool by_polls_ = false;  // the latest proof counted idle pollers
  bool by_sleeps_ = false;  // ... only sleepers
  // The census: anything that may change whether the process is idle bumps the version, and
  // an answer is for one version.
  uint64_t version_ = 0;
  bool census_wanted_ = false;
  CensusRequest census_request_;
  uint64_t answer_version_ = UINT64_MAX;
  bool answer_idle_ = false;
  int64_t answered_ns_ = 0;
  std::string not_idle_reason_;
  // Holds (hold_for): the threads held for in a generation, with the end of the wait held for.
  struct Held
  {
    pid_t tid = 0;
    uint64_t generation = 0;
    int64_t wakes_at_ns = 0;
  };
  std::vector<Held> held_;
  int64_t hold_until_ns_ = INT64_MIN;
  int64_t loop_wait_ns_ = -1;
  uint64_t census_generation_ = 0;  // of the census request, and its hold limit
  int64_t census_hold_limit_ns_ = INT64_MIN;
};

}  // namespace rmw_introspect

#endif  // DETAIL__IDLE_PROOF_HPP_
