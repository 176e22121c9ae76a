// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__ENDPOINT_COMMON_HPP_
#define DETAIL__ENDPOINT_COMMON_HPP_

#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "rmw/error_handling.h"
#include "rmw/network_flow_endpoint_array.h"
#include "rmw/time.h"
#include "rmw/types.h"
#include "rmw/validate_full_topic_name.h"

#include "detail/handles.hpp"
#include "detail/identifier.hpp"
#include "detail/qos.hpp"
#include "detail/log.hpp"
#include "detail/recorder.hpp"
#include "detail/runtime.hpp"

namespace rmw_introspect
{

/// The checks every rmw_create_{publisher,subscription,service,client} makes on the name
/// and QoS (after the NULL checks). `what` is "topic" or "service".
inline bool check_name_and_qos(const char * name, const rmw_qos_profile_t * qos, const char * what)
{
  if (std::strlen(name) == 0) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING("%s_name argument is an empty string", what);
    return false;
  }
  if (!qos->avoid_ros_namespace_conventions) {
    int validation_result = RMW_TOPIC_VALID;
    const rmw_ret_t ret = rmw_validate_full_topic_name(name, &validation_result, nullptr);
    if (ret != RMW_RET_OK) {
      return false;
    }
    if (validation_result != RMW_TOPIC_VALID) {
      RMW_SET_ERROR_MSG_WITH_FORMAT_STRING(
        "invalid %s name: %s", what,
        rmw_full_topic_name_validation_result_string(validation_result));
      return false;
    }
  }
  if (!qos_is_valid(*qos)) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING("create_%s() called with an unknown QoS policy", what);
    return false;
  }
  return true;
}

/// The part of rmw_create_{publisher,subscription,service,client} after the argument checks:
/// resolve the type through `resolve` and make the Impl with its name copied, type, QoS, GID
/// and handle identity. The caller fills the kind's own handle fields, then `record`s it.
template<typename Impl, typename TypeSupportT, typename ResolveFn>
std::unique_ptr<Impl> new_endpoint(
  const rmw_node_t * node, const TypeSupportT * type_support, ResolveFn resolve, const char * name,
  const rmw_qos_profile_t * qos, const char * what)
{
  const auto * node_impl = static_cast<const NodeImpl *>(node->data);
  ResolvedType type;
  std::string error;
  if (!resolve(type_support, &type, &error)) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING("%s", error.c_str());
    return nullptr;
  }
  std::unique_ptr<Impl> impl(new (std::nothrow) Impl());
  if (!impl) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING("failed to allocate %s", what);
    return nullptr;
  }
  impl->name = name;
  impl->node = node_impl;
  impl->type = std::move(type);
  impl->qos = *qos;
  impl->gid = Runtime::instance().recorder().new_gid();
  impl->handle.implementation_identifier = kIdentifier;
  impl->handle.data = impl.get();
  return impl;
}

/// The side of the DDS entity that carries an endpoint's topic: a client writes requests, a
/// service reads them.
inline QosSide topic_side(EndpointKind kind)
{
  return kind == EndpointKind::Publisher || kind == EndpointKind::Client ? QosSide::kWriter :
                                                                           QosSide::kReader;
}

/// The actual QoS of an endpoint about to be recorded, as a real middleware resolves it at
/// creation: BEST_AVAILABLE from the actual QoS of the endpoints now on the other side of the
/// topic (publishers and subscriptions), then what is left to the middleware (system defaults).
/// The capture keeps the requested QoS.
inline rmw_qos_profile_t resolve_actual_qos(
  EndpointKind kind, const std::string & name, const rmw_qos_profile_t & requested)
{
  if (kind == EndpointKind::Service || kind == EndpointKind::Client) {
    return service_actual_qos(requested, topic_side(kind));
  }
  rmw_qos_profile_t qos = requested;
  const bool best_available = qos.reliability == RMW_QOS_POLICY_RELIABILITY_BEST_AVAILABLE ||
    qos.durability == RMW_QOS_POLICY_DURABILITY_BEST_AVAILABLE ||
    qos.liveliness == RMW_QOS_POLICY_LIVELINESS_BEST_AVAILABLE ||
    rmw_time_equal(qos.deadline, RMW_QOS_DEADLINE_BEST_AVAILABLE) ||
    rmw_time_equal(qos.liveliness_lease_duration, RMW_QOS_LIVELINESS_LEASE_DURATION_BEST_AVAILABLE);
  if (best_available) {
    const EndpointKind peer_kind =
      kind == EndpointKind::Publisher ? EndpointKind::Subscription : EndpointKind::Publisher;
    std::vector<rmw_qos_profile_t> peers;
    Runtime::instance().recorder().visit(
      [&](const std::vector<NodeRecord> &, const std::vector<EndpointRecord> & endpoints) {
        for (const auto & e : endpoints) {
          if (e.alive && e.kind == peer_kind && e.name == name) {
            peers.push_back(e.actual_qos);
          }
        }
      });
    if (kind == EndpointKind::Publisher) {
      resolve_best_available_for_publisher(&qos, peers.data(), peers.size());
    } else {
      resolve_best_available_for_subscription(&qos, peers.data(), peers.size());
    }
  }
  return resolve_system_defaults(qos, topic_side(kind));
}

/// How many endpoints of `peer_kind` (Subscription for a publisher, Publisher for a
/// subscription) in this process match an endpoint on `topic` of `type` with `actual_qos`: the
/// same topic name and type, and QoS without an incompatibility (rmw_qos_profile_check_compatible
/// semantics, on both sides' actual QoS). Allocates nothing.
inline size_t count_matched(
  EndpointKind peer_kind, const std::string & topic, const std::string & type,
  const rmw_qos_profile_t & actual_qos)
{
  size_t count = 0;
  Runtime::instance().recorder().visit(
    [&](const std::vector<NodeRecord> &, const std::vector<EndpointRecord> & endpoints) {
      for (const auto & e : endpoints) {
        if (!e.alive || e.kind != peer_kind || e.name != topic || e.type != type) {
          continue;
        }
        const bool match = peer_kind == EndpointKind::Subscription ?
          qos_match(actual_qos, e.actual_qos) :
          qos_match(e.actual_qos, actual_qos);
        count += match ? 1u : 0u;
      }
    });
  return count;
}

/// Record an endpoint of `node` and return its record id (0 when the node is unknown).
inline uint64_t record_endpoint(
  EndpointKind kind, const NodeImpl * node, const std::string & name, const ResolvedType & type,
  const rmw_qos_profile_t & qos, const rmw_qos_profile_t & actual_qos, const Gid & gid)
{
  EndpointRecord record;
  record.kind = kind;
  record.node_id = node->record_id;
  record.name = name;
  record.type = type.name;
  record.type_hash = type.type_hash;
  record.typesupport = type.typesupport;
  record.types = type.descriptions;
  record.qos = qos;
  record.actual_qos = actual_qos;
  record.gid = gid;
  Runtime & runtime = Runtime::instance();
  record.created = runtime.creation_time();
  const uint64_t id = runtime.recorder().add_endpoint(std::move(record));
  verbose_log(
    "%s %s [%s] (node %s/%s, %s)", endpoint_kind_to_string(kind), name.c_str(), type.name.c_str(),
    node->namespace_ == "/" ? "" : node->namespace_.c_str(), node->name.c_str(),
    type.typesupport.c_str());
  runtime.notify_graph_change();
  return id;
}

/// Record a fully made endpoint (see new_endpoint), its actual QoS resolved now.
template<typename Impl>
void record(Impl & impl, EndpointKind kind)
{
  impl.actual_qos = resolve_actual_qos(kind, impl.name, impl.qos);
  impl.record_id =
    record_endpoint(kind, impl.node, impl.name, impl.type, impl.qos, impl.actual_qos, impl.gid);
}

inline void forget_endpoint(
  uint64_t record_id, EndpointKind kind, const std::string & name, const NodeImpl * node)
{
  Runtime & runtime = Runtime::instance();
  const bool teardown = runtime.in_teardown(node != nullptr ? node->context_impl : nullptr);
  runtime.recorder().destroy_endpoint(record_id, teardown, runtime.creation_time());
  verbose_log(
    "destroyed %s %s%s", endpoint_kind_to_string(kind), name.c_str(),
    teardown ? " (teardown)" : "");
  runtime.notify_graph_change();
}

/// rmw_{publisher,subscription}_get_network_flow_endpoints: nothing goes on a network, so the
/// list is empty, and valid (its allocator set): rclcpp's get_network_flow_endpoints() finalizes
/// it and throws on any error, which would end a program that prints its flows (Fast DDS lists them).
inline rmw_ret_t no_network_flow_endpoints(
  rcutils_allocator_t * allocator, rmw_network_flow_endpoint_array_t * array)
{
  if (array->network_flow_endpoint != nullptr || array->size != 0) {
    RMW_SET_ERROR_MSG("network_flow_endpoint_array must be zero initialized");
    return RMW_RET_INVALID_ARGUMENT;
  }
  array->allocator = allocator;
  return RMW_RET_OK;
}

}  // namespace rmw_introspect

#endif  // DETAIL__ENDPOINT_COMMON_HPP_
