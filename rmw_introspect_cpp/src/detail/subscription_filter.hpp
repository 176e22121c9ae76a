// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__SUBSCRIPTION_FILTER_HPP_
#define DETAIL__SUBSCRIPTION_FILTER_HPP_

#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include "rmw/subscription_content_filter_options.h"
#include "rmw/types.h"

#include "detail/content_filter.hpp"
#include "detail/typesupport.hpp"

namespace rmw_introspect
{

/// A subscription's content filter: the options rcl set (returned as they were given) and,
/// with in-process delivery, the expression compiled against the subscription's type. Owns
/// the options (finalized on reset and destruction); every member takes the filter's own
/// mutex, a leaf lock.
class SubscriptionFilter
{
public:
  SubscriptionFilter() = default;
  ~SubscriptionFilter();
  SubscriptionFilter(const SubscriptionFilter &) = delete;
  SubscriptionFilter & operator=(const SubscriptionFilter &) = delete;

  /// rmw_subscription_set_content_filter: replace the filter; an empty expression removes it.
  /// `compile_against` non-NULL compiles the expression (an expression that does not compile
  /// lets everything through, logged with `name`). `*enabled` says whether a filter is set.
  rmw_ret_t set(
    const rmw_subscription_content_filter_options_t & options,
    const MessageLayout * compile_against, const std::string & name, bool * enabled);

  /// rmw_subscription_get_content_filter: fill `out` (which the caller may not have
  /// initialised) from zero; RMW_RET_ERROR when no filter is set.
  rmw_ret_t get(rcutils_allocator_t * allocator, rmw_subscription_content_filter_options_t * out);

  /// Whether a sample passes: true without a (compiled) filter; otherwise `match` is called
  /// with the compiled filter, under the lock.
  bool passes(const std::function<bool(const ContentFilter &)> & match);

private:
  void reset_locked();

  std::mutex mutex_;  // a leaf lock
  bool has_options_ = false;
  rmw_subscription_content_filter_options_t options_{};
  std::unique_ptr<ContentFilter> compiled_;  // NULL: none, or did not compile
};

}  // namespace rmw_introspect

#endif  // DETAIL__SUBSCRIPTION_FILTER_HPP_
