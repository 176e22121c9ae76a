// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Nodes and their graph guard conditions.

#include <cstdarg>
#include <cstdio>
#include <memory>
#include <mutex>
#include <new>
#include <set>

#include "rmw/rmw.h"
#include "rmw/validate_namespace.h"
#include "rmw/validate_node_name.h"

#include "detail/common.hpp"
#include "detail/config.hpp"
#include "detail/handles.hpp"
#include "detail/recorder.hpp"

namespace rmw_introspect
{

namespace
{
std::mutex & graph_mutex()
{
  static std::mutex * m = new std::mutex();
  return *m;
}
std::set<GuardConditionImpl *> & graph_guards()
{
  static auto * guards = new std::set<GuardConditionImpl *>();
  return *guards;
}
}  // namespace

void register_graph_guard(GuardConditionImpl * gc)
{
  std::lock_guard<std::mutex> lock(graph_mutex());
  graph_guards().insert(gc);
}

void unregister_graph_guard(GuardConditionImpl * gc)
{
  std::lock_guard<std::mutex> lock(graph_mutex());
  graph_guards().erase(gc);
}

void notify_graph_change()
{
  std::lock_guard<std::mutex> lock(graph_mutex());
  for (GuardConditionImpl * gc : graph_guards()) {
    WaitHub::instance().trigger(&gc->gc);
  }
}

void verbose_log(const char * format, ...)
{
  if (!Config::get().verbose) {
    return;
  }
  char buffer[1024];
  va_list args;
  va_start(args, format);
  vsnprintf(buffer, sizeof(buffer), format, args);
  va_end(args);
  std::fprintf(stderr, "[rmw_introspect] %s\n", buffer);
}

}  // namespace rmw_introspect

using rmw_introspect::kIdentifier;
using rmw_introspect::NodeImpl;

extern "C"
{

rmw_node_t * rmw_create_node(rmw_context_t * context, const char * name, const char * namespace_)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(context, nullptr);
  RMWI_CHECK_IDENTIFIER(init context, context->implementation_identifier, return nullptr);
  RMW_CHECK_FOR_NULL_WITH_MSG(context->impl, "expected initialized context", return nullptr);
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
  impl->record_id = rmw_introspect::Recorder::instance().add_node(name, namespace_, enclave);
  rmw_introspect::verbose_log(
    "node %s (namespace %s, enclave %s)", impl->name.c_str(), impl->namespace_.c_str(), enclave);
  rmw_introspect::register_graph_guard(&impl->graph_guard);
  rmw_introspect::notify_graph_change();
  context_impl->node_count.fetch_add(1);
  return &impl.release()->handle;
}

rmw_ret_t rmw_destroy_node(rmw_node_t * node)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(node, RMW_RET_INVALID_ARGUMENT);
  RMWI_CHECK_IDENTIFIER(
    node, node->implementation_identifier, return RMW_RET_INCORRECT_RMW_IMPLEMENTATION);
  std::unique_ptr<NodeImpl> impl(static_cast<NodeImpl *>(node->data));
  rmw_introspect::unregister_graph_guard(&impl->graph_guard);
  const bool teardown = rmw_introspect::in_teardown(impl->context_impl);
  rmw_introspect::Recorder::instance().destroy_node(impl->record_id, teardown);
  rmw_introspect::verbose_log(
    "destroyed node %s%s", impl->name.c_str(), teardown ? " (teardown)" : "");
  rmw_introspect::notify_graph_change();
  if (impl->context_impl != nullptr) {
    impl->context_impl->node_count.fetch_sub(1);
  }
  return RMW_RET_OK;
}

const rmw_guard_condition_t * rmw_node_get_graph_guard_condition(const rmw_node_t * node)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(node, nullptr);
  RMWI_CHECK_IDENTIFIER(node, node->implementation_identifier, return nullptr);
  auto * impl = static_cast<NodeImpl *>(node->data);
  RMW_CHECK_FOR_NULL_WITH_MSG(impl, "node impl is null", return nullptr);
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
    default:
      RMW_SET_ERROR_MSG("severity value is invalid");
      return RMW_RET_INVALID_ARGUMENT;
  }
}

}  // extern "C"
