// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Guard conditions: a trigger is remembered until a wait consumes it.

#include <memory>
#include <new>

#include "rmw/rmw.h"

#include "detail/common.hpp"
#include "detail/handles.hpp"
#include "detail/runtime.hpp"
#include "detail/thread_census.hpp"
#include "detail/wait_hub.hpp"

using rmw_introspect::GuardConditionImpl;
using rmw_introspect::kIdentifier;

extern "C" {

rmw_guard_condition_t * rmw_create_guard_condition(rmw_context_t * context)
{
  RMWI_CHECK_HANDLE_OR(context, impl, nullptr, nullptr);
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
  RMWI_CHECK_HANDLE(guard_condition);
  delete static_cast<GuardConditionImpl *>(guard_condition->data);
  return RMW_RET_OK;
}

rmw_ret_t rmw_trigger_guard_condition(const rmw_guard_condition_t * guard_condition)
{
  RMWI_CHECK_HANDLE(guard_condition);
  auto * impl = static_cast<GuardConditionImpl *>(guard_condition->data);
  rmw_introspect::Runtime::instance().wait_hub().trigger(&impl->gc, rmw_introspect::current_tid());
  return RMW_RET_OK;
}

}  // extern "C"
