// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/injector.hpp"

#include <cstring>
#include <string>
#include <utility>

#include "rcutils/time.h"

#include "detail/message_walker.hpp"

namespace rmw_introspect
{

const Gid & Injector::writer_gid()
{
  static const Gid gid = {'r', 'm', 'w', 'i', '/', 'i', 'n', 'j', 'e', 'c', 't', 'o', 'r', 0, 0, 1};
  return gid;
}

void Injector::add_service(ServiceImpl * service)
{
  if (service == nullptr) {
    return;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  services_[service->record_id] = service;
}

void Injector::remove_service(ServiceImpl * service)
{
  if (service == nullptr) {
    return;
  }
  bool notify_due = false;
  bool changes_node = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = services_.find(service->record_id);
    if (it == services_.end() || it->second != service) {
      return;
    }
    services_.erase(it);
    service->injected_ready.store(false);
    if (in_flight_.service_id == service->record_id &&
      (in_flight_.state == State::kReady || in_flight_.state == State::kTaken))
    {
      changes_node = in_flight_.changes_node;
      notify_due = fail_locked("the service " + service->name + " was destroyed before it answered");
    }
  }
  if (notify_due) {
    notify(changes_node);
  }
}

void Injector::set_answer_listener(std::function<void(bool)> listener)
{
  std::lock_guard<std::mutex> lock(listener_mutex_);
  listener_ = std::move(listener);
}

void Injector::notify(bool changes_node)
{
  std::function<void(bool)> listener;
  {
    std::lock_guard<std::mutex> lock(listener_mutex_);
    listener = listener_;
  }
  if (listener) {
    listener(changes_node);
  }
}

ServiceImpl * Injector::service_locked(uint64_t id) const
{
  const auto it = services_.find(id);
  return it != services_.end() ? it->second : nullptr;
}

bool Injector::prepare(
  uint64_t service_id, const DynValue & request, bool changes_node, std::string * error)
{
  std::lock_guard<std::mutex> lock(mutex_);
  ServiceImpl * service = service_locked(service_id);
  if (service == nullptr) {
    if (error != nullptr) {*error = "the service is gone";}
    return false;
  }
  if (!service->in_wait_set.load()) {
    if (error != nullptr) {
      *error = "no executor serves " + service->name + " (it was never in a wait set)";
    }
    return false;
  }
  if (in_flight_.state == State::kReady) {
    // An earlier request nobody took: it is not the node's to take any more.
    if (ServiceImpl * old = service_locked(in_flight_.service_id)) {
      old->injected_ready.store(false);
    }
  }
  in_flight_ = InFlight();
  in_flight_.state = State::kStaged;
  in_flight_.service_id = service_id;
  in_flight_.sequence = next_sequence_++;
  in_flight_.changes_node = changes_node;
  in_flight_.request = request;
  return true;
}

void Injector::release(WaitHub & hub)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (in_flight_.state != State::kStaged) {
    return;
  }
  ServiceImpl * service = service_locked(in_flight_.service_id);
  if (service == nullptr) {
    return;  // destroyed in between: remove_service() did not see it ready; withdraw ends it
  }
  in_flight_.state = State::kReady;
  hub.update_and_wake([service]() {service->injected_ready.store(true);});
}

bool Injector::take(
  ServiceImpl * service, rmw_service_info_t * header, void * ros_request, bool * taken)
{
  if (!service->injected_ready.load()) {
    return false;
  }
  bool notify_due = false;
  bool changes_node = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!service->injected_ready.exchange(false)) {
      *taken = false;  // another thread took it first
      return true;
    }
    if (in_flight_.state != State::kReady || in_flight_.service_id != service->record_id) {
      *taken = false;
      return true;
    }
    MessageLayout request_layout, response_layout;
    std::string error;
    if (!service_message_layouts(service->type, &request_layout, &response_layout, &error) ||
      !write_message(request_layout, in_flight_.request, ros_request, &error))
    {
      *taken = false;
      changes_node = in_flight_.changes_node;
      notify_due = fail_locked(
        "cannot build the request of " + service->name + " (" + service->type.name + "): " + error);
    } else {
      std::memset(header, 0, sizeof(*header));
      std::memcpy(header->request_id.writer_guid, writer_gid().data(), writer_gid().size());
      header->request_id.sequence_number = in_flight_.sequence;
      rcutils_time_point_value_t now = 0;
      if (rcutils_system_time_now(&now) == RCUTILS_RET_OK) {
        header->source_timestamp = now;
        header->received_timestamp = now;
      }
      in_flight_.state = State::kTaken;
      *taken = true;
    }
  }
  if (notify_due) {
    notify(changes_node);
  }
  return true;
}

bool Injector::answer(
  ServiceImpl * service, const rmw_request_id_t * header, const void * ros_response)
{
  if (std::memcmp(header->writer_guid, writer_gid().data(), writer_gid().size()) != 0) {
    return false;
  }
  bool changes_node = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (in_flight_.state != State::kTaken || in_flight_.service_id != service->record_id ||
      in_flight_.sequence != header->sequence_number)
    {
      return true;  // an answer given up on: dropped
    }
    MessageLayout request_layout, response_layout;
    std::string error;
    if (!service_message_layouts(service->type, &request_layout, &response_layout, &error) ||
      !read_message(response_layout, ros_response, &in_flight_.response, &error))
    {
      fail_locked("cannot read the response of " + service->name + ": " + error);
    } else {
      in_flight_.state = State::kAnswered;
    }
    changes_node = in_flight_.changes_node;
  }
  notify(changes_node);
  return true;
}

bool Injector::fail_locked(const std::string & error)
{
  in_flight_.state = State::kFailed;
  in_flight_.error = error;
  in_flight_.request = DynValue();
  return true;
}

Injector::Outcome Injector::outcome(DynValue * answer, std::string * error)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (in_flight_.state == State::kAnswered) {
    *answer = std::move(in_flight_.response);
    in_flight_ = InFlight();
    return Outcome::kAnswered;
  }
  if (in_flight_.state == State::kFailed) {
    *error = in_flight_.error;
    in_flight_ = InFlight();
    return Outcome::kFailed;
  }
  return Outcome::kNone;
}

Injector::Outcome Injector::withdraw(DynValue * answer, std::string * error)
{
  const Outcome ended = outcome(answer, error);
  if (ended != Outcome::kNone) {
    return ended;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  if (ServiceImpl * service = service_locked(in_flight_.service_id)) {
    service->injected_ready.store(false);
  }
  in_flight_ = InFlight();
  return Outcome::kNone;
}

}  // namespace rmw_introspect
