// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/session.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace rmw_introspect
{

namespace
{
// Delay after the last change before a progress snapshot is written.
constexpr int64_t kSnapshotDelayNs = 20 * 1000 * 1000;
constexpr int64_t kNsPerMs = 1000 * 1000;
// Activity calls after the last change that make a process that never waits "in its loop".
constexpr uint64_t kSettlingActivity = 2;
// A process that settled by activity before any wait gets this long to start waiting (an
// executor starting to spin right after a burst of publishes) before the probing is skipped;
// while its main thread is runnable at that moment (still setting up, or waiting for a CPU on a
// busy machine) it gets more, looked at again every kFirstWaitRecheckNs, up to kFirstWaitMaxNs
// (what a node that loops without ever waiting, and without sleeping, costs).
constexpr int64_t kFirstWaitGraceNs = 250 * 1000 * 1000;
constexpr int64_t kFirstWaitRecheckNs = 50 * 1000 * 1000;
constexpr int64_t kFirstWaitMaxNs = 2000 * 1000 * 1000;
// A process proven idle by a sleep loop (settled_by "sleep") whose loop goes round once more in
// that grace - the sleeper wakes, uses ROS and sleeps again, and still no thread waited - is in
// its steady loop: the grace ends this long after (time for a thread it woke to start to spin).
constexpr int64_t kSleepLoopAgainNs = 20 * 1000 * 1000;
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
// A census that found a thread not blocked (a sleep loop, a callback running) is taken again
// this long after, while nothing else changes (each costs a few hundred microseconds).
constexpr int64_t kCensusRecheckNs = 5 * 1000 * 1000;
// Idle pollers (docs/design.md, "Detected quiescence"): a thread that polled rmw_wait back to
// back (never a gap over kPollGapNs in which it blocked or slept: a preempted thread on a busy
// machine did neither) and found nothing ready, at least
// kIdlePolls times over at least kIdlePollingNs (or settle_ms, if shorter), with nothing
// created, destroyed, jumped or called meanwhile, is idle like a blocked one.
constexpr uint64_t kIdlePolls = 20;
constexpr int64_t kIdlePollingNs = 10 * 1000 * 1000;
constexpr int64_t kPollGapNs = 5 * 1000 * 1000;

void propose(int64_t when, bool * has_deadline, int64_t * deadline)
{
  if (!*has_deadline || when < *deadline) {
    *has_deadline = true;
    *deadline = when;
  }
}
}  // namespace

Session::Session(
  const Clock & clock, VirtualClock & virtual_clock, const Settings & settings,
  const MainThreadState * main_thread)
: clock_(clock), main_thread_(main_thread), virtual_clock_(virtual_clock), settings_(settings)
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
  quiet_since_ns_ = t0_ns_;
  return true;
}

void Session::break_quiet(int64_t now, bool voids_polls)
{
  if (voids_polls) {
    ++poll_epoch_;
    ++idle_version_;  // (a poll of the warp changes nothing a census answered)
  }
  ++quiet_epoch_;
  quiet_since_ns_ = now;
  waiters_current_ = 0;
  activity_current_ = 0;
  polls_current_ = 0;
}

void Session::on_change()
{
  steady_jumps_ = 0;  // a timer that creates something is not fast-forwarded
  odd_jumps_ = 0;
  ++generation_;
  last_change_ns_ = clock_.now_ns();
  break_quiet(last_change_ns_);
}

void Session::on_wait_entered()
{
  ever_waited_ = true;
  if (phase_ == Phase::kWarping) {
    break_quiet(clock_.now_ns());
  }
}

bool Session::on_poll(pid_t tid, bool found_nothing, uint64_t voluntary_switches)
{
  const int64_t now = clock_.now_ns();
  ever_waited_ = true;
  if (phase_ == Phase::kWarping) {
    warp_loop_seen_ = true;
    ++warp_polls_;
    break_quiet(now, false);
  }
  ++polls_;
  bool look = ++polls_current_ == kSettlingActivity;
  if (!found_nothing) {
    poll_runs_.erase(tid);  // it had something to do
    return look;
  }
  PollRun & run = poll_runs_[tid];
  const bool paused =
    now - run.last_ns > kPollGapNs && voluntary_switches != run.voluntary_switches;
  if (run.epoch != poll_epoch_ || paused) {
    run = PollRun();  // a new run: something happened, or the thread slept or blocked
    run.epoch = poll_epoch_;
    run.since_ns = now;
  }
  run.last_ns = now;
  run.voluntary_switches = voluntary_switches;
  ++run.polls;
  const int64_t long_enough =
    std::min(kIdlePollingNs, static_cast<int64_t>(settings_.settle_ms) * kNsPerMs);
  if (!run.announced && run.polls >= kIdlePolls && now - run.since_ns >= long_enough) {
    run.announced = true;
    ++idle_version_;
    look = look || settings_.detect_idle;
  }
  return look;
}

uint64_t Session::enter_wait(pid_t tid, int64_t deadline_ns)
{
  ever_waited_ = true;
  poll_runs_.erase(tid);  // it blocks now: the blocked wait proves what it can
  ++waiters_current_;
  ++idle_version_;
  const uint64_t token = next_wait_token_++;
  BlockedWait & blocked = blocked_[token];
  blocked.tid = tid;
  blocked.deadline_ns = deadline_ns;
  blocked.quiet_epoch = quiet_epoch_;
  blocked.wake_epoch = wake_epoch_;
  return token;
}

uint64_t Session::enter_sleep(pid_t tid, int64_t deadline_ns)
{
  poll_runs_.erase(tid);
  ++idle_version_;
  if (phase_ == Phase::kProbing && !ever_waited_ && !probe_done_ && settled_by_sleep() &&
    used_ros_since_change(tid))
  {
    // Its loop went round again since the probing began (see kSleepLoopAgainNs).
    first_wait_give_up_ns_ = std::min(first_wait_give_up_ns_, clock_.now_ns() + kSleepLoopAgainNs);
  }
  const uint64_t token = next_sleep_token_++;
  sleepers_[token] = Sleeper{tid, deadline_ns};
  return token;
}

void Session::leave_sleep(uint64_t token)
{
  if (sleepers_.erase(token) > 0) {
    ++idle_version_;
  }
}

bool Session::used_ros_since_change(pid_t tid) const
{
  return activity_generation_.marked(tid, generation_);
}

bool Session::sleeper_counts(const Sleeper & sleeper) const
{
  if (!settings_.virtual_sleeps || settings_.horizon_ms <= 0) {
    return false;  // nothing steps a sleep: it proves nothing (the census says it sleeps)
  }
  if (phase_ == Phase::kWarping) {
    return false;  // a sleep from before the warp is about to come back and jump
  }
  return used_ros_since_change(sleeper.tid);
}

std::vector<const Session::Sleeper *> Session::counted_sleepers() const
{
  std::vector<const Sleeper *> counted;
  for (const auto & entry : sleepers_) {
    if (sleeper_counts(entry.second)) {
      counted.push_back(&entry.second);
    }
  }
  return counted;
}

bool Session::settled_by_sleep() const
{
  return settled_by_ != nullptr && std::strcmp(settled_by_, "sleep") == 0;
}

void Session::leave_wait(uint64_t token)
{
  const auto it = blocked_.find(token);
  if (it == blocked_.end()) {
    return;
  }
  if (it->second.quiet_epoch == quiet_epoch_ && waiters_current_ > 0) {
    --waiters_current_;
  }
  blocked_.erase(it);
  ++idle_version_;
}

void Session::on_wake(pid_t by)
{
  ++wake_epoch_;
  const auto run = poll_runs_.find(by);
  if (by == 0 || run == poll_runs_.end() || run->second.epoch != poll_epoch_) {
    ++idle_version_;
  }
}

void Session::census_done(uint64_t version, bool idle, const std::string & culprit)
{
  census_answer_version_ = version;
  census_answer_idle_ = idle;
  census_answered_ns_ = clock_.now_ns();
  not_idle_reason_ = idle ? std::string() : culprit;
}

bool Session::deadline_matters(int64_t deadline_ns) const
{
  if (deadline_ns < 0) {
    return false;
  }
  const int64_t horizon_ns = settings_.horizon_ms * kNsPerMs;
  if (horizon_ns <= 0) {
    return true;  // no warp: the quiet window is all the time the process gets
  }
  // Before the warp, the warp jumps to it next; a deadline past the horizon (the settle after
  // the warp) is later than anything the capture covers.
  const bool warp_to_come = phase_ == Phase::kSettling || phase_ == Phase::kProbing;
  return !warp_to_come && deadline_ns + virtual_clock_.offset_ns() - t0_ns_ <= horizon_ns;
}

bool Session::idle_pollers(int64_t now, std::vector<pid_t> * proven)
{
  const int64_t long_enough =
    std::min(kIdlePollingNs, static_cast<int64_t>(settings_.settle_ms) * kNsPerMs);
  for (const auto & entry : poll_runs_) {
    const PollRun & run = entry.second;
    if (run.epoch != poll_epoch_) {
      continue;  // not polling since the last change: the census says what it does
    }
    if (now - run.last_ns > kPollGapNs) {
      poller_recheck_ = poller_recheck_ || run.announced;  // preempted, or stopped polling
      continue;
    }
    if (run.polls < kIdlePolls || now - run.since_ns < long_enough) {
      return false;  // still polling, not yet long enough
    }
    proven->push_back(entry.first);
  }
  return true;
}

bool Session::provably_idle(int64_t now)
{
  if (!settings_.detect_idle) {
    return false;
  }
  std::vector<pid_t> pollers;
  if (!idle_pollers(now, &pollers)) {
    return false;
  }
  const std::vector<const Sleeper *> sleepers = counted_sleepers();
  if (blocked_.empty() && pollers.empty() && sleepers.empty()) {
    return false;
  }
  idle_by_polls_ = !pollers.empty();
  idle_by_sleeps_ = blocked_.empty() && pollers.empty();
  if (phase_ == Phase::kWarping && !pollers.empty() && (jumps_ > 0 || !warp_loop_seen_)) {
    // After jumps, rcl polls while a timer due in real time catches up: the stall rule of
    // poll() decides. Before any, idle polls stall the warp (poll()), they do not settle it.
    return false;
  }
  // Nothing may happen before the quiet window would end: a deadline inside it is waited for.
  const int64_t settle_at = quiet_since_ns_ + static_cast<int64_t>(settings_.settle_ms) * kNsPerMs;
  if (now >= settle_at) {
    return false;  // the quiet window itself decides
  }
  for (const auto & entry : blocked_) {
    const BlockedWait & blocked = entry.second;
    if (blocked.wake_epoch != wake_epoch_) {
      return false;  // woken: it has not looked at its wait set again yet
    }
    if (blocked.deadline_ns >= 0 && blocked.deadline_ns < settle_at &&
      deadline_matters(blocked.deadline_ns))
    {
      return false;  // its timer (or timeout) comes first; it waits again after it
    }
  }
  for (const Sleeper * sleeper : sleepers) {
    if (sleeper->deadline_ns < settle_at && deadline_matters(sleeper->deadline_ns)) {
      return false;  // it wakes first, and uses ROS again
    }
  }
  // Any other sleeper proves what the census would read of a real sleep (it sleeps in slices
  // before the warp): idle when it sleeps past the window, with no exception for a warp to come.
  std::vector<pid_t> asleep;
  for (const auto & entry : sleepers_) {
    if (sleeper_counts(entry.second)) {
      continue;  // (above)
    }
    if (phase_ == Phase::kWarping || entry.second.deadline_ns < settle_at) {
      return false;  // it wakes (or, in the warp, comes back to jump) first
    }
    asleep.push_back(entry.second.tid);
  }
  if (census_answer_version_ == idle_version_) {
    if (census_answer_idle_ || now < census_answered_ns_ + kCensusRecheckNs) {
      return census_answer_idle_;
    }
  }
  census_request_.version = idle_version_;
  census_request_.until_ns = settle_at;
  census_request_.known.clear();
  census_request_.known.push_back(monitor_tid_);
  for (const auto & entry : blocked_) {
    census_request_.known.push_back(entry.second.tid);
  }
  census_request_.known.insert(census_request_.known.end(), pollers.begin(), pollers.end());
  for (const Sleeper * sleeper : sleepers) {
    census_request_.known.push_back(sleeper->tid);
  }
  census_request_.known.insert(census_request_.known.end(), asleep.begin(), asleep.end());
  census_wanted_ = true;
  return false;
}

bool Session::on_activity(pid_t tid)
{
  if (tid != 0) {
    activity_generation_.mark(tid, generation_);
  }
  if (phase_ == Phase::kWarping) {
    warp_loop_seen_ = true;
    ++warp_activity_;
  }
  ++activity_calls_;
  ++idle_version_;
  ++poll_epoch_;  // a loop that publishes or takes is not an idle poller
  return ++activity_current_ == kSettlingActivity;
}

int64_t Session::virtual_now_ns() const
{
  return clock_.now_ns() + virtual_clock_.offset_ns();
}

bool Session::try_jump(int64_t target_ns)
{
  if (phase_ != Phase::kWarping) {
    return false;
  }
  const int64_t now = clock_.now_ns();
  last_timed_wait_ns_ = now;
  if (now - warp_start_ns_ >= settings_.warp_budget_ms * kNsPerMs) {
    budget_exhausted_ = true;
    end_warp(now);
    return false;
  }
  const int64_t virtual_now = now + virtual_clock_.offset_ns();
  if (target_ns <= virtual_now) {
    // Another thread's jump, or real time on a busy machine, already took virtual time past
    // it: no jump, but timers still drive the process, so it is not quiet either.
    break_quiet(now);
    return true;
  }
  if (target_ns - t0_ns_ > settings_.horizon_ms * kNsPerMs) {
    horizon_reached_ = true;
    end_warp(now);
    return false;
  }
  // A periodic timer that fired again and again and created nothing: jump to the horizon
  // at once (rcl then runs its callback once for the missed periods; see kSteadyJumpsBeforeHorizon).
  // Steps are compared with a reference step; a few outliers (the process preempted before its
  // wait on a busy machine) are forgiven, a steady run of other steps becomes the reference.
  const int64_t step = last_jump_target_ns_ != 0 ? target_ns - last_jump_target_ns_ : 0;
  last_jump_target_ns_ = target_ns;
  if (step > 0 && last_jump_step_ns_ > 0 &&
    std::llabs(step - last_jump_step_ns_) <=
    std::max(kSteadyToleranceNs, std::max(step, last_jump_step_ns_) / 2))
  {
    ++steady_jumps_;
  } else if (step > 0 &&
    (last_jump_step_ns_ <= 0 || ++odd_jumps_ > kOddJumpsForgiven + steady_jumps_ / 10))
  {
    last_jump_step_ns_ = step;  // another timer (or none steady): start over with this step
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
  break_quiet(now);
  return true;
}

void Session::end_warp(int64_t now)
{
  phase_ = Phase::kFinalSettling;
  warp_end_ns_ = now;
}

bool Session::quiet_settled(int64_t now, bool * has_deadline, int64_t * deadline)
{
  if (provably_idle(now)) {
    settled_by_ = idle_by_polls_ ? "poll" : (idle_by_sleeps_ ? "sleep" : "wait");
    ++idle_settles_;
    return true;
  }
  const bool by_wait = waiters_current_ > 0;
  const bool by_poll = !by_wait && polls_current_ >= kSettlingActivity;
  // A thread asleep in its loop (it used ROS since the last change) is evidence like a wait.
  const bool by_sleep = !by_wait && !by_poll && !counted_sleepers().empty();
  if (!by_wait && !by_poll && !by_sleep && activity_current_ < kSettlingActivity) {
    return false;  // the next wait, sleep or activity call wakes the monitor
  }
  const int64_t settle_at = quiet_since_ns_ + static_cast<int64_t>(settings_.settle_ms) * kNsPerMs;
  if (now < settle_at) {
    propose(settle_at, has_deadline, deadline);
    return false;
  }
  settled_by_ = by_wait ? "wait" : (by_poll ? "poll" : (by_sleep ? "sleep" : "activity"));
  ++window_settles_;
  return true;
}

Session::Step Session::poll()
{
  Step step;
  census_wanted_ = false;
  poller_recheck_ = false;
  if (!started_ || exiting_) {
    return step;
  }
  const int64_t now = clock_.now_ns();
  const int64_t horizon_ns = settings_.horizon_ms * kNsPerMs;
  if (phase_ == Phase::kWarping) {
    const int64_t budget_end = warp_start_ns_ + settings_.warp_budget_ms * kNsPerMs;
    // Real time also ages the node: the real moment its virtual age reaches the horizon.
    const int64_t horizon_at = t0_ns_ + horizon_ns - virtual_clock_.offset_ns();
    if (now >= budget_end) {
      budget_exhausted_ = true;
      end_warp(now);
    } else if (now >= horizon_at) {
      horizon_reached_ = true;
      end_warp(now);
    } else {
      propose(std::min(budget_end, horizon_at), &step.has_deadline, &step.deadline_ns);
      // No wait with a timeout for a while the process ran a loop (polls, activity): a loop
      // that polls or sleeps on its own clock, with nothing to jump to. Before any jump that
      // is settle_ms; after jumps (timers) kStallAfterJumpsNs at least: a timer due in real
      // time on a busy machine makes rcl poll (timeout 0) until it has caught up.
      const int64_t quiet_ns = static_cast<int64_t>(settings_.settle_ms) * kNsPerMs;
      const int64_t stall_at =
        last_timed_wait_ns_ + (jumps_ == 0 ? quiet_ns : std::max(quiet_ns, kStallAfterJumpsNs));
      if (blocked_.empty() && now >= stall_at && warp_loop_seen_) {
        warp_stalled_ = true;
        end_warp(now);
      } else if (jumps_ == 0 && warp_loop_seen_ && !poll_runs_.empty() && provably_idle(now)) {
        // Every thread polls with nothing ready, or is blocked, and nothing changes: nothing
        // to jump to, proven without waiting for the stall window.
        warp_stalled_ = true;
        end_warp(now);
      } else if (blocked_.empty()) {
        // (looked at again a window later when nothing ran yet)
        propose(
          std::max(stall_at, now + static_cast<int64_t>(settings_.settle_ms) * kNsPerMs),
          &step.has_deadline, &step.deadline_ns);
      }
    }
  }
  if (phase_ == Phase::kProbing) {
    if (poll_probing(now, &step)) {
      return step;
    }
  } else {
    const bool in_warp = phase_ == Phase::kWarping || phase_ == Phase::kFinalSettling;
    if ((in_warp || settled_generation_ != generation_) &&
      (stalled_unchanged() || quiet_settled(now, &step.has_deadline, &step.deadline_ns)))
    {
      mark_settled(now);
      step.has_deadline = false;
      if (phase_ == Phase::kSettling && settings_.probe) {
        phase_ = Phase::kProbing;
        probed_ = true;
        probe_started_ns_ = now;
        first_wait_give_up_ns_ = now + kFirstWaitGraceNs;
        if (!ever_waited_ && settled_by_sleep()) {
          // Proven idle with every thread blocked or asleep in its loop: nothing can start to
          // wait before the first sleeper wakes, so a grace that ends first is not waited for.
          int64_t first_wake = INT64_MAX;
          for (const Sleeper * sleeper : counted_sleepers()) {
            first_wake = std::min(first_wake, sleeper->deadline_ns);
          }
          if (first_wake >= first_wait_give_up_ns_) {
            first_wait_give_up_ns_ = now;
          }
        }
        // Settled by activity before any wait: the first request waits for a settle by wait.
        probe_settle_first_ = !ever_waited_;
        step.action = Action::kStartProbe;
        return step;
      }
      after_first_settle(now, &step);
      return step;
    }
  }
  if (written_generation_ != generation_) {
    const int64_t snapshot_at = last_change_ns_ + kSnapshotDelayNs;
    if (now >= snapshot_at) {
      written_generation_ = generation_;
      step.action = Action::kWriteRunning;
      step.has_deadline = false;
      return step;
    }
    propose(snapshot_at, &step.has_deadline, &step.deadline_ns);
  }
  if (poller_recheck_) {
    propose(now + kCensusRecheckNs, &step.has_deadline, &step.deadline_ns);
  }
  if (census_wanted_) {
    census_wanted_ = false;
    step.action = Action::kCheckIdle;
  } else if (census_answer_version_ == idle_version_ && !census_answer_idle_) {
    propose(census_answered_ns_ + kCensusRecheckNs, &step.has_deadline, &step.deadline_ns);
  }
  return step;
}

bool Session::stalled_unchanged() const
{
  // The warp stalled before its first jump and nothing was created or destroyed since the
  // settle before it: virtual time never moved, so the process is where that settle found it,
  // and a second quiet window (two more polls of a loop that sleeps 0.5 s between them: a
  // second) would give the same capture.
  return phase_ == Phase::kFinalSettling && warp_stalled_ && jumps_ == 0 &&
         settled_generation_ == generation_;
}

void Session::mark_settled(int64_t now)
{
  settled_generation_ = generation_;
  written_generation_ = generation_;
  has_settled_ = true;
  time_to_settle_ns_ = now - t0_ns_;
}

void Session::after_first_settle(int64_t now, Step * step)
{
  step->has_deadline = false;
  const int64_t horizon_ns = settings_.horizon_ms * kNsPerMs;
  if ((phase_ == Phase::kSettling || phase_ == Phase::kProbing) && horizon_ns > 0) {
    if (now + virtual_clock_.offset_ns() - t0_ns_ < horizon_ns) {
      phase_ = Phase::kWarping;
      warp_start_ns_ = now;
      last_timed_wait_ns_ = now;
      break_quiet(now);  // the warp must see settle_ms without a jump before it ends
      step->action = Action::kStartWarp;
      return;
    }
    horizon_reached_ = true;  // settling took longer than the horizon
  }
  phase_ = Phase::kDone;
  step->action = Action::kSettle;
}

bool Session::poll_probing(int64_t now, Step * step)
{
  if (!ever_waited_ && !probe_done_) {
    // No executor has waited yet: nobody could take a request.
    if (now < first_wait_give_up_ns_) {
      propose(first_wait_give_up_ns_, &step->has_deadline, &step->deadline_ns);
      return false;
    }
    const int64_t last_chance = probe_started_ns_ + kFirstWaitMaxNs;
    if (main_thread_ != nullptr && now < last_chance && main_thread_->runnable()) {
      first_wait_give_up_ns_ = std::min(now + kFirstWaitRecheckNs, last_chance);
      propose(first_wait_give_up_ns_, &step->has_deadline, &step->deadline_ns);
      return false;
    }
    probe_skipped_ = true;
    probe_done_ = true;
  }
  if (probe_in_flight_) {
    const int64_t deadline = probe_sent_ns_ + settings_.answer_timeout_ms * kNsPerMs;
    if (now >= deadline) {
      probe_in_flight_ = false;
      probe_settle_first_ = true;  // the node may still be busy with it
      probe_changed_node_ = true;
      break_quiet(now);
      step->action = Action::kProbeTimeout;
      step->has_deadline = false;
      return true;
    }
    propose(deadline, &step->has_deadline, &step->deadline_ns);
    return false;
  }
  if (probe_done_) {
    // Only parameters were read and nothing was created meanwhile: the settle that started
    // the probing still holds (a read runs no code of the node's), so no second one.
    const bool unchanged = !probe_changed_node_ && settled_generation_ == generation_;
    if (unchanged || quiet_settled(now, &step->has_deadline, &step->deadline_ns)) {
      mark_settled(now);
      after_first_settle(now, step);
      return true;
    }
    return false;
  }
  if (!probe_settle_first_ || quiet_settled(now, &step->has_deadline, &step->deadline_ns)) {
    step->action = Action::kProbe;
    step->has_deadline = false;
    return true;
  }
  return false;
}

void Session::probe_sent()
{
  probe_in_flight_ = true;
  probe_sent_ns_ = clock_.now_ns();
}

void Session::probe_answered(bool settle_first)
{
  if (!probe_in_flight_) {
    return;  // late: its timeout was already reported
  }
  probe_in_flight_ = false;
  probe_settle_first_ = settle_first;
  probe_changed_node_ = probe_changed_node_ || settle_first;
  // The answering thread goes back to its wait after this: the settles count from here.
  break_quiet(clock_.now_ns());
}

void Session::probe_done()
{
  probe_done_ = true;
  probe_in_flight_ = false;
}

const char * Session::probe_state() const
{
  if (!settings_.probe) {
    return "off";
  }
  if (phase_ == Phase::kSettling) {
    return "pending";
  }
  if (phase_ == Phase::kProbing) {
    return "running";
  }
  return probed_ && !probe_skipped_ ? "done" : "skipped";
}

const char * Session::progress_state() const
{
  if (phase_ == Phase::kProbing) {
    return "probing";
  }
  return phase_ == Phase::kWarping || phase_ == Phase::kFinalSettling ? "warping" : "running";
}

double Session::real_age_ms() const
{
  return ns_to_ms(clock_.now_ns() - t0_ns_);
}

double Session::virtual_age_ms() const
{
  return ns_to_ms(virtual_now_ns() - t0_ns_);
}

void Session::fill_header(const char * state, CaptureHeader * header) const
{
  const int64_t now = clock_.now_ns();
  const int64_t offset = virtual_clock_.offset_ns();
  header->settle_ms = settings_.settle_ms;
  header->has_time_to_settle = has_settled_;
  header->time_to_settle_ms = ns_to_ms(time_to_settle_ns_);
  header->elapsed_ms = ns_to_ms(now - t0_ns_);
  header->settled_by = settled_by_ != nullptr ? settled_by_ : "";
  header->ever_waited = ever_waited_;
  header->activity_calls = activity_calls_;
  header->horizon_ms = settings_.horizon_ms;
  header->virtual_elapsed_ms = ns_to_ms(now + offset - t0_ns_);
  header->real_elapsed_ms = header->elapsed_ms;
  header->jumps = jumps_;
  header->warp_ms = ns_to_ms(warp_ns_);
  header->horizon_reached = horizon_reached_;
  header->warp_budget_exhausted = budget_exhausted_;
  header->probe_state = probe_state();
  header->answer_timeout_ms = settings_.answer_timeout_ms;
  header->has_ended = std::strcmp(state, "exit") == 0 || std::strcmp(state, "shutdown") == 0;
  header->ended_before_settle = phase_ != Phase::kDone;
  header->idle_detect = settings_.detect_idle;
  header->idle_settles = idle_settles_;
  header->window_settles = window_settles_;
  header->polls = polls_;
  header->not_idle = not_idle_reason_;
  header->warp_stalled = warp_stalled_;
  const bool warped = warp_start_ns_ != 0;
  header->warp_real_ms = warped ? ns_to_ms((warp_end_ns_ != 0 ? warp_end_ns_ : now) - warp_start_ns_) : 0.0;
  header->warp_polls = warp_polls_;
  header->warp_activity = warp_activity_;
}

}  // namespace rmw_introspect
