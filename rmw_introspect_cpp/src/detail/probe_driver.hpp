// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__PROBE_DRIVER_HPP_
#define DETAIL__PROBE_DRIVER_HPP_

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

#include "detail/injector.hpp"
#include "detail/prober.hpp"
#include "detail/recorder.hpp"
#include "detail/wait_hub.hpp"

namespace rmw_introspect
{

/// Runs the Prober against this process: asks it for the next request, sends that through
/// the Injector, hands the answer (or its absence) back, and keeps what it learnt with the
/// node records (Recorder::set_node_probe, set_node_transition for the endpoints' created_in).
/// Used by the monitor thread only, on the Session's kProbe / kProbeTimeout actions, with no
/// lock of the Runtime held.
class ProbeDriver
{
public:
  ProbeDriver(const ProbeSettings & settings, Recorder & recorder, Injector & injector);

  /// kProbe: take the outcome of the request in flight, then send the next one: `before_send`
  /// runs just before the node can see it (the Session's probe_sent). False when nothing is
  /// left to ask.
  bool step(WaitHub & hub, const std::function<void()> & before_send);
  /// kProbeTimeout: the request in flight got no answer within `timeout_ms`.
  void timeout(int64_t timeout_ms);

  const ProbeSettings & settings() const {return prober_.settings();}
  size_t requests() const {return prober_.requests();}
  size_t unanswered() const {return prober_.unanswered();}

private:
  void publish(uint64_t node_id);

  Prober prober_;
  Recorder & recorder_;
  Injector & injector_;
  bool in_flight_ = false;
  uint64_t in_flight_node_ = 0;
  std::string in_flight_service_;
};

}  // namespace rmw_introspect

#endif  // DETAIL__PROBE_DRIVER_HPP_
