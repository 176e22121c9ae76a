// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__INJECTOR_HPP_
#define DETAIL__INJECTOR_HPP_

#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>

#include "rmw/types.h"

#include "detail/dynamic_value.hpp"
#include "detail/handles.hpp"
#include "detail/wait_hub.hpp"

namespace rmw_introspect
{

/// The middleware as a client of this process's own services: the one request in flight at
/// a time, handed to the node in rmw_take_request (built through the service's introspection
/// type support, C or C++) and its answer read in rmw_send_response (recognised by the
/// injector's own writer GID, never any endpoint's). Nothing else ever moves: the node's
/// real traffic is untouched (taken: false, responses dropped), and injected requests and
/// answers create no entity and count as no activity.
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

  /// Called once per answer (or failure) of the request in flight, with its changes_node,
  /// outside the Injector's lock.
  void set_answer_listener(std::function<void(bool changes_node)> listener);

  /// Stage `request` for service `service_id` (not yet visible to the node). False (and
  /// `error`) when the service is gone or no executor ever waited on it.
  bool prepare(
    uint64_t service_id, const DynValue & request, bool changes_node, std::string * error);
  /// Make the staged request ready in the wait sets and wake every waiter.
  void release(WaitHub & hub);

  /// rmw_wait: `service` has a request of ours waiting (lock-free).
  static bool ready(const ServiceImpl * service) {return service->injected_ready.load();}

  /// rmw_take_request: true when the call is the injector's business (the service had a
  /// request of ours ready): `*taken` then says whether it was handed over (a second
  /// thread racing for it gets false). False: the node's own traffic.
  bool take(ServiceImpl * service, rmw_service_info_t * header, void * ros_request, bool * taken);
  /// rmw_send_response: true when `header` is one of our requests (an answer to the
  /// request in flight is read and kept; a late one is dropped).
  bool answer(ServiceImpl * service, const rmw_request_id_t * header, const void * ros_response);

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
    uint64_t service_id = 0;
    int64_t sequence = 0;
    bool changes_node = false;
    DynValue request;
    DynValue response;
    std::string error;
  };

  /// Under mutex_: end the request in flight as failed; returns whether a listener call is due.
  bool fail_locked(const std::string & error);
  void notify(bool changes_node);
  ServiceImpl * service_locked(uint64_t id) const;

  std::mutex mutex_;
  std::map<uint64_t, ServiceImpl *> services_;
  InFlight in_flight_;
  int64_t next_sequence_ = 1;
  std::mutex listener_mutex_;
  std::function<void(bool)> listener_;
};

}  // namespace rmw_introspect

#endif  // DETAIL__INJECTOR_HPP_
