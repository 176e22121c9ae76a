// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Service clients: recorded on creation; requests get sequence numbers and, with in-process
// delivery, go to the matching services of this process, whose responses come back.

#include <cstring>
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
#include "detail/recorder.hpp"
#include "detail/rmw_api.hpp"
#include "detail/delivery.hpp"
#include "detail/runtime.hpp"

using rmw_introspect::ClientImpl;
using rmw_introspect::kIdentifier;

namespace
{

/// A live service of this process with the client's name and type whose request reader
/// matches the client's request writer and whose response writer matches the client's
/// response reader (actual QoS, rmw_qos_profile_check_compatible rules). Allocates nothing.
bool local_server_matches(const ClientImpl & client)
{
  using rmw_introspect::QosSide;
  using rmw_introspect::service_actual_qos;
  const rmw_qos_profile_t request_writer = service_actual_qos(client.qos, QosSide::kWriter);
  const rmw_qos_profile_t response_reader = service_actual_qos(client.qos, QosSide::kReader);
  bool found = false;
  rmw_introspect::Runtime::instance().recorder().visit(
    [&](
      const std::vector<rmw_introspect::NodeRecord> &,
      const std::vector<rmw_introspect::EndpointRecord> & endpoints) {
      for (const auto & e : endpoints) {
        if (found || !e.alive || e.kind != rmw_introspect::EndpointKind::Service ||
            e.name != client.name || e.type != client.type.name)
        {
          continue;
        }
        found =
          rmw_introspect::qos_match(request_writer, service_actual_qos(e.qos, QosSide::kReader)) &&
          rmw_introspect::qos_match(service_actual_qos(e.qos, QosSide::kWriter), response_reader);
      }
    });
  return found;
}

}  // namespace

extern "C" {

rmw_client_t * rmw_create_client(
  const rmw_node_t * node, const rosidl_service_type_support_t * type_supports,
  const char * service_name, const rmw_qos_profile_t * qos_policies)
{
  RMWI_CHECK_HANDLE_RETURN_NULL(node);
  RMW_CHECK_ARGUMENT_FOR_NULL(type_supports, nullptr);
  RMW_CHECK_ARGUMENT_FOR_NULL(service_name, nullptr);
  RMW_CHECK_ARGUMENT_FOR_NULL(qos_policies, nullptr);
  if (!rmw_introspect::check_name_and_qos(service_name, qos_policies, "service")) {
    return nullptr;
  }
  auto impl = rmw_introspect::new_endpoint<ClientImpl>(
    node, type_supports, rmw_introspect::resolve_service_type, service_name, qos_policies,
    "client");
  if (!impl) {
    return nullptr;
  }
  impl->handle.service_name = impl->name.c_str();
  rmw_introspect::service_layouts(impl->type, &impl->request_layout, &impl->response_layout);
  rmw_introspect::record(*impl, rmw_introspect::EndpointKind::Client);
  if (rmw_introspect::Runtime::instance().config().delivery) {
    rmw_introspect::Runtime::instance().delivery().add(impl.get());
  }
  return &impl.release()->handle;
}

rmw_ret_t rmw_destroy_client(rmw_node_t * node, rmw_client_t * client)
{
  RMWI_CHECK_HANDLE(node);
  RMWI_CHECK_HANDLE(client);
  std::unique_ptr<ClientImpl> impl(static_cast<ClientImpl *>(client->data));
  if (rmw_introspect::Runtime::instance().config().delivery) {
    rmw_introspect::Runtime::instance().delivery().remove(impl.get());
  }
  rmw_introspect::forget_endpoint(
    impl->record_id, rmw_introspect::EndpointKind::Client, impl->name, impl->node);
  return RMW_RET_OK;
}

rmw_ret_t rmw_send_request(
  const rmw_client_t * client, const void * ros_request, int64_t * sequence_id)
{
  RMWI_CHECK_HANDLE(client);
  RMW_CHECK_ARGUMENT_FOR_NULL(ros_request, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(sequence_id, RMW_RET_INVALID_ARGUMENT);
  auto * impl = static_cast<ClientImpl *>(client->data);
  rmw_introspect::Runtime & runtime = rmw_introspect::Runtime::instance();
  runtime.on_activity();
  if (!runtime.config().delivery) {
    *sequence_id = impl->next_sequence.fetch_add(1);
    return RMW_RET_OK;  // the request is dropped; no response will come
  }
  // In-process delivery: to every matching service of this process.
  std::vector<uint8_t> data;
  std::string error;
  if (!rmw_introspect::cdr_serialize(impl->request_layout, ros_request, &data, &error)) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING("cannot serialize the request: %s", error.c_str());
    return RMW_RET_ERROR;
  }
  *sequence_id = impl->next_sequence.fetch_add(1);
  runtime.delivery().send_request(*impl, *sequence_id, std::move(data));
  return RMW_RET_OK;
}

rmw_ret_t rmw_take_response(
  const rmw_client_t * client, rmw_service_info_t * request_header, void * ros_response,
  bool * taken)
{
  RMWI_CHECK_HANDLE(client);
  RMW_CHECK_ARGUMENT_FOR_NULL(request_header, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(ros_response, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(taken, RMW_RET_INVALID_ARGUMENT);
  rmw_introspect::Runtime::instance().on_activity();
  return rmw_introspect::take_response(
    *static_cast<ClientImpl *>(client->data), request_header, ros_response, taken);
}

rmw_ret_t rmw_client_request_publisher_get_actual_qos(
  const rmw_client_t * client, rmw_qos_profile_t * qos)
{
  RMWI_CHECK_HANDLE(client);
  RMW_CHECK_ARGUMENT_FOR_NULL(qos, RMW_RET_INVALID_ARGUMENT);
  *qos = rmw_introspect::service_actual_qos(
    static_cast<const ClientImpl *>(client->data)->qos, rmw_introspect::QosSide::kWriter);
  return RMW_RET_OK;
}

rmw_ret_t rmw_client_response_subscription_get_actual_qos(
  const rmw_client_t * client, rmw_qos_profile_t * qos)
{
  RMWI_CHECK_HANDLE(client);
  RMW_CHECK_ARGUMENT_FOR_NULL(qos, RMW_RET_INVALID_ARGUMENT);
  *qos = rmw_introspect::service_actual_qos(
    static_cast<const ClientImpl *>(client->data)->qos, rmw_introspect::QosSide::kReader);
  return RMW_RET_OK;
}

rmw_ret_t rmw_client_set_on_new_response_callback(
  rmw_client_t * client, rmw_event_callback_t callback, const void * user_data)
{
  RMWI_CHECK_HANDLE(client);
  static_cast<ClientImpl *>(client->data)->on_new_response.set(callback, user_data);
  return RMW_RET_OK;
}

rmw_ret_t rmw_get_gid_for_client(const rmw_client_t * client, rmw_gid_t * gid)
{
  RMWI_CHECK_HANDLE(client);
  RMW_CHECK_ARGUMENT_FOR_NULL(gid, RMW_RET_INVALID_ARGUMENT);
  const auto * impl = static_cast<const ClientImpl *>(client->data);
  gid->implementation_identifier = kIdentifier;
  std::memcpy(gid->data, impl->gid.data(), RMW_GID_STORAGE_SIZE);
  return RMW_RET_OK;
}

rmw_ret_t rmw_service_server_is_available(
  const rmw_node_t * node, const rmw_client_t * client, bool * is_available)
{
  // A NULL argument is RMW_RET_ERROR on Jazzy, RMW_RET_INVALID_ARGUMENT from Kilted on
  // (detail/rmw_api.hpp says why).
  constexpr rmw_ret_t kNullRet = rmw_introspect::kNullArgumentRetOfOldChecks;
  RMWI_CHECK_HANDLE_OR(node, data, kNullRet, RMW_RET_INCORRECT_RMW_IMPLEMENTATION);
  RMWI_CHECK_HANDLE_OR(client, data, kNullRet, RMW_RET_INCORRECT_RMW_IMPLEMENTATION);
  RMW_CHECK_ARGUMENT_FOR_NULL(is_available, kNullRet);
  // Answer "available" so that clients go on to what they do after wait_for_service()
  // (and create the entities that follow). With RMW_INTROSPECT_SERVER_AVAILABLE=0, answer as a
  // real middleware would from what it can see: a server of this process.
  rmw_introspect::Runtime & runtime = rmw_introspect::Runtime::instance();
  *is_available = runtime.config().server_available ||
    local_server_matches(*static_cast<const ClientImpl *>(client->data));
  runtime.on_activity();
  return RMW_RET_OK;
}

}  // extern "C"
