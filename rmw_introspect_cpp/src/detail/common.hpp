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
inline void ignore_result(T) {}
}  // namespace rmw_introspect

/// RMW_RET_INCORRECT_RMW_IMPLEMENTATION (or `on_failure`) when a handle is not ours.
#define RMWI_CHECK_IDENTIFIER(element_name, identifier, on_failure) \
  RMW_CHECK_TYPE_IDENTIFIERS_MATCH( \
    element_name, identifier, rmw_introspect::kIdentifier, on_failure)

#endif  // DETAIL__COMMON_HPP_
