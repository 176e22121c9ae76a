// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__LOG_HPP_
#define DETAIL__LOG_HPP_

namespace rmw_introspect
{

/// Whether verbose_log writes (RMW_INTROSPECT_VERBOSE; off until set). The Runtime sets it from
/// its configuration as it is made, and every caller of verbose_log reaches the Runtime first.
void set_verbose_log(bool verbose);

/// A "[rmw_introspect] ..." line on stderr when verbose (set_verbose_log).
void verbose_log(const char * format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace rmw_introspect

#endif  // DETAIL__LOG_HPP_
