// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// QoS spellings, durations and the DDS compatibility rules.

#include <gtest/gtest.h>

#include <string>

#include "rmw/error_handling.h"
#include "rmw/qos_profiles.h"

#include "detail/qos.hpp"

using rmw_introspect::check_qos_compatible;

namespace
{
rmw_qos_compatibility_type_t check(
  const rmw_qos_profile_t & pub, const rmw_qos_profile_t & sub, std::string * reason = nullptr)
{
  rmw_qos_compatibility_type_t compat = RMW_QOS_COMPATIBILITY_OK;
  char buffer[512];
  EXPECT_EQ(RMW_RET_OK, check_qos_compatible(pub, sub, &compat, buffer, sizeof(buffer)));
  if (reason) {
    *reason = buffer;
  }
  return compat;
}
}  // namespace

TEST(Qos, spellings_and_durations)
{
  EXPECT_STREQ("KEEP_LAST", rmw_introspect::history_to_string(RMW_QOS_POLICY_HISTORY_KEEP_LAST));
  EXPECT_STREQ("KEEP_ALL", rmw_introspect::history_to_string(RMW_QOS_POLICY_HISTORY_KEEP_ALL));
  EXPECT_STREQ(
    "BEST_EFFORT", rmw_introspect::reliability_to_string(RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT));
  EXPECT_STREQ(
    "BEST_AVAILABLE",
    rmw_introspect::reliability_to_string(RMW_QOS_POLICY_RELIABILITY_BEST_AVAILABLE));
  EXPECT_STREQ(
    "TRANSIENT_LOCAL",
    rmw_introspect::durability_to_string(RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL));
  EXPECT_STREQ(
    "MANUAL_BY_TOPIC",
    rmw_introspect::liveliness_to_string(RMW_QOS_POLICY_LIVELINESS_MANUAL_BY_TOPIC));
  EXPECT_STREQ(
    "SYSTEM_DEFAULT",
    rmw_introspect::liveliness_to_string(RMW_QOS_POLICY_LIVELINESS_SYSTEM_DEFAULT));
  EXPECT_EQ(0, rmw_introspect::duration_to_ns(rmw_time_t{0, 0}));
  EXPECT_EQ(-1, rmw_introspect::duration_to_ns(RMW_DURATION_INFINITE));
  EXPECT_EQ(1500000000, rmw_introspect::duration_to_ns(rmw_time_t{1, 500000000}));
  EXPECT_EQ(10000000000, rmw_introspect::duration_to_ns(rmw_time_t{10, 0}));
}

TEST(Qos, compatibility_errors)
{
  // rmw_qos_profile_default leaves liveliness at SYSTEM_DEFAULT, which alone is a warning.
  rmw_qos_profile_t base = rmw_qos_profile_default;
  base.liveliness = RMW_QOS_POLICY_LIVELINESS_AUTOMATIC;
  rmw_qos_profile_t pub = base;
  rmw_qos_profile_t sub = base;
  EXPECT_EQ(RMW_QOS_COMPATIBILITY_OK, check(pub, sub));
  pub.reliability = RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT;
  std::string reason;
  EXPECT_EQ(RMW_QOS_COMPATIBILITY_ERROR, check(pub, sub, &reason));
  EXPECT_NE(std::string::npos, reason.find("Best effort publisher and reliable subscription"));
  pub = base;
  sub.durability = RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL;
  EXPECT_EQ(RMW_QOS_COMPATIBILITY_ERROR, check(pub, sub));
  sub = base;
  sub.deadline = {1, 0};
  EXPECT_EQ(RMW_QOS_COMPATIBILITY_ERROR, check(pub, sub));  // pub has no deadline
  pub.deadline = {2, 0};
  EXPECT_EQ(RMW_QOS_COMPATIBILITY_ERROR, check(pub, sub));  // sub deadline shorter
  pub.deadline = {1, 0};
  EXPECT_EQ(RMW_QOS_COMPATIBILITY_OK, check(pub, sub));
  pub = base;
  sub = base;
  pub.liveliness = RMW_QOS_POLICY_LIVELINESS_AUTOMATIC;
  sub.liveliness = RMW_QOS_POLICY_LIVELINESS_MANUAL_BY_TOPIC;
  EXPECT_EQ(RMW_QOS_COMPATIBILITY_ERROR, check(pub, sub));
  sub.liveliness = RMW_QOS_POLICY_LIVELINESS_AUTOMATIC;
  sub.liveliness_lease_duration = {1, 0};
  EXPECT_EQ(RMW_QOS_COMPATIBILITY_ERROR, check(pub, sub));
  // History, depth and lifespan are never compared.
  pub = base;
  sub = rmw_qos_profile_sensor_data;
  sub.liveliness = RMW_QOS_POLICY_LIVELINESS_AUTOMATIC;
  sub.reliability = RMW_QOS_POLICY_RELIABILITY_RELIABLE;
  pub.lifespan = {3, 0};
  EXPECT_EQ(RMW_QOS_COMPATIBILITY_OK, check(pub, sub));
}

TEST(Qos, compatibility_warnings)
{
  rmw_qos_profile_t pub = rmw_qos_profile_system_default;
  rmw_qos_profile_t sub = rmw_qos_profile_system_default;
  EXPECT_EQ(RMW_QOS_COMPATIBILITY_WARNING, check(pub, sub));
  // Both liveliness SYSTEM_DEFAULT (the default profile) is a warning too.
  EXPECT_EQ(RMW_QOS_COMPATIBILITY_WARNING, check(rmw_qos_profile_default, rmw_qos_profile_default));
  pub = rmw_qos_profile_default;
  pub.reliability = RMW_QOS_POLICY_RELIABILITY_SYSTEM_DEFAULT;
  sub = rmw_qos_profile_default;  // reliable
  EXPECT_EQ(RMW_QOS_COMPATIBILITY_WARNING, check(pub, sub));
  // An error hides the warnings.
  pub = rmw_qos_profile_sensor_data;
  sub = rmw_qos_profile_default;
  sub.liveliness = RMW_QOS_POLICY_LIVELINESS_SYSTEM_DEFAULT;
  EXPECT_EQ(RMW_QOS_COMPATIBILITY_ERROR, check(pub, sub));
}

TEST(Qos, compatibility_arguments)
{
  rmw_qos_compatibility_type_t compat;
  EXPECT_EQ(
    RMW_RET_INVALID_ARGUMENT,
    check_qos_compatible(rmw_qos_profile_default, rmw_qos_profile_default, nullptr, nullptr, 0));
  EXPECT_EQ(
    RMW_RET_INVALID_ARGUMENT,
    check_qos_compatible(rmw_qos_profile_default, rmw_qos_profile_default, &compat, nullptr, 5));
  rmw_reset_error();
  char tiny[8];
  rmw_qos_profile_t pub = rmw_qos_profile_sensor_data;
  EXPECT_EQ(
    RMW_RET_OK, check_qos_compatible(pub, rmw_qos_profile_default, &compat, tiny, sizeof(tiny)));
  EXPECT_EQ(RMW_QOS_COMPATIBILITY_ERROR, compat);
  EXPECT_LT(std::string(tiny).size(), sizeof(tiny));  // truncated, terminated
}

namespace
{
bool same_time(const rmw_time_t & a, const rmw_time_t & b)
{
  return a.sec == b.sec && a.nsec == b.nsec;
}
const rmw_time_t kInfinite = RMW_DURATION_INFINITE;
const rmw_time_t kUnset = RMW_DURATION_UNSPECIFIED;
}  // namespace

TEST(Qos, system_defaults_resolve_like_fast_dds)
{
  using rmw_introspect::QosSide;
  using rmw_introspect::resolve_system_defaults;
  const rmw_qos_profile_t writer =
    resolve_system_defaults(rmw_qos_profile_system_default, QosSide::kWriter);
  EXPECT_EQ(RMW_QOS_POLICY_HISTORY_KEEP_LAST, writer.history);
  EXPECT_EQ(1u, writer.depth);
  EXPECT_EQ(RMW_QOS_POLICY_RELIABILITY_RELIABLE, writer.reliability);
  EXPECT_EQ(RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL, writer.durability);
  EXPECT_EQ(RMW_QOS_POLICY_LIVELINESS_AUTOMATIC, writer.liveliness);
  EXPECT_TRUE(same_time(kInfinite, writer.deadline));
  EXPECT_TRUE(same_time(kInfinite, writer.lifespan));
  EXPECT_TRUE(same_time(kInfinite, writer.liveliness_lease_duration));
  const rmw_qos_profile_t reader =
    resolve_system_defaults(rmw_qos_profile_system_default, QosSide::kReader);
  EXPECT_EQ(RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT, reader.reliability);
  EXPECT_EQ(RMW_QOS_POLICY_DURABILITY_VOLATILE, reader.durability);
  EXPECT_EQ(1u, reader.depth);

  // Concrete policies and set durations are kept, whatever the side.
  rmw_qos_profile_t asked = rmw_qos_profile_sensor_data;
  asked.history = RMW_QOS_POLICY_HISTORY_KEEP_ALL;
  asked.deadline = {2, 5};
  asked.avoid_ros_namespace_conventions = true;
  for (QosSide side : {QosSide::kWriter, QosSide::kReader}) {
    const rmw_qos_profile_t got = resolve_system_defaults(asked, side);
    EXPECT_EQ(RMW_QOS_POLICY_HISTORY_KEEP_ALL, got.history);
    EXPECT_EQ(5u, got.depth);
    EXPECT_EQ(RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT, got.reliability);
    EXPECT_EQ(RMW_QOS_POLICY_DURABILITY_VOLATILE, got.durability);
    EXPECT_TRUE(same_time(asked.deadline, got.deadline));
    EXPECT_TRUE(got.avoid_ros_namespace_conventions);
  }
  // Nothing resolved is SYSTEM_DEFAULT or UNKNOWN any more: the suite's check.
  for (const rmw_qos_profile_t & got : {writer, reader}) {
    EXPECT_NE(rmw_qos_profile_system_default.history, got.history);
    EXPECT_NE(rmw_qos_profile_unknown.history, got.history);
    EXPECT_NE(rmw_qos_profile_system_default.reliability, got.reliability);
    EXPECT_NE(rmw_qos_profile_unknown.reliability, got.reliability);
    EXPECT_NE(rmw_qos_profile_system_default.durability, got.durability);
    EXPECT_NE(rmw_qos_profile_unknown.durability, got.durability);
    EXPECT_NE(rmw_qos_profile_system_default.liveliness, got.liveliness);
    EXPECT_NE(rmw_qos_profile_unknown.liveliness, got.liveliness);
  }
}

TEST(Qos, best_available_follows_rmw_dds_common)
{
  // A publisher: RELIABLE, TRANSIENT_LOCAL; liveliness MANUAL_BY_TOPIC only if a subscription
  // asks for it; the smallest deadline / lease of the subscriptions that set one.
  rmw_qos_profile_t pub = rmw_qos_profile_best_available;
  rmw_introspect::resolve_best_available_for_publisher(&pub, nullptr, 0);
  EXPECT_EQ(RMW_QOS_POLICY_RELIABILITY_RELIABLE, pub.reliability);
  EXPECT_EQ(RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL, pub.durability);
  EXPECT_EQ(RMW_QOS_POLICY_LIVELINESS_AUTOMATIC, pub.liveliness);
  EXPECT_TRUE(same_time(kUnset, pub.deadline));
  EXPECT_TRUE(same_time(kUnset, pub.liveliness_lease_duration));
  rmw_qos_profile_t subs[2] = {rmw_qos_profile_default, rmw_qos_profile_default};
  subs[0].liveliness = RMW_QOS_POLICY_LIVELINESS_MANUAL_BY_TOPIC;
  subs[0].deadline = {3, 0};
  subs[1].deadline = {2, 0};
  pub = rmw_qos_profile_best_available;
  rmw_introspect::resolve_best_available_for_publisher(&pub, subs, 2);
  EXPECT_EQ(RMW_QOS_POLICY_LIVELINESS_MANUAL_BY_TOPIC, pub.liveliness);
  EXPECT_EQ(2u, pub.deadline.sec);

  // A subscription: the strong value only if every publisher offers it (and with none).
  rmw_qos_profile_t sub = rmw_qos_profile_best_available;
  rmw_introspect::resolve_best_available_for_subscription(&sub, nullptr, 0);
  EXPECT_EQ(RMW_QOS_POLICY_RELIABILITY_RELIABLE, sub.reliability);
  EXPECT_EQ(RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL, sub.durability);
  EXPECT_EQ(RMW_QOS_POLICY_LIVELINESS_MANUAL_BY_TOPIC, sub.liveliness);
  rmw_qos_profile_t pubs[2] = {rmw_qos_profile_default, rmw_qos_profile_sensor_data};
  pubs[0].deadline = {1, 0};
  pubs[1].deadline = {4, 0};
  sub = rmw_qos_profile_best_available;
  rmw_introspect::resolve_best_available_for_subscription(&sub, pubs, 2);
  EXPECT_EQ(RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT, sub.reliability);
  EXPECT_EQ(RMW_QOS_POLICY_DURABILITY_VOLATILE, sub.durability);
  EXPECT_EQ(RMW_QOS_POLICY_LIVELINESS_AUTOMATIC, sub.liveliness);
  EXPECT_EQ(4u, sub.deadline.sec);

  // Services: RELIABLE, VOLATILE, AUTOMATIC, default durations.
  rmw_qos_profile_t srv = rmw_qos_profile_best_available;
  rmw_introspect::resolve_best_available_for_service(&srv);
  EXPECT_EQ(RMW_QOS_POLICY_RELIABILITY_RELIABLE, srv.reliability);
  EXPECT_EQ(RMW_QOS_POLICY_DURABILITY_VOLATILE, srv.durability);
  EXPECT_EQ(RMW_QOS_POLICY_LIVELINESS_AUTOMATIC, srv.liveliness);
  EXPECT_TRUE(same_time(kUnset, srv.deadline));

  // Concrete policies are never touched.
  rmw_qos_profile_t fixed = rmw_qos_profile_sensor_data;
  rmw_introspect::resolve_best_available_for_subscription(&fixed, pubs, 2);
  rmw_introspect::resolve_best_available_for_publisher(&fixed, subs, 2);
  EXPECT_EQ(RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT, fixed.reliability);
  EXPECT_TRUE(same_time(kUnset, fixed.deadline));
}

TEST(Qos, match_is_no_compatibility_error)
{
  using rmw_introspect::qos_match;
  using rmw_introspect::QosSide;
  using rmw_introspect::resolve_system_defaults;
  rmw_qos_profile_t best_effort = rmw_qos_profile_default;
  best_effort.reliability = RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT;
  EXPECT_FALSE(qos_match(best_effort, rmw_qos_profile_default));
  EXPECT_TRUE(qos_match(rmw_qos_profile_default, best_effort));
  EXPECT_TRUE(qos_match(rmw_qos_profile_default, rmw_qos_profile_default));
  // Resolved system defaults (durations infinite) keep the rules' meaning: a subscription
  // deadline against an unset (now infinite) publisher deadline is still an error.
  const rmw_qos_profile_t pub =
    resolve_system_defaults(rmw_qos_profile_system_default, QosSide::kWriter);
  rmw_qos_profile_t sub = rmw_qos_profile_system_default;
  EXPECT_TRUE(qos_match(pub, resolve_system_defaults(sub, QosSide::kReader)));
  sub.deadline = {1, 0};
  EXPECT_FALSE(qos_match(pub, resolve_system_defaults(sub, QosSide::kReader)));
  rmw_qos_profile_t offered = rmw_qos_profile_system_default;
  offered.deadline = {1, 0};
  EXPECT_TRUE(qos_match(
    resolve_system_defaults(offered, QosSide::kWriter),
    resolve_system_defaults(rmw_qos_profile_system_default, QosSide::kReader)));
  // Writer defaults against a TRANSIENT_LOCAL reader: fine; VOLATILE writer: not.
  rmw_qos_profile_t latched = rmw_qos_profile_default;
  latched.durability = RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL;
  EXPECT_TRUE(qos_match(pub, latched));
  EXPECT_FALSE(qos_match(rmw_qos_profile_default, latched));
}
