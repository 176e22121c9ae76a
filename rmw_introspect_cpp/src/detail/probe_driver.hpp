// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__PROBE_DRIVER_HPP_
#define DETAIL__PROBE_DRIVER_HPP_

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "detail/component_loads.hpp"
#include "detail/injector.hpp"
#include "detail/prober.hpp"
#include "detail/recorder.hpp"
#include "detail/stimuli.hpp"
#include "detail/wait_hub.hpp"

namespace rmw_introspect
{

/// First sends the launch file's component loads (ComponentLoadPlan) to this process's
/// component containers, one at a time, each followed by a settle (the nodes they create are
/// then probed like the others). Then runs the Prober against this process: asks it for the next request, sends that through
/// the Injector, hands the answer (or its absence) back, and keeps what it learnt with the
/// node records (Recorder::set_node_probe, set_node_transition for the endpoints' created_in).
/// When the Prober has nothing left to ask (or is off), the stimuli follow the same way
/// (StimulusPlan: one default message or request at a time through the Injector, each
/// followed by a settle; endpoints created in between record "stimulus:<name>").
/// Used by the monitor thread only, on the Session's kProbe / kProbeTimeout actions, with no
/// lock of the Runtime held.
class ProbeDriver
{
public:
  ProbeDriver(
    const ProbeSettings & settings, const std::vector<std::string> & stimuli,
    const std::vector<ComponentLoad> & loads, Recorder & recorder, Injector & injector);

  /// kProbe: take the outcome of the request in flight, then send the next one: `before_send`
  /// runs just before the node can see it (the Session's probe_sent). False when nothing is
  /// left to ask.
  bool step(WaitHub & hub, const std::function<void()> & before_send);
  /// kProbeTimeout: the request in flight got no answer within `timeout_ms`.
  void timeout(int64_t timeout_ms);

  /// The probing was skipped (no thread ever waited): the stimuli not delivered say `why`.
  void skip(const std::string & why);

  const ProbeSettings & settings() const { return prober_.settings(); }
  size_t requests() const { return prober_.requests(); }
  size_t unanswered() const { return prober_.unanswered(); }
  /// What the stimuli came to so far (in the order given).
  const std::vector<StimulusRecord> & stimuli() const { return stimuli_.records(); }
  /// What the component loads came to so far (in the order given).
  const std::vector<ComponentLoadRecord> & component_loads() const { return loads_.records(); }

private:
  void publish(uint64_t node_id);
  /// The outcome of the request or stimulus in flight (`timeout_ms` > 0: it timed out).
  void finish_in_flight(
    Injector::Outcome outcome, const DynValue & answer, const std::string & error,
    int64_t timeout_ms);
  /// Send the next stimulus; false when none is left.
  bool send_stimulus(WaitHub & hub, const std::function<void()> & before_send);
  /// Send the next component load; false when none is left.
  bool send_load(WaitHub & hub, const std::function<void()> & before_send);

  Prober prober_;
  StimulusPlan stimuli_;
  ComponentLoadPlan loads_;
  bool loads_done_ = false;
  bool in_flight_load_ = false;
  Recorder & recorder_;
  Injector & injector_;
  bool prober_done_ = false;  // the Prober has nothing left to ask (or is off)
  bool in_flight_ = false;
  bool in_flight_stimulus_ = false;
  uint64_t in_flight_node_ = 0;
  std::string in_flight_service_;
  std::string in_flight_silence_;  // a stimulus: what no outcome means
};

}  // namespace rmw_introspect

#endif  // DETAIL__PROBE_DRIVER_HPP_
