// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Wait sets and rmw_wait: blocks until a guard condition of the set is triggered or the
// timeout expires; subscriptions, services, clients and events are never ready.

#include <chrono>
#include <memory>
#include <mutex>
#include <new>

#include "rmw/rmw.h"

#include "detail/common.hpp"
#include "detail/handles.hpp"
#include "detail/session.hpp"
#include "detail/wait_hub.hpp"

using rmw_introspect::GuardConditionImpl;
using rmw_introspect::kIdentifier;
using rmw_introspect::WaitSetImpl;

namespace
{

// rcl stores each guard condition's `data` (our GuardConditionImpl) in the array.
bool any_triggered(const rmw_guard_conditions_t * gcs)
{
  if (gcs == nullptr) {
    return false;
  }
  for (size_t i = 0; i < gcs->guard_condition_count; ++i) {
    auto * impl = static_cast<GuardConditionImpl *>(gcs->guard_conditions[i]);
    if (impl != nullptr && impl->gc.triggered.load()) {
      return true;
    }
  }
  return false;
}

template<typename T>
void clear_all(T ** entries, size_t count)
{
  if (entries == nullptr) {
    return;
  }
  for (size_t i = 0; i < count; ++i) {
    entries[i] = nullptr;
  }
}

// RAII registration of a thread blocked in rmw_wait (for settle detection).
class WaitRegistration
{
public:
  WaitRegistration()
  : token_(rmw_introspect::Session::instance().enter_wait()) {}
  ~WaitRegistration() {rmw_introspect::Session::instance().leave_wait(token_);}
  WaitRegistration(const WaitRegistration &) = delete;
  WaitRegistration & operator=(const WaitRegistration &) = delete;

private:
  uint64_t token_;
};

}  // namespace

extern "C"
{

rmw_wait_set_t * rmw_create_wait_set(rmw_context_t * context, size_t max_conditions)
{
  (void)max_conditions;  // no per-set storage is needed
  RMW_CHECK_ARGUMENT_FOR_NULL(context, nullptr);
  RMWI_CHECK_IDENTIFIER(init context, context->implementation_identifier, return nullptr);
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
  RMW_CHECK_ARGUMENT_FOR_NULL(wait_set, RMW_RET_INVALID_ARGUMENT);
  RMWI_CHECK_IDENTIFIER(
    wait set, wait_set->implementation_identifier, return RMW_RET_INCORRECT_RMW_IMPLEMENTATION);
  delete static_cast<WaitSetImpl *>(wait_set->data);
  return RMW_RET_OK;
}

rmw_ret_t rmw_wait(
  rmw_subscriptions_t * subscriptions, rmw_guard_conditions_t * guard_conditions,
  rmw_services_t * services, rmw_clients_t * clients, rmw_events_t * events,
  rmw_wait_set_t * wait_set, const rmw_time_t * wait_timeout)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(wait_set, RMW_RET_INVALID_ARGUMENT);
  RMWI_CHECK_IDENTIFIER(
    wait set, wait_set->implementation_identifier, return RMW_RET_INCORRECT_RMW_IMPLEMENTATION);

  auto & hub = rmw_introspect::WaitHub::instance();
  const auto * ws = static_cast<const WaitSetImpl *>(wait_set->data);
  // Once the context is shut down (rmw_shutdown wakes every waiter), waits return at once:
  // an executor woken by its SIGINT guard condition just before the shutdown must not go
  // back to sleep forever.
  auto shut_down = [ws]() {
      return ws != nullptr && ws->context != nullptr && ws->context->is_shutdown.load();
    };
  {
    std::unique_lock<std::mutex> lock(hub.mutex);
    if (!any_triggered(guard_conditions) && !shut_down()) {
      const bool poll = wait_timeout != nullptr && wait_timeout->sec == 0 &&
        wait_timeout->nsec == 0;
      if (!poll) {
        WaitRegistration registration;
        auto ready = [&]() {return any_triggered(guard_conditions) || shut_down();};
        if (wait_timeout == nullptr) {
          hub.cv.wait(lock, ready);
        } else {
          // Saturate: RMW_DURATION_INFINITE and other huge timeouts wait "forever".
          const uint64_t max_sec = 100ull * 365ull * 24ull * 3600ull;
          if (wait_timeout->sec >= max_sec) {
            hub.cv.wait(lock, ready);
          } else {
            const auto timeout = std::chrono::seconds(wait_timeout->sec) +
              std::chrono::nanoseconds(wait_timeout->nsec);
            hub.cv.wait_until(lock, std::chrono::steady_clock::now() + timeout, ready);
          }
        }
      }
    }
  }

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
  if (subscriptions != nullptr) {
    clear_all(subscriptions->subscribers, subscriptions->subscriber_count);
  }
  if (services != nullptr) {
    clear_all(services->services, services->service_count);
  }
  if (clients != nullptr) {
    clear_all(clients->clients, clients->client_count);
  }
  if (events != nullptr) {
    clear_all(events->events, events->event_count);
  }
  return any_ready ? RMW_RET_OK : RMW_RET_TIMEOUT;
}

}  // extern "C"
