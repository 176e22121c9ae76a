// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Identity, init options, init / shutdown / context_fini.

#include <new>

#include "rcutils/allocator.h"
#include "rcutils/strdup.h"
#include "rmw/discovery_options.h"
#include "rmw/init.h"
#include "rmw/init_options.h"
#include "rmw/rmw.h"
#include "rmw/security_options.h"

#include "detail/common.hpp"
#include "detail/handles.hpp"
#include "detail/rmw_api.hpp"
#include "detail/runtime.hpp"

using rmw_introspect::kIdentifier;

extern "C" {

const char * rmw_get_implementation_identifier(void)
{
  return kIdentifier;
}

const char * rmw_get_serialization_format(void)
{
  return rmw_introspect::kSerializationFormat;
}

rmw_ret_t rmw_init_options_init(rmw_init_options_t * init_options, rcutils_allocator_t allocator)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(init_options, RMW_RET_INVALID_ARGUMENT);
  RCUTILS_CHECK_ALLOCATOR_WITH_MSG(
    &allocator, "allocator argument is invalid", return RMW_RET_INVALID_ARGUMENT);
  if (init_options->implementation_identifier != nullptr) {
    RMW_SET_ERROR_MSG("expected zero-initialized init_options");
    return RMW_RET_INVALID_ARGUMENT;
  }
  init_options->instance_id = 0;
  init_options->implementation_identifier = kIdentifier;
  init_options->allocator = allocator;
  init_options->impl = nullptr;
#if RMWI_RMW_HAS_LOCALHOST_ONLY
  init_options->localhost_only = RMW_LOCALHOST_ONLY_DEFAULT;
#endif
  init_options->domain_id = RMW_DEFAULT_DOMAIN_ID;
  init_options->enclave = nullptr;
  init_options->security_options = rmw_get_zero_initialized_security_options();
  init_options->discovery_options = rmw_get_zero_initialized_discovery_options();
  return rmw_discovery_options_init(&init_options->discovery_options, 0, &allocator);
}

rmw_ret_t rmw_init_options_copy(const rmw_init_options_t * src, rmw_init_options_t * dst)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(src, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(dst, RMW_RET_INVALID_ARGUMENT);
  if (src->implementation_identifier == nullptr) {
    RMW_SET_ERROR_MSG("expected initialized src");
    return RMW_RET_INVALID_ARGUMENT;
  }
  RMWI_CHECK_IDENTIFIER(
    source init options, src->implementation_identifier,
    return RMW_RET_INCORRECT_RMW_IMPLEMENTATION);
  if (dst->implementation_identifier != nullptr) {
    RMW_SET_ERROR_MSG("expected zero-initialized dst");
    return RMW_RET_INVALID_ARGUMENT;
  }
  rcutils_allocator_t allocator_copy = src->allocator;
  rcutils_allocator_t * allocator = &allocator_copy;
  RCUTILS_CHECK_ALLOCATOR_WITH_MSG(
    allocator, "allocator argument is invalid", return RMW_RET_INVALID_ARGUMENT);
  rmw_init_options_t tmp = *src;
  tmp.enclave = rcutils_strdup(src->enclave, *allocator);
  if (src->enclave != nullptr && tmp.enclave == nullptr) {
    RMW_SET_ERROR_MSG("failed to copy the enclave");
    return RMW_RET_BAD_ALLOC;
  }
  tmp.security_options = rmw_get_zero_initialized_security_options();
  rmw_ret_t ret =
    rmw_security_options_copy(&src->security_options, allocator, &tmp.security_options);
  if (ret != RMW_RET_OK) {
    allocator->deallocate(tmp.enclave, allocator->state);
    return ret;
  }
  tmp.discovery_options = rmw_get_zero_initialized_discovery_options();
  ret = rmw_discovery_options_copy(&src->discovery_options, allocator, &tmp.discovery_options);
  if (ret != RMW_RET_OK) {
    allocator->deallocate(tmp.enclave, allocator->state);
    rmw_introspect::ignore_result(rmw_security_options_fini(&tmp.security_options, allocator));
    return ret;
  }
  *dst = tmp;
  return RMW_RET_OK;
}

rmw_ret_t rmw_init_options_fini(rmw_init_options_t * init_options)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(init_options, RMW_RET_INVALID_ARGUMENT);
  if (init_options->implementation_identifier == nullptr) {
    RMW_SET_ERROR_MSG("expected initialized init_options");
    return RMW_RET_INVALID_ARGUMENT;
  }
  RMWI_CHECK_IDENTIFIER(
    init options, init_options->implementation_identifier,
    return RMW_RET_INCORRECT_RMW_IMPLEMENTATION);
  rcutils_allocator_t * allocator = &init_options->allocator;
  RCUTILS_CHECK_ALLOCATOR_WITH_MSG(
    allocator, "allocator argument is invalid", return RMW_RET_INVALID_ARGUMENT);
  allocator->deallocate(init_options->enclave, allocator->state);
  rmw_ret_t ret = rmw_security_options_fini(&init_options->security_options, allocator);
  if (ret != RMW_RET_OK) {
    return ret;
  }
  ret = rmw_discovery_options_fini(&init_options->discovery_options);
  *init_options = rmw_get_zero_initialized_init_options();
  return ret;
}

rmw_ret_t rmw_init(const rmw_init_options_t * options, rmw_context_t * context)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(options, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(context, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_FOR_NULL_WITH_MSG(
    options->implementation_identifier, "expected initialized init options",
    return RMW_RET_INVALID_ARGUMENT);
  RMWI_CHECK_IDENTIFIER(
    init options, options->implementation_identifier, return RMW_RET_INCORRECT_RMW_IMPLEMENTATION);
  RMW_CHECK_FOR_NULL_WITH_MSG(
    options->enclave, "expected non-null enclave", return RMW_RET_INVALID_ARGUMENT);
  if (context->implementation_identifier != nullptr) {
    RMW_SET_ERROR_MSG("expected a zero-initialized context");
    return RMW_RET_INVALID_ARGUMENT;
  }
  auto * impl = new (std::nothrow) rmw_introspect::ContextImpl();
  if (impl == nullptr) {
    RMW_SET_ERROR_MSG("failed to allocate context impl");
    return RMW_RET_BAD_ALLOC;
  }
  context->instance_id = options->instance_id;
  context->implementation_identifier = kIdentifier;
  context->actual_domain_id = options->domain_id == RMW_DEFAULT_DOMAIN_ID ? 0u : options->domain_id;
  context->options = rmw_get_zero_initialized_init_options();
  const rmw_ret_t ret = rmw_init_options_copy(options, &context->options);
  if (ret != RMW_RET_OK) {
    delete impl;
    *context = rmw_get_zero_initialized_context();
    return ret;
  }
  context->impl = reinterpret_cast<rmw_context_impl_t *>(impl);
  rmw_introspect::Runtime::instance().on_init();
  return RMW_RET_OK;
}

// rmw_shutdown and rmw_context_fini check the context's impl before its identifier (like
// rmw_zenoh_cpp): a finalized, zero-initialized context is an invalid argument, not a
// foreign one. Every other entry point checks its handles with RMWI_CHECK_HANDLE*.
rmw_ret_t rmw_shutdown(rmw_context_t * context)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(context, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_FOR_NULL_WITH_MSG(
    context->impl, "expected initialized context", return RMW_RET_INVALID_ARGUMENT);
  RMWI_CHECK_IDENTIFIER(
    context, context->implementation_identifier, return RMW_RET_INCORRECT_RMW_IMPLEMENTATION);
  auto * impl = reinterpret_cast<rmw_introspect::ContextImpl *>(context->impl);
  auto & runtime = rmw_introspect::Runtime::instance();
  // Under the wait hub's lock, so that no waiter misses it between its check and its sleep.
  runtime.wait_hub().update_and_wake([impl]() { impl->is_shutdown.store(true); });
  runtime.on_shutdown();
  return RMW_RET_OK;
}

rmw_ret_t rmw_context_fini(rmw_context_t * context)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(context, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_FOR_NULL_WITH_MSG(
    context->impl, "expected initialized context", return RMW_RET_INVALID_ARGUMENT);
  RMWI_CHECK_IDENTIFIER(
    context, context->implementation_identifier, return RMW_RET_INCORRECT_RMW_IMPLEMENTATION);
  auto * impl = reinterpret_cast<rmw_introspect::ContextImpl *>(context->impl);
  if (!impl->is_shutdown.load()) {
    RMW_SET_ERROR_MSG("context has not been shutdown");
    return RMW_RET_INVALID_ARGUMENT;
  }
  if (impl->node_count.load() > 0) {
    RMW_SET_ERROR_MSG("finalizing a context with active nodes");
    return RMW_RET_ERROR;
  }
  const rmw_ret_t ret = rmw_init_options_fini(&context->options);
  delete impl;
  *context = rmw_get_zero_initialized_context();
  return ret;
}

}  // extern "C"
