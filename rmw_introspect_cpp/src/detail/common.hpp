// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__COMMON_HPP_
#define DETAIL__COMMON_HPP_

#include "rcutils/macros.h"
#include "rmw/check_type_identifiers_match.h"
#include "rmw/error_handling.h"

#include "detail/identifier.hpp"

namespace rmw_introspect
{
/// Cleanup on an error path whose own result cannot change what we report.
template<typename T>
inline void ignore_result(T)
{
}
}  // namespace rmw_introspect

/// RMW_RET_INCORRECT_RMW_IMPLEMENTATION (or `on_failure`) when a handle is not ours.
#define RMWI_CHECK_IDENTIFIER(element_name, identifier, on_failure) \
  RMW_CHECK_TYPE_IDENTIFIERS_MATCH(                                 \
    element_name, identifier, rmw_introspect::kIdentifier, on_failure)

/// The checks every entry point makes first on each handle it is given, in rmw_zenoh_cpp's
/// order: the handle is not NULL (`on_null`), it was made by this implementation
/// (`on_foreign`), and it carries its implementation data in `data_member` (`on_null`).
#define RMWI_CHECK_HANDLE_OR(handle, data_member, on_null, on_foreign)                   \
  RMW_CHECK_ARGUMENT_FOR_NULL(handle, on_null);                                          \
  RMWI_CHECK_IDENTIFIER(handle, (handle)->implementation_identifier, return on_foreign); \
  RMW_CHECK_FOR_NULL_WITH_MSG(                                                           \
    (handle)->data_member, #handle " implementation is null", return on_null)

/// For the entry points that return rmw_ret_t.
#define RMWI_CHECK_HANDLE(handle) \
  RMWI_CHECK_HANDLE_OR(handle, data, RMW_RET_INVALID_ARGUMENT, RMW_RET_INCORRECT_RMW_IMPLEMENTATION)

/// For the entry points that return a pointer (NULL on every failure).
#define RMWI_CHECK_HANDLE_RETURN_NULL(handle) RMWI_CHECK_HANDLE_OR(handle, data, nullptr, nullptr)

/// The loan entry points, after the handle checks and before their other arguments (like
/// rmw_fastrtps_cpp, which test_rmw_implementation follows): RMW_RET_UNSUPPORTED when the
/// publisher or subscription cannot loan (ours can only with in-process delivery, for plain
/// types).
#define RMWI_CHECK_CAN_LOAN(handle)                \
  if (!(handle)->can_loan_messages) {              \
    RMW_SET_ERROR_MSG("Loaning is not supported"); \
    return RMW_RET_UNSUPPORTED;                    \
  }

#endif  // DETAIL__COMMON_HPP_
