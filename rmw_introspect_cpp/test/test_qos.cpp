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
  if (reason) {*reason = buffer;}
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
    RMW_RET_OK,
    check_qos_compatible(pub, rmw_qos_profile_default, &compat, tiny, sizeof(tiny)));
  EXPECT_EQ(RMW_QOS_COMPATIBILITY_ERROR, compat);
  EXPECT_LT(std::string(tiny).size(), sizeof(tiny));  // truncated, terminated
}
