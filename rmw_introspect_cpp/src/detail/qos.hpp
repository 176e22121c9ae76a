// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__QOS_HPP_
#define DETAIL__QOS_HPP_

#include <cstddef>
#include <cstdint>

#include "rmw/qos_profiles.h"
#include "rmw/types.h"

namespace rmw_introspect
{

const char * history_to_string(rmw_qos_history_policy_t value);
const char * reliability_to_string(rmw_qos_reliability_policy_t value);
const char * durability_to_string(rmw_qos_durability_policy_t value);
const char * liveliness_to_string(rmw_qos_liveliness_policy_t value);

/// Duration in integer nanoseconds: 0 = unspecified, -1 = infinite (RMW_DURATION_INFINITE).
int64_t duration_to_ns(const rmw_time_t & time);

/// True when every policy holds a value a middleware can act on (no *_UNKNOWN).
bool qos_is_valid(const rmw_qos_profile_t & qos);

/// The QoS compatibility rules of the DDS middlewares (rmw_dds_common).
rmw_ret_t check_qos_compatible(
  const rmw_qos_profile_t & publisher, const rmw_qos_profile_t & subscription,
  rmw_qos_compatibility_type_t * compatibility, char * reason, size_t reason_size);

}  // namespace rmw_introspect

#endif  // DETAIL__QOS_HPP_
