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

/// Which DDS entity carries a QoS: publishers, a client's requests and a service's responses
/// are written (DataWriter); subscriptions, a client's responses and a service's requests are
/// read (DataReader).
enum class QosSide { kWriter, kReader };

/// The actual QoS rmw_fastrtps_cpp reports for an endpoint created with `requested` (its
/// BEST_AVAILABLE policies already resolved, see below): what is left to the middleware takes
/// Fast DDS's defaults - SYSTEM_DEFAULT history is KEEP_LAST, depth 0 is 1, a writer is
/// RELIABLE + TRANSIENT_LOCAL and a reader BEST_EFFORT + VOLATILE, liveliness is AUTOMATIC -
/// and unspecified (zero) durations read back as infinite. avoid_ros_namespace_conventions is
/// kept. Measured on the Jazzy wheels (rmw_fastrtps_cpp 8.4, Fast DDS 2.14).
rmw_qos_profile_t resolve_system_defaults(const rmw_qos_profile_t & requested, QosSide side);

/// BEST_AVAILABLE policies resolved at creation from the endpoints already on the other side
/// of the topic (their actual QoS), with the rules of rmw_dds_common
/// (qos_profile_get_best_available_for_{publisher,subscription}) that the DDS middlewares use.
void resolve_best_available_for_publisher(
  rmw_qos_profile_t * qos, const rmw_qos_profile_t * subscriptions, size_t count);
void resolve_best_available_for_subscription(
  rmw_qos_profile_t * qos, const rmw_qos_profile_t * publishers, size_t count);
/// Services and clients: BEST_AVAILABLE is RELIABLE, VOLATILE, AUTOMATIC, default durations
/// (rmw_dds_common::qos_profile_update_best_available_for_services).
void resolve_best_available_for_service(rmw_qos_profile_t * qos);
/// The actual QoS of a service's or client's request or response entity (`side`).
rmw_qos_profile_t service_actual_qos(const rmw_qos_profile_t & requested, QosSide side);

/// A publisher and a subscription with these (actual) QoS match: the compatibility check
/// finds no error. Allocates nothing.
bool qos_match(const rmw_qos_profile_t & publisher, const rmw_qos_profile_t & subscription);

}  // namespace rmw_introspect

#endif  // DETAIL__QOS_HPP_
