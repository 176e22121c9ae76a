// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Service servers: recorded on creation; requests arrive only from the middleware itself
// (parameters, lifecycle: detail/injector) or, with in-process delivery, from clients of the
// same process.

#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "rmw/rmw.h"

#include "detail/cdr.hpp"
#include "detail/common.hpp"
#include "detail/endpoint_common.hpp"
#include "detail/handles.hpp"
#include "detail/delivery.hpp"
#include "detail/runtime.hpp"
#include "detail/recorder.hpp"

using rmw_introspect::kIdentifier;
using rmw_introspect::ServiceImpl;

extern "C" {

rmw_service_t * rmw_create_service(
  const rmw_node_t * node, const rosidl_service_type_support_t * type_supports,
  const char * service_name, const rmw_qos_profile_t * qos_profile)
{
  RMWI_CHECK_HANDLE_RETURN_NULL(node);
  RMW_CHECK_ARGUMENT_FOR_NULL(type_supports, nullptr);
  RMW_CHECK_ARGUMENT_FOR_NULL(service_name, nullptr);
  RMW_CHECK_ARGUMENT_FOR_NULL(qos_profile, nullptr);
  if (!rmw_introspect::check_name_and_qos(service_name, qos_profile, "service")) {
    return nullptr;
  }
  auto impl = rmw_introspect::new_endpoint<ServiceImpl>(
    node, type_supports, rmw_introspect::resolve_service_type, service_name, qos_profile,
    "service");
  if (!impl) {
    return nullptr;
  }
  impl->handle.service_name = impl->name.c_str();
  rmw_introspect::service_layouts(impl->type, &impl->request_layout, &impl->response_layout);
  rmw_introspect::record(*impl, rmw_introspect::EndpointKind::Service);
  if (rmw_introspect::Runtime::instance().config().delivery) {
    rmw_introspect::Runtime::instance().delivery().add(impl.get());
  }
  rmw_introspect::Runtime::instance().injector().add_service(impl.get());
  return &impl.release()->handle;
}

rmw_ret_t rmw_destroy_service(rmw_node_t * node, rmw_service_t * service)
{
  RMWI_CHECK_HANDLE(node);
  RMWI_CHECK_HANDLE(service);
  std::unique_ptr<ServiceImpl> impl(static_cast<ServiceImpl *>(service->data));
  if (rmw_introspect::Runtime::instance().config().delivery) {
    rmw_introspect::Runtime::instance().delivery().remove(impl.get());
  }
  rmw_introspect::Runtime::instance().injector().remove_service(impl.get());
  rmw_introspect::forget_endpoint(
    impl->record_id, rmw_introspect::EndpointKind::Service, impl->name, impl->node);
  return RMW_RET_OK;
}

rmw_ret_t rmw_take_request(
  const rmw_service_t * service, rmw_service_info_t * request_header, void * ros_request,
  bool * taken)
{
  RMWI_CHECK_HANDLE(service);
  RMW_CHECK_ARGUMENT_FOR_NULL(request_header, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(ros_request, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(taken, RMW_RET_INVALID_ARGUMENT);
  auto & runtime = rmw_introspect::Runtime::instance();
  auto * impl = static_cast<ServiceImpl *>(service->data);
  if (runtime.injector().take(impl, request_header, ros_request, taken)) {
    return RMW_RET_OK;  // the middleware's own request: no activity of the node
  }
  runtime.on_activity();
  return rmw_introspect::take_request(*impl, request_header, ros_request, taken);
}

rmw_ret_t rmw_send_response(
  const rmw_service_t * service, rmw_request_id_t * request_header, void * ros_response)
{
  RMWI_CHECK_HANDLE(service);
  RMW_CHECK_ARGUMENT_FOR_NULL(request_header, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(ros_response, RMW_RET_INVALID_ARGUMENT);
  rmw_introspect::Runtime & runtime = rmw_introspect::Runtime::instance();
  auto * impl = static_cast<ServiceImpl *>(service->data);
  if (runtime.injector().answer(impl, request_header, ros_response)) {
    return RMW_RET_OK;  // the answer to the middleware's own request: read, no activity
  }
  runtime.on_activity();
  if (!runtime.config().delivery) {
    return RMW_RET_OK;  // dropped
  }
  // In-process delivery: back to the client of this process that asked, if it is still there
  // (RMW_RET_OK either way, as rmw_fastrtps_cpp answers).
  std::vector<uint8_t> data;
  std::string error;
  if (!rmw_introspect::cdr_serialize(impl->response_layout, ros_response, &data, &error)) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING("cannot serialize the response: %s", error.c_str());
    return RMW_RET_ERROR;
  }
  runtime.delivery().send_response(*impl, *request_header, std::move(data));
  return RMW_RET_OK;
}

rmw_ret_t rmw_service_request_subscription_get_actual_qos(
  const rmw_service_t * service, rmw_qos_profile_t * qos)
{
  RMWI_CHECK_HANDLE(service);
  RMW_CHECK_ARGUMENT_FOR_NULL(qos, RMW_RET_INVALID_ARGUMENT);
  *qos = rmw_introspect::service_actual_qos(
    static_cast<const ServiceImpl *>(service->data)->qos, rmw_introspect::QosSide::kReader);
  return RMW_RET_OK;
}

rmw_ret_t rmw_service_response_publisher_get_actual_qos(
  const rmw_service_t * service, rmw_qos_profile_t * qos)
{
  RMWI_CHECK_HANDLE(service);
  RMW_CHECK_ARGUMENT_FOR_NULL(qos, RMW_RET_INVALID_ARGUMENT);
  *qos = rmw_introspect::service_actual_qos(
    static_cast<const ServiceImpl *>(service->data)->qos, rmw_introspect::QosSide::kWriter);
  return RMW_RET_OK;
}

rmw_ret_t rmw_service_set_on_new_request_callback(
  rmw_service_t * service, rmw_event_callback_t callback, const void * user_data)
{
  RMWI_CHECK_HANDLE(service);
  static_cast<ServiceImpl *>(service->data)->on_new_request.set(callback, user_data);
  return RMW_RET_OK;
}

}  // extern "C"
