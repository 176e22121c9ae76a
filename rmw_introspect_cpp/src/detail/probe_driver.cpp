// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/probe_driver.hpp"

#include <string>
#include <vector>

namespace rmw_introspect
{

ProbeDriver::ProbeDriver(
  const ProbeSettings & settings, const std::vector<std::string> & stimuli,
  const std::vector<ComponentLoad> & loads, Recorder & recorder, Injector & injector)
: prober_(settings),
  stimuli_(stimuli),
  loads_(loads),
  recorder_(recorder),
  injector_(injector),
  prober_done_(!settings.enabled())
{
}

void ProbeDriver::publish(uint64_t node_id)
{
  if (const NodeProbe * result = prober_.result(node_id)) {
    recorder_.set_node_probe(node_id, *result);
  }
}

void ProbeDriver::finish_in_flight(
  Injector::Outcome outcome, const DynValue & answer, const std::string & error, int64_t timeout_ms)
{
  const std::string within =
    timeout_ms > 0 ? " within " + std::to_string(timeout_ms) + " ms" : std::string();
  if (in_flight_load_) {
    switch (outcome) {
      case Injector::Outcome::kAnswered: loads_.on_answer(answer); break;
      case Injector::Outcome::kFailed: loads_.on_failed(error, false); break;
      case Injector::Outcome::kNone:
        loads_.on_failed("no answer from " + in_flight_service_ + within, true);
        break;
    }
  } else if (in_flight_stimulus_) {
    // The process settled after it (or gave up): what it creates now is not its reaction.
    recorder_.set_cause("");
    switch (outcome) {
      case Injector::Outcome::kAnswered: stimuli_.on_delivered(); break;
      case Injector::Outcome::kFailed: stimuli_.on_failed(error, false); break;
      case Injector::Outcome::kNone: stimuli_.on_failed(in_flight_silence_ + within, true); break;
    }
  } else {
    switch (outcome) {
      case Injector::Outcome::kAnswered: prober_.on_answer(answer); break;
      case Injector::Outcome::kFailed: prober_.on_no_answer(error); break;
      case Injector::Outcome::kNone:
        prober_.on_no_answer("no answer from " + in_flight_service_ + within);
        break;
    }
    publish(in_flight_node_);
  }
  in_flight_ = false;
  in_flight_stimulus_ = false;
  in_flight_load_ = false;
}

bool ProbeDriver::step(WaitHub & hub, const std::function<void()> & before_send)
{
  if (in_flight_) {
    DynValue answer;
    std::string error;
    const Injector::Outcome outcome = injector_.withdraw(&answer, &error);
    finish_in_flight(outcome, answer, error, 0);
  }
  if (send_load(hub, before_send)) {
    return true;
  }
  while (!prober_done_) {
    ProbeRequest request;
    if (!prober_.next(recorder_.snapshot(), &request)) {
      prober_done_ = true;  // nodes created from now on (by a stimulus) are not asked
      break;
    }
    std::string error;
    if (!injector_.prepare(request.service_id, request.request, request.changes_node, &error)) {
      prober_.on_no_answer(error);
      publish(request.node_id);
      continue;
    }
    if (!request.transition.empty()) {
      // Endpoints the node creates from now on were created in this transition.
      recorder_.set_node_transition(request.node_id, request.transition);
    }
    publish(request.node_id);  // a transition shows as pending in a capture written meanwhile
    in_flight_ = true;
    in_flight_node_ = request.node_id;
    in_flight_service_ = request.service_name;
    before_send();
    injector_.release(hub);
    return true;
  }
  return send_stimulus(hub, before_send);
}

bool ProbeDriver::send_load(WaitHub & hub, const std::function<void()> & before_send)
{
  while (!loads_done_) {
    uint64_t service_id = 0;
    const ComponentLoad * load = nullptr;
    if (!loads_.next(recorder_.snapshot(), &service_id, &load)) {
      loads_done_ = true;
      break;
    }
    std::string error;
    // A load creates a node: wait for the process to settle again before the next request.
    if (!injector_.prepare(service_id, load->request, true, &error)) {
      loads_.on_failed(error, false);
      continue;
    }
    in_flight_ = true;
    in_flight_load_ = true;
    in_flight_service_ = load->service;
    before_send();
    injector_.release(hub);
    return true;
  }
  return false;
}

bool ProbeDriver::send_stimulus(WaitHub & hub, const std::function<void()> & before_send)
{
  while (true) {
    StimulusRequest request;
    if (!stimuli_.next(recorder_.snapshot(), &request)) {
      return false;
    }
    std::string error;
    if (!injector_.prepare_stimulus(request.kind, request.endpoint_id, &error)) {
      stimuli_.on_failed(error, false);
      continue;
    }
    // Endpoints the process creates until it settled again are its reaction to the stimulus.
    recorder_.set_cause(stimulus_label(request.name));
    in_flight_ = true;
    in_flight_stimulus_ = true;
    in_flight_node_ = request.node_id;
    in_flight_silence_ = request.kind == EndpointKind::Service ?
      "no answer from " + request.name + " of " + request.node :
      "the subscription " + request.name + " of " + request.node + " did not take the message";
    before_send();
    injector_.release(hub);
    return true;
  }
}

void ProbeDriver::skip(const std::string & why)
{
  if (in_flight_stimulus_) {
    recorder_.set_cause("");
  }
  stimuli_.skip_remaining(why);
}

void ProbeDriver::timeout(int64_t timeout_ms)
{
  if (!in_flight_) {
    return;
  }
  DynValue answer;
  std::string error;
  const Injector::Outcome outcome = injector_.withdraw(&answer, &error);
  finish_in_flight(outcome, answer, error, timeout_ms);
}

}  // namespace rmw_introspect
