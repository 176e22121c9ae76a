// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Graph queries, answered from this process's own records (a real middleware includes its
// own entities in what it reports, so a process sees at least itself).

#include <cstring>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "rcutils/strdup.h"
#include "rmw/get_node_info_and_types.h"
#include "rmw/get_service_names_and_types.h"
#include "rmw/get_topic_endpoint_info.h"
#include "rmw/get_topic_names_and_types.h"
#include "rmw/names_and_types.h"
#include "rmw/rmw.h"
#include "rmw/sanity_checks.h"
#include "rmw/topic_endpoint_info_array.h"
#include "rmw/validate_full_topic_name.h"
#include "rmw/validate_namespace.h"
#include "rmw/validate_node_name.h"
#include "rosidl_runtime_c/type_hash.h"

#include "detail/common.hpp"
#include "detail/recorder.hpp"
#include "detail/runtime.hpp"

using rmw_introspect::EndpointKind;
using rmw_introspect::EndpointRecord;
using rmw_introspect::NodeRecord;

namespace
{

using NameTypes = std::map<std::string, std::set<std::string>>;

rmw_ret_t fill_names_and_types(
  const NameTypes & entries, rcutils_allocator_t * allocator, rmw_names_and_types_t * out)
{
  if (entries.empty()) {
    return RMW_RET_OK;
  }
  rmw_ret_t ret = rmw_names_and_types_init(out, entries.size(), allocator);
  if (ret != RMW_RET_OK) {
    return ret;
  }
  size_t i = 0;
  for (const auto & entry : entries) {
    out->names.data[i] = rcutils_strdup(entry.first.c_str(), *allocator);
    if (out->names.data[i] == nullptr) {
      RMW_SET_ERROR_MSG("failed to allocate a name");
      rmw_introspect::ignore_result(rmw_names_and_types_fini(out));
      return RMW_RET_BAD_ALLOC;
    }
    if (rcutils_string_array_init(&out->types[i], entry.second.size(), allocator) != RCUTILS_RET_OK)
    {
      RMW_SET_ERROR_MSG("failed to allocate the types");
      rmw_introspect::ignore_result(rmw_names_and_types_fini(out));
      return RMW_RET_BAD_ALLOC;
    }
    size_t j = 0;
    for (const auto & type : entry.second) {
      out->types[i].data[j] = rcutils_strdup(type.c_str(), *allocator);
      if (out->types[i].data[j] == nullptr) {
        RMW_SET_ERROR_MSG("failed to allocate a type");
        rmw_introspect::ignore_result(rmw_names_and_types_fini(out));
        return RMW_RET_BAD_ALLOC;
      }
      ++j;
    }
    ++i;
  }
  return RMW_RET_OK;
}

// Every graph query reads the records through this; a query also counts as activity (a
// process polling the graph in a loop settles like one that waits).
template<typename Fn>
void visit_graph(Fn && fn)
{
  auto & runtime = rmw_introspect::Runtime::instance();
  runtime.on_activity();
  runtime.recorder().visit(std::forward<Fn>(fn));
}

bool is_topic_kind(EndpointKind kind)
{
  return kind == EndpointKind::Publisher || kind == EndpointKind::Subscription;
}

rmw_ret_t check_node(const rmw_node_t * node)
{
  RMWI_CHECK_HANDLE(node);
  return RMW_RET_OK;
}

rmw_ret_t check_names_and_types_args(
  const rmw_node_t * node, rcutils_allocator_t * allocator, rmw_names_and_types_t * out)
{
  rmw_ret_t ret = check_node(node);
  if (ret != RMW_RET_OK) {
    return ret;
  }
  RMW_CHECK_ARGUMENT_FOR_NULL(allocator, RMW_RET_INVALID_ARGUMENT);
  RCUTILS_CHECK_ALLOCATOR_WITH_MSG(
    allocator, "allocator argument is invalid", return RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(out, RMW_RET_INVALID_ARGUMENT);
  return rmw_names_and_types_check_zero(out);
}

rmw_ret_t check_node_name_args(const char * node_name, const char * node_namespace)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(node_name, RMW_RET_INVALID_ARGUMENT);
  int validation_result = RMW_NODE_NAME_VALID;
  rmw_ret_t ret = rmw_validate_node_name(node_name, &validation_result, nullptr);
  if (ret != RMW_RET_OK) {
    return ret;
  }
  if (validation_result != RMW_NODE_NAME_VALID) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING(
      "node_name argument is invalid: %s",
      rmw_node_name_validation_result_string(validation_result));
    return RMW_RET_INVALID_ARGUMENT;
  }
  RMW_CHECK_ARGUMENT_FOR_NULL(node_namespace, RMW_RET_INVALID_ARGUMENT);
  validation_result = RMW_NAMESPACE_VALID;
  ret = rmw_validate_namespace(node_namespace, &validation_result, nullptr);
  if (ret != RMW_RET_OK) {
    return ret;
  }
  if (validation_result != RMW_NAMESPACE_VALID) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING(
      "node_namespace argument is invalid: %s",
      rmw_namespace_validation_result_string(validation_result));
    return RMW_RET_INVALID_ARGUMENT;
  }
  return RMW_RET_OK;
}

rmw_ret_t check_topic_name(const char * name, const char * what)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(name, RMW_RET_INVALID_ARGUMENT);
  int validation_result = RMW_TOPIC_VALID;
  const rmw_ret_t ret = rmw_validate_full_topic_name(name, &validation_result, nullptr);
  if (ret != RMW_RET_OK) {
    return ret;
  }
  if (validation_result != RMW_TOPIC_VALID) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING(
      "%s argument is invalid: %s", what,
      rmw_full_topic_name_validation_result_string(validation_result));
    return RMW_RET_INVALID_ARGUMENT;
  }
  return RMW_RET_OK;
}

// Endpoints of one live node, by kind.
rmw_ret_t names_and_types_by_node(
  const rmw_node_t * node, rcutils_allocator_t * allocator, const char * node_name,
  const char * node_namespace, rmw_names_and_types_t * out, EndpointKind kind)
{
  rmw_ret_t ret = check_names_and_types_args(node, allocator, out);
  if (ret != RMW_RET_OK) {
    return ret;
  }
  ret = check_node_name_args(node_name, node_namespace);
  if (ret != RMW_RET_OK) {
    return ret;
  }
  bool found = false;
  NameTypes entries;
  visit_graph(
    [&](const std::vector<NodeRecord> & nodes, const std::vector<EndpointRecord> & endpoints) {
      std::set<uint64_t> ids;
      for (const auto & n : nodes) {
        if (n.alive && n.name == node_name && n.namespace_ == node_namespace) {
          ids.insert(n.id);
        }
      }
      found = !ids.empty();
      for (const auto & e : endpoints) {
        if (e.alive && e.kind == kind && ids.count(e.node_id) != 0) {
          entries[e.name].insert(e.type);
        }
      }
    });
  if (!found) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING(
      "node '%s' in namespace '%s' not found", node_name, node_namespace);
    return RMW_RET_NODE_NAME_NON_EXISTENT;
  }
  return fill_names_and_types(entries, allocator, out);
}

rmw_ret_t count_endpoints(
  const rmw_node_t * node, const char * name, size_t * count, EndpointKind kind, const char * what)
{
  rmw_ret_t ret = check_node(node);
  if (ret != RMW_RET_OK) {
    return ret;
  }
  ret = check_topic_name(name, what);
  if (ret != RMW_RET_OK) {
    return ret;
  }
  RMW_CHECK_ARGUMENT_FOR_NULL(count, RMW_RET_INVALID_ARGUMENT);
  size_t n = 0;
  visit_graph([&](const std::vector<NodeRecord> &, const std::vector<EndpointRecord> & endpoints) {
    for (const auto & e : endpoints) {
      if (e.alive && e.kind == kind && e.name == name) {
        ++n;
      }
    }
  });
  *count = n;
  return RMW_RET_OK;
}

rmw_ret_t info_by_topic(
  const rmw_node_t * node, rcutils_allocator_t * allocator, const char * topic_name,
  rmw_topic_endpoint_info_array_t * out, EndpointKind kind)
{
  rmw_ret_t ret = check_node(node);
  if (ret != RMW_RET_OK) {
    return ret;
  }
  RMW_CHECK_ARGUMENT_FOR_NULL(allocator, RMW_RET_INVALID_ARGUMENT);
  RCUTILS_CHECK_ALLOCATOR_WITH_MSG(
    allocator, "allocator argument is invalid", return RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(topic_name, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(out, RMW_RET_INVALID_ARGUMENT);
  if (rmw_topic_endpoint_info_array_check_zero(out) != RMW_RET_OK) {
    return RMW_RET_INVALID_ARGUMENT;  // the check says RMW_RET_ERROR; rmw.h and the suite want this
  }
  std::vector<EndpointRecord> matches;
  visit_graph([&](const std::vector<NodeRecord> &, const std::vector<EndpointRecord> & endpoints) {
    for (const auto & e : endpoints) {
      if (e.alive && e.kind == kind && e.name == topic_name) {
        matches.push_back(e);
      }
    }
  });
  if (matches.empty()) {
    return RMW_RET_OK;
  }
  ret = rmw_topic_endpoint_info_array_init_with_size(out, matches.size(), allocator);
  if (ret != RMW_RET_OK) {
    return ret;
  }
  for (size_t i = 0; i < matches.size(); ++i) {
    const EndpointRecord & e = matches[i];
    rmw_topic_endpoint_info_t * info = &out->info_array[i];
    *info = rmw_get_zero_initialized_topic_endpoint_info();
    rosidl_type_hash_t hash = rosidl_get_zero_initialized_type_hash();
    if (!e.type_hash.empty() &&
        rosidl_parse_type_hash_string(e.type_hash.c_str(), &hash) != RCUTILS_RET_OK)
    {
      rcutils_reset_error();
      hash = rosidl_get_zero_initialized_type_hash();
    }
    if ((ret = rmw_topic_endpoint_info_set_node_name(info, e.node_name.c_str(), allocator)) !=
          RMW_RET_OK ||
        (ret = rmw_topic_endpoint_info_set_node_namespace(
           info, e.node_namespace.c_str(), allocator)) != RMW_RET_OK ||
        (ret = rmw_topic_endpoint_info_set_topic_type(info, e.type.c_str(), allocator)) !=
          RMW_RET_OK ||
        (ret = rmw_topic_endpoint_info_set_topic_type_hash(info, &hash)) != RMW_RET_OK ||
        (ret = rmw_topic_endpoint_info_set_endpoint_type(
           info,
           kind == EndpointKind::Publisher ? RMW_ENDPOINT_PUBLISHER : RMW_ENDPOINT_SUBSCRIPTION)) !=
          RMW_RET_OK ||
        (ret = rmw_topic_endpoint_info_set_gid(info, e.gid.data(), e.gid.size())) != RMW_RET_OK ||
        (ret = rmw_topic_endpoint_info_set_qos_profile(info, &e.qos)) != RMW_RET_OK)
    {
      rmw_introspect::ignore_result(rmw_topic_endpoint_info_array_fini(out, allocator));
      return ret;
    }
  }
  return RMW_RET_OK;
}

rmw_ret_t node_names_impl(
  const rmw_node_t * node, rcutils_string_array_t * node_names,
  rcutils_string_array_t * node_namespaces, rcutils_string_array_t * enclaves)
{
  std::vector<NodeRecord> live;
  visit_graph([&](const std::vector<NodeRecord> & nodes, const std::vector<EndpointRecord> &) {
    for (const auto & n : nodes) {
      if (n.alive) {
        live.push_back(n);
      }
    }
  });
  (void)node;
  rcutils_allocator_t allocator = rcutils_get_default_allocator();
  rcutils_ret_t rret = rcutils_string_array_init(node_names, live.size(), &allocator);
  if (rret == RCUTILS_RET_OK) {
    rret = rcutils_string_array_init(node_namespaces, live.size(), &allocator);
  }
  if (rret == RCUTILS_RET_OK && enclaves != nullptr) {
    rret = rcutils_string_array_init(enclaves, live.size(), &allocator);
  }
  bool ok = rret == RCUTILS_RET_OK;
  for (size_t i = 0; ok && i < live.size(); ++i) {
    node_names->data[i] = rcutils_strdup(live[i].name.c_str(), allocator);
    node_namespaces->data[i] = rcutils_strdup(live[i].namespace_.c_str(), allocator);
    ok = node_names->data[i] != nullptr && node_namespaces->data[i] != nullptr;
    if (ok && enclaves != nullptr) {
      enclaves->data[i] = rcutils_strdup(live[i].enclave.c_str(), allocator);
      ok = enclaves->data[i] != nullptr;
    }
  }
  if (!ok) {
    rcutils_reset_error();
    RMW_SET_ERROR_MSG("failed to allocate the node name arrays");
    rmw_introspect::ignore_result(rcutils_string_array_fini(node_names));
    rmw_introspect::ignore_result(rcutils_string_array_fini(node_namespaces));
    if (enclaves != nullptr) {
      rmw_introspect::ignore_result(rcutils_string_array_fini(enclaves));
    }
    return RMW_RET_BAD_ALLOC;
  }
  return RMW_RET_OK;
}

}  // namespace

// An output string array must be given and empty (zero-initialized), as rmw requires.
#define RMWI_CHECK_ZERO_STRING_ARRAY(array)                     \
  RMW_CHECK_ARGUMENT_FOR_NULL(array, RMW_RET_INVALID_ARGUMENT); \
  if (rmw_check_zero_rmw_string_array(array) != RMW_RET_OK) {   \
    return RMW_RET_INVALID_ARGUMENT;                            \
  }

extern "C" {

rmw_ret_t rmw_get_node_names(
  const rmw_node_t * node, rcutils_string_array_t * node_names,
  rcutils_string_array_t * node_namespaces)
{
  rmw_ret_t ret = check_node(node);
  if (ret != RMW_RET_OK) {
    return ret;
  }
  RMWI_CHECK_ZERO_STRING_ARRAY(node_names);
  RMWI_CHECK_ZERO_STRING_ARRAY(node_namespaces);
  return node_names_impl(node, node_names, node_namespaces, nullptr);
}

rmw_ret_t rmw_get_node_names_with_enclaves(
  const rmw_node_t * node, rcutils_string_array_t * node_names,
  rcutils_string_array_t * node_namespaces, rcutils_string_array_t * enclaves)
{
  rmw_ret_t ret = check_node(node);
  if (ret != RMW_RET_OK) {
    return ret;
  }
  RMWI_CHECK_ZERO_STRING_ARRAY(node_names);
  RMWI_CHECK_ZERO_STRING_ARRAY(node_namespaces);
  RMWI_CHECK_ZERO_STRING_ARRAY(enclaves);
  return node_names_impl(node, node_names, node_namespaces, enclaves);
}

rmw_ret_t rmw_get_topic_names_and_types(
  const rmw_node_t * node, rcutils_allocator_t * allocator, bool no_demangle,
  rmw_names_and_types_t * topic_names_and_types)
{
  (void)no_demangle;  // names are recorded as ROS names; there is no mangled form
  rmw_ret_t ret = check_names_and_types_args(node, allocator, topic_names_and_types);
  if (ret != RMW_RET_OK) {
    return ret;
  }
  NameTypes entries;
  visit_graph([&](const std::vector<NodeRecord> &, const std::vector<EndpointRecord> & endpoints) {
    for (const auto & e : endpoints) {
      if (e.alive && is_topic_kind(e.kind)) {
        entries[e.name].insert(e.type);
      }
    }
  });
  return fill_names_and_types(entries, allocator, topic_names_and_types);
}

rmw_ret_t rmw_get_service_names_and_types(
  const rmw_node_t * node, rcutils_allocator_t * allocator,
  rmw_names_and_types_t * service_names_and_types)
{
  rmw_ret_t ret = check_names_and_types_args(node, allocator, service_names_and_types);
  if (ret != RMW_RET_OK) {
    return ret;
  }
  NameTypes entries;
  visit_graph([&](const std::vector<NodeRecord> &, const std::vector<EndpointRecord> & endpoints) {
    for (const auto & e : endpoints) {
      if (e.alive && !is_topic_kind(e.kind)) {
        entries[e.name].insert(e.type);
      }
    }
  });
  return fill_names_and_types(entries, allocator, service_names_and_types);
}

rmw_ret_t rmw_get_publisher_names_and_types_by_node(
  const rmw_node_t * node, rcutils_allocator_t * allocator, const char * node_name,
  const char * node_namespace, bool no_demangle, rmw_names_and_types_t * topic_names_and_types)
{
  (void)no_demangle;
  return names_and_types_by_node(
    node, allocator, node_name, node_namespace, topic_names_and_types, EndpointKind::Publisher);
}

rmw_ret_t rmw_get_subscriber_names_and_types_by_node(
  const rmw_node_t * node, rcutils_allocator_t * allocator, const char * node_name,
  const char * node_namespace, bool no_demangle, rmw_names_and_types_t * topic_names_and_types)
{
  (void)no_demangle;
  return names_and_types_by_node(
    node, allocator, node_name, node_namespace, topic_names_and_types, EndpointKind::Subscription);
}

rmw_ret_t rmw_get_service_names_and_types_by_node(
  const rmw_node_t * node, rcutils_allocator_t * allocator, const char * node_name,
  const char * node_namespace, rmw_names_and_types_t * service_names_and_types)
{
  return names_and_types_by_node(
    node, allocator, node_name, node_namespace, service_names_and_types, EndpointKind::Service);
}

rmw_ret_t rmw_get_client_names_and_types_by_node(
  const rmw_node_t * node, rcutils_allocator_t * allocator, const char * node_name,
  const char * node_namespace, rmw_names_and_types_t * service_names_and_types)
{
  return names_and_types_by_node(
    node, allocator, node_name, node_namespace, service_names_and_types, EndpointKind::Client);
}

rmw_ret_t rmw_get_publishers_info_by_topic(
  const rmw_node_t * node, rcutils_allocator_t * allocator, const char * topic_name, bool no_mangle,
  rmw_topic_endpoint_info_array_t * publishers_info)
{
  (void)no_mangle;
  return info_by_topic(node, allocator, topic_name, publishers_info, EndpointKind::Publisher);
}

rmw_ret_t rmw_get_subscriptions_info_by_topic(
  const rmw_node_t * node, rcutils_allocator_t * allocator, const char * topic_name, bool no_mangle,
  rmw_topic_endpoint_info_array_t * subscriptions_info)
{
  (void)no_mangle;
  return info_by_topic(node, allocator, topic_name, subscriptions_info, EndpointKind::Subscription);
}

rmw_ret_t rmw_count_publishers(const rmw_node_t * node, const char * topic_name, size_t * count)
{
  return count_endpoints(node, topic_name, count, EndpointKind::Publisher, "topic_name");
}

rmw_ret_t rmw_count_subscribers(const rmw_node_t * node, const char * topic_name, size_t * count)
{
  return count_endpoints(node, topic_name, count, EndpointKind::Subscription, "topic_name");
}

rmw_ret_t rmw_count_clients(const rmw_node_t * node, const char * service_name, size_t * count)
{
  return count_endpoints(node, service_name, count, EndpointKind::Client, "service_name");
}

rmw_ret_t rmw_count_services(const rmw_node_t * node, const char * service_name, size_t * count)
{
  return count_endpoints(node, service_name, count, EndpointKind::Service, "service_name");
}

}  // extern "C"
