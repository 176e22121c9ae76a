// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/subscription_filter.hpp"

#include <string>
#include <vector>

#include "rcutils/allocator.h"
#include "rmw/error_handling.h"

#include "detail/common.hpp"
#include "detail/log.hpp"

namespace rmw_introspect
{

SubscriptionFilter::~SubscriptionFilter()
{
  std::lock_guard<std::mutex> lock(mutex_);
  reset_locked();
}

void SubscriptionFilter::reset_locked()
{
  if (has_options_) {
    rcutils_allocator_t allocator = rcutils_get_default_allocator();
    ignore_result(rmw_subscription_content_filter_options_fini(&options_, &allocator));
    has_options_ = false;
  }
  compiled_.reset();
}

rmw_ret_t SubscriptionFilter::set(
  const rmw_subscription_content_filter_options_t & options, const MessageLayout * compile_against,
  const std::string & name, bool * enabled)
{
  std::lock_guard<std::mutex> lock(mutex_);
  reset_locked();
  *enabled = false;
  if (options.filter_expression == nullptr || options.filter_expression[0] == '\0') {
    return RMW_RET_OK;  // an empty expression resets the filter
  }
  rcutils_allocator_t allocator = rcutils_get_default_allocator();
  options_ = rmw_get_zero_initialized_content_filter_options();
  const rmw_ret_t ret =
    rmw_subscription_content_filter_options_copy(&options, &allocator, &options_);
  if (ret != RMW_RET_OK) {
    return ret;
  }
  has_options_ = true;
  *enabled = true;
  if (compile_against != nullptr) {
    // An expression that does not compile (a syntax this filter does not know) lets everything
    // through rather than failing a subscription the node expects to have.
    std::vector<std::string> parameters;
    for (size_t i = 0; i < options_.expression_parameters.size; ++i) {
      parameters.emplace_back(options_.expression_parameters.data[i]);
    }
    std::string error;
    compiled_ =
      ContentFilter::compile(*compile_against, options_.filter_expression, parameters, &error);
    if (!compiled_) {
      verbose_log("content filter of %s not applied: %s", name.c_str(), error.c_str());
    }
  }
  return RMW_RET_OK;
}

rmw_ret_t SubscriptionFilter::get(
  rcutils_allocator_t * allocator, rmw_subscription_content_filter_options_t * out)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!has_options_) {
    RMW_SET_ERROR_MSG("this subscription has no content filter");
    return RMW_RET_ERROR;
  }
  // `out` is an output the caller has not necessarily initialised (the suite passes an
  // uninitialised struct): never _copy()/_set() into it, they finalize it first and would free
  // garbage. Fill it from zero, as rmw_fastrtps_cpp does with _init().
  *out = rmw_get_zero_initialized_content_filter_options();
  return rmw_subscription_content_filter_options_init(
    options_.filter_expression, options_.expression_parameters.size,
    const_cast<const char **>(options_.expression_parameters.data), allocator, out);
}

bool SubscriptionFilter::passes(const std::function<bool(const ContentFilter &)> & match)
{
  std::lock_guard<std::mutex> lock(mutex_);
  return !compiled_ || match(*compiled_);
}

}  // namespace rmw_introspect
