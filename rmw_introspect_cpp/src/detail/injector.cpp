// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/injector.hpp"

#include <algorithm>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "rcutils/time.h"
#include "rmw/serialized_message.h"

#include "detail/cdr.hpp"
#include "detail/identifier.hpp"
#include "detail/members.hpp"
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
      notify_due =
        fail_locked("the service " + service->name + " was destroyed before it answered");
    }
  }
  if (notify_due) {
    notify(changes_node);
  }
}

void Injector::add_subscription(SubscriptionImpl * subscription)
{
  if (subscription == nullptr) {
    return;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  subscriptions_[subscription->record_id] = subscription;
}

void Injector::remove_subscription(SubscriptionImpl * subscription)
{
  if (subscription == nullptr) {
    return;
  }
  bool notify_due = false;
  bool changes_node = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = subscriptions_.find(subscription->record_id);
    if (it == subscriptions_.end() || it->second != subscription) {
      return;
    }
    subscriptions_.erase(it);
    subscription->injected_ready.store(false);
    if (in_flight_.subscription_id == subscription->record_id && in_flight_.state == State::kReady)
    {
      changes_node = in_flight_.changes_node;
      notify_due = fail_locked(
        "the subscription " + subscription->name + " was destroyed before it took the message");
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

SubscriptionImpl * Injector::subscription_locked(uint64_t id) const
{
  const auto it = subscriptions_.find(id);
  return it != subscriptions_.end() ? it->second : nullptr;
}

void Injector::clear_ready_locked()
{
  if (in_flight_.state != State::kReady) {
    return;
  }
  if (in_flight_.subscription_id != 0) {
    if (SubscriptionImpl * old = subscription_locked(in_flight_.subscription_id)) {
      old->injected_ready.store(false);
    }
  } else if (ServiceImpl * old = service_locked(in_flight_.service_id)) {
    old->injected_ready.store(false);
  }
}

namespace
{
// One default-constructed message of `layout` (its init function), as CDR.
bool default_message_cdr(
  const MessageLayout & layout, std::vector<uint8_t> * out, std::string * error)
{
  if (layout.members == nullptr) {
    *error = "its type support has no introspection members";
    return false;
  }
  void * message = members::create_message(layout.members, layout.is_cpp);
  if (message == nullptr) {
    *error = "out of memory";
    return false;
  }
  const bool ok = cdr_serialize(layout, message, out, error);
  members::destroy_message(layout.members, layout.is_cpp, message);
  return ok;
}
}  // namespace

bool Injector::prepare_stimulus(EndpointKind kind, uint64_t endpoint_id, std::string * error)
{
  std::string why;
  std::lock_guard<std::mutex> lock(mutex_);
  InFlight staged;
  staged.stimulus = true;
  staged.changes_node = true;  // the node reacts: it settles again before the next one
  if (kind == EndpointKind::Subscription) {
    SubscriptionImpl * subscription = subscription_locked(endpoint_id);
    if (subscription == nullptr) {
      why = "the subscription is gone";
    } else if (!subscription->in_wait_set.load()) {
      why = "no executor takes from the subscription " + subscription->name +
        " (it was never in a wait set)";
    } else if (!default_message_cdr(subscription->layout, &staged.stimulus_cdr, &why)) {
      why = "cannot build a default " + subscription->type.name + " message: " + why;
    }
    staged.subscription_id = endpoint_id;
  } else if (kind == EndpointKind::Service) {
    ServiceImpl * service = service_locked(endpoint_id);
    MessageLayout request_layout, response_layout;
    if (service == nullptr) {
      why = "the service is gone";
    } else if (!service->in_wait_set.load()) {
      why = "no executor serves " + service->name + " (it was never in a wait set)";
    } else if (!service_message_layouts(service->type, &request_layout, &response_layout, &why) ||
               !default_message_cdr(request_layout, &staged.stimulus_cdr, &why))
    {
      why = "cannot build a default " + service->type.name + " request: " + why;
    }
    staged.service_id = endpoint_id;
  } else {
    why = "only subscriptions and services take stimuli";
  }
  if (!why.empty()) {
    if (error != nullptr) {
      *error = why;
    }
    return false;
  }
  clear_ready_locked();
  staged.state = State::kStaged;
  staged.sequence = next_sequence_++;
  in_flight_ = std::move(staged);
  return true;
}

bool Injector::prepare(
  uint64_t service_id, const DynValue & request, bool changes_node, std::string * error)
{
  std::lock_guard<std::mutex> lock(mutex_);
  ServiceImpl * service = service_locked(service_id);
  if (service == nullptr) {
    if (error != nullptr) {
      *error = "the service is gone";
    }
    return false;
  }
  if (!service->in_wait_set.load()) {
    if (error != nullptr) {
      *error = "no executor serves " + service->name + " (it was never in a wait set)";
    }
    return false;
  }
  // An earlier request nobody took: it is not the node's to take any more.
  clear_ready_locked();
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
  if (in_flight_.subscription_id != 0) {
    SubscriptionImpl * subscription = subscription_locked(in_flight_.subscription_id);
    if (subscription == nullptr) {
      return;  // destroyed in between; withdraw ends it
    }
    in_flight_.state = State::kReady;
    hub.update_and_wake([subscription]() { subscription->injected_ready.store(true); });
    return;
  }
  ServiceImpl * service = service_locked(in_flight_.service_id);
  if (service == nullptr) {
    return;  // destroyed in between: remove_service() did not see it ready; withdraw ends it
  }
  in_flight_.state = State::kReady;
  hub.update_and_wake([service]() { service->injected_ready.store(true); });
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
    const bool built =
      service_message_layouts(service->type, &request_layout, &response_layout, &error) &&
      (in_flight_.stimulus ?
         cdr_deserialize(
           request_layout, in_flight_.stimulus_cdr.data(), in_flight_.stimulus_cdr.size(),
           ros_request, &error) :
         write_message(request_layout, in_flight_.request, ros_request, &error));
    if (!built) {
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
    if (in_flight_.stimulus) {
      in_flight_.state = State::kAnswered;  // a stimulus's answer is discarded unread
    } else if (!service_message_layouts(service->type, &request_layout, &response_layout, &error) ||
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

template<typename WriteFn>
bool Injector::take_stimulus(
  SubscriptionImpl * subscription, bool * taken, rmw_message_info_t * info, WriteFn write)
{
  if (!subscription->injected_ready.load()) {
    return false;
  }
  bool notify_due = false;
  const bool changes_node = true;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!subscription->injected_ready.exchange(false)) {
      *taken = false;  // another thread took it first
      return true;
    }
    if (in_flight_.state != State::kReady || in_flight_.subscription_id != subscription->record_id)
    {
      *taken = false;
      return true;
    }
    std::string error;
    if (!write(in_flight_.stimulus_cdr, &error)) {
      *taken = false;
      notify_due = fail_locked(
        "cannot hand the message over to " + subscription->name + " (" + subscription->type.name +
        "): " + error);
    } else {
      if (info != nullptr) {
        std::memset(info, 0, sizeof(*info));
        info->publisher_gid.implementation_identifier = kIdentifier;
        std::memcpy(
          info->publisher_gid.data, writer_gid().data(),
          std::min(sizeof(info->publisher_gid.data), writer_gid().size()));
        rcutils_time_point_value_t now = 0;
        if (rcutils_system_time_now(&now) == RCUTILS_RET_OK) {
          info->source_timestamp = now;
          info->received_timestamp = now;
        }
        info->publication_sequence_number = static_cast<uint64_t>(in_flight_.sequence);
        info->reception_sequence_number = static_cast<uint64_t>(in_flight_.sequence);
        info->from_intra_process = false;
      }
      // Taking it is the whole delivery: the stimulus has its outcome.
      in_flight_.state = State::kAnswered;
      in_flight_.response = DynValue();
      *taken = true;
      notify_due = true;
    }
  }
  if (notify_due) {
    notify(changes_node);
  }
  return true;
}

bool Injector::take_message(
  SubscriptionImpl * subscription, void * ros_message, bool * taken, rmw_message_info_t * info)
{
  return take_stimulus(
    subscription, taken, info,
    [subscription, ros_message](const std::vector<uint8_t> & cdr, std::string * error) {
      return cdr_deserialize(subscription->layout, cdr.data(), cdr.size(), ros_message, error);
    });
}

bool Injector::take_serialized(
  SubscriptionImpl * subscription, rmw_serialized_message_t * serialized_message, bool * taken,
  rmw_message_info_t * info)
{
  return take_stimulus(
    subscription, taken, info,
    [serialized_message](const std::vector<uint8_t> & cdr, std::string * error) {
      if (serialized_message->buffer_capacity < cdr.size() &&
          rmw_serialized_message_resize(serialized_message, cdr.size()) != RMW_RET_OK)
      {
        rcutils_reset_error();
        *error = "cannot resize the serialized message";
        return false;
      }
      std::memcpy(serialized_message->buffer, cdr.data(), cdr.size());
      serialized_message->buffer_length = cdr.size();
      return true;
    });
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
  if (in_flight_.subscription_id != 0) {
    if (SubscriptionImpl * subscription = subscription_locked(in_flight_.subscription_id)) {
      subscription->injected_ready.store(false);
    }
  } else if (ServiceImpl * service = service_locked(in_flight_.service_id)) {
    service->injected_ready.store(false);
  }
  in_flight_ = InFlight();
  return Outcome::kNone;
}

}  // namespace rmw_introspect
