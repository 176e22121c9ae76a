// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/probe_driver.hpp"

#include <string>

namespace rmw_introspect
{

ProbeDriver::ProbeDriver(const ProbeSettings & settings, Recorder & recorder, Injector & injector)
: prober_(settings), recorder_(recorder), injector_(injector)
{
}

void ProbeDriver::publish(uint64_t node_id)
{
  if (const NodeProbe * result = prober_.result(node_id)) {
    recorder_.set_node_probe(node_id, *result);
  }
}

bool ProbeDriver::step(WaitHub & hub, const std::function<void()> & before_send)
{
  if (in_flight_) {
    DynValue answer;
    std::string error;
    switch (injector_.withdraw(&answer, &error)) {
      case Injector::Outcome::kAnswered:
        prober_.on_answer(answer);
        break;
      case Injector::Outcome::kFailed:
        prober_.on_no_answer(error);
        break;
      case Injector::Outcome::kNone:
        prober_.on_no_answer("no answer from " + in_flight_service_);
        break;
    }
    in_flight_ = false;
    publish(in_flight_node_);
  }
  while (true) {
    ProbeRequest request;
    if (!prober_.next(recorder_.snapshot(), &request)) {
      return false;
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
}

void ProbeDriver::timeout(int64_t timeout_ms)
{
  if (!in_flight_) {
    return;
  }
  DynValue answer;
  std::string error;
  switch (injector_.withdraw(&answer, &error)) {
    case Injector::Outcome::kAnswered:
      prober_.on_answer(answer);
      break;
    case Injector::Outcome::kFailed:
      prober_.on_no_answer(error);
      break;
    case Injector::Outcome::kNone:
      prober_.on_no_answer(
        "no answer from " + in_flight_service_ + " within " + std::to_string(timeout_ms) + " ms");
      break;
  }
  in_flight_ = false;
  publish(in_flight_node_);
}

}  // namespace rmw_introspect
