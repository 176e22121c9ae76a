// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__PROBING_HPP_
#define DETAIL__PROBING_HPP_

#include <cstdint>
#include <optional>

#include "detail/clock.hpp"

namespace rmw_introspect
{

/// The probing phase's pace (Settings::probe; docs/design.md, "Probing"): one request at a time,
/// each answered or timed out before the next, a settle after a request that changed the node,
/// and none at all for a process with no executor to take a request. What to ask and what the
/// answers mean is the Prober's (prober.hpp); settles are the Session's, which asks next() what
/// is due and acts on it.
class Probing
{
public:
  /// `main_thread`: whether the main thread is runnable (null: taken as never; unit tests).
  Probing(int64_t answer_timeout_ms, const MainThreadState * main_thread);

  /// The first settle at `now` starts the probing. `ever_waited`: a thread entered rmw_wait
  /// before; `sleep_loop_wake`: for a settle proven by sleepers alone, the first of their
  /// wakes (nothing can start to wait before it).
  void begin(int64_t now, bool ever_waited, std::optional<int64_t> sleep_loop_wake);
  /// A sleeper of a settle proven by sleepers went round its loop again at `now` (it used
  /// ROS and sleeps again) and still no thread waited: it is in its steady loop.
  void sleep_loop_again(int64_t now);

  enum class Next {
    kWait,              // nothing due before `*look_at_ns`
    kTimeout,           // the request in flight got no answer in time
    kSend,              // send the next request now
    kSendAfterSettle,   // ... once the process settled again
    kEnd,               // nothing left to ask, and the settle before still holds
    kEndAfterSettle,    // nothing left to ask; the end waits for a settle
  };
  /// What is due at `now`. `unchanged`: no entity was created or destroyed since the latest
  /// settle. Lowers `*look_at_ns` for kWait.
  Next next(int64_t now, bool ever_waited, bool unchanged, int64_t * look_at_ns);

  /// A request is about to reach the node, at `now`.
  void sent(int64_t now);
  /// The answer to the request in flight came; false when it is late (its timeout was
  /// reported). `settle_first`: the node changed (a transition).
  bool answered(bool settle_first);
  /// Nothing (more) to ask.
  void done();
  /// Whether, after the phase, the nodes were asked: "done", or "skipped" (no thread entered
  /// rmw_wait in time after the settle: no executor to ask).
  const char * outcome() const { return probed_ && !skipped_ ? "done" : "skipped"; }

private:
  const int64_t answer_timeout_ms_;
  const MainThreadState * main_thread_;
  bool probed_ = false;   // the probing phase was entered
  bool skipped_ = false;  // ... and left: no thread ever waited
  int64_t started_ns_ = 0;
  bool in_flight_ = false;
  int64_t sent_ns_ = 0;
  bool settle_first_ = false;
  bool done_ = false;
  int64_t first_wait_give_up_ns_ = 0;  // when a process that never waited is not probed
  // An answer that runs the node's own code (a transition, a stimulus) or a timeout: the node
  // may have changed, so the end of the probing waits for a settle. Reads need none.
  bool changed_node_ = false;
};

}  // namespace rmw_introspect

#endif  // DETAIL__PROBING_HPP_
