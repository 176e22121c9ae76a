// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__HANDLES_HPP_
#define DETAIL__HANDLES_HPP_

#include <atomic>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <set>
#include <string>

#include "rmw/event.h"
#include "rmw/event_callback_type.h"
#include "rmw/init.h"
#include "rmw/subscription_content_filter_options.h"
#include "rmw/types.h"

#include "detail/cdr.hpp"
#include "detail/inbox.hpp"
#include "detail/recorder.hpp"
#include "detail/rmw_api.hpp"
#include "detail/subscription_filter.hpp"
#include "detail/typesupport.hpp"
#include "detail/wait_hub.hpp"

namespace rmw_introspect
{

/// rmw_context_t::impl
struct ContextImpl
{
  std::atomic<bool> is_shutdown{false};
  std::atomic<size_t> node_count{0};
};

/// A stored "on new data" / event callback. Called only with in-process delivery
/// (RMW_INTROSPECT_DELIVERY=1): new messages, requests, responses, matched changes.
class Callback
{
public:
  void set(rmw_event_callback_t cb, const void * data)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    callback_ = cb;
    user_data_ = data;
  }
  /// Call it (if set) with `count` new events.
  void notify(size_t count)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (callback_ != nullptr) {
      callback_(user_data_, count);
    }
  }

private:
  std::mutex mutex_;  // a leaf lock
  rmw_event_callback_t callback_ = nullptr;
  const void * user_data_ = nullptr;
};

/// Publishers and subscriptions are the targets of rmw_event_t::data.
struct EventSource
{
  Callback event_callbacks[kEventTypeEnd];
  MatchedState matched;  // PUBLICATION_MATCHED / SUBSCRIPTION_MATCHED (delivery only)
  std::atomic<bool> delivered{false};  // registered with the Delivery: events are live
};

struct GuardConditionImpl
{
  rmw_guard_condition_t handle{};
  GuardCondition gc;
};

struct NodeImpl
{
  rmw_node_t handle{};
  std::string name;
  std::string namespace_;
  uint64_t record_id = 0;
  ContextImpl * context_impl = nullptr;
  GuardConditionImpl graph_guard;
};

/// What every publisher, subscription, service and client keeps; `HandleT` is the handle
/// rcl holds (its `data` points back at the Impl).
template<typename HandleT>
struct EndpointImpl
{
  HandleT handle{};
  std::string name;  // a copy: rcl frees the name it passes right after the create call
  uint64_t record_id = 0;
  const NodeImpl * node = nullptr;
  ResolvedType type;
  rmw_qos_profile_t qos{};         // as requested (recorded as such)
  rmw_qos_profile_t actual_qos{};  // as a middleware resolves it (see endpoint_common.hpp)
  Gid gid{};
};

/// Messages loaned out (in-process delivery, plain types): made by the middleware, the
/// caller's until returned; any still out when the endpoint goes are freed with it.
struct Loans
{
  std::mutex mutex;
  std::set<void *> out;
};

struct PublisherImpl : EventSource, EndpointImpl<rmw_publisher_t>
{
  /// A publisher of /rosout or /parameter_events, which client libraries use by themselves:
  /// logging while waiting for a device, or declaring thousands of parameters, is set-up, not
  /// the steady state of a loop, so its publications are not activity (Session::on_activity).
  bool bookkeeping = false;
  Loans loans;
  MessageLayout layout;                 // the caller's type support (C or C++)
  std::atomic<int64_t> next_sequence{1};  // publication sequence numbers
  std::mutex history_mutex;             // TRANSIENT_LOCAL: the last `depth` samples
  std::deque<Sample> history;
};

struct SubscriptionImpl : EventSource, EndpointImpl<rmw_subscription_t>
{
  Callback on_new_message;
  Loans loans;
  SubscriptionFilter filter;  // content filter: options, and compiled with delivery
  MessageLayout layout;
  Inbox inbox;
  std::atomic<int64_t> next_reception{1};
  /// A stimulus of the middleware's own (Injector, RMW_INTROSPECT_STIMULI) waits to be
  /// taken: rmw_wait reports the subscription ready. Set and cleared under the Injector's
  /// mutex (and the wait hub's lock).
  std::atomic<bool> injected_ready{false};
  /// The subscription was in the wait set of some rmw_wait: an executor takes from it.
  std::atomic<bool> in_wait_set{false};
};

struct ServiceImpl : EndpointImpl<rmw_service_t>
{
  Callback on_new_request;
  MessageLayout request_layout;
  MessageLayout response_layout;
  Inbox requests;
  /// A request of the middleware's own (Injector) waits to be taken: rmw_wait reports the
  /// service ready. Set and cleared under the Injector's mutex (and the wait hub's lock).
  std::atomic<bool> injected_ready{false};
  /// The service was in the wait set of some rmw_wait: an executor serves it.
  std::atomic<bool> in_wait_set{false};
};

struct ClientImpl : EndpointImpl<rmw_client_t>
{
  std::atomic<int64_t> next_sequence{1};
  Callback on_new_response;
  MessageLayout request_layout;
  MessageLayout response_layout;
  Inbox responses;
};

struct WaitSetImpl
{
  rmw_wait_set_t handle{};
  const ContextImpl * context = nullptr;  // a wait on a shut down context does not block
};

}  // namespace rmw_introspect

#endif  // DETAIL__HANDLES_HPP_
