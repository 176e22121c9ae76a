// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Wait sets and rmw_wait: blocks until a guard condition of the set is triggered, an entry has
// something to take (a request or stimulus of the middleware's own: detail/injector; anything
// else only with in-process delivery) or the timeout expires.

#include <cstdint>
#include <memory>
#include <new>

#include "rmw/rmw.h"

#include "detail/common.hpp"
#include "detail/delivery.hpp"
#include "detail/handles.hpp"
#include "detail/injector.hpp"
#include "detail/rmw_api.hpp"
#include "detail/runtime.hpp"
#include "detail/thread_census.hpp"
#include "detail/wait_hub.hpp"

using rmw_introspect::GuardConditionImpl;
using rmw_introspect::kIdentifier;
using rmw_introspect::WaitSetImpl;

namespace
{

// rcl stores each guard condition's `data` (our GuardConditionImpl) in the array. A trigger of
// thread `except_tid` (non-zero) does not count.
bool any_triggered(const rmw_guard_conditions_t * gcs, pid_t except_tid = 0)
{
  if (gcs == nullptr) {
    return false;
  }
  for (size_t i = 0; i < gcs->guard_condition_count; ++i) {
    auto * impl = static_cast<GuardConditionImpl *>(gcs->guard_conditions[i]);
    if (impl != nullptr && impl->gc.triggered.load() &&
        (except_tid == 0 || impl->gc.triggered_by.load() != except_tid))
    {
      return true;
    }
  }
  return false;
}

// rcl stores each service's and subscription's `data` (our ServiceImpl, SubscriptionImpl) in
// the arrays. Marks them served: an executor takes from them (the Injector asks only those).
void mark_served(const rmw_services_t * services, const rmw_subscriptions_t * subscriptions)
{
  if (services != nullptr) {
    for (size_t i = 0; i < services->service_count; ++i) {
      auto * impl = static_cast<rmw_introspect::ServiceImpl *>(services->services[i]);
      if (impl != nullptr) {
        impl->in_wait_set.store(true);
      }
    }
  }
  if (subscriptions != nullptr) {
    for (size_t i = 0; i < subscriptions->subscriber_count; ++i) {
      auto * impl = static_cast<rmw_introspect::SubscriptionImpl *>(subscriptions->subscribers[i]);
      if (impl != nullptr && !impl->in_wait_set.load(std::memory_order_relaxed)) {
        impl->in_wait_set.store(true);
      }
    }
  }
}

// The timeout in ns: negative = forever (NULL, RMW_DURATION_INFINITE and other huge values
// saturate), 0 = poll.
int64_t timeout_ns(const rmw_time_t * timeout)
{
  constexpr uint64_t kMaxSec = 100ull * 365ull * 24ull * 3600ull;
  if (timeout == nullptr || timeout->sec >= kMaxSec) {
    return -1;
  }
  return static_cast<int64_t>(timeout->sec) * 1000000000 + static_cast<int64_t>(timeout->nsec);
}

}  // namespace

extern "C" {

rmw_wait_set_t * rmw_create_wait_set(rmw_context_t * context, size_t max_conditions)
{
  (void)max_conditions;  // no per-set storage is needed
  RMWI_CHECK_HANDLE_OR(context, impl, nullptr, nullptr);
  std::unique_ptr<WaitSetImpl> impl(new (std::nothrow) WaitSetImpl());
  if (!impl) {
    RMW_SET_ERROR_MSG("failed to allocate wait set");
    return nullptr;
  }
  impl->handle.implementation_identifier = kIdentifier;
  impl->handle.data = impl.get();
  impl->handle.guard_conditions = nullptr;
  impl->context = reinterpret_cast<const rmw_introspect::ContextImpl *>(context->impl);
  return &impl.release()->handle;
}

rmw_ret_t rmw_destroy_wait_set(rmw_wait_set_t * wait_set)
{
  // NULL is RMW_RET_ERROR on Jazzy, RMW_RET_INVALID_ARGUMENT from Kilted on (detail/rmw_api.hpp).
  RMWI_CHECK_HANDLE_OR(
    wait_set, data, rmw_introspect::kNullArgumentRetOfOldChecks,
    RMW_RET_INCORRECT_RMW_IMPLEMENTATION);
  delete static_cast<WaitSetImpl *>(wait_set->data);
  return RMW_RET_OK;
}

rmw_ret_t rmw_wait(
  rmw_subscriptions_t * subscriptions, rmw_guard_conditions_t * guard_conditions,
  rmw_services_t * services, rmw_clients_t * clients, rmw_events_t * events,
  rmw_wait_set_t * wait_set, const rmw_time_t * wait_timeout)
{
  RMWI_CHECK_HANDLE(wait_set);

  const auto * ws = static_cast<const WaitSetImpl *>(wait_set->data);
  mark_served(services, subscriptions);
  // Once the context is shut down (rmw_shutdown wakes every waiter), waits return at once:
  // an executor woken by its SIGINT guard condition just before the shutdown must not go
  // back to sleep forever. `except_tid`: a guard condition last triggered by that thread does
  // not count (0: every trigger does).
  auto ready_except = [ws, guard_conditions, subscriptions, services, clients,
                       events](pid_t except_tid) {
    return any_triggered(guard_conditions, except_tid) ||
      rmw_introspect::any_ready(subscriptions, services, clients, events) ||
      (ws->context != nullptr && ws->context->is_shutdown.load());
  };
  auto ready = [&ready_except]() { return ready_except(0); };
  // Work for the thread from outside: anything ready but the guard conditions it triggered
  // itself (rclpy's spin_once(node) adds and removes the node, each a trigger, before every
  // wait). A poll that finds none is an idle poll (detected quiescence).
  const pid_t tid = rmw_introspect::current_tid();
  auto work = [&ready_except, tid]() { return ready_except(tid); };
  // Blocks, or in the warp jumps virtual time by the timeout and returns at once.
  rmw_introspect::Runtime::instance().wait(ready, work, timeout_ns(wait_timeout));

  // Consume the triggers of the ready guard conditions; NULL out everything not ready.
  bool any_ready = false;
  if (guard_conditions != nullptr) {
    for (size_t i = 0; i < guard_conditions->guard_condition_count; ++i) {
      auto * impl = static_cast<GuardConditionImpl *>(guard_conditions->guard_conditions[i]);
      if (impl != nullptr && impl->gc.triggered.exchange(false)) {
        any_ready = true;
      } else {
        guard_conditions->guard_conditions[i] = nullptr;
      }
    }
  }
  // Subscriptions, services, clients and events are ready only with in-process delivery, or
  // with a request or stimulus of the middleware's own (detail/injector).
  if (rmw_introspect::keep_ready(subscriptions, services, clients, events)) {
    any_ready = true;
  }
  return any_ready ? RMW_RET_OK : RMW_RET_TIMEOUT;
}

}  // extern "C"
