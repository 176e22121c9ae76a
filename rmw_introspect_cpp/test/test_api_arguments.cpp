// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Argument checking of every rmw_* entry point: NULL for each pointer argument gives
// RMW_RET_INVALID_ARGUMENT with an error message set (NULL + error for functions returning
// pointers); a handle of another implementation gives RMW_RET_INCORRECT_RMW_IMPLEMENTATION.
// Exceptions, where test_rmw_implementation and rmw_fastrtps_cpp agree against rmw.h:
// rmw_service_server_is_available and rmw_destroy_wait_set answer NULL with RMW_RET_ERROR up to
// Jazzy (RMW_RET_INVALID_ARGUMENT from Kilted on, as that distribution's suite expects);
// the loan functions answer RMW_RET_UNSUPPORTED right after the handle checks; the allocation
// functions and rmw_get_serialized_message_size answer RMW_RET_UNSUPPORTED before any check.

#include <gtest/gtest.h>

#include <cstring>

#include "rmw/dynamic_message_type_support.h"
#include "rmw/features.h"
#include "rmw/get_network_flow_endpoints.h"
#include "rmw/get_node_info_and_types.h"
#include "rmw/get_service_names_and_types.h"
#include "rmw/get_topic_endpoint_info.h"
#include "rmw/get_topic_names_and_types.h"
#include "rmw/message_sequence.h"
#include "rmw/names_and_types.h"
#include "rmw/network_flow_endpoint_array.h"
#include "rmw/topic_endpoint_info_array.h"
#include "rcutils/types/string_array.h"

#include "api_fixture.hpp"
#include "detail/rmw_api.hpp"

#define EXPECT_UNSUPPORTED(expr) EXPECT_RET_WITH_ERROR(RMW_RET_UNSUPPORTED, expr)
// The two functions whose NULL answer changed between Jazzy and Kilted (detail/rmw_api.hpp).
#define EXPECT_OLD_NULL_CHECK(expr) \
  EXPECT_RET_WITH_ERROR(rmw_introspect::kNullArgumentRetOfOldChecks, expr)

namespace
{
const rmw_time_t kZeroTime{0, 0};
}

TEST(ApiIdentity, identifier_and_format)
{
  ASSERT_NE(nullptr, rmw_get_implementation_identifier());
  EXPECT_STREQ("rmw_introspect_cpp", rmw_get_implementation_identifier());
  EXPECT_STREQ("cdr", rmw_get_serialization_format());
  EXPECT_FALSE(rmw_feature_supported(RMW_FEATURE_MESSAGE_INFO_PUBLICATION_SEQUENCE_NUMBER));
  EXPECT_TRUE(rmw_event_type_is_supported(RMW_EVENT_OFFERED_QOS_INCOMPATIBLE));
  EXPECT_TRUE(rmw_event_type_is_supported(RMW_EVENT_SUBSCRIPTION_MATCHED));
  EXPECT_FALSE(rmw_event_type_is_supported(RMW_EVENT_INVALID));
  EXPECT_EQ(RMW_RET_OK, rmw_set_log_severity(RMW_LOG_SEVERITY_WARN));
  EXPECT_INVALID(rmw_set_log_severity(static_cast<rmw_log_severity_t>(12345)));
}

TEST(ApiInit, init_options)
{
  rcutils_allocator_t allocator = rcutils_get_default_allocator();
  EXPECT_INVALID(rmw_init_options_init(nullptr, allocator));
  rmw_init_options_t options = rmw_get_zero_initialized_init_options();
  rcutils_allocator_t bad = rcutils_get_zero_initialized_allocator();
  EXPECT_INVALID(rmw_init_options_init(&options, bad));
  ASSERT_EQ(RMW_RET_OK, rmw_init_options_init(&options, allocator));
  EXPECT_EQ(rmw_get_implementation_identifier(), options.implementation_identifier);
  EXPECT_INVALID(rmw_init_options_init(&options, allocator));  // not zero-initialized

  rmw_init_options_t copy = rmw_get_zero_initialized_init_options();
  EXPECT_INVALID(rmw_init_options_copy(nullptr, &copy));
  EXPECT_INVALID(rmw_init_options_copy(&options, nullptr));
  rmw_init_options_t foreign = options;
  foreign.implementation_identifier = foreign_identifier();
  EXPECT_FOREIGN(rmw_init_options_copy(&foreign, &copy));
  ASSERT_EQ(RMW_RET_OK, rmw_init_options_copy(&options, &copy));
  EXPECT_INVALID(rmw_init_options_copy(&options, &copy));  // dst not zero-initialized

  EXPECT_INVALID(rmw_init_options_fini(nullptr));
  EXPECT_FOREIGN(rmw_init_options_fini(&foreign));
  EXPECT_EQ(RMW_RET_OK, rmw_init_options_fini(&copy));
  EXPECT_INVALID(rmw_init_options_fini(&copy));  // already finalized
  EXPECT_EQ(RMW_RET_OK, rmw_init_options_fini(&options));
}

TEST(ApiInit, init_shutdown_fini)
{
  rcutils_allocator_t allocator = rcutils_get_default_allocator();
  rmw_init_options_t options = rmw_get_zero_initialized_init_options();
  ASSERT_EQ(RMW_RET_OK, rmw_init_options_init(&options, allocator));
  rmw_context_t context = rmw_get_zero_initialized_context();
  EXPECT_INVALID(rmw_init(nullptr, &context));
  EXPECT_INVALID(rmw_init(&options, nullptr));
  EXPECT_INVALID(rmw_init(&options, &context));  // enclave is NULL
  options.enclave = rcutils_strdup("/", allocator);
  rmw_init_options_t foreign = options;
  foreign.implementation_identifier = foreign_identifier();
  EXPECT_FOREIGN(rmw_init(&foreign, &context));
  ASSERT_EQ(RMW_RET_OK, rmw_init(&options, &context));
  EXPECT_INVALID(rmw_init(&options, &context));  // context not zero-initialized

  rmw_context_t foreign_context = context;
  foreign_context.implementation_identifier = foreign_identifier();
  EXPECT_INVALID(rmw_shutdown(nullptr));
  EXPECT_FOREIGN(rmw_shutdown(&foreign_context));
  EXPECT_INVALID(rmw_context_fini(nullptr));
  EXPECT_FOREIGN(rmw_context_fini(&foreign_context));
  EXPECT_INVALID(rmw_context_fini(&context));  // not shut down yet
  ASSERT_EQ(RMW_RET_OK, rmw_shutdown(&context));
  // A shut down context refuses new nodes.
  EXPECT_NULL_WITH_ERROR(rmw_create_node(&context, "late", "/"));
  ASSERT_EQ(RMW_RET_OK, rmw_context_fini(&context));
  EXPECT_INVALID(rmw_shutdown(&context));  // zero-initialized again
  EXPECT_EQ(RMW_RET_OK, rmw_init_options_fini(&options));
}

using ApiArgs = ApiFixture;

TEST_F(ApiArgs, node)
{
  EXPECT_NULL_WITH_ERROR(rmw_create_node(nullptr, "n", "/"));
  EXPECT_NULL_WITH_ERROR(rmw_create_node(&context, nullptr, "/"));
  EXPECT_NULL_WITH_ERROR(rmw_create_node(&context, "n", nullptr));
  EXPECT_NULL_WITH_ERROR(rmw_create_node(&foreign_context, "n", "/"));
  EXPECT_NULL_WITH_ERROR(rmw_create_node(&context, "bad name", "/"));
  EXPECT_NULL_WITH_ERROR(rmw_create_node(&context, "n", "no_leading_slash"));
  EXPECT_INVALID(rmw_destroy_node(nullptr));
  EXPECT_FOREIGN(rmw_destroy_node(&foreign_node));
  EXPECT_NULL_WITH_ERROR(rmw_node_get_graph_guard_condition(nullptr));
  EXPECT_NULL_WITH_ERROR(rmw_node_get_graph_guard_condition(&foreign_node));
  EXPECT_NE(nullptr, rmw_node_get_graph_guard_condition(node));
}

TEST_F(ApiArgs, create_publisher)
{
  EXPECT_NULL_WITH_ERROR(rmw_create_publisher(nullptr, msg_ts, "/t", &qos, &pub_options));
  EXPECT_NULL_WITH_ERROR(rmw_create_publisher(&foreign_node, msg_ts, "/t", &qos, &pub_options));
  EXPECT_NULL_WITH_ERROR(rmw_create_publisher(node, nullptr, "/t", &qos, &pub_options));
  EXPECT_NULL_WITH_ERROR(rmw_create_publisher(node, msg_ts, nullptr, &qos, &pub_options));
  EXPECT_NULL_WITH_ERROR(rmw_create_publisher(node, msg_ts, "/t", nullptr, &pub_options));
  EXPECT_NULL_WITH_ERROR(rmw_create_publisher(node, msg_ts, "/t", &qos, nullptr));
  EXPECT_NULL_WITH_ERROR(rmw_create_publisher(node, msg_ts, "", &qos, &pub_options));
  EXPECT_NULL_WITH_ERROR(rmw_create_publisher(node, msg_ts, "not/absolute", &qos, &pub_options));
  rmw_qos_profile_t unknown = qos;
  unknown.reliability = RMW_QOS_POLICY_RELIABILITY_UNKNOWN;
  EXPECT_NULL_WITH_ERROR(rmw_create_publisher(node, msg_ts, "/t", &unknown, &pub_options));
  // A type support that is not (and does not lead to) an introspection one.
  rosidl_message_type_support_t bogus = *msg_ts;
  bogus.typesupport_identifier = "bogus_typesupport";
  bogus.func = nullptr;
  EXPECT_NULL_WITH_ERROR(rmw_create_publisher(node, &bogus, "/t", &qos, &pub_options));
  EXPECT_INVALID(rmw_destroy_publisher(nullptr, publisher));
  EXPECT_INVALID(rmw_destroy_publisher(node, nullptr));
  EXPECT_FOREIGN(rmw_destroy_publisher(&foreign_node, publisher));
  EXPECT_FOREIGN(rmw_destroy_publisher(node, &foreign_publisher));
}

TEST_F(ApiArgs, publisher_operations)
{
  std_msgs__msg__String msg;
  std_msgs__msg__String__init(&msg);
  EXPECT_INVALID(rmw_publish(nullptr, &msg, nullptr));
  EXPECT_INVALID(rmw_publish(publisher, nullptr, nullptr));
  EXPECT_FOREIGN(rmw_publish(&foreign_publisher, &msg, nullptr));
  EXPECT_EQ(RMW_RET_OK, rmw_publish(publisher, &msg, nullptr));
  std_msgs__msg__String__fini(&msg);

  rmw_serialized_message_t serialized = rmw_get_zero_initialized_serialized_message();
  EXPECT_INVALID(rmw_publish_serialized_message(nullptr, &serialized, nullptr));
  EXPECT_INVALID(rmw_publish_serialized_message(publisher, nullptr, nullptr));
  EXPECT_FOREIGN(rmw_publish_serialized_message(&foreign_publisher, &serialized, nullptr));

  // Loans: handle checks, then "cannot loan" before the other arguments (rmw_fastrtps_cpp).
  ASSERT_FALSE(publisher->can_loan_messages);
  void * loan = nullptr;
  EXPECT_INVALID(rmw_borrow_loaned_message(nullptr, msg_ts, &loan));
  EXPECT_FOREIGN(rmw_borrow_loaned_message(&foreign_publisher, msg_ts, &loan));
  EXPECT_UNSUPPORTED(rmw_borrow_loaned_message(publisher, nullptr, &loan));
  EXPECT_UNSUPPORTED(rmw_borrow_loaned_message(publisher, msg_ts, nullptr));
  EXPECT_UNSUPPORTED(rmw_borrow_loaned_message(publisher, msg_ts, &loan));
  EXPECT_EQ(nullptr, loan);
  int dummy = 0;
  EXPECT_INVALID(rmw_publish_loaned_message(nullptr, &dummy, nullptr));
  EXPECT_FOREIGN(rmw_publish_loaned_message(&foreign_publisher, &dummy, nullptr));
  EXPECT_UNSUPPORTED(rmw_publish_loaned_message(publisher, nullptr, nullptr));
  EXPECT_UNSUPPORTED(rmw_publish_loaned_message(publisher, &dummy, nullptr));
  EXPECT_INVALID(rmw_return_loaned_message_from_publisher(nullptr, &dummy));
  EXPECT_FOREIGN(rmw_return_loaned_message_from_publisher(&foreign_publisher, &dummy));
  EXPECT_UNSUPPORTED(rmw_return_loaned_message_from_publisher(publisher, nullptr));
  EXPECT_UNSUPPORTED(rmw_return_loaned_message_from_publisher(publisher, &dummy));

  size_t count = 0;
  EXPECT_INVALID(rmw_publisher_count_matched_subscriptions(nullptr, &count));
  EXPECT_INVALID(rmw_publisher_count_matched_subscriptions(publisher, nullptr));
  EXPECT_FOREIGN(rmw_publisher_count_matched_subscriptions(&foreign_publisher, &count));

  rmw_qos_profile_t actual;
  EXPECT_INVALID(rmw_publisher_get_actual_qos(nullptr, &actual));
  EXPECT_INVALID(rmw_publisher_get_actual_qos(publisher, nullptr));
  EXPECT_FOREIGN(rmw_publisher_get_actual_qos(&foreign_publisher, &actual));

  EXPECT_INVALID(rmw_publisher_assert_liveliness(nullptr));
  EXPECT_FOREIGN(rmw_publisher_assert_liveliness(&foreign_publisher));
  EXPECT_INVALID(rmw_publisher_wait_for_all_acked(nullptr, kZeroTime));
  EXPECT_FOREIGN(rmw_publisher_wait_for_all_acked(&foreign_publisher, kZeroTime));

  rcutils_allocator_t alloc = rcutils_get_default_allocator();
  rmw_network_flow_endpoint_array_t flows = rmw_get_zero_initialized_network_flow_endpoint_array();
  EXPECT_INVALID(rmw_publisher_get_network_flow_endpoints(nullptr, &alloc, &flows));
  EXPECT_INVALID(rmw_publisher_get_network_flow_endpoints(publisher, nullptr, &flows));
  EXPECT_INVALID(rmw_publisher_get_network_flow_endpoints(publisher, &alloc, nullptr));
  EXPECT_FOREIGN(rmw_publisher_get_network_flow_endpoints(&foreign_publisher, &alloc, &flows));

  rmw_gid_t gid;
  EXPECT_INVALID(rmw_get_gid_for_publisher(nullptr, &gid));
  EXPECT_INVALID(rmw_get_gid_for_publisher(publisher, nullptr));
  EXPECT_FOREIGN(rmw_get_gid_for_publisher(&foreign_publisher, &gid));

  // Unsupported before any argument check: the suite probes with NULLs.
  rmw_publisher_allocation_t allocation;
  EXPECT_UNSUPPORTED(rmw_init_publisher_allocation(nullptr, nullptr, nullptr));
  EXPECT_UNSUPPORTED(rmw_init_publisher_allocation(nullptr, nullptr, &allocation));
  EXPECT_UNSUPPORTED(rmw_init_publisher_allocation(msg_ts, nullptr, nullptr));
  EXPECT_UNSUPPORTED(rmw_init_publisher_allocation(msg_ts, nullptr, &allocation));
  EXPECT_UNSUPPORTED(rmw_fini_publisher_allocation(nullptr));
  EXPECT_UNSUPPORTED(rmw_fini_publisher_allocation(&allocation));

  rmw_event_t event = rmw_get_zero_initialized_event();
  EXPECT_INVALID(rmw_publisher_event_init(nullptr, publisher, RMW_EVENT_LIVELINESS_LOST));
  EXPECT_INVALID(rmw_publisher_event_init(&event, nullptr, RMW_EVENT_LIVELINESS_LOST));
  EXPECT_FOREIGN(rmw_publisher_event_init(&event, &foreign_publisher, RMW_EVENT_LIVELINESS_LOST));
  EXPECT_RET_WITH_ERROR(
    RMW_RET_UNSUPPORTED,
    rmw_publisher_event_init(&event, publisher, RMW_EVENT_REQUESTED_DEADLINE_MISSED));
}

TEST_F(ApiArgs, create_subscription)
{
  EXPECT_NULL_WITH_ERROR(rmw_create_subscription(nullptr, msg_ts, "/t", &qos, &sub_options));
  EXPECT_NULL_WITH_ERROR(rmw_create_subscription(&foreign_node, msg_ts, "/t", &qos, &sub_options));
  EXPECT_NULL_WITH_ERROR(rmw_create_subscription(node, nullptr, "/t", &qos, &sub_options));
  EXPECT_NULL_WITH_ERROR(rmw_create_subscription(node, msg_ts, nullptr, &qos, &sub_options));
  EXPECT_NULL_WITH_ERROR(rmw_create_subscription(node, msg_ts, "/t", nullptr, &sub_options));
  EXPECT_NULL_WITH_ERROR(rmw_create_subscription(node, msg_ts, "/t", &qos, nullptr));
  EXPECT_NULL_WITH_ERROR(rmw_create_subscription(node, msg_ts, "", &qos, &sub_options));
  EXPECT_NULL_WITH_ERROR(rmw_create_subscription(node, msg_ts, "/a b", &qos, &sub_options));
  EXPECT_INVALID(rmw_destroy_subscription(nullptr, subscription));
  EXPECT_INVALID(rmw_destroy_subscription(node, nullptr));
  EXPECT_FOREIGN(rmw_destroy_subscription(&foreign_node, subscription));
  EXPECT_FOREIGN(rmw_destroy_subscription(node, &foreign_subscription));
}

// rmw_fastrtps_cpp accepts unique network flow endpoints strictly required on a subscription,
// not on a publisher: a program asking for them on a subscription runs, as on Fast DDS.
TEST_F(ApiArgs, unique_network_flow_endpoints)
{
  rmw_subscription_options_t strict_sub = sub_options;
  strict_sub.require_unique_network_flow_endpoints =
    RMW_UNIQUE_NETWORK_FLOW_ENDPOINTS_STRICTLY_REQUIRED;
  rmw_subscription_t * strict = rmw_create_subscription(node, msg_ts, "/strict", &qos, &strict_sub);
  ASSERT_NE(nullptr, strict) << rmw_get_error_string().str;
  rmw_publisher_options_t strict_pub = pub_options;
  strict_pub.require_unique_network_flow_endpoints =
    RMW_UNIQUE_NETWORK_FLOW_ENDPOINTS_STRICTLY_REQUIRED;
  EXPECT_NULL_WITH_ERROR(rmw_create_publisher(node, msg_ts, "/strict", &qos, &strict_pub));
  strict_pub.require_unique_network_flow_endpoints =
    RMW_UNIQUE_NETWORK_FLOW_ENDPOINTS_OPTIONALLY_REQUIRED;
  rmw_publisher_t * optional = rmw_create_publisher(node, msg_ts, "/strict", &qos, &strict_pub);
  ASSERT_NE(nullptr, optional) << rmw_get_error_string().str;

  // the flows of both: an empty list that finalizes cleanly (nothing goes on a network)
  rcutils_allocator_t alloc = rcutils_get_default_allocator();
  rmw_network_flow_endpoint_array_t flows = rmw_get_zero_initialized_network_flow_endpoint_array();
  ASSERT_EQ(RMW_RET_OK, rmw_subscription_get_network_flow_endpoints(strict, &alloc, &flows));
  EXPECT_EQ(0u, flows.size);
  EXPECT_EQ(RMW_RET_OK, rmw_network_flow_endpoint_array_fini(&flows));
  flows = rmw_get_zero_initialized_network_flow_endpoint_array();
  ASSERT_EQ(RMW_RET_OK, rmw_publisher_get_network_flow_endpoints(optional, &alloc, &flows));
  EXPECT_EQ(0u, flows.size);
  EXPECT_EQ(RMW_RET_OK, rmw_network_flow_endpoint_array_fini(&flows));

  EXPECT_EQ(RMW_RET_OK, rmw_destroy_publisher(node, optional));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_subscription(node, strict));
}

TEST_F(ApiArgs, subscription_operations)
{
  size_t count = 0;
  EXPECT_INVALID(rmw_subscription_count_matched_publishers(nullptr, &count));
  EXPECT_INVALID(rmw_subscription_count_matched_publishers(subscription, nullptr));
  EXPECT_FOREIGN(rmw_subscription_count_matched_publishers(&foreign_subscription, &count));
  rmw_qos_profile_t actual;
  EXPECT_INVALID(rmw_subscription_get_actual_qos(nullptr, &actual));
  EXPECT_INVALID(rmw_subscription_get_actual_qos(subscription, nullptr));
  EXPECT_FOREIGN(rmw_subscription_get_actual_qos(&foreign_subscription, &actual));

  rmw_subscription_content_filter_options_t filter =
    rmw_get_zero_initialized_content_filter_options();
  rcutils_allocator_t alloc = rcutils_get_default_allocator();
  EXPECT_INVALID(rmw_subscription_set_content_filter(nullptr, &filter));
  EXPECT_INVALID(rmw_subscription_set_content_filter(subscription, nullptr));
  EXPECT_FOREIGN(rmw_subscription_set_content_filter(&foreign_subscription, &filter));
  EXPECT_INVALID(rmw_subscription_get_content_filter(nullptr, &alloc, &filter));
  EXPECT_INVALID(rmw_subscription_get_content_filter(subscription, nullptr, &filter));
  EXPECT_INVALID(rmw_subscription_get_content_filter(subscription, &alloc, nullptr));
  EXPECT_FOREIGN(rmw_subscription_get_content_filter(&foreign_subscription, &alloc, &filter));

  rmw_network_flow_endpoint_array_t flows = rmw_get_zero_initialized_network_flow_endpoint_array();
  EXPECT_INVALID(rmw_subscription_get_network_flow_endpoints(nullptr, &alloc, &flows));
  EXPECT_INVALID(rmw_subscription_get_network_flow_endpoints(subscription, nullptr, &flows));
  EXPECT_INVALID(rmw_subscription_get_network_flow_endpoints(subscription, &alloc, nullptr));
  EXPECT_FOREIGN(
    rmw_subscription_get_network_flow_endpoints(&foreign_subscription, &alloc, &flows));

  EXPECT_INVALID(rmw_subscription_set_on_new_message_callback(nullptr, nullptr, nullptr));
  EXPECT_FOREIGN(
    rmw_subscription_set_on_new_message_callback(&foreign_subscription, nullptr, nullptr));

  // Unsupported before any argument check: the suite probes with NULLs.
  rmw_subscription_allocation_t allocation;
  EXPECT_UNSUPPORTED(rmw_init_subscription_allocation(nullptr, nullptr, nullptr));
  EXPECT_UNSUPPORTED(rmw_init_subscription_allocation(nullptr, nullptr, &allocation));
  EXPECT_UNSUPPORTED(rmw_init_subscription_allocation(msg_ts, nullptr, nullptr));
  EXPECT_UNSUPPORTED(rmw_init_subscription_allocation(msg_ts, nullptr, &allocation));
  EXPECT_UNSUPPORTED(rmw_fini_subscription_allocation(nullptr));
  EXPECT_UNSUPPORTED(rmw_fini_subscription_allocation(&allocation));

  rmw_event_t event = rmw_get_zero_initialized_event();
  EXPECT_INVALID(rmw_subscription_event_init(nullptr, subscription, RMW_EVENT_MESSAGE_LOST));
  EXPECT_INVALID(rmw_subscription_event_init(&event, nullptr, RMW_EVENT_MESSAGE_LOST));
  EXPECT_FOREIGN(
    rmw_subscription_event_init(&event, &foreign_subscription, RMW_EVENT_MESSAGE_LOST));
  EXPECT_RET_WITH_ERROR(
    RMW_RET_UNSUPPORTED,
    rmw_subscription_event_init(&event, subscription, RMW_EVENT_LIVELINESS_LOST));
}

TEST_F(ApiArgs, take)
{
  std_msgs__msg__String msg;
  bool taken = true;
  rmw_message_info_t info = rmw_get_zero_initialized_message_info();
  EXPECT_INVALID(rmw_take(nullptr, &msg, &taken, nullptr));
  EXPECT_INVALID(rmw_take(subscription, nullptr, &taken, nullptr));
  EXPECT_INVALID(rmw_take(subscription, &msg, nullptr, nullptr));
  EXPECT_FOREIGN(rmw_take(&foreign_subscription, &msg, &taken, nullptr));

  EXPECT_INVALID(rmw_take_with_info(nullptr, &msg, &taken, &info, nullptr));
  EXPECT_INVALID(rmw_take_with_info(subscription, nullptr, &taken, &info, nullptr));
  EXPECT_INVALID(rmw_take_with_info(subscription, &msg, nullptr, &info, nullptr));
  EXPECT_INVALID(rmw_take_with_info(subscription, &msg, &taken, nullptr, nullptr));
  EXPECT_FOREIGN(rmw_take_with_info(&foreign_subscription, &msg, &taken, &info, nullptr));

  rcutils_allocator_t alloc = rcutils_get_default_allocator();
  rmw_message_sequence_t seq = rmw_get_zero_initialized_message_sequence();
  rmw_message_info_sequence_t info_seq = rmw_get_zero_initialized_message_info_sequence();
  ASSERT_EQ(RMW_RET_OK, rmw_message_sequence_init(&seq, 2, &alloc));
  ASSERT_EQ(RMW_RET_OK, rmw_message_info_sequence_init(&info_seq, 2, &alloc));
  size_t n = 5;
  EXPECT_INVALID(rmw_take_sequence(nullptr, 1, &seq, &info_seq, &n, nullptr));
  EXPECT_INVALID(rmw_take_sequence(subscription, 1, nullptr, &info_seq, &n, nullptr));
  EXPECT_INVALID(rmw_take_sequence(subscription, 1, &seq, nullptr, &n, nullptr));
  EXPECT_INVALID(rmw_take_sequence(subscription, 1, &seq, &info_seq, nullptr, nullptr));
  EXPECT_INVALID(rmw_take_sequence(subscription, 0, &seq, &info_seq, &n, nullptr));
  EXPECT_INVALID(rmw_take_sequence(subscription, 3, &seq, &info_seq, &n, nullptr));
  EXPECT_FOREIGN(rmw_take_sequence(&foreign_subscription, 1, &seq, &info_seq, &n, nullptr));
  EXPECT_EQ(RMW_RET_OK, rmw_message_sequence_fini(&seq));
  EXPECT_EQ(RMW_RET_OK, rmw_message_info_sequence_fini(&info_seq));

  rmw_serialized_message_t serialized = rmw_get_zero_initialized_serialized_message();
  EXPECT_INVALID(rmw_take_serialized_message(nullptr, &serialized, &taken, nullptr));
  EXPECT_INVALID(rmw_take_serialized_message(subscription, nullptr, &taken, nullptr));
  EXPECT_INVALID(rmw_take_serialized_message(subscription, &serialized, nullptr, nullptr));
  EXPECT_FOREIGN(rmw_take_serialized_message(&foreign_subscription, &serialized, &taken, nullptr));
  EXPECT_INVALID(
    rmw_take_serialized_message_with_info(nullptr, &serialized, &taken, &info, nullptr));
  EXPECT_INVALID(
    rmw_take_serialized_message_with_info(subscription, nullptr, &taken, &info, nullptr));
  EXPECT_INVALID(
    rmw_take_serialized_message_with_info(subscription, &serialized, nullptr, &info, nullptr));
  EXPECT_INVALID(
    rmw_take_serialized_message_with_info(subscription, &serialized, &taken, nullptr, nullptr));
  EXPECT_FOREIGN(rmw_take_serialized_message_with_info(
    &foreign_subscription, &serialized, &taken, &info, nullptr));

  // Loans: handle checks, then "cannot loan" before the other arguments (rmw_fastrtps_cpp;
  // test_rmw_implementation returns a NULL loan to a subscription that cannot loan and
  // expects RMW_RET_UNSUPPORTED).
  ASSERT_FALSE(subscription->can_loan_messages);
  void * loan = nullptr;
  EXPECT_INVALID(rmw_take_loaned_message(nullptr, &loan, &taken, nullptr));
  EXPECT_FOREIGN(rmw_take_loaned_message(&foreign_subscription, &loan, &taken, nullptr));
  EXPECT_UNSUPPORTED(rmw_take_loaned_message(subscription, nullptr, &taken, nullptr));
  EXPECT_UNSUPPORTED(rmw_take_loaned_message(subscription, &loan, nullptr, nullptr));
  EXPECT_UNSUPPORTED(rmw_take_loaned_message(subscription, &loan, &taken, nullptr));
  EXPECT_INVALID(rmw_take_loaned_message_with_info(nullptr, &loan, &taken, &info, nullptr));
  EXPECT_FOREIGN(
    rmw_take_loaned_message_with_info(&foreign_subscription, &loan, &taken, &info, nullptr));
  EXPECT_UNSUPPORTED(
    rmw_take_loaned_message_with_info(subscription, nullptr, &taken, &info, nullptr));
  EXPECT_UNSUPPORTED(
    rmw_take_loaned_message_with_info(subscription, &loan, nullptr, &info, nullptr));
  EXPECT_UNSUPPORTED(
    rmw_take_loaned_message_with_info(subscription, &loan, &taken, nullptr, nullptr));
  EXPECT_UNSUPPORTED(
    rmw_take_loaned_message_with_info(subscription, &loan, &taken, &info, nullptr));
  EXPECT_EQ(nullptr, loan);
  int dummy = 0;
  EXPECT_INVALID(rmw_return_loaned_message_from_subscription(nullptr, &dummy));
  EXPECT_FOREIGN(rmw_return_loaned_message_from_subscription(&foreign_subscription, &dummy));
  EXPECT_UNSUPPORTED(rmw_return_loaned_message_from_subscription(subscription, nullptr));
  EXPECT_UNSUPPORTED(rmw_return_loaned_message_from_subscription(subscription, &dummy));

  rosidl_dynamic_typesupport_dynamic_data_t * dyn =
    reinterpret_cast<rosidl_dynamic_typesupport_dynamic_data_t *>(&dummy);
  EXPECT_INVALID(rmw_take_dynamic_message(nullptr, dyn, &taken, nullptr));
  EXPECT_INVALID(rmw_take_dynamic_message(subscription, nullptr, &taken, nullptr));
  EXPECT_INVALID(rmw_take_dynamic_message(subscription, dyn, nullptr, nullptr));
  EXPECT_FOREIGN(rmw_take_dynamic_message(&foreign_subscription, dyn, &taken, nullptr));
  EXPECT_INVALID(rmw_take_dynamic_message_with_info(nullptr, dyn, &taken, &info, nullptr));
  EXPECT_INVALID(rmw_take_dynamic_message_with_info(subscription, nullptr, &taken, &info, nullptr));
  EXPECT_INVALID(rmw_take_dynamic_message_with_info(subscription, dyn, nullptr, &info, nullptr));
  EXPECT_INVALID(rmw_take_dynamic_message_with_info(subscription, dyn, &taken, nullptr, nullptr));
  EXPECT_FOREIGN(
    rmw_take_dynamic_message_with_info(&foreign_subscription, dyn, &taken, &info, nullptr));
}

TEST_F(ApiArgs, service)
{
  const rmw_qos_profile_t * sqos = &rmw_qos_profile_services_default;
  EXPECT_NULL_WITH_ERROR(rmw_create_service(nullptr, srv_ts, "/s", sqos));
  EXPECT_NULL_WITH_ERROR(rmw_create_service(&foreign_node, srv_ts, "/s", sqos));
  EXPECT_NULL_WITH_ERROR(rmw_create_service(node, nullptr, "/s", sqos));
  EXPECT_NULL_WITH_ERROR(rmw_create_service(node, srv_ts, nullptr, sqos));
  EXPECT_NULL_WITH_ERROR(rmw_create_service(node, srv_ts, "/s", nullptr));
  EXPECT_NULL_WITH_ERROR(rmw_create_service(node, srv_ts, "", sqos));
  EXPECT_NULL_WITH_ERROR(rmw_create_service(node, srv_ts, "/bad name", sqos));
  EXPECT_INVALID(rmw_destroy_service(nullptr, service));
  EXPECT_INVALID(rmw_destroy_service(node, nullptr));
  EXPECT_FOREIGN(rmw_destroy_service(&foreign_node, service));
  EXPECT_FOREIGN(rmw_destroy_service(node, &foreign_service));

  rmw_service_info_t header{};
  rmw_request_id_t request_id{};
  int request = 0;
  bool taken = true;
  EXPECT_INVALID(rmw_take_request(nullptr, &header, &request, &taken));
  EXPECT_INVALID(rmw_take_request(service, nullptr, &request, &taken));
  EXPECT_INVALID(rmw_take_request(service, &header, nullptr, &taken));
  EXPECT_INVALID(rmw_take_request(service, &header, &request, nullptr));
  EXPECT_FOREIGN(rmw_take_request(&foreign_service, &header, &request, &taken));
  EXPECT_INVALID(rmw_send_response(nullptr, &request_id, &request));
  EXPECT_INVALID(rmw_send_response(service, nullptr, &request));
  EXPECT_INVALID(rmw_send_response(service, &request_id, nullptr));
  EXPECT_FOREIGN(rmw_send_response(&foreign_service, &request_id, &request));
  rmw_qos_profile_t actual;
  EXPECT_INVALID(rmw_service_request_subscription_get_actual_qos(nullptr, &actual));
  EXPECT_INVALID(rmw_service_request_subscription_get_actual_qos(service, nullptr));
  EXPECT_FOREIGN(rmw_service_request_subscription_get_actual_qos(&foreign_service, &actual));
  EXPECT_INVALID(rmw_service_response_publisher_get_actual_qos(nullptr, &actual));
  EXPECT_INVALID(rmw_service_response_publisher_get_actual_qos(service, nullptr));
  EXPECT_FOREIGN(rmw_service_response_publisher_get_actual_qos(&foreign_service, &actual));
  EXPECT_INVALID(rmw_service_set_on_new_request_callback(nullptr, nullptr, nullptr));
  EXPECT_FOREIGN(rmw_service_set_on_new_request_callback(&foreign_service, nullptr, nullptr));
}

TEST_F(ApiArgs, client)
{
  const rmw_qos_profile_t * sqos = &rmw_qos_profile_services_default;
  EXPECT_NULL_WITH_ERROR(rmw_create_client(nullptr, srv_ts, "/s", sqos));
  EXPECT_NULL_WITH_ERROR(rmw_create_client(&foreign_node, srv_ts, "/s", sqos));
  EXPECT_NULL_WITH_ERROR(rmw_create_client(node, nullptr, "/s", sqos));
  EXPECT_NULL_WITH_ERROR(rmw_create_client(node, srv_ts, nullptr, sqos));
  EXPECT_NULL_WITH_ERROR(rmw_create_client(node, srv_ts, "/s", nullptr));
  EXPECT_NULL_WITH_ERROR(rmw_create_client(node, srv_ts, "", sqos));
  EXPECT_INVALID(rmw_destroy_client(nullptr, client));
  EXPECT_INVALID(rmw_destroy_client(node, nullptr));
  EXPECT_FOREIGN(rmw_destroy_client(&foreign_node, client));
  EXPECT_FOREIGN(rmw_destroy_client(node, &foreign_client));

  int request = 0;
  int64_t sequence = 0;
  rmw_service_info_t header{};
  bool taken = true;
  EXPECT_INVALID(rmw_send_request(nullptr, &request, &sequence));
  EXPECT_INVALID(rmw_send_request(client, nullptr, &sequence));
  EXPECT_INVALID(rmw_send_request(client, &request, nullptr));
  EXPECT_FOREIGN(rmw_send_request(&foreign_client, &request, &sequence));
  EXPECT_INVALID(rmw_take_response(nullptr, &header, &request, &taken));
  EXPECT_INVALID(rmw_take_response(client, nullptr, &request, &taken));
  EXPECT_INVALID(rmw_take_response(client, &header, nullptr, &taken));
  EXPECT_INVALID(rmw_take_response(client, &header, &request, nullptr));
  EXPECT_FOREIGN(rmw_take_response(&foreign_client, &header, &request, &taken));
  rmw_qos_profile_t actual;
  EXPECT_INVALID(rmw_client_request_publisher_get_actual_qos(nullptr, &actual));
  EXPECT_INVALID(rmw_client_request_publisher_get_actual_qos(client, nullptr));
  EXPECT_FOREIGN(rmw_client_request_publisher_get_actual_qos(&foreign_client, &actual));
  EXPECT_INVALID(rmw_client_response_subscription_get_actual_qos(nullptr, &actual));
  EXPECT_INVALID(rmw_client_response_subscription_get_actual_qos(client, nullptr));
  EXPECT_FOREIGN(rmw_client_response_subscription_get_actual_qos(&foreign_client, &actual));
  EXPECT_INVALID(rmw_client_set_on_new_response_callback(nullptr, nullptr, nullptr));
  EXPECT_FOREIGN(rmw_client_set_on_new_response_callback(&foreign_client, nullptr, nullptr));
  rmw_gid_t gid;
  EXPECT_INVALID(rmw_get_gid_for_client(nullptr, &gid));
  EXPECT_INVALID(rmw_get_gid_for_client(client, nullptr));
  EXPECT_FOREIGN(rmw_get_gid_for_client(&foreign_client, &gid));
  // RMW_RET_ERROR for NULL here (rmw_fastrtps_cpp, test_client.cpp), not INVALID_ARGUMENT.
  bool available = false;
  EXPECT_OLD_NULL_CHECK(rmw_service_server_is_available(nullptr, client, &available));
  EXPECT_OLD_NULL_CHECK(rmw_service_server_is_available(node, nullptr, &available));
  EXPECT_OLD_NULL_CHECK(rmw_service_server_is_available(node, client, nullptr));
  EXPECT_OLD_NULL_CHECK(rmw_service_server_is_available(nullptr, nullptr, nullptr));
  EXPECT_FOREIGN(rmw_service_server_is_available(&foreign_node, client, &available));
  EXPECT_FOREIGN(rmw_service_server_is_available(node, &foreign_client, &available));
}

TEST_F(ApiArgs, guard_conditions_wait_sets_events)
{
  EXPECT_NULL_WITH_ERROR(rmw_create_guard_condition(nullptr));
  EXPECT_NULL_WITH_ERROR(rmw_create_guard_condition(&foreign_context));
  EXPECT_INVALID(rmw_destroy_guard_condition(nullptr));
  EXPECT_FOREIGN(rmw_destroy_guard_condition(&foreign_guard_condition));
  EXPECT_INVALID(rmw_trigger_guard_condition(nullptr));
  EXPECT_FOREIGN(rmw_trigger_guard_condition(&foreign_guard_condition));

  EXPECT_NULL_WITH_ERROR(rmw_create_wait_set(nullptr, 1));
  EXPECT_NULL_WITH_ERROR(rmw_create_wait_set(&foreign_context, 1));
  EXPECT_OLD_NULL_CHECK(rmw_destroy_wait_set(nullptr));  // as test_wait_set.cpp expects
  EXPECT_FOREIGN(rmw_destroy_wait_set(&foreign_wait_set));
  rmw_time_t timeout{0, 0};
  EXPECT_INVALID(rmw_wait(nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, &timeout));
  EXPECT_FOREIGN(
    rmw_wait(nullptr, nullptr, nullptr, nullptr, nullptr, &foreign_wait_set, &timeout));

  int info = 0;
  bool taken = true;
  EXPECT_INVALID(rmw_take_event(nullptr, &info, &taken));
  EXPECT_INVALID(rmw_take_event(&pub_event, nullptr, &taken));
  EXPECT_INVALID(rmw_take_event(&pub_event, &info, nullptr));
  EXPECT_FOREIGN(rmw_take_event(&foreign_event, &info, &taken));
  EXPECT_INVALID(rmw_event_set_callback(nullptr, nullptr, nullptr));
  EXPECT_FOREIGN(rmw_event_set_callback(&foreign_event, nullptr, nullptr));
}

TEST_F(ApiArgs, graph)
{
  rcutils_allocator_t alloc = rcutils_get_default_allocator();
  rcutils_allocator_t bad_alloc = rcutils_get_zero_initialized_allocator();
  rcutils_string_array_t names = rcutils_get_zero_initialized_string_array();
  rcutils_string_array_t namespaces = rcutils_get_zero_initialized_string_array();
  rcutils_string_array_t enclaves = rcutils_get_zero_initialized_string_array();
  EXPECT_INVALID(rmw_get_node_names(nullptr, &names, &namespaces));
  EXPECT_INVALID(rmw_get_node_names(node, nullptr, &namespaces));
  EXPECT_INVALID(rmw_get_node_names(node, &names, nullptr));
  EXPECT_FOREIGN(rmw_get_node_names(&foreign_node, &names, &namespaces));
  EXPECT_INVALID(rmw_get_node_names_with_enclaves(nullptr, &names, &namespaces, &enclaves));
  EXPECT_INVALID(rmw_get_node_names_with_enclaves(node, nullptr, &namespaces, &enclaves));
  EXPECT_INVALID(rmw_get_node_names_with_enclaves(node, &names, nullptr, &enclaves));
  EXPECT_INVALID(rmw_get_node_names_with_enclaves(node, &names, &namespaces, nullptr));
  EXPECT_FOREIGN(rmw_get_node_names_with_enclaves(&foreign_node, &names, &namespaces, &enclaves));

  rmw_names_and_types_t nt = rmw_get_zero_initialized_names_and_types();
  EXPECT_INVALID(rmw_get_topic_names_and_types(nullptr, &alloc, false, &nt));
  EXPECT_INVALID(rmw_get_topic_names_and_types(node, nullptr, false, &nt));
  EXPECT_INVALID(rmw_get_topic_names_and_types(node, &bad_alloc, false, &nt));
  EXPECT_INVALID(rmw_get_topic_names_and_types(node, &alloc, false, nullptr));
  EXPECT_FOREIGN(rmw_get_topic_names_and_types(&foreign_node, &alloc, false, &nt));
  EXPECT_INVALID(rmw_get_service_names_and_types(nullptr, &alloc, &nt));
  EXPECT_INVALID(rmw_get_service_names_and_types(node, nullptr, &nt));
  EXPECT_INVALID(rmw_get_service_names_and_types(node, &alloc, nullptr));
  EXPECT_FOREIGN(rmw_get_service_names_and_types(&foreign_node, &alloc, &nt));

  using ByNodeTopics = rmw_ret_t (*)(
    const rmw_node_t *, rcutils_allocator_t *, const char *, const char *, bool,
    rmw_names_and_types_t *);
  for (ByNodeTopics fn :
       {rmw_get_publisher_names_and_types_by_node, rmw_get_subscriber_names_and_types_by_node})
  {
    EXPECT_INVALID(fn(nullptr, &alloc, "fixture_node", "/ns", false, &nt));
    EXPECT_INVALID(fn(node, nullptr, "fixture_node", "/ns", false, &nt));
    EXPECT_INVALID(fn(node, &alloc, nullptr, "/ns", false, &nt));
    EXPECT_INVALID(fn(node, &alloc, "fixture_node", nullptr, false, &nt));
    EXPECT_INVALID(fn(node, &alloc, "fixture_node", "/ns", false, nullptr));
    EXPECT_INVALID(fn(node, &alloc, "bad name", "/ns", false, &nt));
    EXPECT_FOREIGN(fn(&foreign_node, &alloc, "fixture_node", "/ns", false, &nt));
    EXPECT_RET_WITH_ERROR(
      RMW_RET_NODE_NAME_NON_EXISTENT, fn(node, &alloc, "nobody", "/ns", false, &nt));
  }
  using ByNodeServices = rmw_ret_t (*)(
    const rmw_node_t *, rcutils_allocator_t *, const char *, const char *, rmw_names_and_types_t *);
  for (ByNodeServices fn :
       {rmw_get_service_names_and_types_by_node, rmw_get_client_names_and_types_by_node})
  {
    EXPECT_INVALID(fn(nullptr, &alloc, "fixture_node", "/ns", &nt));
    EXPECT_INVALID(fn(node, nullptr, "fixture_node", "/ns", &nt));
    EXPECT_INVALID(fn(node, &alloc, nullptr, "/ns", &nt));
    EXPECT_INVALID(fn(node, &alloc, "fixture_node", nullptr, &nt));
    EXPECT_INVALID(fn(node, &alloc, "fixture_node", "/ns", nullptr));
    EXPECT_FOREIGN(fn(&foreign_node, &alloc, "fixture_node", "/ns", &nt));
    EXPECT_RET_WITH_ERROR(RMW_RET_NODE_NAME_NON_EXISTENT, fn(node, &alloc, "nobody", "/", &nt));
  }
  using InfoByTopic = rmw_ret_t (*)(
    const rmw_node_t *, rcutils_allocator_t *, const char *, bool,
    rmw_topic_endpoint_info_array_t *);
  rmw_topic_endpoint_info_array_t infos = rmw_get_zero_initialized_topic_endpoint_info_array();
  for (InfoByTopic fn : {rmw_get_publishers_info_by_topic, rmw_get_subscriptions_info_by_topic}) {
    EXPECT_INVALID(fn(nullptr, &alloc, "/chatter", false, &infos));
    EXPECT_INVALID(fn(node, nullptr, "/chatter", false, &infos));
    EXPECT_INVALID(fn(node, &alloc, nullptr, false, &infos));
    EXPECT_INVALID(fn(node, &alloc, "/chatter", false, nullptr));
    EXPECT_FOREIGN(fn(&foreign_node, &alloc, "/chatter", false, &infos));
    // An output array that is not zero-initialized (test_graph_api.cpp).
    rmw_topic_endpoint_info_array_t used = rmw_get_zero_initialized_topic_endpoint_info_array();
    ASSERT_EQ(RMW_RET_OK, rmw_topic_endpoint_info_array_init_with_size(&used, 1u, &alloc));
    EXPECT_INVALID(fn(node, &alloc, "/chatter", false, &used));
    EXPECT_EQ(1u, used.size);  // untouched
    EXPECT_EQ(RMW_RET_OK, rmw_topic_endpoint_info_array_fini(&used, &alloc));
  }
  using Count = rmw_ret_t (*)(const rmw_node_t *, const char *, size_t *);
  size_t count = 0;
  for (Count fn :
       {rmw_count_publishers, rmw_count_subscribers, rmw_count_clients, rmw_count_services})
  {
    EXPECT_INVALID(fn(nullptr, "/chatter", &count));
    EXPECT_INVALID(fn(node, nullptr, &count));
    EXPECT_INVALID(fn(node, "/chatter", nullptr));
    EXPECT_INVALID(fn(node, "no//good", &count));
    EXPECT_FOREIGN(fn(&foreign_node, "/chatter", &count));
  }
}

TEST_F(ApiArgs, gids_qos_serialization)
{
  rmw_gid_t a, b;
  ASSERT_EQ(RMW_RET_OK, rmw_get_gid_for_publisher(publisher, &a));
  ASSERT_EQ(RMW_RET_OK, rmw_get_gid_for_client(client, &b));
  bool result = false;
  EXPECT_INVALID(rmw_compare_gids_equal(nullptr, &b, &result));
  EXPECT_INVALID(rmw_compare_gids_equal(&a, nullptr, &result));
  EXPECT_INVALID(rmw_compare_gids_equal(&a, &b, nullptr));
  rmw_gid_t foreign = a;
  foreign.implementation_identifier = foreign_identifier();
  EXPECT_FOREIGN(rmw_compare_gids_equal(&foreign, &b, &result));
  EXPECT_FOREIGN(rmw_compare_gids_equal(&a, &foreign, &result));

  rmw_qos_compatibility_type_t compat;
  char reason[64];
  EXPECT_INVALID(rmw_qos_profile_check_compatible(qos, qos, nullptr, reason, sizeof(reason)));
  EXPECT_INVALID(rmw_qos_profile_check_compatible(qos, qos, &compat, nullptr, 10));
  EXPECT_EQ(RMW_RET_OK, rmw_qos_profile_check_compatible(qos, qos, &compat, nullptr, 0));

  std_msgs__msg__String msg;
  std_msgs__msg__String__init(&msg);
  rmw_serialized_message_t serialized = rmw_get_zero_initialized_serialized_message();
  EXPECT_INVALID(rmw_serialize(nullptr, msg_ts, &serialized));
  EXPECT_INVALID(rmw_serialize(&msg, nullptr, &serialized));
  EXPECT_INVALID(rmw_serialize(&msg, msg_ts, nullptr));
  EXPECT_INVALID(rmw_deserialize(nullptr, msg_ts, &msg));
  EXPECT_INVALID(rmw_deserialize(&serialized, nullptr, &msg));
  EXPECT_INVALID(rmw_deserialize(&serialized, msg_ts, nullptr));
  // Unsupported before any argument check: the suite probes with NULLs.
  size_t size = 0;
  EXPECT_UNSUPPORTED(rmw_get_serialized_message_size(nullptr, nullptr, nullptr));
  EXPECT_UNSUPPORTED(rmw_get_serialized_message_size(nullptr, nullptr, &size));
  EXPECT_UNSUPPORTED(rmw_get_serialized_message_size(msg_ts, nullptr, nullptr));
  EXPECT_UNSUPPORTED(rmw_get_serialized_message_size(msg_ts, nullptr, &size));
  std_msgs__msg__String__fini(&msg);
  rcutils_allocator_t alloc = rcutils_get_default_allocator();
  rosidl_dynamic_typesupport_serialization_support_t support;
  EXPECT_INVALID(rmw_serialization_support_init(nullptr, &alloc, &support));
  EXPECT_INVALID(rmw_serialization_support_init("fastrtps", nullptr, &support));
  EXPECT_INVALID(rmw_serialization_support_init("fastrtps", &alloc, nullptr));
}
