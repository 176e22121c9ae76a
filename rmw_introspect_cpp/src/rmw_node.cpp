// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Nodes and their graph guard conditions.

#include <memory>
#include <new>

#include "rmw/rmw.h"
#include "rmw/validate_namespace.h"
#include "rmw/validate_node_name.h"

#include "detail/common.hpp"
#include "detail/handles.hpp"
#include "detail/log.hpp"
#include "detail/runtime.hpp"

using rmw_introspect::kIdentifier;
using rmw_introspect::NodeImpl;

extern "C" {

rmw_node_t * rmw_create_node(rmw_context_t * context, const char * name, const char * namespace_)
{
  RMWI_CHECK_HANDLE_OR(context, impl, nullptr, nullptr);
  auto * context_impl = reinterpret_cast<rmw_introspect::ContextImpl *>(context->impl);
  if (context_impl->is_shutdown.load()) {
    RMW_SET_ERROR_MSG("context has been shutdown");
    return nullptr;
  }
  RMW_CHECK_ARGUMENT_FOR_NULL(name, nullptr);
  RMW_CHECK_ARGUMENT_FOR_NULL(namespace_, nullptr);
  int validation_result = RMW_NODE_NAME_VALID;
  rmw_ret_t ret = rmw_validate_node_name(name, &validation_result, nullptr);
  if (ret != RMW_RET_OK) {
    return nullptr;
  }
  if (validation_result != RMW_NODE_NAME_VALID) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING(
      "invalid node name: %s", rmw_node_name_validation_result_string(validation_result));
    return nullptr;
  }
  validation_result = RMW_NAMESPACE_VALID;
  ret = rmw_validate_namespace(namespace_, &validation_result, nullptr);
  if (ret != RMW_RET_OK) {
    return nullptr;
  }
  if (validation_result != RMW_NAMESPACE_VALID) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING(
      "invalid node namespace: %s", rmw_namespace_validation_result_string(validation_result));
    return nullptr;
  }
  std::unique_ptr<NodeImpl> impl(new (std::nothrow) NodeImpl());
  if (!impl) {
    RMW_SET_ERROR_MSG("failed to allocate node");
    return nullptr;
  }
  impl->name = name;
  impl->namespace_ = namespace_;
  impl->context_impl = context_impl;
  impl->handle.implementation_identifier = kIdentifier;
  impl->handle.data = impl.get();
  impl->handle.name = impl->name.c_str();
  impl->handle.namespace_ = impl->namespace_.c_str();
  impl->handle.context = context;
  impl->graph_guard.handle.implementation_identifier = kIdentifier;
  impl->graph_guard.handle.data = &impl->graph_guard;
  impl->graph_guard.handle.context = context;
  const char * enclave = context->options.enclave != nullptr ? context->options.enclave : "/";
  auto & runtime = rmw_introspect::Runtime::instance();
  impl->record_id = runtime.recorder().add_node(name, namespace_, enclave, runtime.creation_time());
  rmw_introspect::verbose_log(
    "node %s (namespace %s, enclave %s)", impl->name.c_str(), impl->namespace_.c_str(), enclave);
  runtime.graph_guards().add(&impl->graph_guard.gc);
  runtime.notify_graph_change();
  context_impl->node_count.fetch_add(1);
  return &impl.release()->handle;
}

rmw_ret_t rmw_destroy_node(rmw_node_t * node)
{
  RMWI_CHECK_HANDLE(node);
  std::unique_ptr<NodeImpl> impl(static_cast<NodeImpl *>(node->data));
  auto & runtime = rmw_introspect::Runtime::instance();
  runtime.graph_guards().remove(&impl->graph_guard.gc);
  const bool teardown = runtime.in_teardown(impl->context_impl);
  runtime.recorder().destroy_node(impl->record_id, teardown, runtime.creation_time());
  rmw_introspect::verbose_log(
    "destroyed node %s%s", impl->name.c_str(), teardown ? " (teardown)" : "");
  runtime.notify_graph_change();
  if (impl->context_impl != nullptr) {
    impl->context_impl->node_count.fetch_sub(1);
  }
  return RMW_RET_OK;
}

const rmw_guard_condition_t * rmw_node_get_graph_guard_condition(const rmw_node_t * node)
{
  RMWI_CHECK_HANDLE_RETURN_NULL(node);
  auto * impl = static_cast<NodeImpl *>(node->data);
  return &impl->graph_guard.handle;
}

rmw_ret_t rmw_set_log_severity(rmw_log_severity_t severity)
{
  switch (severity) {
    case RMW_LOG_SEVERITY_DEBUG:
    case RMW_LOG_SEVERITY_INFO:
    case RMW_LOG_SEVERITY_WARN:
    case RMW_LOG_SEVERITY_ERROR:
    case RMW_LOG_SEVERITY_FATAL:
      return RMW_RET_OK;  // nothing of ours logs below what the caller asks for
    default: RMW_SET_ERROR_MSG("severity value is invalid"); return RMW_RET_INVALID_ARGUMENT;
  }
}

}  // extern "C"
