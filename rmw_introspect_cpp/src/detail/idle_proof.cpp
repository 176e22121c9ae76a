// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/idle_proof.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace rmw_introspect
{

namespace
{
constexpr int64_t kNsPerMs = 1000 * 1000;
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
// Two deadlines of one thread this close are one wait (a CLOCK_REALTIME deadline is placed on
// CLOCK_MONOTONIC anew at each census, within microseconds).
constexpr int64_t kSameWaitNs = 1000 * 1000;
}  // namespace

IdleProof::IdleProof(const Settings & settings)
: settings_(settings)
{
}

void IdleProof::new_epoch()
{
  ++poll_epoch_;
  ++version_;
}

int64_t IdleProof::long_enough_ns() const
{
  return std::min(kIdlePollingNs, static_cast<int64_t>(settings_.settle_ms) * kNsPerMs);
}

bool IdleProof::on_poll(pid_t tid, int64_t now, bool found_nothing, uint64_t voluntary_switches)
{
  on_ros_call(tid);
  if (!found_nothing) {
    poll_runs_.erase(tid);  // it had something to do
    return false;
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
  if (!run.announced && run.polls >= kIdlePolls && now - run.since_ns >= long_enough_ns()) {
    run.announced = true;
    ++version_;
    return settings_.detect_idle;
  }
  return false;
}

uint64_t IdleProof::enter_wait(pid_t tid, int64_t deadline_ns, uint64_t quiet_epoch)
{
  on_ros_call(tid);
  poll_runs_.erase(tid);  // it blocks now: the blocked wait proves what it can
  ++version_;
  const uint64_t token = next_wait_token_++;
  BlockedWait & blocked = blocked_[token];
  blocked.tid = tid;
  blocked.deadline_ns = deadline_ns;
  blocked.quiet_epoch = quiet_epoch;
  blocked.wake_epoch = wake_epoch_;
  return token;
}

bool IdleProof::leave_wait(uint64_t token, uint64_t * quiet_epoch)
{
  const auto it = blocked_.find(token);
  if (it == blocked_.end()) {
    return false;
  }
  *quiet_epoch = it->second.quiet_epoch;
  blocked_.erase(it);
  ++version_;
  return true;
}

uint64_t IdleProof::enter_sleep(pid_t tid, int64_t deadline_ns)
{
  poll_runs_.erase(tid);
  ++version_;
  const uint64_t token = next_sleep_token_++;
  sleepers_[token] = Sleeper{tid, deadline_ns};
  return token;
}

void IdleProof::leave_sleep(uint64_t token)
{
  if (sleepers_.erase(token) > 0) {
    ++version_;
  }
}

void IdleProof::on_activity(pid_t tid, uint64_t generation)
{
  if (tid != 0) {
    activity_generation_.mark(tid, generation);
    ros_threads_.mark(tid, 1);
  }
  new_epoch();  // a loop that publishes or takes is not an idle poller
}

void IdleProof::on_wake(pid_t by)
{
  ++wake_epoch_;
  const auto run = poll_runs_.find(by);
  if (by == 0 || run == poll_runs_.end() || run->second.epoch != poll_epoch_) {
    ++version_;
  }
}

bool IdleProof::used_ros_in(pid_t tid, uint64_t generation) const
{
  return activity_generation_.marked(tid, generation);
}

void IdleProof::on_ros_call(pid_t tid)
{
  if (tid != 0) {
    ros_threads_.mark(tid, 1);
  }
}

bool IdleProof::settling(pid_t tid, uint64_t generation) const
{
  return ros_threads_.marked(tid, 1) && !used_ros_in(tid, generation);
}

bool IdleProof::sleeper_counts(const Sleeper & sleeper, const Moment & moment) const
{
  if (!settings_.sleeps_count) {
    return false;  // nothing steps a sleep: it proves nothing (the census says it sleeps)
  }
  if (moment.warping) {
    return false;  // a sleep from before the warp is about to come back and jump
  }
  return used_ros_in(sleeper.tid, moment.generation);
}

bool IdleProof::sleepers_count(const Moment & moment) const
{
  return std::any_of(sleepers_.begin(), sleepers_.end(), [&](const auto & entry) {
    return sleeper_counts(entry.second, moment);
  });
}

int64_t IdleProof::first_counted_wake(const Moment & moment) const
{
  int64_t first_wake = INT64_MAX;
  for (const auto & entry : sleepers_) {
    if (sleeper_counts(entry.second, moment)) {
      first_wake = std::min(first_wake, entry.second.deadline_ns);
    }
  }
  return first_wake;
}

bool IdleProof::deadline_matters(int64_t deadline_ns, const Moment & moment)
{
  return deadline_ns >= 0 && deadline_ns <= moment.deadlines_until_ns;
}

bool IdleProof::idle_pollers(int64_t now, std::vector<pid_t> * proven)
{
  for (const auto & entry : poll_runs_) {
    const PollRun & run = entry.second;
    if (run.epoch != poll_epoch_) {
      continue;  // not polling since the last change: the census says what it does
    }
    if (now - run.last_ns > kPollGapNs) {
      poller_recheck_ = poller_recheck_ || run.announced;  // preempted, or stopped polling
      continue;
    }
    if (run.polls < kIdlePolls || now - run.since_ns < long_enough_ns()) {
      return false;  // still polling, not yet long enough
    }
    proven->push_back(entry.first);
  }
  return true;
}

bool IdleProof::provably_idle(const Moment & moment)
{
  if (!settings_.detect_idle) {
    return false;
  }
  const int64_t now = moment.now_ns;
  // A thread asleep before it used ROS again is still setting up: what it does when it wakes
  // is not known, and the settle waits for it (issue 50 item 1; a census finds the same of the
  // threads in other waits with a deadline, census_done).
  if (!moment.warping) {
    for (const auto & entry : sleepers_) {
      const Sleeper & sleeper = entry.second;
      if (settling(sleeper.tid, moment.generation) &&
          hold_for(sleeper.tid, sleeper.deadline_ns, moment.generation, moment.hold_limit_ns, now))
      {
        return false;
      }
    }
  }
  std::vector<pid_t> pollers;
  if (!idle_pollers(now, &pollers)) {
    return false;
  }
  const bool sleepers = sleepers_count(moment);
  if (blocked_.empty() && pollers.empty() && !sleepers) {
    return false;
  }
  by_polls_ = !pollers.empty();
  by_sleeps_ = blocked_.empty() && pollers.empty();
  if (!moment.pollers_prove && !pollers.empty()) {
    return false;
  }
  // Nothing may happen before the quiet window would end: a deadline inside it is waited for.
  const int64_t settle_at = moment.window_end_ns;
  if (now >= settle_at) {
    return false;  // the quiet window itself decides
  }
  for (const auto & entry : blocked_) {
    const BlockedWait & blocked = entry.second;
    if (blocked.wake_epoch != wake_epoch_) {
      return false;  // woken: it has not looked at its wait set again yet
    }
    if (blocked.deadline_ns >= 0 && blocked.deadline_ns < settle_at &&
        deadline_matters(blocked.deadline_ns, moment))
    {
      return false;  // its timer (or timeout) comes first; it waits again after it
    }
  }
  for (const auto & entry : sleepers_) {
    const Sleeper & sleeper = entry.second;
    if (sleeper_counts(sleeper, moment) && sleeper.deadline_ns < settle_at &&
        deadline_matters(sleeper.deadline_ns, moment))
    {
      return false;  // it wakes first, and uses ROS again
    }
  }
  // Any other sleeper proves what the census would read of a real sleep (it sleeps in slices
  // before the warp): idle when it sleeps past the window, with no exception for a warp to come.
  std::vector<pid_t> asleep;
  for (const auto & entry : sleepers_) {
    if (sleeper_counts(entry.second, moment)) {
      continue;  // (above)
    }
    if (moment.warping || entry.second.deadline_ns < settle_at) {
      return false;  // it wakes (or, in the warp, comes back to jump) first
    }
    asleep.push_back(entry.second.tid);
  }
  if (answer_version_ == version_) {
    if (answer_idle_ || now < answered_ns_ + kCensusRecheckNs || now < hold_until_ns_) {
      return answer_idle_;
    }
  }
  want_census(moment, pollers, asleep);
  return false;
}

void IdleProof::want_census(
  const Moment & moment, const std::vector<pid_t> & pollers, const std::vector<pid_t> & asleep)
{
  census_request_.version = version_;
  census_request_.until_ns = moment.window_end_ns;
  census_request_.known.clear();
  census_request_.known.push_back(monitor_tid_);
  for (const auto & entry : blocked_) {
    census_request_.known.push_back(entry.second.tid);
  }
  census_request_.known.insert(census_request_.known.end(), pollers.begin(), pollers.end());
  for (const auto & entry : sleepers_) {
    if (sleeper_counts(entry.second, moment)) {
      census_request_.known.push_back(entry.second.tid);
    }
  }
  census_request_.known.insert(census_request_.known.end(), asleep.begin(), asleep.end());
  census_request_.settling.clear();
  std::vector<pid_t> ros_threads;
  ros_threads_.collect(&ros_threads);
  const std::vector<pid_t> & known = census_request_.known;
  census_request_.looping.clear();
  for (const pid_t tid : ros_threads) {
    if (used_ros_in(tid, moment.generation) &&
        std::find(known.begin(), known.end(), tid) == known.end())
    {
      census_request_.looping.push_back(tid);
    }
    if (settling(tid, moment.generation) &&
        std::find(known.begin(), known.end(), tid) == known.end())
    {
      census_request_.settling.push_back(tid);
    }
  }
  census_generation_ = moment.generation;
  census_hold_limit_ns_ = moment.hold_limit_ns;
  census_wanted_ = true;
}

bool IdleProof::hold_for(
  pid_t tid, int64_t wakes_at_ns, uint64_t generation, int64_t limit_ns, int64_t now)
{
  if (wakes_at_ns <= now || wakes_at_ns > limit_ns) {
    return false;  // awake already, or it wakes past what the capture covers
  }
  for (const Held & held : held_) {
    if (held.tid == tid && held.generation == generation) {
      // The same wait still (held for), or another one with nothing created since the first:
      // a loop that waits on its own clock, not set-up.
      return std::llabs(held.wakes_at_ns - wakes_at_ns) <= kSameWaitNs;
    }
  }
  held_.push_back(Held{tid, generation, wakes_at_ns});
  hold_until_ns_ = std::max(hold_until_ns_, wakes_at_ns);
  ++version_;
  return true;
}

bool IdleProof::holding(int64_t now, int64_t * until_ns) const
{
  // The quiet window counts from the wake: the woken thread gets settle_ms to create the rest
  // (a hold that ended at the deadline let the window settle in the instant the thread woke).
  if (hold_until_ns_ == INT64_MIN) {
    return false;
  }
  const int64_t until = hold_until_ns_ + static_cast<int64_t>(settings_.settle_ms) * kNsPerMs;
  if (now < until) {
    *until_ns = until;
    return true;
  }
  return false;
}

const char * IdleProof::proven_by() const
{
  return by_polls_ ? "poll" : (by_sleeps_ ? "sleep" : "wait");
}

void IdleProof::look_begins()
{
  census_wanted_ = false;
  poller_recheck_ = false;
}

bool IdleProof::look_done(int64_t now, int64_t * recheck_ns)
{
  if (poller_recheck_) {
    *recheck_ns = std::min(*recheck_ns, now + kCensusRecheckNs);
  }
  if (census_wanted_) {
    census_wanted_ = false;
    return true;
  }
  if (answer_version_ == version_ && !answer_idle_) {
    // (a thread setting up is not looked at again before it wakes)
    *recheck_ns = std::min(*recheck_ns, std::max(answered_ns_ + kCensusRecheckNs, hold_until_ns_));
  }
  return false;
}

void IdleProof::census_done(
  uint64_t version, bool idle, const std::string & culprit, int64_t now,
  const SettingUp & setting_up)
{
  // What a census found setting up holds even when something else happened meanwhile (a wake
  // of a parked thread): that thread still waits until its deadline.
  if (!idle && setting_up.wakes_at_ns >= 0) {
    const bool current = version == version_;
    hold_for(
      setting_up.tid, setting_up.wakes_at_ns, census_generation_, census_hold_limit_ns_, now);
    if (current) {
      version = version_;  // (hold_for moved it on: the answer stays the one for now)
    }
  }
  answer_version_ = version;
  loop_wait_ns_ = idle ? setting_up.loop_wait_ns : -1;
  answer_idle_ = idle;
  answered_ns_ = now;
  not_idle_reason_ = idle ? std::string() : culprit;
}

}  // namespace rmw_introspect
