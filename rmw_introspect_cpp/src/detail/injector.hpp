// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__INJECTOR_HPP_
#define DETAIL__INJECTOR_HPP_

#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "rmw/types.h"

#include "detail/dynamic_value.hpp"
#include "detail/handles.hpp"
#include "detail/recorder.hpp"
#include "detail/wait_hub.hpp"

namespace rmw_introspect
{

/// The middleware as a client of this process's own services, and as a publisher to its own
/// subscriptions (stimuli): the one request or message in flight at a time. A request is
/// handed to the node in rmw_take_request (built through the service's introspection type
/// support, C or C++) and its answer read in rmw_send_response (recognised by the injector's
/// own writer GID, never any endpoint's); a stimulus message (one default-constructed message
/// of the subscription's type, built with its type support's init function and handed over
/// as CDR through the subscription's own type support) in rmw_take*, which ends it. Nothing
/// else ever moves: the node's real traffic is untouched (taken: false, responses dropped),
/// and injected requests, messages and answers create no entity and count as no activity.
///
/// Lock order: the Injector's mutex comes before the wait hub's (release() makes a request
/// ready under both); the answer listener runs after it is released.
class Injector
{
public:
  /// The writer GID of every injected request (no endpoint has it: their GIDs start with
  /// the recorder's pid + random prefix).
  static const Gid & writer_gid();

  /// rmw_create_service / rmw_destroy_service: the services of this process by record id.
  /// Removing the service of the request in flight ends it as failed.
  void add_service(ServiceImpl * service);
  void remove_service(ServiceImpl * service);
  /// rmw_create_subscription / rmw_destroy_subscription: the same for subscriptions
  /// (stimuli). Removing the subscription of the stimulus in flight ends it as failed.
  void add_subscription(SubscriptionImpl * subscription);
  void remove_subscription(SubscriptionImpl * subscription);

  /// Called once per answer (or failure) of the request in flight, with its changes_node,
  /// outside the Injector's lock.
  void set_answer_listener(std::function<void(bool changes_node)> listener);

  /// Stage `request` for service `service_id` (not yet visible to the node). False (and
  /// `error`) when the service is gone or no executor ever waited on it.
  bool prepare(
    uint64_t service_id, const DynValue & request, bool changes_node, std::string * error);
  /// Stage a stimulus (not yet visible to the node): one default-constructed message for
  /// subscription `endpoint_id` (kind Subscription), or a default request for service
  /// `endpoint_id` (kind Service), built through the endpoint's introspection type support
  /// with its init function. Its "answer" is the take (a subscription) or the response (a
  /// service), read and discarded. False (and `error`) when the endpoint is gone, no executor
  /// ever waited on it, or the message cannot be built.
  bool prepare_stimulus(EndpointKind kind, uint64_t endpoint_id, std::string * error);
  /// Make the staged request or stimulus ready in the wait sets and wake every waiter.
  void release(WaitHub & hub);

  /// rmw_wait: `service` has a request of ours waiting (lock-free).
  static bool ready(const ServiceImpl * service) { return service->injected_ready.load(); }
  /// rmw_wait: `subscription` has a stimulus of ours waiting (lock-free).
  static bool ready(const SubscriptionImpl * subscription)
  {
    return subscription->injected_ready.load();
  }

  /// rmw_take_request: true when the call is the injector's business (the service had a
  /// request of ours ready): `*taken` then says whether it was handed over (a second
  /// thread racing for it gets false). False: the node's own traffic.
  bool take(ServiceImpl * service, rmw_service_info_t * header, void * ros_request, bool * taken);
  /// rmw_send_response: true when `header` is one of our requests (an answer to the
  /// request in flight is read and kept; a late one is dropped).
  bool answer(ServiceImpl * service, const rmw_request_id_t * header, const void * ros_response);
  /// rmw_take, rmw_take_with_info, rmw_take_sequence, loaned takes: true when the call is the
  /// injector's business (the subscription had a stimulus of ours ready): `*taken` then says
  /// whether it was handed over into `ros_message` (`info`, if not NULL, names the
  /// injector's writer GID). False: the node's own traffic.
  bool take_message(
    SubscriptionImpl * subscription, void * ros_message, bool * taken, rmw_message_info_t * info);
  /// rmw_take_serialized_message*: the same, the stimulus handed over as CDR.
  bool take_serialized(
    SubscriptionImpl * subscription, rmw_serialized_message_t * serialized_message, bool * taken,
    rmw_message_info_t * info);

  enum class Outcome { kNone, kAnswered, kFailed };
  /// The outcome of the request in flight: kAnswered moves the answer to `answer`, kFailed
  /// says why in `error`; either ends it. kNone: still waiting.
  Outcome outcome(DynValue * answer, std::string * error);
  /// Give up the request in flight (no answer in time). Returns outcome() had it ended
  /// meanwhile, else kNone.
  Outcome withdraw(DynValue * answer, std::string * error);

private:
  enum class State { kIdle, kStaged, kReady, kTaken, kAnswered, kFailed };
  struct InFlight
  {
    State state = State::kIdle;
    uint64_t service_id = 0;       // a request (or a stimulus request) to this service
    uint64_t subscription_id = 0;  // or a stimulus message for this subscription
    int64_t sequence = 0;
    bool changes_node = false;
    DynValue request;
    /// A stimulus: the default message or request as CDR (the request then ignores `request`).
    bool stimulus = false;
    std::vector<uint8_t> stimulus_cdr;
    DynValue response;
    std::string error;
  };

  /// Under mutex_: end the request in flight as failed; returns whether a listener call is due.
  bool fail_locked(const std::string & error);
  /// Under mutex_: whatever is in flight is not the node's to take any more.
  void clear_ready_locked();
  /// rmw_take*: hand the stimulus of `subscription` over with `write(cdr, error)`.
  template<typename WriteFn>
  bool take_stimulus(
    SubscriptionImpl * subscription, bool * taken, rmw_message_info_t * info, WriteFn write);
  void notify(bool changes_node);
  ServiceImpl * service_locked(uint64_t id) const;
  SubscriptionImpl * subscription_locked(uint64_t id) const;

  std::mutex mutex_;
  std::map<uint64_t, ServiceImpl *> services_;
  std::map<uint64_t, SubscriptionImpl *> subscriptions_;
  InFlight in_flight_;
  int64_t next_sequence_ = 1;
  std::mutex listener_mutex_;
  std::function<void(bool)> listener_;
};

}  // namespace rmw_introspect

#endif  // DETAIL__INJECTOR_HPP_
