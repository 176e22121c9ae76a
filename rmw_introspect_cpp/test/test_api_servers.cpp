// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// RMW_INTROSPECT_SERVER_AVAILABLE=0: nothing is simulated; a client sees a server only when
// this process has one it would talk to (test_client.cpp:380/399 expect exactly that), and an
// action client's feedback/status subscriptions count only real publishers.

#include <gtest/gtest.h>

#include <cstdlib>

#include "test_msgs/action/fibonacci.h"

#include "api_fixture.hpp"

namespace
{
// Before anything reads the configuration (it is read once per process).
struct SetEnvironment
{
  SetEnvironment()
  {
    setenv("RMW_INTROSPECT_SERVER_AVAILABLE", "0", 1);
    setenv("RMW_INTROSPECT_AUTO_EXPORT", "0", 1);
  }
} set_environment;
}  // namespace

using ApiServers = ApiFixture;

TEST_F(ApiServers, a_client_sees_the_servers_of_its_process)
{
  const rmw_qos_profile_t * sqos = &rmw_qos_profile_services_default;
  rmw_client_t * cli = rmw_create_client(node, srv_ts, "/lonely", sqos);
  ASSERT_NE(nullptr, cli);
  bool available = true;
  ASSERT_EQ(RMW_RET_OK, rmw_service_server_is_available(node, cli, &available));
  EXPECT_FALSE(available);

  // Another name, then another type: still nobody.
  rmw_service_t * elsewhere = rmw_create_service(node, srv_ts, "/elsewhere", sqos);
  ASSERT_NE(nullptr, elsewhere);
  const rosidl_service_type_support_t * other_ts =
    ROSIDL_GET_SRV_TYPE_SUPPORT(test_msgs, action, Fibonacci_SendGoal);
  rmw_service_t * other_type = rmw_create_service(node, other_ts, "/lonely", sqos);
  ASSERT_NE(nullptr, other_type);
  ASSERT_EQ(RMW_RET_OK, rmw_service_server_is_available(node, cli, &available));
  EXPECT_FALSE(available);

  // The server it waits for.
  rmw_service_t * srv = rmw_create_service(node, srv_ts, "/lonely", sqos);
  ASSERT_NE(nullptr, srv);
  ASSERT_EQ(RMW_RET_OK, rmw_service_server_is_available(node, cli, &available));
  EXPECT_TRUE(available);
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_service(node, srv));
  ASSERT_EQ(RMW_RET_OK, rmw_service_server_is_available(node, cli, &available));
  EXPECT_FALSE(available);

  // A server whose QoS the client cannot match (it answers BEST_EFFORT, the client wants
  // RELIABLE responses) is not available either; with system defaults on both sides it is.
  rmw_qos_profile_t best_effort = rmw_qos_profile_services_default;
  best_effort.reliability = RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT;
  rmw_service_t * lossy = rmw_create_service(node, srv_ts, "/lonely", &best_effort);
  ASSERT_NE(nullptr, lossy);
  ASSERT_EQ(RMW_RET_OK, rmw_service_server_is_available(node, cli, &available));
  EXPECT_FALSE(available);
  const rmw_qos_profile_t * sysdef = &rmw_qos_profile_system_default;
  rmw_client_t * sysdef_cli = rmw_create_client(node, srv_ts, "/sysdef", sysdef);
  ASSERT_NE(nullptr, sysdef_cli);
  rmw_service_t * sysdef_srv = rmw_create_service(node, srv_ts, "/sysdef", sysdef);
  ASSERT_NE(nullptr, sysdef_srv);
  ASSERT_EQ(RMW_RET_OK, rmw_service_server_is_available(node, sysdef_cli, &available));
  EXPECT_TRUE(available);

  // The fixture's client has its server.
  ASSERT_EQ(RMW_RET_OK, rmw_service_server_is_available(node, client, &available));
  EXPECT_TRUE(available);

  for (rmw_service_t * s : {elsewhere, other_type, lossy, sysdef_srv}) {
    EXPECT_EQ(RMW_RET_OK, rmw_destroy_service(node, s));
  }
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_client(node, sysdef_cli));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_client(node, cli));
}

TEST_F(ApiServers, action_topics_count_only_real_publishers)
{
  const rosidl_message_type_support_t * feedback_ts =
    ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, action, Fibonacci_FeedbackMessage);
  rmw_subscription_t * sub =
    rmw_create_subscription(node, feedback_ts, "/fib/_action/feedback", &qos, &sub_options);
  ASSERT_NE(nullptr, sub);
  size_t count = 9;
  ASSERT_EQ(RMW_RET_OK, rmw_subscription_count_matched_publishers(sub, &count));
  EXPECT_EQ(0u, count);
  rmw_publisher_t * pub =
    rmw_create_publisher(node, feedback_ts, "/fib/_action/feedback", &qos, &pub_options);
  ASSERT_NE(nullptr, pub);
  ASSERT_EQ(RMW_RET_OK, rmw_subscription_count_matched_publishers(sub, &count));
  EXPECT_EQ(1u, count);
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_publisher(node, pub));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_subscription(node, sub));
}
