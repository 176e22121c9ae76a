// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/probing.hpp"

#include <algorithm>
#include <cstdint>
#include <optional>

namespace rmw_introspect
{

namespace
{
constexpr int64_t kNsPerMs = 1000 * 1000;
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
}  // namespace

Probing::Probing(int64_t answer_timeout_ms, const MainThreadState * main_thread)
: answer_timeout_ms_(answer_timeout_ms), main_thread_(main_thread)
{
}

void Probing::begin(int64_t now, bool ever_waited, std::optional<int64_t> sleep_loop_wake)
{
  probed_ = true;
  started_ns_ = now;
  first_wait_give_up_ns_ = now + kFirstWaitGraceNs;
  if (!ever_waited && sleep_loop_wake.has_value()) {
    // Proven idle with every thread blocked or asleep in its loop: nothing can start to
    // wait before the first sleeper wakes, so a grace that ends first is not waited for.
    if (*sleep_loop_wake >= first_wait_give_up_ns_) {
      first_wait_give_up_ns_ = now;
    }
  }
  // Settled by activity before any wait: the first request waits for a settle by wait.
  settle_first_ = !ever_waited;
}

void Probing::sleep_loop_again(int64_t now)
{
  if (!done_) {
    first_wait_give_up_ns_ = std::min(first_wait_give_up_ns_, now + kSleepLoopAgainNs);
  }
}

Probing::Next Probing::next(int64_t now, bool ever_waited, bool unchanged, int64_t * look_at_ns)
{
  if (!ever_waited && !done_) {
    // No executor has waited yet: nobody could take a request.
    if (now < first_wait_give_up_ns_) {
      *look_at_ns = std::min(*look_at_ns, first_wait_give_up_ns_);
      return Next::kWait;
    }
    const int64_t last_chance = started_ns_ + kFirstWaitMaxNs;
    if (main_thread_ != nullptr && now < last_chance && main_thread_->runnable()) {
      first_wait_give_up_ns_ = std::min(now + kFirstWaitRecheckNs, last_chance);
      *look_at_ns = std::min(*look_at_ns, first_wait_give_up_ns_);
      return Next::kWait;
    }
    skipped_ = true;
    done_ = true;
  }
  if (in_flight_) {
    const int64_t deadline = sent_ns_ + answer_timeout_ms_ * kNsPerMs;
    if (now >= deadline) {
      in_flight_ = false;
      settle_first_ = true;  // the node may still be busy with it
      changed_node_ = true;
      return Next::kTimeout;
    }
    *look_at_ns = std::min(*look_at_ns, deadline);
    return Next::kWait;
  }
  if (done_) {
    // Only parameters were read and nothing was created meanwhile: the settle that started
    // the probing still holds (a read runs no code of the node's), so no second one.
    return !changed_node_ && unchanged ? Next::kEnd : Next::kEndAfterSettle;
  }
  return settle_first_ ? Next::kSendAfterSettle : Next::kSend;
}

void Probing::sent(int64_t now)
{
  in_flight_ = true;
  sent_ns_ = now;
}

bool Probing::answered(bool settle_first)
{
  if (!in_flight_) {
    return false;  // late: its timeout was already reported
  }
  in_flight_ = false;
  settle_first_ = settle_first;
  changed_node_ = changed_node_ || settle_first;
  return true;
}

void Probing::done()
{
  done_ = true;
  in_flight_ = false;
}

}  // namespace rmw_introspect
