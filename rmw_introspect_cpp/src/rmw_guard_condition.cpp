// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Guard conditions: a trigger is remembered until a wait consumes it.

#include <memory>
#include <new>

#include "rmw/rmw.h"

#include "detail/common.hpp"
#include "detail/handles.hpp"
#include "detail/wait_hub.hpp"

using rmw_introspect::GuardConditionImpl;
using rmw_introspect::kIdentifier;

extern "C"
{

rmw_guard_condition_t * rmw_create_guard_condition(rmw_context_t * context)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(context, nullptr);
  RMWI_CHECK_IDENTIFIER(init context, context->implementation_identifier, return nullptr);
  std::unique_ptr<GuardConditionImpl> impl(new (std::nothrow) GuardConditionImpl());
  if (!impl) {
    RMW_SET_ERROR_MSG("failed to allocate guard condition");
    return nullptr;
  }
  impl->handle.implementation_identifier = kIdentifier;
  impl->handle.data = impl.get();
  impl->handle.context = context;
  return &impl.release()->handle;
}

rmw_ret_t rmw_destroy_guard_condition(rmw_guard_condition_t * guard_condition)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(guard_condition, RMW_RET_INVALID_ARGUMENT);
  RMWI_CHECK_IDENTIFIER(
    guard condition, guard_condition->implementation_identifier,
    return RMW_RET_INCORRECT_RMW_IMPLEMENTATION);
  delete static_cast<GuardConditionImpl *>(guard_condition->data);
  return RMW_RET_OK;
}

rmw_ret_t rmw_trigger_guard_condition(const rmw_guard_condition_t * guard_condition)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(guard_condition, RMW_RET_INVALID_ARGUMENT);
  RMWI_CHECK_IDENTIFIER(
    guard condition, guard_condition->implementation_identifier,
    return RMW_RET_INCORRECT_RMW_IMPLEMENTATION);
  auto * impl = static_cast<GuardConditionImpl *>(guard_condition->data);
  rmw_introspect::WaitHub::instance().trigger(&impl->gc);
  return RMW_RET_OK;
}

}  // extern "C"
