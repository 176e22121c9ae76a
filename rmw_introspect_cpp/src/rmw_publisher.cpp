// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Publishers: recorded on creation; publishing accepts and drops (or, with in-process
// delivery, hands the message to the matching subscriptions of this process).

#include <cstring>
#include <memory>
#include <vector>
#include <new>
#include <string>

#include "rmw/get_network_flow_endpoints.h"
#include "rmw/rmw.h"

#include "detail/cdr.hpp"
#include "detail/common.hpp"
#include "detail/endpoint_common.hpp"
#include "detail/handles.hpp"
#include "detail/recorder.hpp"
#include "detail/delivery.hpp"
#include "detail/runtime.hpp"

using rmw_introspect::kIdentifier;
using rmw_introspect::PublisherImpl;

namespace
{

// A publication is activity (a sign of a steady loop), except on the bookkeeping topics.
void note_publication(rmw_introspect::Runtime & runtime, const PublisherImpl & impl)
{
  if (!impl.bookkeeping) {
    runtime.on_activity();
  }
}

}  // namespace

extern "C" {

rmw_publisher_t * rmw_create_publisher(
  const rmw_node_t * node, const rosidl_message_type_support_t * type_supports,
  const char * topic_name, const rmw_qos_profile_t * qos_profile,
  const rmw_publisher_options_t * publisher_options)
{
  RMWI_CHECK_HANDLE_RETURN_NULL(node);
  RMW_CHECK_ARGUMENT_FOR_NULL(type_supports, nullptr);
  RMW_CHECK_ARGUMENT_FOR_NULL(topic_name, nullptr);
  RMW_CHECK_ARGUMENT_FOR_NULL(qos_profile, nullptr);
  RMW_CHECK_ARGUMENT_FOR_NULL(publisher_options, nullptr);
  if (!rmw_introspect::check_name_and_qos(topic_name, qos_profile, "topic")) {
    return nullptr;
  }
  // as rmw_fastrtps_cpp: unique flows cannot be strictly required of a publisher
  if (publisher_options->require_unique_network_flow_endpoints ==
      RMW_UNIQUE_NETWORK_FLOW_ENDPOINTS_STRICTLY_REQUIRED)
  {
    RMW_SET_ERROR_MSG(
      "Strict requirement on unique network flow endpoints for publishers not supported");
    return nullptr;
  }
  auto impl = rmw_introspect::new_endpoint<PublisherImpl>(
    node, type_supports, rmw_introspect::resolve_message_type, topic_name, qos_profile,
    "publisher");
  if (!impl) {
    return nullptr;
  }
  impl->bookkeeping = impl->name == "/rosout" || impl->name == "/parameter_events";
  impl->handle.topic_name = impl->name.c_str();
  impl->handle.options = *publisher_options;
  impl->layout = rmw_introspect::message_layout(impl->type);
  const bool delivery = rmw_introspect::Runtime::instance().config().delivery;
  impl->handle.can_loan_messages = delivery && rmw_introspect::can_loan(impl->layout);
  rmw_introspect::record(*impl, rmw_introspect::EndpointKind::Publisher);
  if (delivery) {
    rmw_introspect::Runtime::instance().delivery().add(impl.get());
  }
  return &impl.release()->handle;
}

rmw_ret_t rmw_destroy_publisher(rmw_node_t * node, rmw_publisher_t * publisher)
{
  RMWI_CHECK_HANDLE(node);
  RMWI_CHECK_HANDLE(publisher);
  std::unique_ptr<PublisherImpl> impl(static_cast<PublisherImpl *>(publisher->data));
  if (impl->delivered.load()) {
    rmw_introspect::Runtime::instance().delivery().remove(impl.get());
  }
  rmw_introspect::free_loans(impl->loans, impl->layout);
  rmw_introspect::forget_endpoint(
    impl->record_id, rmw_introspect::EndpointKind::Publisher, impl->name, impl->node);
  return RMW_RET_OK;
}

rmw_ret_t rmw_publish(
  const rmw_publisher_t * publisher, const void * ros_message,
  rmw_publisher_allocation_t * allocation)
{
  (void)allocation;
  RMWI_CHECK_HANDLE(publisher);
  RMW_CHECK_ARGUMENT_FOR_NULL(ros_message, RMW_RET_INVALID_ARGUMENT);
  rmw_introspect::Runtime & runtime = rmw_introspect::Runtime::instance();
  auto * impl = static_cast<PublisherImpl *>(publisher->data);
  note_publication(runtime, *impl);
  if (!impl->delivered.load()) {
    return RMW_RET_OK;  // accepted and dropped: nothing leaves the process
  }
  // In-process delivery: to the matching subscriptions of this process, as CDR.
  std::vector<uint8_t> data;
  std::string error;
  if (!rmw_introspect::cdr_serialize(impl->layout, ros_message, &data, &error)) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING("cannot serialize the message: %s", error.c_str());
    return RMW_RET_ERROR;
  }
  runtime.delivery().publish(*impl, ros_message, data.data(), data.size());
  return RMW_RET_OK;
}

rmw_ret_t rmw_publish_serialized_message(
  const rmw_publisher_t * publisher, const rmw_serialized_message_t * serialized_message,
  rmw_publisher_allocation_t * allocation)
{
  (void)allocation;
  RMWI_CHECK_HANDLE(publisher);
  RMW_CHECK_ARGUMENT_FOR_NULL(serialized_message, RMW_RET_INVALID_ARGUMENT);
  rmw_introspect::Runtime & runtime = rmw_introspect::Runtime::instance();
  auto * impl = static_cast<PublisherImpl *>(publisher->data);
  note_publication(runtime, *impl);
  if (impl->delivered.load() && serialized_message->buffer != nullptr) {
    runtime.delivery().publish(
      *impl, nullptr, serialized_message->buffer, serialized_message->buffer_length);
  }
  return RMW_RET_OK;
}

rmw_ret_t rmw_borrow_loaned_message(
  const rmw_publisher_t * publisher, const rosidl_message_type_support_t * type_support,
  void ** ros_message)
{
  RMWI_CHECK_HANDLE(publisher);
  RMWI_CHECK_CAN_LOAN(publisher);
  RMW_CHECK_ARGUMENT_FOR_NULL(type_support, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(ros_message, RMW_RET_INVALID_ARGUMENT);
  if (*ros_message != nullptr) {
    RMW_SET_ERROR_MSG("ros_message argument must point to a null pointer");
    return RMW_RET_INVALID_ARGUMENT;
  }
  return rmw_introspect::borrow_loaned_message(
    *static_cast<PublisherImpl *>(publisher->data), ros_message);
}

rmw_ret_t rmw_publish_loaned_message(
  const rmw_publisher_t * publisher, void * ros_message, rmw_publisher_allocation_t * allocation)
{
  (void)allocation;
  RMWI_CHECK_HANDLE(publisher);
  RMWI_CHECK_CAN_LOAN(publisher);
  RMW_CHECK_ARGUMENT_FOR_NULL(ros_message, RMW_RET_INVALID_ARGUMENT);
  rmw_introspect::Runtime & runtime = rmw_introspect::Runtime::instance();
  auto * impl = static_cast<PublisherImpl *>(publisher->data);
  note_publication(runtime, *impl);
  return rmw_introspect::publish_loaned_message(runtime.delivery(), *impl, ros_message);
}

rmw_ret_t rmw_return_loaned_message_from_publisher(
  const rmw_publisher_t * publisher, void * loaned_message)
{
  RMWI_CHECK_HANDLE(publisher);
  RMWI_CHECK_CAN_LOAN(publisher);
  RMW_CHECK_ARGUMENT_FOR_NULL(loaned_message, RMW_RET_INVALID_ARGUMENT);
  auto * impl = static_cast<PublisherImpl *>(publisher->data);
  return rmw_introspect::return_loaned_message(impl->loans, impl->layout, loaned_message);
}

rmw_ret_t rmw_publisher_count_matched_subscriptions(
  const rmw_publisher_t * publisher, size_t * subscription_count)
{
  RMWI_CHECK_HANDLE(publisher);
  RMW_CHECK_ARGUMENT_FOR_NULL(subscription_count, RMW_RET_INVALID_ARGUMENT);
  auto * impl = static_cast<const PublisherImpl *>(publisher->data);
  *subscription_count = rmw_introspect::count_matched(
    rmw_introspect::EndpointKind::Subscription, impl->name, impl->type.name, impl->actual_qos);
  rmw_introspect::Runtime::instance().on_activity();
  return RMW_RET_OK;
}

rmw_ret_t rmw_publisher_get_actual_qos(const rmw_publisher_t * publisher, rmw_qos_profile_t * qos)
{
  RMWI_CHECK_HANDLE(publisher);
  RMW_CHECK_ARGUMENT_FOR_NULL(qos, RMW_RET_INVALID_ARGUMENT);
  *qos = static_cast<const PublisherImpl *>(publisher->data)->actual_qos;
  return RMW_RET_OK;
}

rmw_ret_t rmw_publisher_assert_liveliness(const rmw_publisher_t * publisher)
{
  RMWI_CHECK_HANDLE(publisher);
  return RMW_RET_OK;
}

rmw_ret_t rmw_publisher_wait_for_all_acked(
  const rmw_publisher_t * publisher, rmw_time_t wait_timeout)
{
  (void)wait_timeout;
  RMWI_CHECK_HANDLE(publisher);
  return RMW_RET_OK;  // nothing was sent, so everything is acknowledged
}

rmw_ret_t rmw_publisher_get_network_flow_endpoints(
  const rmw_publisher_t * publisher, rcutils_allocator_t * allocator,
  rmw_network_flow_endpoint_array_t * network_flow_endpoint_array)
{
  RMWI_CHECK_HANDLE(publisher);
  RMW_CHECK_ARGUMENT_FOR_NULL(allocator, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(network_flow_endpoint_array, RMW_RET_INVALID_ARGUMENT);
  return rmw_introspect::no_network_flow_endpoints(allocator, network_flow_endpoint_array);
}

rmw_ret_t rmw_get_gid_for_publisher(const rmw_publisher_t * publisher, rmw_gid_t * gid)
{
  RMWI_CHECK_HANDLE(publisher);
  RMW_CHECK_ARGUMENT_FOR_NULL(gid, RMW_RET_INVALID_ARGUMENT);
  const auto * impl = static_cast<const PublisherImpl *>(publisher->data);
  gid->implementation_identifier = kIdentifier;
  std::memcpy(gid->data, impl->gid.data(), RMW_GID_STORAGE_SIZE);
  return RMW_RET_OK;
}

rmw_ret_t rmw_init_publisher_allocation(
  const rosidl_message_type_support_t * type_support,
  const rosidl_runtime_c__Sequence__bound * message_bounds, rmw_publisher_allocation_t * allocation)
{
  // Unsupported whatever the arguments, like rmw_fastrtps_cpp (the suite probes with NULLs).
  (void)type_support;
  (void)message_bounds;
  (void)allocation;
  RMW_SET_ERROR_MSG("publisher allocations are not supported");
  return RMW_RET_UNSUPPORTED;
}

rmw_ret_t rmw_fini_publisher_allocation(rmw_publisher_allocation_t * allocation)
{
  (void)allocation;
  RMW_SET_ERROR_MSG("publisher allocations are not supported");
  return RMW_RET_UNSUPPORTED;
}

}  // extern "C"
