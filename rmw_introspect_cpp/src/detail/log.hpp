// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__LOG_HPP_
#define DETAIL__LOG_HPP_

namespace rmw_introspect
{

/// A "[rmw_introspect] ..." line on stderr when RMW_INTROSPECT_VERBOSE=1.
void verbose_log(const char * format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace rmw_introspect

#endif  // DETAIL__LOG_HPP_
