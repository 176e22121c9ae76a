// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/session.hpp"

#include <cstdint>
#include <cstring>
#include <optional>

namespace rmw_introspect
{

namespace
{
// Delay after the last change before a progress snapshot is written.
constexpr int64_t kSnapshotDelayNs = 20 * 1000 * 1000;
constexpr int64_t kNsPerMs = 1000 * 1000;
// Activity calls after the last change that make a process that never waits "in its loop".
constexpr uint64_t kSettlingActivity = 2;

/// Lowers the step's deadline to `when` (INT64_MAX: no deadline, what a part leaves untouched).
void propose(int64_t when, bool * has_deadline, int64_t * deadline)
{
  if (when != INT64_MAX && (!*has_deadline || when < *deadline)) {
    *has_deadline = true;
    *deadline = when;
  }
}
}  // namespace

Session::Session(
  const Clock & clock, VirtualClock & virtual_clock, const Settings & settings,
  const MainThreadState * main_thread)
: clock_(clock),
  virtual_clock_(virtual_clock),
  settings_(settings),
  idle_(
    {settings.settle_ms, settings.detect_idle, settings.virtual_sleeps && settings.horizon_ms > 0}),
  warp_(virtual_clock, {settings.settle_ms, settings.horizon_ms, settings.warp_budget_ms}),
  probing_(settings.answer_timeout_ms, main_thread)
{
}

bool Session::start()
{
  if (started_) {
    return false;
  }
  started_ = true;
  t0_ns_ = clock_.now_ns();
  warp_.set_origin(t0_ns_);
  last_change_ns_ = t0_ns_;
  quiet_since_ns_ = t0_ns_;
  return true;
}

void Session::break_quiet(int64_t now, bool voids_polls)
{
  if (voids_polls) {
    idle_.new_epoch();  // (a poll of the warp changes nothing a census answered)
  }
  ++quiet_epoch_;
  quiet_since_ns_ = now;
  waiters_current_ = 0;
  activity_current_ = 0;
  polls_current_ = 0;
}

void Session::on_change(pid_t tid)
{
  idle_.on_ros_call(tid);
  warp_.on_change();
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
    warp_.on_poll();
    break_quiet(now, false);
  }
  ++polls_;
  const bool look = ++polls_current_ == kSettlingActivity;
  const bool proven = idle_.on_poll(tid, now, found_nothing, voluntary_switches);
  return look || proven;
}

uint64_t Session::enter_wait(pid_t tid, int64_t deadline_ns)
{
  ever_waited_ = true;
  ++waiters_current_;
  return idle_.enter_wait(tid, deadline_ns, quiet_epoch_);
}

uint64_t Session::enter_sleep(pid_t tid, int64_t deadline_ns)
{
  if (phase_ == Phase::kProbing && !ever_waited_ && settled_by_sleep() &&
      idle_.used_ros_in(tid, generation_))
  {
    probing_.sleep_loop_again(clock_.now_ns());  // (see Probing::sleep_loop_again)
  }
  return idle_.enter_sleep(tid, deadline_ns);
}

bool Session::settled_by_sleep() const
{
  return settled_by_ != nullptr && std::strcmp(settled_by_, "sleep") == 0;
}

void Session::leave_wait(uint64_t token)
{
  uint64_t quiet_epoch = 0;
  if (idle_.leave_wait(token, &quiet_epoch) && quiet_epoch == quiet_epoch_ && waiters_current_ > 0)
  {
    --waiters_current_;
  }
}

IdleProof::Moment Session::moment(int64_t now) const
{
  IdleProof::Moment moment;
  moment.now_ns = now;
  moment.window_end_ns = quiet_since_ns_ + static_cast<int64_t>(settings_.settle_ms) * kNsPerMs;
  moment.generation = generation_;
  moment.warping = phase_ == Phase::kWarping;
  // Before the warp, the warp jumps to a deadline next; a deadline past the horizon (the
  // settle after the warp) is later than anything the capture covers. Without a warp, the
  // quiet window is all the time the process gets.
  const int64_t horizon_ns = settings_.horizon_ms * kNsPerMs;
  const bool warp_to_come = phase_ == Phase::kSettling || phase_ == Phase::kProbing;
  if (horizon_ns <= 0) {
    moment.deadlines_until_ns = INT64_MAX;
  } else if (warp_to_come) {
    moment.deadlines_until_ns = INT64_MIN;
  } else {
    moment.deadlines_until_ns = t0_ns_ + horizon_ns - virtual_clock_.offset_ns();
  }
  // A thread still setting up is waited for when it wakes before the node's virtual age
  // reaches the horizon (issue 50 item 1); without virtual time, the quiet window decides.
  if (horizon_ns > 0) {
    moment.hold_limit_ns = t0_ns_ + horizon_ns - virtual_clock_.offset_ns();
  }
  // After jumps, rcl polls while a timer due in real time catches up: the stall rule of the
  // warp decides. Before any, idle polls stall the warp (poll()), they do not settle it.
  moment.pollers_prove = !(moment.warping && (warp_.jumps() > 0 || !warp_.loop_seen()));
  return moment;
}

bool Session::provably_idle(int64_t now)
{
  return idle_.provably_idle(moment(now));
}

bool Session::on_activity(pid_t tid)
{
  idle_.on_activity(tid, generation_);
  if (phase_ == Phase::kWarping) {
    warp_.on_activity();
  }
  ++activity_calls_;
  return ++activity_current_ == kSettlingActivity;
}

bool Session::try_jump(int64_t target_ns)
{
  if (phase_ != Phase::kWarping) {
    return false;
  }
  const int64_t now = clock_.now_ns();
  if (warp_.jump(now, target_ns) == Warp::Jump::kEnded) {
    end_warp(now);
    return false;
  }
  break_quiet(now);  // a jump, or timers that still drive the process
  return true;
}

void Session::end_warp(int64_t now)
{
  phase_ = Phase::kFinalSettling;
  warp_.end(now);
}

bool Session::quiet_settled(int64_t now, bool * has_deadline, int64_t * deadline)
{
  if (provably_idle(now)) {
    settled_by_ = idle_.proven_by();
    ++idle_settles_;
    const int64_t loop_wait = idle_.loop_wait_ns();
    if ((phase_ == Phase::kWarping || phase_ == Phase::kFinalSettling) && loop_wait >= 0 &&
        loop_wait < moment(now).deadlines_until_ns)
    {
      warp_.note_real_waits();  // (a note says virtual time ended short of the horizon, and why)
    }
    return true;
  }
  int64_t held_until = 0;
  if (idle_.holding(now, &held_until)) {
    // A thread still setting up wakes then: neither the proof nor the window settles before.
    propose(held_until, has_deadline, deadline);
    return false;
  }
  const bool by_wait = waiters_current_ > 0;
  const bool by_poll = !by_wait && polls_current_ >= kSettlingActivity;
  // A thread asleep in its loop (it used ROS since the last change) is evidence like a wait.
  const bool by_sleep = !by_wait && !by_poll && idle_.sleepers_count(moment(now));
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
  idle_.look_begins();
  if (!started_ || exiting_) {
    return step;
  }
  const int64_t now = clock_.now_ns();
  if (phase_ == Phase::kWarping) {
    int64_t look_at = INT64_MAX;
    const bool over = warp_.check(
      now, idle_.any_blocked(), [this, now]() { return idle_.any_polling() && provably_idle(now); },
      &look_at);
    propose(look_at, &step.has_deadline, &step.deadline_ns);
    if (over) {
      end_warp(now);
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
        start_probing(now, &step);
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
  int64_t recheck_at = INT64_MAX;
  if (idle_.look_done(now, &recheck_at)) {
    step.action = Action::kCheckIdle;
  }
  propose(recheck_at, &step.has_deadline, &step.deadline_ns);
  return step;
}

bool Session::stalled_unchanged() const
{
  // The warp stalled before its first jump and nothing was created or destroyed since the
  // settle before it: virtual time never moved, so the process is where that settle found it,
  // and a second quiet window (two more polls of a loop that sleeps 0.5 s between them: a
  // second) would give the same capture.
  return phase_ == Phase::kFinalSettling && warp_.stalled() && warp_.jumps() == 0 &&
    settled_generation_ == generation_;
}

void Session::mark_settled(int64_t now)
{
  settled_generation_ = generation_;
  written_generation_ = generation_;
  has_settled_ = true;
  time_to_settle_ns_ = now - t0_ns_;
}

void Session::start_probing(int64_t now, Step * step)
{
  std::optional<int64_t> sleep_loop_wake;
  if (settled_by_sleep()) {
    sleep_loop_wake = idle_.first_counted_wake(moment(now));
  }
  phase_ = Phase::kProbing;
  probing_.begin(now, ever_waited_, sleep_loop_wake);
  step->action = Action::kStartProbe;
}

void Session::after_first_settle(int64_t now, Step * step)
{
  step->has_deadline = false;
  if ((phase_ == Phase::kSettling || phase_ == Phase::kProbing) && settings_.horizon_ms > 0) {
    if (warp_.begin(now)) {
      phase_ = Phase::kWarping;
      break_quiet(now);  // the warp must see settle_ms without a jump before it ends
      step->action = Action::kStartWarp;
      return;
    }
  }
  phase_ = Phase::kDone;
  step->action = Action::kSettle;
}

bool Session::poll_probing(int64_t now, Step * step)
{
  using Next = Probing::Next;
  int64_t look_at = INT64_MAX;
  const Next next = probing_.next(now, ever_waited_, settled_generation_ == generation_, &look_at);
  if (next == Next::kWait) {
    propose(look_at, &step->has_deadline, &step->deadline_ns);
    return false;
  }
  if (next == Next::kTimeout) {
    break_quiet(now);
    step->action = Action::kProbeTimeout;
    step->has_deadline = false;
    return true;
  }
  const bool settle_first = next == Next::kEndAfterSettle || next == Next::kSendAfterSettle;
  if (settle_first && !quiet_settled(now, &step->has_deadline, &step->deadline_ns)) {
    return false;
  }
  if (next == Next::kEnd || next == Next::kEndAfterSettle) {
    mark_settled(now);
    after_first_settle(now, step);
    return true;
  }
  step->action = Action::kProbe;
  step->has_deadline = false;
  return true;
}

void Session::probe_answered(bool settle_first)
{
  if (probing_.answered(settle_first)) {
    // The answering thread goes back to its wait after this: the settles count from here.
    break_quiet(clock_.now_ns());
  }
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
  return probing_.outcome();
}

const char * Session::progress_state() const
{
  if (phase_ == Phase::kProbing) {
    return "probing";
  }
  return phase_ == Phase::kWarping || phase_ == Phase::kFinalSettling ? "warping" : "running";
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
  header->probe_state = probe_state();
  header->answer_timeout_ms = settings_.answer_timeout_ms;
  header->has_ended = std::strcmp(state, "exit") == 0 || std::strcmp(state, "shutdown") == 0;
  header->ended_before_settle = phase_ != Phase::kDone;
  header->idle_detect = settings_.detect_idle;
  header->idle_settles = idle_settles_;
  header->window_settles = window_settles_;
  header->polls = polls_;
  header->not_idle = idle_.not_idle_reason();
  warp_.fill_header(now, header);
}

}  // namespace rmw_introspect
