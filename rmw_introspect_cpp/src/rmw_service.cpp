// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Service servers: recorded on creation; no request of another process ever arrives. The
// middleware's own requests to the nodes' services (parameters, lifecycle: detail/injector)
// are taken and answered here.

#include <memory>
#include <new>
#include <string>

#include "rmw/rmw.h"

#include "detail/common.hpp"
#include "detail/endpoint_common.hpp"
#include "detail/handles.hpp"
#include "detail/runtime.hpp"
#include "detail/recorder.hpp"

using rmw_introspect::kIdentifier;
using rmw_introspect::ServiceImpl;

extern "C"
{

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
    node, type_supports, rmw_introspect::resolve_service_type, service_name, qos_profile, "service");
  if (!impl) {
    return nullptr;
  }
  impl->handle.service_name = impl->name.c_str();
  rmw_introspect::record(*impl, rmw_introspect::EndpointKind::Service);
  rmw_introspect::Runtime::instance().injector().add_service(impl.get());
  return &impl.release()->handle;
}

rmw_ret_t rmw_destroy_service(rmw_node_t * node, rmw_service_t * service)
{
  RMWI_CHECK_HANDLE(node);
  RMWI_CHECK_HANDLE(service);
  std::unique_ptr<ServiceImpl> impl(static_cast<ServiceImpl *>(service->data));
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
  *taken = false;
  auto & runtime = rmw_introspect::Runtime::instance();
  if (runtime.injector().take(
      static_cast<ServiceImpl *>(service->data), request_header, ros_request, taken))
  {
    return RMW_RET_OK;  // the middleware's own request: no activity of the node
  }
  runtime.on_activity();
  return RMW_RET_OK;
}

rmw_ret_t rmw_send_response(
  const rmw_service_t * service, rmw_request_id_t * request_header, void * ros_response)
{
  RMWI_CHECK_HANDLE(service);
  RMW_CHECK_ARGUMENT_FOR_NULL(request_header, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(ros_response, RMW_RET_INVALID_ARGUMENT);
  auto & runtime = rmw_introspect::Runtime::instance();
  if (runtime.injector().answer(
      static_cast<ServiceImpl *>(service->data), request_header, ros_response))
  {
    return RMW_RET_OK;  // the answer to the middleware's own request: read, no activity
  }
  runtime.on_activity();
  return RMW_RET_OK;  // dropped
}

rmw_ret_t rmw_service_request_subscription_get_actual_qos(
  const rmw_service_t * service, rmw_qos_profile_t * qos)
{
  RMWI_CHECK_HANDLE(service);
  RMW_CHECK_ARGUMENT_FOR_NULL(qos, RMW_RET_INVALID_ARGUMENT);
  *qos = static_cast<const ServiceImpl *>(service->data)->qos;
  return RMW_RET_OK;
}

rmw_ret_t rmw_service_response_publisher_get_actual_qos(
  const rmw_service_t * service, rmw_qos_profile_t * qos)
{
  RMWI_CHECK_HANDLE(service);
  RMW_CHECK_ARGUMENT_FOR_NULL(qos, RMW_RET_INVALID_ARGUMENT);
  *qos = static_cast<const ServiceImpl *>(service->data)->qos;
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
