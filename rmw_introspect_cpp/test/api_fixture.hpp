// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// A live context with one node and one entity of every kind, on real type supports.
#ifndef API_FIXTURE_HPP_
#define API_FIXTURE_HPP_

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "rcutils/allocator.h"
#include "rcutils/strdup.h"
#include "rmw/error_handling.h"
#include "rmw/event.h"
#include "rmw/init.h"
#include "rmw/init_options.h"
#include "rmw/rmw.h"
#include "rosidl_runtime_c/message_type_support_struct.h"
#include "rosidl_runtime_c/service_type_support_struct.h"
#include "std_msgs/msg/string.h"
#include "test_msgs/srv/basic_types.h"

#define EXPECT_RET_WITH_ERROR(expected, expr)                            \
  do {                                                                   \
    rmw_reset_error();                                                   \
    EXPECT_EQ(expected, (expr)) << #expr;                                \
    EXPECT_TRUE(rmw_error_is_set()) << "no error message set by " #expr; \
    rmw_reset_error();                                                   \
  } while (0)

#define EXPECT_INVALID(expr) EXPECT_RET_WITH_ERROR(RMW_RET_INVALID_ARGUMENT, expr)
#define EXPECT_FOREIGN(expr) EXPECT_RET_WITH_ERROR(RMW_RET_INCORRECT_RMW_IMPLEMENTATION, expr)
#define EXPECT_NULL_WITH_ERROR(expr)                                     \
  do {                                                                   \
    rmw_reset_error();                                                   \
    EXPECT_EQ(nullptr, (expr)) << #expr;                                 \
    EXPECT_TRUE(rmw_error_is_set()) << "no error message set by " #expr; \
    rmw_reset_error();                                                   \
  } while (0)

inline const char * foreign_identifier()
{
  static const char id[] = "some_other_rmw";
  return id;
}

class ApiFixture : public ::testing::Test
{
protected:
  void SetUp() override
  {
    allocator = rcutils_get_default_allocator();
    ASSERT_EQ(RMW_RET_OK, rmw_init_options_init(&options, allocator));
    options.enclave = rcutils_strdup("/", allocator);
    ASSERT_EQ(RMW_RET_OK, rmw_init(&options, &context)) << rmw_get_error_string().str;
    node = rmw_create_node(&context, "fixture_node", "/ns");
    ASSERT_NE(nullptr, node) << rmw_get_error_string().str;
    msg_ts = ROSIDL_GET_MSG_TYPE_SUPPORT(std_msgs, msg, String);
    srv_ts = ROSIDL_GET_SRV_TYPE_SUPPORT(test_msgs, srv, BasicTypes);
    qos = rmw_qos_profile_default;
    pub_options = rmw_get_default_publisher_options();
    sub_options = rmw_get_default_subscription_options();
    publisher = rmw_create_publisher(node, msg_ts, "/chatter", &qos, &pub_options);
    ASSERT_NE(nullptr, publisher) << rmw_get_error_string().str;
    subscription = rmw_create_subscription(node, msg_ts, "/chatter", &qos, &sub_options);
    ASSERT_NE(nullptr, subscription) << rmw_get_error_string().str;
    service = rmw_create_service(node, srv_ts, "/basic", &rmw_qos_profile_services_default);
    ASSERT_NE(nullptr, service) << rmw_get_error_string().str;
    client = rmw_create_client(node, srv_ts, "/basic", &rmw_qos_profile_services_default);
    ASSERT_NE(nullptr, client) << rmw_get_error_string().str;
    guard_condition = rmw_create_guard_condition(&context);
    ASSERT_NE(nullptr, guard_condition);
    wait_set = rmw_create_wait_set(&context, 8);
    ASSERT_NE(nullptr, wait_set);
    pub_event = rmw_get_zero_initialized_event();
    ASSERT_EQ(
      RMW_RET_OK,
      rmw_publisher_event_init(&pub_event, publisher, RMW_EVENT_OFFERED_QOS_INCOMPATIBLE));
    sub_event = rmw_get_zero_initialized_event();
    ASSERT_EQ(
      RMW_RET_OK,
      rmw_subscription_event_init(&sub_event, subscription, RMW_EVENT_REQUESTED_QOS_INCOMPATIBLE));

    foreign_context = context;
    foreign_context.implementation_identifier = foreign_identifier();
    foreign_node = *node;
    foreign_node.implementation_identifier = foreign_identifier();
    foreign_publisher = *publisher;
    foreign_publisher.implementation_identifier = foreign_identifier();
    foreign_subscription = *subscription;
    foreign_subscription.implementation_identifier = foreign_identifier();
    foreign_service = *service;
    foreign_service.implementation_identifier = foreign_identifier();
    foreign_client = *client;
    foreign_client.implementation_identifier = foreign_identifier();
    foreign_guard_condition = *guard_condition;
    foreign_guard_condition.implementation_identifier = foreign_identifier();
    foreign_wait_set = *wait_set;
    foreign_wait_set.implementation_identifier = foreign_identifier();
    foreign_event = pub_event;
    foreign_event.implementation_identifier = foreign_identifier();
    rmw_reset_error();
  }

  void TearDown() override
  {
    EXPECT_EQ(RMW_RET_OK, rmw_destroy_wait_set(wait_set));
    EXPECT_EQ(RMW_RET_OK, rmw_destroy_guard_condition(guard_condition));
    EXPECT_EQ(RMW_RET_OK, rmw_destroy_client(node, client));
    EXPECT_EQ(RMW_RET_OK, rmw_destroy_service(node, service));
    EXPECT_EQ(RMW_RET_OK, rmw_destroy_subscription(node, subscription));
    EXPECT_EQ(RMW_RET_OK, rmw_destroy_publisher(node, publisher));
    EXPECT_EQ(RMW_RET_OK, rmw_destroy_node(node));
    EXPECT_EQ(RMW_RET_OK, rmw_shutdown(&context));
    EXPECT_EQ(RMW_RET_OK, rmw_context_fini(&context));
    EXPECT_EQ(RMW_RET_OK, rmw_init_options_fini(&options));
    rmw_reset_error();
  }

  rcutils_allocator_t allocator{};
  rmw_init_options_t options = rmw_get_zero_initialized_init_options();
  rmw_context_t context = rmw_get_zero_initialized_context();
  rmw_node_t * node = nullptr;
  const rosidl_message_type_support_t * msg_ts = nullptr;
  const rosidl_service_type_support_t * srv_ts = nullptr;
  rmw_qos_profile_t qos{};
  rmw_publisher_options_t pub_options{};
  rmw_subscription_options_t sub_options{};
  rmw_publisher_t * publisher = nullptr;
  rmw_subscription_t * subscription = nullptr;
  rmw_service_t * service = nullptr;
  rmw_client_t * client = nullptr;
  rmw_guard_condition_t * guard_condition = nullptr;
  rmw_wait_set_t * wait_set = nullptr;
  rmw_event_t pub_event{};
  rmw_event_t sub_event{};

  rmw_context_t foreign_context{};
  rmw_node_t foreign_node{};
  rmw_publisher_t foreign_publisher{};
  rmw_subscription_t foreign_subscription{};
  rmw_service_t foreign_service{};
  rmw_client_t foreign_client{};
  rmw_guard_condition_t foreign_guard_condition{};
  rmw_wait_set_t foreign_wait_set{};
  rmw_event_t foreign_event{};
};

#endif  // API_FIXTURE_HPP_
