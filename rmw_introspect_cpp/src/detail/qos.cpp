// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/qos.hpp"

#include <cstdarg>
#include <cstdio>
#include <cstring>

#include "rmw/error_handling.h"
#include "rmw/qos_string_conversions.h"

namespace rmw_introspect
{

const char * history_to_string(rmw_qos_history_policy_t value)
{
  switch (value) {
    case RMW_QOS_POLICY_HISTORY_SYSTEM_DEFAULT: return "SYSTEM_DEFAULT";
    case RMW_QOS_POLICY_HISTORY_KEEP_LAST: return "KEEP_LAST";
    case RMW_QOS_POLICY_HISTORY_KEEP_ALL: return "KEEP_ALL";
    case RMW_QOS_POLICY_HISTORY_UNKNOWN: return "UNKNOWN";
  }
  return "UNKNOWN";
}

const char * reliability_to_string(rmw_qos_reliability_policy_t value)
{
  switch (value) {
    case RMW_QOS_POLICY_RELIABILITY_SYSTEM_DEFAULT: return "SYSTEM_DEFAULT";
    case RMW_QOS_POLICY_RELIABILITY_RELIABLE: return "RELIABLE";
    case RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT: return "BEST_EFFORT";
    case RMW_QOS_POLICY_RELIABILITY_BEST_AVAILABLE: return "BEST_AVAILABLE";
    case RMW_QOS_POLICY_RELIABILITY_UNKNOWN: return "UNKNOWN";
  }
  return "UNKNOWN";
}

const char * durability_to_string(rmw_qos_durability_policy_t value)
{
  switch (value) {
    case RMW_QOS_POLICY_DURABILITY_SYSTEM_DEFAULT: return "SYSTEM_DEFAULT";
    case RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL: return "TRANSIENT_LOCAL";
    case RMW_QOS_POLICY_DURABILITY_VOLATILE: return "VOLATILE";
    case RMW_QOS_POLICY_DURABILITY_BEST_AVAILABLE: return "BEST_AVAILABLE";
    case RMW_QOS_POLICY_DURABILITY_UNKNOWN: return "UNKNOWN";
  }
  return "UNKNOWN";
}

const char * liveliness_to_string(rmw_qos_liveliness_policy_t value)
{
  switch (static_cast<int>(value)) {
    case RMW_QOS_POLICY_LIVELINESS_SYSTEM_DEFAULT: return "SYSTEM_DEFAULT";
    case RMW_QOS_POLICY_LIVELINESS_AUTOMATIC: return "AUTOMATIC";
    case 2: return "MANUAL_BY_NODE";  // deprecated RMW_QOS_POLICY_LIVELINESS_MANUAL_BY_NODE
    case RMW_QOS_POLICY_LIVELINESS_MANUAL_BY_TOPIC: return "MANUAL_BY_TOPIC";
    case RMW_QOS_POLICY_LIVELINESS_BEST_AVAILABLE: return "BEST_AVAILABLE";
    case RMW_QOS_POLICY_LIVELINESS_UNKNOWN: return "UNKNOWN";
  }
  return "UNKNOWN";
}

int64_t duration_to_ns(const rmw_time_t & time)
{
  if (time.sec == 0 && time.nsec == 0) {
    return 0;
  }
  const rmw_time_t infinite = RMW_DURATION_INFINITE;
  if (time.sec >= infinite.sec) {
    return -1;  // RMW_DURATION_INFINITE (and anything beyond it)
  }
  const uint64_t ns = time.sec * 1000000000ull + time.nsec;
  if (ns >= static_cast<uint64_t>(INT64_MAX)) {
    return -1;
  }
  return static_cast<int64_t>(ns);
}

bool qos_is_valid(const rmw_qos_profile_t & qos)
{
  return qos.history != RMW_QOS_POLICY_HISTORY_UNKNOWN &&
    qos.reliability != RMW_QOS_POLICY_RELIABILITY_UNKNOWN &&
    qos.durability != RMW_QOS_POLICY_DURABILITY_UNKNOWN &&
    qos.liveliness != RMW_QOS_POLICY_LIVELINESS_UNKNOWN;
}

namespace
{

bool time_unset(const rmw_time_t & t)
{
  return t.sec == 0 && t.nsec == 0;
}

bool time_less(const rmw_time_t & a, const rmw_time_t & b)
{
  return a.sec < b.sec || (a.sec == b.sec && a.nsec < b.nsec);
}

void append_reason(char * reason, size_t reason_size, const char * format, ...)
  __attribute__((format(printf, 3, 4)));

void append_reason(char * reason, size_t reason_size, const char * format, ...)
{
  if (reason == nullptr || reason_size == 0) {
    return;
  }
  const size_t used = strnlen(reason, reason_size);
  if (used + 1 >= reason_size) {
    return;
  }
  va_list args;
  va_start(args, format);
  vsnprintf(reason + used, reason_size - used, format, args);
  va_end(args);
}

const char * lower_or_unknown(const char * s)
{
  return s != nullptr ? s : "unknown";
}

}  // namespace

rmw_ret_t check_qos_compatible(
  const rmw_qos_profile_t & pub, const rmw_qos_profile_t & sub,
  rmw_qos_compatibility_type_t * compatibility, char * reason, size_t reason_size)
{
  if (compatibility == nullptr) {
    RMW_SET_ERROR_MSG("compatibility parameter is null");
    return RMW_RET_INVALID_ARGUMENT;
  }
  if (reason == nullptr && reason_size != 0u) {
    RMW_SET_ERROR_MSG("reason parameter is null, but reason_size parameter is not zero");
    return RMW_RET_INVALID_ARGUMENT;
  }
  *compatibility = RMW_QOS_COMPATIBILITY_OK;
  if (reason != nullptr && reason_size != 0u) {
    reason[0] = '\0';
  }
  auto error = [&](const char * text) {
    *compatibility = RMW_QOS_COMPATIBILITY_ERROR;
    append_reason(reason, reason_size, "ERROR: %s;", text);
  };
  if (pub.reliability == RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT &&
      sub.reliability == RMW_QOS_POLICY_RELIABILITY_RELIABLE)
  {
    error("Best effort publisher and reliable subscription");
  }
  if (pub.durability == RMW_QOS_POLICY_DURABILITY_VOLATILE &&
      sub.durability == RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL)
  {
    error("Volatile publisher and transient local subscription");
  }
  if (time_unset(pub.deadline) && !time_unset(sub.deadline)) {
    error("Subscription has a deadline, but publisher does not");
  }
  if (!time_unset(pub.deadline) && !time_unset(sub.deadline) &&
      time_less(sub.deadline, pub.deadline))
  {
    error("Subscription deadline is less than publisher deadline");
  }
  if (pub.liveliness == RMW_QOS_POLICY_LIVELINESS_AUTOMATIC &&
      sub.liveliness == RMW_QOS_POLICY_LIVELINESS_MANUAL_BY_TOPIC)
  {
    error("Publisher's liveliness is automatic and subscription's is manual by topic");
  }
  if (time_unset(pub.liveliness_lease_duration) && !time_unset(sub.liveliness_lease_duration)) {
    error("Subscription has a liveliness lease duration, but publisher does not");
  }
  if (!time_unset(pub.liveliness_lease_duration) && !time_unset(sub.liveliness_lease_duration) &&
      time_less(sub.liveliness_lease_duration, pub.liveliness_lease_duration))
  {
    error("Subscription liveliness lease duration is less than publisher");
  }
  if (*compatibility != RMW_QOS_COMPATIBILITY_OK) {
    return RMW_RET_OK;
  }
  auto warning = [&](const char * format, const char * a, const char * b) {
    *compatibility = RMW_QOS_COMPATIBILITY_WARNING;
    char text[256];
    snprintf(text, sizeof(text), format, a, b);
    append_reason(reason, reason_size, "WARNING: %s;", text);
  };
  const bool pub_rel_unknown = pub.reliability == RMW_QOS_POLICY_RELIABILITY_SYSTEM_DEFAULT ||
    pub.reliability == RMW_QOS_POLICY_RELIABILITY_UNKNOWN;
  const bool sub_rel_unknown = sub.reliability == RMW_QOS_POLICY_RELIABILITY_SYSTEM_DEFAULT ||
    sub.reliability == RMW_QOS_POLICY_RELIABILITY_UNKNOWN;
  const bool pub_dur_unknown = pub.durability == RMW_QOS_POLICY_DURABILITY_SYSTEM_DEFAULT ||
    pub.durability == RMW_QOS_POLICY_DURABILITY_UNKNOWN;
  const bool sub_dur_unknown = sub.durability == RMW_QOS_POLICY_DURABILITY_SYSTEM_DEFAULT ||
    sub.durability == RMW_QOS_POLICY_DURABILITY_UNKNOWN;
  const bool pub_live_unknown = pub.liveliness == RMW_QOS_POLICY_LIVELINESS_SYSTEM_DEFAULT ||
    pub.liveliness == RMW_QOS_POLICY_LIVELINESS_UNKNOWN;
  const bool sub_live_unknown = sub.liveliness == RMW_QOS_POLICY_LIVELINESS_SYSTEM_DEFAULT ||
    sub.liveliness == RMW_QOS_POLICY_LIVELINESS_UNKNOWN;
  const char * pub_rel = lower_or_unknown(rmw_qos_reliability_policy_to_str(pub.reliability));
  const char * sub_rel = lower_or_unknown(rmw_qos_reliability_policy_to_str(sub.reliability));
  const char * pub_dur = lower_or_unknown(rmw_qos_durability_policy_to_str(pub.durability));
  const char * sub_dur = lower_or_unknown(rmw_qos_durability_policy_to_str(sub.durability));
  const char * pub_live = lower_or_unknown(rmw_qos_liveliness_policy_to_str(pub.liveliness));
  const char * sub_live = lower_or_unknown(rmw_qos_liveliness_policy_to_str(sub.liveliness));

  if (pub_rel_unknown && sub_rel_unknown) {
    warning("Publisher reliability is %s and subscription reliability is %s", pub_rel, sub_rel);
  } else if (pub_rel_unknown && sub.reliability == RMW_QOS_POLICY_RELIABILITY_RELIABLE) {
    warning("Reliable subscription, but publisher is %s%s", pub_rel, "");
  } else if (pub.reliability == RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT && sub_rel_unknown) {
    warning("Best effort publisher, but subscription is %s%s", sub_rel, "");
  }
  if (pub_dur_unknown && sub_dur_unknown) {
    warning("Publisher durability is %s and subscription durability is %s", pub_dur, sub_dur);
  } else if (pub_dur_unknown && sub.durability == RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL) {
    warning("Transient local subscription, but publisher is %s%s", pub_dur, "");
  } else if (pub.durability == RMW_QOS_POLICY_DURABILITY_VOLATILE && sub_dur_unknown) {
    warning("Volatile publisher, but subscription is %s%s", sub_dur, "");
  }
  if (pub_live_unknown && sub_live_unknown) {
    warning("Publisher liveliness is %s and subscription liveliness is %s", pub_live, sub_live);
  } else if (pub_live_unknown && sub.liveliness == RMW_QOS_POLICY_LIVELINESS_MANUAL_BY_TOPIC) {
    warning("Subscription's liveliness is manual by topic, but publisher's is %s%s", pub_live, "");
  } else if (pub.liveliness == RMW_QOS_POLICY_LIVELINESS_AUTOMATIC && sub_live_unknown) {
    warning("Publisher's liveliness is automatic, but subscription's is %s%s", sub_live, "");
  }
  return RMW_RET_OK;
}

namespace
{

bool time_equal(const rmw_time_t & a, const rmw_time_t & b)
{
  return a.sec == b.sec && a.nsec == b.nsec;
}

const rmw_time_t kInfinite = RMW_DURATION_INFINITE;
const rmw_time_t kDeadlineDefault = RMW_QOS_DEADLINE_DEFAULT;
const rmw_time_t kDeadlineBestAvailable = RMW_QOS_DEADLINE_BEST_AVAILABLE;
const rmw_time_t kLeaseDefault = RMW_QOS_LIVELINESS_LEASE_DURATION_DEFAULT;
const rmw_time_t kLeaseBestAvailable = RMW_QOS_LIVELINESS_LEASE_DURATION_BEST_AVAILABLE;

rmw_time_t unset_is_infinite(const rmw_time_t & t)
{
  return time_unset(t) ? kInfinite : t;
}

}  // namespace

rmw_qos_profile_t resolve_system_defaults(const rmw_qos_profile_t & requested, QosSide side)
{
  rmw_qos_profile_t actual = requested;
  if (actual.history == RMW_QOS_POLICY_HISTORY_SYSTEM_DEFAULT) {
    actual.history = RMW_QOS_POLICY_HISTORY_KEEP_LAST;
  }
  if (actual.depth == RMW_QOS_POLICY_DEPTH_SYSTEM_DEFAULT) {
    actual.depth = 1u;
  }
  if (actual.reliability == RMW_QOS_POLICY_RELIABILITY_SYSTEM_DEFAULT) {
    actual.reliability = side == QosSide::kWriter ? RMW_QOS_POLICY_RELIABILITY_RELIABLE :
                                                    RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT;
  }
  if (actual.durability == RMW_QOS_POLICY_DURABILITY_SYSTEM_DEFAULT) {
    actual.durability = side == QosSide::kWriter ? RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL :
                                                   RMW_QOS_POLICY_DURABILITY_VOLATILE;
  }
  if (actual.liveliness == RMW_QOS_POLICY_LIVELINESS_SYSTEM_DEFAULT) {
    actual.liveliness = RMW_QOS_POLICY_LIVELINESS_AUTOMATIC;
  }
  actual.deadline = unset_is_infinite(actual.deadline);
  actual.lifespan = unset_is_infinite(actual.lifespan);
  actual.liveliness_lease_duration = unset_is_infinite(actual.liveliness_lease_duration);
  return actual;
}

void resolve_best_available_for_publisher(
  rmw_qos_profile_t * qos, const rmw_qos_profile_t * subscriptions, size_t count)
{
  bool any_manual_by_topic = false;
  bool default_deadline = true;
  rmw_time_t smallest_deadline = kInfinite;
  bool default_lease = true;
  rmw_time_t smallest_lease = kInfinite;
  for (size_t i = 0; i < count; ++i) {
    const rmw_qos_profile_t & sub = subscriptions[i];
    any_manual_by_topic |= sub.liveliness == RMW_QOS_POLICY_LIVELINESS_MANUAL_BY_TOPIC;
    if (!time_equal(sub.deadline, kDeadlineDefault)) {
      default_deadline = false;
      if (time_less(sub.deadline, smallest_deadline)) {
        smallest_deadline = sub.deadline;
      }
    }
    if (!time_equal(sub.liveliness_lease_duration, kLeaseDefault)) {
      default_lease = false;
      if (time_less(sub.liveliness_lease_duration, smallest_lease)) {
        smallest_lease = sub.liveliness_lease_duration;
      }
    }
  }
  if (qos->reliability == RMW_QOS_POLICY_RELIABILITY_BEST_AVAILABLE) {
    qos->reliability = RMW_QOS_POLICY_RELIABILITY_RELIABLE;
  }
  if (qos->durability == RMW_QOS_POLICY_DURABILITY_BEST_AVAILABLE) {
    qos->durability = RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL;
  }
  if (qos->liveliness == RMW_QOS_POLICY_LIVELINESS_BEST_AVAILABLE) {
    qos->liveliness = any_manual_by_topic ? RMW_QOS_POLICY_LIVELINESS_MANUAL_BY_TOPIC :
                                            RMW_QOS_POLICY_LIVELINESS_AUTOMATIC;
  }
  if (time_equal(qos->deadline, kDeadlineBestAvailable)) {
    qos->deadline = default_deadline ? kDeadlineDefault : smallest_deadline;
  }
  if (time_equal(qos->liveliness_lease_duration, kLeaseBestAvailable)) {
    qos->liveliness_lease_duration = default_lease ? kLeaseDefault : smallest_lease;
  }
}

void resolve_best_available_for_subscription(
  rmw_qos_profile_t * qos, const rmw_qos_profile_t * publishers, size_t count)
{
  size_t reliable = 0;
  size_t transient_local = 0;
  size_t manual_by_topic = 0;
  bool default_deadline = true;
  rmw_time_t largest_deadline = {0u, 0u};
  bool default_lease = true;
  rmw_time_t largest_lease = {0u, 0u};
  for (size_t i = 0; i < count; ++i) {
    const rmw_qos_profile_t & pub = publishers[i];
    reliable += pub.reliability == RMW_QOS_POLICY_RELIABILITY_RELIABLE;
    transient_local += pub.durability == RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL;
    manual_by_topic += pub.liveliness == RMW_QOS_POLICY_LIVELINESS_MANUAL_BY_TOPIC;
    if (!time_equal(pub.deadline, kDeadlineDefault)) {
      default_deadline = false;
      if (time_less(largest_deadline, pub.deadline)) {
        largest_deadline = pub.deadline;
      }
    }
    if (!time_equal(pub.liveliness_lease_duration, kLeaseDefault)) {
      default_lease = false;
      if (time_less(largest_lease, pub.liveliness_lease_duration)) {
        largest_lease = pub.liveliness_lease_duration;
      }
    }
  }
  if (qos->reliability == RMW_QOS_POLICY_RELIABILITY_BEST_AVAILABLE) {
    qos->reliability = reliable == count ? RMW_QOS_POLICY_RELIABILITY_RELIABLE :
                                           RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT;
  }
  if (qos->durability == RMW_QOS_POLICY_DURABILITY_BEST_AVAILABLE) {
    qos->durability = transient_local == count ? RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL :
                                                 RMW_QOS_POLICY_DURABILITY_VOLATILE;
  }
  if (qos->liveliness == RMW_QOS_POLICY_LIVELINESS_BEST_AVAILABLE) {
    qos->liveliness = manual_by_topic == count ? RMW_QOS_POLICY_LIVELINESS_MANUAL_BY_TOPIC :
                                                 RMW_QOS_POLICY_LIVELINESS_AUTOMATIC;
  }
  if (time_equal(qos->deadline, kDeadlineBestAvailable)) {
    qos->deadline = default_deadline ? kDeadlineDefault : largest_deadline;
  }
  if (time_equal(qos->liveliness_lease_duration, kLeaseBestAvailable)) {
    qos->liveliness_lease_duration = default_lease ? kLeaseDefault : largest_lease;
  }
}

void resolve_best_available_for_service(rmw_qos_profile_t * qos)
{
  if (qos->reliability == RMW_QOS_POLICY_RELIABILITY_BEST_AVAILABLE) {
    qos->reliability = RMW_QOS_POLICY_RELIABILITY_RELIABLE;
  }
  if (qos->durability == RMW_QOS_POLICY_DURABILITY_BEST_AVAILABLE) {
    qos->durability = RMW_QOS_POLICY_DURABILITY_VOLATILE;
  }
  if (qos->liveliness == RMW_QOS_POLICY_LIVELINESS_BEST_AVAILABLE) {
    qos->liveliness = RMW_QOS_POLICY_LIVELINESS_AUTOMATIC;
  }
  if (time_equal(qos->deadline, kDeadlineBestAvailable)) {
    qos->deadline = kDeadlineDefault;
  }
  if (time_equal(qos->liveliness_lease_duration, kLeaseBestAvailable)) {
    qos->liveliness_lease_duration = kLeaseDefault;
  }
}

rmw_qos_profile_t service_actual_qos(const rmw_qos_profile_t & requested, QosSide side)
{
  rmw_qos_profile_t qos = requested;
  resolve_best_available_for_service(&qos);
  return resolve_system_defaults(qos, side);
}

bool qos_match(const rmw_qos_profile_t & publisher, const rmw_qos_profile_t & subscription)
{
  rmw_qos_compatibility_type_t compatibility = RMW_QOS_COMPATIBILITY_OK;
  // No reason buffer: only the error rules run their course, nothing is formatted.
  if (check_qos_compatible(publisher, subscription, &compatibility, nullptr, 0u) != RMW_RET_OK) {
    return false;
  }
  return compatibility != RMW_QOS_COMPATIBILITY_ERROR;
}

}  // namespace rmw_introspect
