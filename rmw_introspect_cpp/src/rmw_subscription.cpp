// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Subscriptions: recorded on creation; nothing is received unless in-process delivery is on,
// except the middleware's own stimuli (RMW_INTROSPECT_STIMULI: detail/injector).

#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "rmw/get_network_flow_endpoints.h"
#include "rmw/rmw.h"
#include "rmw/subscription_content_filter_options.h"

#include "detail/common.hpp"
#include "detail/endpoint_common.hpp"
#include "detail/handles.hpp"
#include "detail/recorder.hpp"
#include "detail/content_filter.hpp"
#include "detail/delivery.hpp"
#include "detail/log.hpp"
#include "detail/runtime.hpp"

using rmw_introspect::kIdentifier;
using rmw_introspect::SubscriptionImpl;

namespace
{
bool ends_with(const std::string & s, const char * suffix)
{
  const size_t n = std::strlen(suffix);
  return s.size() >= n && s.compare(s.size() - n, n, suffix) == 0;
}

// rmw_take / rmw_take_with_info after their argument checks: a stimulus of the middleware's
// own first (not the node's activity), then what in-process delivery brought.
rmw_ret_t take_one(
  const rmw_subscription_t * subscription, void * ros_message, bool * taken,
  rmw_message_info_t * info)
{
  auto & runtime = rmw_introspect::Runtime::instance();
  auto * impl = static_cast<SubscriptionImpl *>(subscription->data);
  if (runtime.injector().take_message(impl, ros_message, taken, info)) {
    return RMW_RET_OK;
  }
  runtime.on_activity();
  return rmw_introspect::take_message(*impl, ros_message, taken, info);
}

// The same for the serialized takes.
rmw_ret_t take_one_serialized(
  const rmw_subscription_t * subscription, rmw_serialized_message_t * serialized_message,
  bool * taken, rmw_message_info_t * info)
{
  auto & runtime = rmw_introspect::Runtime::instance();
  auto * impl = static_cast<SubscriptionImpl *>(subscription->data);
  if (runtime.injector().take_serialized(impl, serialized_message, taken, info)) {
    return RMW_RET_OK;
  }
  runtime.on_activity();
  return rmw_introspect::take_serialized_message(*impl, serialized_message, taken, info);
}
}  // namespace

extern "C" {

rmw_subscription_t * rmw_create_subscription(
  const rmw_node_t * node, const rosidl_message_type_support_t * type_supports,
  const char * topic_name, const rmw_qos_profile_t * qos_policies,
  const rmw_subscription_options_t * subscription_options)
{
  RMWI_CHECK_HANDLE_RETURN_NULL(node);
  RMW_CHECK_ARGUMENT_FOR_NULL(type_supports, nullptr);
  RMW_CHECK_ARGUMENT_FOR_NULL(topic_name, nullptr);
  RMW_CHECK_ARGUMENT_FOR_NULL(qos_policies, nullptr);
  RMW_CHECK_ARGUMENT_FOR_NULL(subscription_options, nullptr);
  if (!rmw_introspect::check_name_and_qos(topic_name, qos_policies, "topic")) {
    return nullptr;
  }
  // require_unique_network_flow_endpoints: every value is accepted, STRICTLY_REQUIRED too, as
  // rmw_fastrtps_cpp accepts it on subscriptions (it refuses it on publishers only)
  auto impl = rmw_introspect::new_endpoint<SubscriptionImpl>(
    node, type_supports, rmw_introspect::resolve_message_type, topic_name, qos_policies,
    "subscription");
  if (!impl) {
    return nullptr;
  }
  impl->handle.topic_name = impl->name.c_str();
  impl->handle.options = *subscription_options;
  impl->handle.options.content_filter_options = nullptr;  // not owned by us
  impl->handle.is_cft_enabled = false;
  impl->layout = rmw_introspect::message_layout(impl->type);
  impl->handle.can_loan_messages =
    rmw_introspect::Runtime::instance().config().delivery && rmw_introspect::can_loan(impl->layout);
  if (subscription_options->content_filter_options != nullptr &&
      subscription_options->content_filter_options->filter_expression != nullptr)
  {
    const rmw_ret_t ret = rmw_subscription_set_content_filter(
      &impl->handle, subscription_options->content_filter_options);
    if (ret != RMW_RET_OK) {
      return nullptr;
    }
  }
  rmw_introspect::record(*impl, rmw_introspect::EndpointKind::Subscription);
  if (rmw_introspect::Runtime::instance().config().delivery) {
    rmw_introspect::Runtime::instance().delivery().add(impl.get());
  }
  if (!rmw_introspect::Runtime::instance().config().stimuli.empty()) {
    rmw_introspect::Runtime::instance().injector().add_subscription(impl.get());
  }
  return &impl.release()->handle;
}

rmw_ret_t rmw_destroy_subscription(rmw_node_t * node, rmw_subscription_t * subscription)
{
  RMWI_CHECK_HANDLE(node);
  RMWI_CHECK_HANDLE(subscription);
  std::unique_ptr<SubscriptionImpl> impl(static_cast<SubscriptionImpl *>(subscription->data));
  if (impl->delivered.load()) {
    rmw_introspect::Runtime::instance().delivery().remove(impl.get());
  }
  if (!rmw_introspect::Runtime::instance().config().stimuli.empty()) {
    rmw_introspect::Runtime::instance().injector().remove_subscription(impl.get());
  }
  rmw_introspect::free_loans(impl->loans, impl->layout);
  rmw_introspect::forget_endpoint(
    impl->record_id, rmw_introspect::EndpointKind::Subscription, impl->name, impl->node);
  return RMW_RET_OK;
}

rmw_ret_t rmw_subscription_count_matched_publishers(
  const rmw_subscription_t * subscription, size_t * publisher_count)
{
  RMWI_CHECK_HANDLE(subscription);
  RMW_CHECK_ARGUMENT_FOR_NULL(publisher_count, RMW_RET_INVALID_ARGUMENT);
  const auto * impl = static_cast<const SubscriptionImpl *>(subscription->data);
  size_t count = rmw_introspect::count_matched(
    rmw_introspect::EndpointKind::Publisher, impl->name, impl->type.name, impl->actual_qos);
  // With RMW_INTROSPECT_SERVER_AVAILABLE=1 every server a client waits for is "there". An
  // action server is there for rcl_action_server_is_available() only when its feedback and
  // status publishers are matched too, so those two topics count the simulated server.
  if (rmw_introspect::Runtime::instance().config().server_available && count == 0 &&
      (ends_with(impl->name, "/_action/feedback") || ends_with(impl->name, "/_action/status")))
  {
    count = 1;
  }
  *publisher_count = count;
  rmw_introspect::Runtime::instance().on_activity();
  return RMW_RET_OK;
}

rmw_ret_t rmw_subscription_get_actual_qos(
  const rmw_subscription_t * subscription, rmw_qos_profile_t * qos)
{
  RMWI_CHECK_HANDLE(subscription);
  RMW_CHECK_ARGUMENT_FOR_NULL(qos, RMW_RET_INVALID_ARGUMENT);
  *qos = static_cast<const SubscriptionImpl *>(subscription->data)->actual_qos;
  return RMW_RET_OK;
}

rmw_ret_t rmw_subscription_set_content_filter(
  rmw_subscription_t * subscription, const rmw_subscription_content_filter_options_t * options)
{
  RMWI_CHECK_HANDLE(subscription);
  RMW_CHECK_ARGUMENT_FOR_NULL(options, RMW_RET_INVALID_ARGUMENT);
  auto * impl = static_cast<SubscriptionImpl *>(subscription->data);
  // Filtering applies to in-process delivery only: without it the options are just kept.
  const bool compile = rmw_introspect::Runtime::instance().config().delivery;
  bool enabled = false;
  const rmw_ret_t ret =
    impl->filter.set(*options, compile ? &impl->layout : nullptr, impl->name, &enabled);
  subscription->is_cft_enabled = enabled;
  return ret;
}

rmw_ret_t rmw_subscription_get_content_filter(
  const rmw_subscription_t * subscription, rcutils_allocator_t * allocator,
  rmw_subscription_content_filter_options_t * options)
{
  RMWI_CHECK_HANDLE(subscription);
  RMW_CHECK_ARGUMENT_FOR_NULL(allocator, RMW_RET_INVALID_ARGUMENT);
  RCUTILS_CHECK_ALLOCATOR_WITH_MSG(
    allocator, "allocator argument is invalid", return RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(options, RMW_RET_INVALID_ARGUMENT);
  return static_cast<SubscriptionImpl *>(subscription->data)->filter.get(allocator, options);
}

rmw_ret_t rmw_subscription_get_network_flow_endpoints(
  const rmw_subscription_t * subscription, rcutils_allocator_t * allocator,
  rmw_network_flow_endpoint_array_t * network_flow_endpoint_array)
{
  RMWI_CHECK_HANDLE(subscription);
  RMW_CHECK_ARGUMENT_FOR_NULL(allocator, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(network_flow_endpoint_array, RMW_RET_INVALID_ARGUMENT);
  return rmw_introspect::no_network_flow_endpoints(allocator, network_flow_endpoint_array);
}

rmw_ret_t rmw_subscription_set_on_new_message_callback(
  rmw_subscription_t * subscription, rmw_event_callback_t callback, const void * user_data)
{
  RMWI_CHECK_HANDLE(subscription);
  static_cast<SubscriptionImpl *>(subscription->data)->on_new_message.set(callback, user_data);
  return RMW_RET_OK;
}

rmw_ret_t rmw_init_subscription_allocation(
  const rosidl_message_type_support_t * type_support,
  const rosidl_runtime_c__Sequence__bound * message_bounds,
  rmw_subscription_allocation_t * allocation)
{
  // Unsupported whatever the arguments, like rmw_fastrtps_cpp (the suite probes with NULLs).
  (void)type_support;
  (void)message_bounds;
  (void)allocation;
  RMW_SET_ERROR_MSG("subscription allocations are not supported");
  return RMW_RET_UNSUPPORTED;
}

rmw_ret_t rmw_fini_subscription_allocation(rmw_subscription_allocation_t * allocation)
{
  (void)allocation;
  RMW_SET_ERROR_MSG("subscription allocations are not supported");
  return RMW_RET_UNSUPPORTED;
}

rmw_ret_t rmw_take(
  const rmw_subscription_t * subscription, void * ros_message, bool * taken,
  rmw_subscription_allocation_t * allocation)
{
  (void)allocation;
  RMWI_CHECK_HANDLE(subscription);
  RMW_CHECK_ARGUMENT_FOR_NULL(ros_message, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(taken, RMW_RET_INVALID_ARGUMENT);
  return take_one(subscription, ros_message, taken, nullptr);
}

rmw_ret_t rmw_take_with_info(
  const rmw_subscription_t * subscription, void * ros_message, bool * taken,
  rmw_message_info_t * message_info, rmw_subscription_allocation_t * allocation)
{
  (void)allocation;
  RMWI_CHECK_HANDLE(subscription);
  RMW_CHECK_ARGUMENT_FOR_NULL(ros_message, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(taken, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(message_info, RMW_RET_INVALID_ARGUMENT);
  return take_one(subscription, ros_message, taken, message_info);
}

rmw_ret_t rmw_take_sequence(
  const rmw_subscription_t * subscription, size_t count, rmw_message_sequence_t * message_sequence,
  rmw_message_info_sequence_t * message_info_sequence, size_t * taken,
  rmw_subscription_allocation_t * allocation)
{
  (void)allocation;
  RMWI_CHECK_HANDLE(subscription);
  RMW_CHECK_ARGUMENT_FOR_NULL(message_sequence, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(message_info_sequence, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(taken, RMW_RET_INVALID_ARGUMENT);
  if (count == 0u) {
    RMW_SET_ERROR_MSG("count cannot be 0");
    return RMW_RET_INVALID_ARGUMENT;
  }
  if (count > message_sequence->capacity) {
    RMW_SET_ERROR_MSG("Insufficient capacity in message_sequence");
    return RMW_RET_INVALID_ARGUMENT;
  }
  if (count > message_info_sequence->capacity) {
    RMW_SET_ERROR_MSG("Insufficient capacity in message_info_sequence");
    return RMW_RET_INVALID_ARGUMENT;
  }
  *taken = 0u;
  message_sequence->size = 0u;
  message_info_sequence->size = 0u;
  auto & runtime = rmw_introspect::Runtime::instance();
  auto * impl = static_cast<SubscriptionImpl *>(subscription->data);
  bool stimulus_taken = false;
  if (runtime.injector().take_message(
        impl, message_sequence->data[0], &stimulus_taken, &message_info_sequence->data[0]))
  {
    // A stimulus of the middleware's own, alone in the sequence: no activity of the node.
    *taken = stimulus_taken ? 1u : 0u;
    message_sequence->size = *taken;
    message_info_sequence->size = *taken;
    return RMW_RET_OK;
  }
  runtime.on_activity();
  for (size_t i = 0; i < count; ++i) {
    bool one = false;
    const rmw_ret_t ret = rmw_introspect::take_message(
      *impl, message_sequence->data[i], &one, &message_info_sequence->data[i]);
    if (ret != RMW_RET_OK) {
      return ret;
    }
    if (!one) {
      break;
    }
    ++*taken;
    message_sequence->size = *taken;
    message_info_sequence->size = *taken;
  }
  return RMW_RET_OK;
}

rmw_ret_t rmw_take_serialized_message(
  const rmw_subscription_t * subscription, rmw_serialized_message_t * serialized_message,
  bool * taken, rmw_subscription_allocation_t * allocation)
{
  (void)allocation;
  RMWI_CHECK_HANDLE(subscription);
  RMW_CHECK_ARGUMENT_FOR_NULL(serialized_message, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(taken, RMW_RET_INVALID_ARGUMENT);
  return take_one_serialized(subscription, serialized_message, taken, nullptr);
}

rmw_ret_t rmw_take_serialized_message_with_info(
  const rmw_subscription_t * subscription, rmw_serialized_message_t * serialized_message,
  bool * taken, rmw_message_info_t * message_info, rmw_subscription_allocation_t * allocation)
{
  (void)allocation;
  RMWI_CHECK_HANDLE(subscription);
  RMW_CHECK_ARGUMENT_FOR_NULL(serialized_message, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(taken, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(message_info, RMW_RET_INVALID_ARGUMENT);
  return take_one_serialized(subscription, serialized_message, taken, message_info);
}

rmw_ret_t rmw_take_loaned_message(
  const rmw_subscription_t * subscription, void ** loaned_message, bool * taken,
  rmw_subscription_allocation_t * allocation)
{
  (void)allocation;
  RMWI_CHECK_HANDLE(subscription);
  RMWI_CHECK_CAN_LOAN(subscription);
  RMW_CHECK_ARGUMENT_FOR_NULL(loaned_message, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(taken, RMW_RET_INVALID_ARGUMENT);
  rmw_introspect::Runtime & runtime = rmw_introspect::Runtime::instance();
  runtime.on_activity();
  return rmw_introspect::take_loaned_message(
    runtime.injector(), *static_cast<SubscriptionImpl *>(subscription->data), loaned_message, taken,
    nullptr);
}

rmw_ret_t rmw_take_loaned_message_with_info(
  const rmw_subscription_t * subscription, void ** loaned_message, bool * taken,
  rmw_message_info_t * message_info, rmw_subscription_allocation_t * allocation)
{
  (void)allocation;
  RMWI_CHECK_HANDLE(subscription);
  RMWI_CHECK_CAN_LOAN(subscription);
  RMW_CHECK_ARGUMENT_FOR_NULL(loaned_message, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(taken, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(message_info, RMW_RET_INVALID_ARGUMENT);
  rmw_introspect::Runtime & runtime = rmw_introspect::Runtime::instance();
  runtime.on_activity();
  return rmw_introspect::take_loaned_message(
    runtime.injector(), *static_cast<SubscriptionImpl *>(subscription->data), loaned_message, taken,
    message_info);
}

rmw_ret_t rmw_return_loaned_message_from_subscription(
  const rmw_subscription_t * subscription, void * loaned_message)
{
  RMWI_CHECK_HANDLE(subscription);
  RMWI_CHECK_CAN_LOAN(subscription);
  RMW_CHECK_ARGUMENT_FOR_NULL(loaned_message, RMW_RET_INVALID_ARGUMENT);
  auto * impl = static_cast<SubscriptionImpl *>(subscription->data);
  return rmw_introspect::return_loaned_message(impl->loans, impl->layout, loaned_message);
}

rmw_ret_t rmw_take_dynamic_message(
  const rmw_subscription_t * subscription,
  rosidl_dynamic_typesupport_dynamic_data_t * dynamic_message, bool * taken,
  rmw_subscription_allocation_t * allocation)
{
  (void)allocation;
  RMWI_CHECK_HANDLE(subscription);
  RMW_CHECK_ARGUMENT_FOR_NULL(dynamic_message, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(taken, RMW_RET_INVALID_ARGUMENT);
  *taken = false;
  rmw_introspect::Runtime::instance().on_activity();
  return RMW_RET_OK;
}

rmw_ret_t rmw_take_dynamic_message_with_info(
  const rmw_subscription_t * subscription,
  rosidl_dynamic_typesupport_dynamic_data_t * dynamic_message, bool * taken,
  rmw_message_info_t * message_info, rmw_subscription_allocation_t * allocation)
{
  (void)allocation;
  RMWI_CHECK_HANDLE(subscription);
  RMW_CHECK_ARGUMENT_FOR_NULL(dynamic_message, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(taken, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(message_info, RMW_RET_INVALID_ARGUMENT);
  *taken = false;
  rmw_introspect::Runtime::instance().on_activity();
  return RMW_RET_OK;
}

}  // extern "C"
