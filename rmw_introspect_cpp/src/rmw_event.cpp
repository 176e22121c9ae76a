// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// QoS events: initialised for every type a DDS middleware supports; they never fire, but for
// the matched events with in-process delivery.

#include "rmw/event.h"
#include "rmw/events_statuses/matched.h"
#include "rmw/rmw.h"

#include "detail/common.hpp"
#include "detail/handles.hpp"
#include "detail/rmw_api.hpp"
#include "detail/runtime.hpp"

using rmw_introspect::EventSource;
using rmw_introspect::is_valid_event_type;
using rmw_introspect::kIdentifier;

namespace
{

bool is_subscription_event(rmw_event_type_t type)
{
  switch (type) {
    case RMW_EVENT_LIVELINESS_CHANGED:
    case RMW_EVENT_REQUESTED_DEADLINE_MISSED:
    case RMW_EVENT_REQUESTED_QOS_INCOMPATIBLE:
    case RMW_EVENT_MESSAGE_LOST:
    case RMW_EVENT_SUBSCRIPTION_INCOMPATIBLE_TYPE:
    case RMW_EVENT_SUBSCRIPTION_MATCHED: return true;
    default: return false;
  }
}

bool is_publisher_event(rmw_event_type_t type)
{
  switch (type) {
    case RMW_EVENT_LIVELINESS_LOST:
    case RMW_EVENT_OFFERED_DEADLINE_MISSED:
    case RMW_EVENT_OFFERED_QOS_INCOMPATIBLE:
    case RMW_EVENT_PUBLISHER_INCOMPATIBLE_TYPE:
    case RMW_EVENT_PUBLICATION_MATCHED: return true;
    default: return false;
  }
}

bool is_matched_event(rmw_event_type_t type)
{
  return type == RMW_EVENT_PUBLICATION_MATCHED || type == RMW_EVENT_SUBSCRIPTION_MATCHED;
}

rmw_ret_t init_event(
  rmw_event_t * rmw_event, EventSource * source, rmw_event_type_t event_type, bool publisher_side)
{
  const bool ok =
    publisher_side ? is_publisher_event(event_type) : is_subscription_event(event_type);
  if (!ok) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING(
      "provided event_type %d is not supported by %s for a %s", static_cast<int>(event_type),
      kIdentifier, publisher_side ? "publisher" : "subscription");
    return RMW_RET_UNSUPPORTED;
  }
  rmw_event->implementation_identifier = kIdentifier;
  rmw_event->data = source;
  rmw_event->event_type = event_type;
  return RMW_RET_OK;
}

}  // namespace

extern "C" {

bool rmw_event_type_is_supported(rmw_event_type_t rmw_event_type)
{
  return is_subscription_event(rmw_event_type) || is_publisher_event(rmw_event_type);
}

rmw_ret_t rmw_publisher_event_init(
  rmw_event_t * rmw_event, const rmw_publisher_t * publisher, rmw_event_type_t event_type)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(rmw_event, RMW_RET_INVALID_ARGUMENT);
  RMWI_CHECK_HANDLE(publisher);
  auto * source =
    static_cast<EventSource *>(static_cast<rmw_introspect::PublisherImpl *>(publisher->data));
  return init_event(rmw_event, source, event_type, true);
}

rmw_ret_t rmw_subscription_event_init(
  rmw_event_t * rmw_event, const rmw_subscription_t * subscription, rmw_event_type_t event_type)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(rmw_event, RMW_RET_INVALID_ARGUMENT);
  RMWI_CHECK_HANDLE(subscription);
  auto * source =
    static_cast<EventSource *>(static_cast<rmw_introspect::SubscriptionImpl *>(subscription->data));
  return init_event(rmw_event, source, event_type, false);
}

rmw_ret_t rmw_take_event(const rmw_event_t * event_handle, void * event_info, bool * taken)
{
  RMWI_CHECK_HANDLE(event_handle);
  RMW_CHECK_ARGUMENT_FOR_NULL(event_info, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(taken, RMW_RET_INVALID_ARGUMENT);
  *taken = false;
  rmw_introspect::Runtime::instance().on_activity();
  // Matched events, with in-process delivery: the status of this process's matching, its
  // changes since the last take (taken even when nothing changed, as rmw_fastrtps_cpp does).
  auto * source = static_cast<EventSource *>(event_handle->data);
  if (is_matched_event(event_handle->event_type) && source->delivered.load()) {
    *static_cast<rmw_matched_status_t *>(event_info) = source->matched.take();
    *taken = true;
  }
  return RMW_RET_OK;
}

rmw_ret_t rmw_event_set_callback(
  rmw_event_t * event, rmw_event_callback_t callback, const void * user_data)
{
  RMWI_CHECK_HANDLE(event);
  auto * source = static_cast<EventSource *>(event->data);
  if (!is_valid_event_type(event->event_type)) {
    RMW_SET_ERROR_MSG("invalid event type");
    return RMW_RET_INVALID_ARGUMENT;
  }
  source->event_callbacks[event->event_type].set(callback, user_data);
  if (callback != nullptr && is_matched_event(event->event_type) && source->matched.unread.load()) {
    source->event_callbacks[event->event_type].notify(1u);  // changes before the callback came
  }
  return RMW_RET_OK;
}

}  // extern "C"
