// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Behaviour of the rmw API on real type supports: recording (names copied, types, hashes,
// QoS), graph queries answered from our own records, GIDs, requests, takes, QoS checks.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <set>
#include <string>

#include "rcutils/types/string_array.h"
#include "rmw/time.h"
#include "rmw/get_node_info_and_types.h"
#include "rmw/get_service_names_and_types.h"
#include "rmw/get_topic_endpoint_info.h"
#include "rmw/get_topic_names_and_types.h"
#include "rmw/events_statuses/matched.h"
#include "rmw/names_and_types.h"
#include "rmw/serialized_message.h"
#include "rmw/subscription_content_filter_options.h"
#include "rmw/topic_endpoint_info_array.h"
#include "rosidl_runtime_c/string_functions.h"
#include "rosidl_typesupport_cpp/message_type_support.hpp"
#include "std_msgs/msg/string.hpp"
#include "test_msgs/action/fibonacci.h"

#include "api_fixture.hpp"

namespace
{
std::string capture_path()
{
  static const std::string path =
    "/tmp/rmwi_test_api_behaviour_" + std::to_string(getpid()) + ".json";
  return path;
}

// Before anything reads the configuration: where rmw_shutdown writes the capture.
struct SetEnvironment
{
  SetEnvironment()
  {
    setenv("RMW_INTROSPECT_OUTPUT", capture_path().c_str(), 1);
    setenv("RMW_INTROSPECT_SETTLE_MS", "10", 1);
  }
} set_environment;

std::string read_file(const std::string & path)
{
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::set<std::string> names_of(const rmw_names_and_types_t & nt)
{
  std::set<std::string> out;
  for (size_t i = 0; i < nt.names.size; ++i) {
    std::string entry = nt.names.data[i];
    for (size_t j = 0; j < nt.types[i].size; ++j) {
      entry += std::string(" ") + nt.types[i].data[j];
    }
    out.insert(entry);
  }
  return out;
}
bool is_infinite(const rmw_time_t & t)
{
  const rmw_time_t infinite = RMW_DURATION_INFINITE;
  return t.sec == infinite.sec && t.nsec == infinite.nsec;
}

}  // namespace

using ApiBehaviour = ApiFixture;

TEST_F(ApiBehaviour, topic_name_is_copied)
{
  char * topic = strdup("/copied_topic");
  rmw_publisher_t * pub = rmw_create_publisher(node, msg_ts, topic, &qos, &pub_options);
  ASSERT_NE(nullptr, pub);
  std::memset(topic, 'x', std::strlen(topic));  // what rcl does: frees it right away
  free(topic);
  EXPECT_STREQ("/copied_topic", pub->topic_name);
  size_t count = 0;
  EXPECT_EQ(RMW_RET_OK, rmw_count_publishers(node, "/copied_topic", &count));
  EXPECT_EQ(1u, count);
  char * service_name = strdup("/copied_service");
  rmw_service_t * srv =
    rmw_create_service(node, srv_ts, service_name, &rmw_qos_profile_services_default);
  ASSERT_NE(nullptr, srv);
  std::memset(service_name, 'y', std::strlen(service_name));
  free(service_name);
  EXPECT_STREQ("/copied_service", srv->service_name);
  char * name = strdup("copied_node");
  char * ns = strdup("/copied_ns");
  rmw_node_t * other = rmw_create_node(&context, name, ns);
  ASSERT_NE(nullptr, other);
  std::memset(name, 'z', std::strlen(name));
  std::memset(ns + 1, 'z', std::strlen(ns) - 1);
  free(name);
  free(ns);
  EXPECT_STREQ("copied_node", other->name);
  EXPECT_STREQ("/copied_ns", other->namespace_);
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_service(node, srv));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_publisher(node, pub));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_node(other));
}

TEST_F(ApiBehaviour, graph_answers_from_own_records)
{
  rcutils_allocator_t alloc = rcutils_get_default_allocator();
  rcutils_string_array_t names = rcutils_get_zero_initialized_string_array();
  rcutils_string_array_t namespaces = rcutils_get_zero_initialized_string_array();
  rcutils_string_array_t enclaves = rcutils_get_zero_initialized_string_array();
  ASSERT_EQ(RMW_RET_OK, rmw_get_node_names_with_enclaves(node, &names, &namespaces, &enclaves));
  bool found = false;
  for (size_t i = 0; i < names.size; ++i) {
    if (std::string(names.data[i]) == "fixture_node") {
      found = true;
      EXPECT_STREQ("/ns", namespaces.data[i]);
      EXPECT_STREQ("/", enclaves.data[i]);
    }
  }
  EXPECT_TRUE(found);
  EXPECT_EQ(RCUTILS_RET_OK, rcutils_string_array_fini(&names));
  EXPECT_EQ(RCUTILS_RET_OK, rcutils_string_array_fini(&namespaces));
  EXPECT_EQ(RCUTILS_RET_OK, rcutils_string_array_fini(&enclaves));

  rmw_names_and_types_t nt = rmw_get_zero_initialized_names_and_types();
  ASSERT_EQ(RMW_RET_OK, rmw_get_topic_names_and_types(node, &alloc, false, &nt));
  EXPECT_EQ(1u, names_of(nt).count("/chatter std_msgs/msg/String"));
  EXPECT_EQ(RMW_RET_OK, rmw_names_and_types_fini(&nt));
  ASSERT_EQ(RMW_RET_OK, rmw_get_service_names_and_types(node, &alloc, &nt));
  EXPECT_EQ(1u, names_of(nt).count("/basic test_msgs/srv/BasicTypes"));
  EXPECT_EQ(RMW_RET_OK, rmw_names_and_types_fini(&nt));

  ASSERT_EQ(
    RMW_RET_OK,
    rmw_get_publisher_names_and_types_by_node(node, &alloc, "fixture_node", "/ns", false, &nt));
  EXPECT_EQ(std::set<std::string>{"/chatter std_msgs/msg/String"}, names_of(nt));
  EXPECT_EQ(RMW_RET_OK, rmw_names_and_types_fini(&nt));
  ASSERT_EQ(
    RMW_RET_OK,
    rmw_get_subscriber_names_and_types_by_node(node, &alloc, "fixture_node", "/ns", false, &nt));
  EXPECT_EQ(std::set<std::string>{"/chatter std_msgs/msg/String"}, names_of(nt));
  EXPECT_EQ(RMW_RET_OK, rmw_names_and_types_fini(&nt));
  ASSERT_EQ(
    RMW_RET_OK, rmw_get_service_names_and_types_by_node(node, &alloc, "fixture_node", "/ns", &nt));
  EXPECT_EQ(std::set<std::string>{"/basic test_msgs/srv/BasicTypes"}, names_of(nt));
  EXPECT_EQ(RMW_RET_OK, rmw_names_and_types_fini(&nt));
  ASSERT_EQ(
    RMW_RET_OK, rmw_get_client_names_and_types_by_node(node, &alloc, "fixture_node", "/ns", &nt));
  EXPECT_EQ(std::set<std::string>{"/basic test_msgs/srv/BasicTypes"}, names_of(nt));
  EXPECT_EQ(RMW_RET_OK, rmw_names_and_types_fini(&nt));

  size_t count = 99;
  EXPECT_EQ(RMW_RET_OK, rmw_count_publishers(node, "/chatter", &count));
  EXPECT_EQ(1u, count);
  EXPECT_EQ(RMW_RET_OK, rmw_count_subscribers(node, "/chatter", &count));
  EXPECT_EQ(1u, count);
  EXPECT_EQ(RMW_RET_OK, rmw_count_services(node, "/basic", &count));
  EXPECT_EQ(1u, count);
  EXPECT_EQ(RMW_RET_OK, rmw_count_clients(node, "/basic", &count));
  EXPECT_EQ(1u, count);
  EXPECT_EQ(RMW_RET_OK, rmw_count_publishers(node, "/nobody", &count));
  EXPECT_EQ(0u, count);
  EXPECT_EQ(RMW_RET_OK, rmw_publisher_count_matched_subscriptions(publisher, &count));
  EXPECT_EQ(1u, count);
  EXPECT_EQ(RMW_RET_OK, rmw_subscription_count_matched_publishers(subscription, &count));
  EXPECT_EQ(1u, count);

  rmw_topic_endpoint_info_array_t infos = rmw_get_zero_initialized_topic_endpoint_info_array();
  ASSERT_EQ(RMW_RET_OK, rmw_get_publishers_info_by_topic(node, &alloc, "/chatter", false, &infos));
  ASSERT_EQ(1u, infos.size);
  EXPECT_STREQ("fixture_node", infos.info_array[0].node_name);
  EXPECT_STREQ("/ns", infos.info_array[0].node_namespace);
  EXPECT_STREQ("std_msgs/msg/String", infos.info_array[0].topic_type);
  EXPECT_EQ(RMW_ENDPOINT_PUBLISHER, infos.info_array[0].endpoint_type);
  EXPECT_EQ(1, infos.info_array[0].topic_type_hash.version);
  EXPECT_EQ(0xdf, infos.info_array[0].topic_type_hash.value[0]);
  EXPECT_EQ(0x18, infos.info_array[0].topic_type_hash.value[31]);
  rmw_gid_t gid;
  ASSERT_EQ(RMW_RET_OK, rmw_get_gid_for_publisher(publisher, &gid));
  EXPECT_EQ(0, std::memcmp(gid.data, infos.info_array[0].endpoint_gid, RMW_GID_STORAGE_SIZE));
  EXPECT_EQ(qos.depth, infos.info_array[0].qos_profile.depth);
  EXPECT_EQ(RMW_RET_OK, rmw_topic_endpoint_info_array_fini(&infos, &alloc));
  ASSERT_EQ(
    RMW_RET_OK, rmw_get_subscriptions_info_by_topic(node, &alloc, "/chatter", false, &infos));
  ASSERT_EQ(1u, infos.size);
  EXPECT_EQ(RMW_ENDPOINT_SUBSCRIPTION, infos.info_array[0].endpoint_type);
  EXPECT_EQ(RMW_RET_OK, rmw_topic_endpoint_info_array_fini(&infos, &alloc));

  // A destroyed endpoint leaves the graph.
  rmw_publisher_t * extra = rmw_create_publisher(node, msg_ts, "/extra", &qos, &pub_options);
  ASSERT_NE(nullptr, extra);
  EXPECT_EQ(RMW_RET_OK, rmw_count_publishers(node, "/extra", &count));
  EXPECT_EQ(1u, count);
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_publisher(node, extra));
  EXPECT_EQ(RMW_RET_OK, rmw_count_publishers(node, "/extra", &count));
  EXPECT_EQ(0u, count);
}

TEST_F(ApiBehaviour, gids_requests_takes_qos)
{
  rmw_gid_t a, b, a2;
  ASSERT_EQ(RMW_RET_OK, rmw_get_gid_for_publisher(publisher, &a));
  ASSERT_EQ(RMW_RET_OK, rmw_get_gid_for_publisher(publisher, &a2));
  ASSERT_EQ(RMW_RET_OK, rmw_get_gid_for_client(client, &b));
  bool equal = false;
  EXPECT_EQ(RMW_RET_OK, rmw_compare_gids_equal(&a, &a2, &equal));
  EXPECT_TRUE(equal);
  EXPECT_EQ(RMW_RET_OK, rmw_compare_gids_equal(&a, &b, &equal));
  EXPECT_FALSE(equal);

  int request = 0;
  int64_t s1 = 0, s2 = 0;
  EXPECT_EQ(RMW_RET_OK, rmw_send_request(client, &request, &s1));
  EXPECT_EQ(RMW_RET_OK, rmw_send_request(client, &request, &s2));
  EXPECT_GT(s1, 0);
  EXPECT_EQ(s1 + 1, s2);
  rmw_service_info_t header{};
  bool taken = true;
  EXPECT_EQ(RMW_RET_OK, rmw_take_response(client, &header, &request, &taken));
  EXPECT_FALSE(taken);
  taken = true;
  EXPECT_EQ(RMW_RET_OK, rmw_take_request(service, &header, &request, &taken));
  EXPECT_FALSE(taken);
  std_msgs__msg__String msg;
  std_msgs__msg__String__init(&msg);
  taken = true;
  EXPECT_EQ(RMW_RET_OK, rmw_take(subscription, &msg, &taken, nullptr));
  EXPECT_FALSE(taken);
  std_msgs__msg__String__fini(&msg);
  bool available = false;
  EXPECT_EQ(RMW_RET_OK, rmw_service_server_is_available(node, client, &available));
  EXPECT_TRUE(available);

  // Actual QoS: concrete policies kept as requested, BEST_AVAILABLE resolved (a publisher
  // makes it TRANSIENT_LOCAL), what was set kept.
  rmw_qos_profile_t requested = rmw_qos_profile_sensor_data;
  requested.durability = RMW_QOS_POLICY_DURABILITY_BEST_AVAILABLE;
  requested.deadline = {1, 500};
  rmw_publisher_t * pub = rmw_create_publisher(node, msg_ts, "/qos", &requested, &pub_options);
  ASSERT_NE(nullptr, pub);
  rmw_qos_profile_t actual{};
  ASSERT_EQ(RMW_RET_OK, rmw_publisher_get_actual_qos(pub, &actual));
  EXPECT_EQ(requested.history, actual.history);
  EXPECT_EQ(requested.depth, actual.depth);
  EXPECT_EQ(requested.reliability, actual.reliability);
  EXPECT_EQ(RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL, actual.durability);
  EXPECT_EQ(1u, actual.deadline.sec);
  EXPECT_EQ(500u, actual.deadline.nsec);
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_publisher(node, pub));
  ASSERT_EQ(RMW_RET_OK, rmw_service_request_subscription_get_actual_qos(service, &actual));
  EXPECT_EQ(rmw_qos_profile_services_default.depth, actual.depth);
  EXPECT_EQ(RMW_QOS_POLICY_RELIABILITY_RELIABLE, actual.reliability);

  // Content filter round trip.
  rmw_subscription_content_filter_options_t filter =
    rmw_get_zero_initialized_content_filter_options();
  rcutils_allocator_t alloc = rcutils_get_default_allocator();
  const char * params[] = {"'x'"};
  ASSERT_EQ(
    RMW_RET_OK,
    rmw_subscription_content_filter_options_init("data = %0", 1, params, &alloc, &filter));
  EXPECT_EQ(RMW_RET_OK, rmw_subscription_set_content_filter(subscription, &filter));
  EXPECT_TRUE(subscription->is_cft_enabled);
  rmw_subscription_content_filter_options_t got = rmw_get_zero_initialized_content_filter_options();
  ASSERT_EQ(RMW_RET_OK, rmw_subscription_get_content_filter(subscription, &alloc, &got));
  EXPECT_STREQ("data = %0", got.filter_expression);
  EXPECT_EQ(RMW_RET_OK, rmw_subscription_content_filter_options_fini(&got, &alloc));
  EXPECT_EQ(RMW_RET_OK, rmw_subscription_content_filter_options_fini(&filter, &alloc));
}

TEST_F(ApiBehaviour, content_filter_is_read_into_an_uninitialised_struct)
{
  // test_subscription.cpp passes an uninitialised struct: nothing in it may be freed.
  rmw_subscription_content_filter_options_t got;
  std::memset(&got, 0xa5, sizeof(got));
  rcutils_allocator_t alloc = rcutils_get_default_allocator();
  rmw_reset_error();
  EXPECT_EQ(RMW_RET_ERROR, rmw_subscription_get_content_filter(subscription, &alloc, &got));
  EXPECT_TRUE(rmw_error_is_set());  // no filter set yet
  rmw_reset_error();

  rmw_subscription_content_filter_options_t filter =
    rmw_get_zero_initialized_content_filter_options();
  const char * params[] = {"3.14159", "'x'"};
  ASSERT_EQ(
    RMW_RET_OK,
    rmw_subscription_content_filter_options_init(
      "float32_value = %0 OR data = %1", 2, params, &alloc, &filter));
  rmw_subscription_options_t options = rmw_get_default_subscription_options();
  options.content_filter_options = &filter;
  rmw_subscription_t * sub = rmw_create_subscription(node, msg_ts, "/filtered", &qos, &options);
  ASSERT_NE(nullptr, sub) << rmw_get_error_string().str;
  EXPECT_EQ(RMW_RET_OK, rmw_subscription_content_filter_options_fini(&filter, &alloc));
  EXPECT_TRUE(sub->is_cft_enabled);

  std::memset(&got, 0xa5, sizeof(got));
  ASSERT_EQ(RMW_RET_OK, rmw_subscription_get_content_filter(sub, &alloc, &got));
  EXPECT_STREQ("float32_value = %0 OR data = %1", got.filter_expression);
  ASSERT_EQ(2u, got.expression_parameters.size);
  EXPECT_STREQ("3.14159", got.expression_parameters.data[0]);
  EXPECT_STREQ("'x'", got.expression_parameters.data[1]);
  EXPECT_EQ(RMW_RET_OK, rmw_subscription_content_filter_options_fini(&got, &alloc));

  // No parameters: the output's parameter array is empty, not garbage.
  rmw_subscription_content_filter_options_t plain =
    rmw_get_zero_initialized_content_filter_options();
  ASSERT_EQ(
    RMW_RET_OK,
    rmw_subscription_content_filter_options_init("data = 'y'", 0, nullptr, &alloc, &plain));
  ASSERT_EQ(RMW_RET_OK, rmw_subscription_set_content_filter(sub, &plain));
  EXPECT_EQ(RMW_RET_OK, rmw_subscription_content_filter_options_fini(&plain, &alloc));
  std::memset(&got, 0xa5, sizeof(got));
  ASSERT_EQ(RMW_RET_OK, rmw_subscription_get_content_filter(sub, &alloc, &got));
  EXPECT_STREQ("data = 'y'", got.filter_expression);
  EXPECT_EQ(0u, got.expression_parameters.size);
  EXPECT_EQ(RMW_RET_OK, rmw_subscription_content_filter_options_fini(&got, &alloc));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_subscription(node, sub));
}

TEST_F(ApiBehaviour, actual_qos_is_resolved_and_the_capture_keeps_the_request)
{
  // test_publisher.cpp:246-252, test_subscription.cpp:254-262: what was left to the
  // middleware comes back concrete, as rmw_fastrtps_cpp resolves it.
  const rmw_qos_profile_t sysdef = rmw_qos_profile_system_default;
  rmw_publisher_t * pub = rmw_create_publisher(node, msg_ts, "/sysdef", &sysdef, &pub_options);
  ASSERT_NE(nullptr, pub);
  rmw_qos_profile_t actual = rmw_qos_profile_unknown;
  ASSERT_EQ(RMW_RET_OK, rmw_publisher_get_actual_qos(pub, &actual));
  EXPECT_EQ(RMW_QOS_POLICY_HISTORY_KEEP_LAST, actual.history);
  EXPECT_EQ(1u, actual.depth);
  EXPECT_EQ(RMW_QOS_POLICY_RELIABILITY_RELIABLE, actual.reliability);  // DataWriter default
  EXPECT_EQ(RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL, actual.durability);
  EXPECT_EQ(RMW_QOS_POLICY_LIVELINESS_AUTOMATIC, actual.liveliness);
  EXPECT_TRUE(is_infinite(actual.deadline));
  EXPECT_TRUE(is_infinite(actual.lifespan));
  EXPECT_TRUE(is_infinite(actual.liveliness_lease_duration));

  rmw_subscription_t * sub =
    rmw_create_subscription(node, msg_ts, "/sysdef", &sysdef, &sub_options);
  ASSERT_NE(nullptr, sub);
  actual = rmw_qos_profile_unknown;
  ASSERT_EQ(RMW_RET_OK, rmw_subscription_get_actual_qos(sub, &actual));
  EXPECT_EQ(RMW_QOS_POLICY_HISTORY_KEEP_LAST, actual.history);
  EXPECT_EQ(1u, actual.depth);
  EXPECT_EQ(RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT, actual.reliability);  // DataReader default
  EXPECT_EQ(RMW_QOS_POLICY_DURABILITY_VOLATILE, actual.durability);
  EXPECT_EQ(RMW_QOS_POLICY_LIVELINESS_AUTOMATIC, actual.liveliness);
  // Resolved this way the two match, as on Fast DDS.
  size_t count = 0;
  EXPECT_EQ(RMW_RET_OK, rmw_publisher_count_matched_subscriptions(pub, &count));
  EXPECT_EQ(1u, count);

  // A depth that was asked for stays; so does a concrete policy.
  rmw_qos_profile_t some = sysdef;
  some.depth = 7;
  some.reliability = RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT;
  rmw_publisher_t * pub7 = rmw_create_publisher(node, msg_ts, "/sysdef7", &some, &pub_options);
  ASSERT_NE(nullptr, pub7);
  ASSERT_EQ(RMW_RET_OK, rmw_publisher_get_actual_qos(pub7, &actual));
  EXPECT_EQ(7u, actual.depth);
  EXPECT_EQ(RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT, actual.reliability);

  // BEST_AVAILABLE (rmw_dds_common rules): a subscription follows the publishers already there
  // (the one here: BEST_EFFORT, TRANSIENT_LOCAL as resolved), a publisher is RELIABLE +
  // TRANSIENT_LOCAL.
  const rmw_qos_profile_t best = rmw_qos_profile_best_available;
  rmw_subscription_t * best_sub =
    rmw_create_subscription(node, msg_ts, "/sysdef7", &best, &sub_options);
  ASSERT_NE(nullptr, best_sub);
  ASSERT_EQ(RMW_RET_OK, rmw_subscription_get_actual_qos(best_sub, &actual));
  EXPECT_EQ(RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT, actual.reliability);
  EXPECT_EQ(RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL, actual.durability);
  EXPECT_EQ(RMW_QOS_POLICY_LIVELINESS_AUTOMATIC, actual.liveliness);
  EXPECT_TRUE(is_infinite(actual.deadline));  // the publisher's (infinite) is the largest
  EXPECT_EQ(RMW_RET_OK, rmw_subscription_count_matched_publishers(best_sub, &count));
  EXPECT_EQ(1u, count);
  rmw_publisher_t * best_pub =
    rmw_create_publisher(node, msg_ts, "/best_alone", &best, &pub_options);
  ASSERT_NE(nullptr, best_pub);
  ASSERT_EQ(RMW_RET_OK, rmw_publisher_get_actual_qos(best_pub, &actual));
  EXPECT_EQ(RMW_QOS_POLICY_RELIABILITY_RELIABLE, actual.reliability);
  EXPECT_EQ(RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL, actual.durability);
  EXPECT_EQ(RMW_QOS_POLICY_LIVELINESS_AUTOMATIC, actual.liveliness);

  // Services and clients: requests are written by the client and read by the service.
  rmw_client_t * cli = rmw_create_client(node, srv_ts, "/sysdef_srv", &sysdef);
  ASSERT_NE(nullptr, cli);
  rmw_service_t * srv = rmw_create_service(node, srv_ts, "/sysdef_srv", &sysdef);
  ASSERT_NE(nullptr, srv);
  ASSERT_EQ(RMW_RET_OK, rmw_client_request_publisher_get_actual_qos(cli, &actual));
  EXPECT_EQ(RMW_QOS_POLICY_RELIABILITY_RELIABLE, actual.reliability);
  EXPECT_EQ(RMW_QOS_POLICY_HISTORY_KEEP_LAST, actual.history);
  ASSERT_EQ(RMW_RET_OK, rmw_client_response_subscription_get_actual_qos(cli, &actual));
  EXPECT_EQ(RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT, actual.reliability);
  ASSERT_EQ(RMW_RET_OK, rmw_service_request_subscription_get_actual_qos(srv, &actual));
  EXPECT_EQ(RMW_QOS_POLICY_DURABILITY_VOLATILE, actual.durability);
  ASSERT_EQ(RMW_RET_OK, rmw_service_response_publisher_get_actual_qos(srv, &actual));
  EXPECT_EQ(RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL, actual.durability);

  // The graph and the capture keep what the node asked for.
  rcutils_allocator_t alloc = rcutils_get_default_allocator();
  rmw_topic_endpoint_info_array_t infos = rmw_get_zero_initialized_topic_endpoint_info_array();
  ASSERT_EQ(RMW_RET_OK, rmw_get_publishers_info_by_topic(node, &alloc, "/sysdef", false, &infos));
  ASSERT_EQ(1u, infos.size);
  EXPECT_EQ(RMW_QOS_POLICY_RELIABILITY_SYSTEM_DEFAULT, infos.info_array[0].qos_profile.reliability);
  EXPECT_EQ(RMW_RET_OK, rmw_topic_endpoint_info_array_fini(&infos, &alloc));
  std::remove(capture_path().c_str());
  ASSERT_EQ(RMW_RET_OK, rmw_shutdown(&context));
  const std::string text = read_file(capture_path());
  const size_t at = text.find("\"name\": \"/sysdef\"");
  ASSERT_NE(std::string::npos, at) << text;
  const size_t next = text.find("\"seq\":", at);
  const std::string entry = text.substr(at, next - at);
  EXPECT_NE(std::string::npos, entry.find("\"reliability\": \"SYSTEM_DEFAULT\"")) << entry;
  EXPECT_NE(std::string::npos, entry.find("\"durability\": \"SYSTEM_DEFAULT\"")) << entry;
  EXPECT_NE(std::string::npos, entry.find("\"history\": \"SYSTEM_DEFAULT\"")) << entry;
  unlink(capture_path().c_str());

  EXPECT_EQ(RMW_RET_OK, rmw_destroy_service(node, srv));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_client(node, cli));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_publisher(node, best_pub));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_subscription(node, best_sub));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_publisher(node, pub7));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_subscription(node, sub));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_publisher(node, pub));
}

TEST_F(ApiBehaviour, matched_counts_follow_qos_compatibility_and_type)
{
  // test_publisher.cpp:413, test_subscription.cpp:424: BEST_EFFORT publisher, RELIABLE
  // subscription in one process: no match on either side.
  rmw_qos_profile_t best_effort = rmw_qos_profile_default;
  best_effort.reliability = RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT;
  rmw_qos_profile_t reliable = rmw_qos_profile_default;
  rmw_publisher_t * pub = rmw_create_publisher(node, msg_ts, "/m", &best_effort, &pub_options);
  ASSERT_NE(nullptr, pub);
  rmw_subscription_t * rsub = rmw_create_subscription(node, msg_ts, "/m", &reliable, &sub_options);
  ASSERT_NE(nullptr, rsub);
  size_t count = 9;
  EXPECT_EQ(RMW_RET_OK, rmw_publisher_count_matched_subscriptions(pub, &count));
  EXPECT_EQ(0u, count);
  EXPECT_EQ(RMW_RET_OK, rmw_subscription_count_matched_publishers(rsub, &count));
  EXPECT_EQ(0u, count);
  // ... still both in the graph.
  EXPECT_EQ(RMW_RET_OK, rmw_count_subscribers(node, "/m", &count));
  EXPECT_EQ(1u, count);

  // A BEST_EFFORT subscription matches.
  rmw_subscription_t * bsub =
    rmw_create_subscription(node, msg_ts, "/m", &best_effort, &sub_options);
  ASSERT_NE(nullptr, bsub);
  EXPECT_EQ(RMW_RET_OK, rmw_publisher_count_matched_subscriptions(pub, &count));
  EXPECT_EQ(1u, count);
  EXPECT_EQ(RMW_RET_OK, rmw_subscription_count_matched_publishers(bsub, &count));
  EXPECT_EQ(1u, count);

  // Other incompatibilities: a deadline the publisher does not offer, TRANSIENT_LOCAL asked of
  // a VOLATILE publisher.
  rmw_qos_profile_t deadline = best_effort;
  deadline.deadline = {1, 0};
  rmw_subscription_t * dsub = rmw_create_subscription(node, msg_ts, "/m", &deadline, &sub_options);
  ASSERT_NE(nullptr, dsub);
  rmw_qos_profile_t latched = best_effort;
  latched.durability = RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL;
  rmw_subscription_t * lsub = rmw_create_subscription(node, msg_ts, "/m", &latched, &sub_options);
  ASSERT_NE(nullptr, lsub);
  EXPECT_EQ(RMW_RET_OK, rmw_publisher_count_matched_subscriptions(pub, &count));
  EXPECT_EQ(1u, count);

  // Another type on the same topic name does not match either.
  const rosidl_message_type_support_t * other_ts =
    ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, action, Fibonacci_FeedbackMessage);
  rmw_subscription_t * tsub =
    rmw_create_subscription(node, other_ts, "/m", &best_effort, &sub_options);
  ASSERT_NE(nullptr, tsub);
  EXPECT_EQ(RMW_RET_OK, rmw_publisher_count_matched_subscriptions(pub, &count));
  EXPECT_EQ(1u, count);
  EXPECT_EQ(RMW_RET_OK, rmw_subscription_count_matched_publishers(tsub, &count));
  EXPECT_EQ(0u, count);

  for (rmw_subscription_t * s : {rsub, bsub, dsub, lsub, tsub}) {
    EXPECT_EQ(RMW_RET_OK, rmw_destroy_subscription(node, s));
  }
  EXPECT_EQ(RMW_RET_OK, rmw_publisher_count_matched_subscriptions(pub, &count));
  EXPECT_EQ(0u, count);
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_publisher(node, pub));
}

TEST_F(ApiBehaviour, without_delivery_nothing_arrives_but_serialization_works)
{
  // RMW_INTROSPECT_DELIVERY is off by default: publishing drops, nothing is ever ready.
  std_msgs__msg__String msg;
  std_msgs__msg__String__init(&msg);
  ASSERT_TRUE(rosidl_runtime_c__String__assign(&msg.data, "round trip"));
  ASSERT_EQ(RMW_RET_OK, rmw_publish(publisher, &msg, nullptr));
  std_msgs__msg__String out;
  std_msgs__msg__String__init(&out);
  bool taken = true;
  ASSERT_EQ(RMW_RET_OK, rmw_take(subscription, &out, &taken, nullptr));
  EXPECT_FALSE(taken);
  void * storage[1] = {subscription->data};
  rmw_subscriptions_t subs{1, storage};
  rmw_time_t timeout{0, 10000000};
  EXPECT_EQ(
    RMW_RET_TIMEOUT, rmw_wait(&subs, nullptr, nullptr, nullptr, nullptr, wait_set, &timeout));
  EXPECT_EQ(nullptr, storage[0]);
  rmw_event_t matched = rmw_get_zero_initialized_event();
  ASSERT_EQ(
    RMW_RET_OK, rmw_publisher_event_init(&matched, publisher, RMW_EVENT_PUBLICATION_MATCHED));
  rmw_matched_status_t status{};
  EXPECT_EQ(RMW_RET_OK, rmw_take_event(&matched, &status, &taken));
  EXPECT_FALSE(taken);
  EXPECT_EQ(RMW_RET_OK, rmw_event_fini(&matched));

  // rmw_serialize / rmw_deserialize: CDR through the type support, C or C++.
  rcutils_allocator_t alloc = rcutils_get_default_allocator();
  rmw_serialized_message_t bytes = rmw_get_zero_initialized_serialized_message();
  ASSERT_EQ(RMW_RET_OK, rmw_serialized_message_init(&bytes, 0u, &alloc));
  ASSERT_EQ(RMW_RET_OK, rmw_serialize(&msg, msg_ts, &bytes));
  EXPECT_EQ(4u + 4u + 11u, bytes.buffer_length);  // header, length, "round trip\0"
  ASSERT_EQ(RMW_RET_OK, rmw_deserialize(&bytes, msg_ts, &out));
  EXPECT_STREQ("round trip", out.data.data);
  std_msgs::msg::String cpp;
  const rosidl_message_type_support_t * cpp_ts =
    rosidl_typesupport_cpp::get_message_type_support_handle<std_msgs::msg::String>();
  ASSERT_EQ(RMW_RET_OK, rmw_deserialize(&bytes, cpp_ts, &cpp));
  EXPECT_EQ("round trip", cpp.data);
  bytes.buffer_length = 6;  // truncated
  EXPECT_RET_WITH_ERROR(RMW_RET_ERROR, rmw_deserialize(&bytes, msg_ts, &out));
  EXPECT_EQ(RMW_RET_OK, rmw_serialized_message_fini(&bytes));
  std_msgs__msg__String__fini(&out);
  std_msgs__msg__String__fini(&msg);
}

TEST_F(ApiBehaviour, cpp_and_action_type_supports_are_recorded)
{
  const rosidl_message_type_support_t * cpp_ts =
    rosidl_typesupport_cpp::get_message_type_support_handle<std_msgs::msg::String>();
  rmw_publisher_t * pub = rmw_create_publisher(node, cpp_ts, "/cpp_topic", &qos, &pub_options);
  ASSERT_NE(nullptr, pub) << rmw_get_error_string().str;
  EXPECT_FALSE(rmw_error_is_set());
  const rosidl_message_type_support_t * feedback_ts =
    ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, action, Fibonacci_FeedbackMessage);
  rmw_subscription_t * sub =
    rmw_create_subscription(node, feedback_ts, "/fib/_action/feedback", &qos, &sub_options);
  ASSERT_NE(nullptr, sub) << rmw_get_error_string().str;
  const rosidl_service_type_support_t * goal_ts =
    ROSIDL_GET_SRV_TYPE_SUPPORT(test_msgs, action, Fibonacci_SendGoal);
  rmw_client_t * cli =
    rmw_create_client(node, goal_ts, "/fib/_action/send_goal", &rmw_qos_profile_services_default);
  ASSERT_NE(nullptr, cli) << rmw_get_error_string().str;
  // A failed lookup inside rosidl's dispatch must not leave an error behind.
  EXPECT_FALSE(rmw_error_is_set()) << rmw_get_error_string().str;

  rcutils_allocator_t alloc = rcutils_get_default_allocator();
  rmw_names_and_types_t nt = rmw_get_zero_initialized_names_and_types();
  ASSERT_EQ(RMW_RET_OK, rmw_get_topic_names_and_types(node, &alloc, false, &nt));
  auto topics = names_of(nt);
  EXPECT_EQ(1u, topics.count("/cpp_topic std_msgs/msg/String"));
  EXPECT_EQ(1u, topics.count("/fib/_action/feedback test_msgs/action/Fibonacci_FeedbackMessage"));
  EXPECT_EQ(RMW_RET_OK, rmw_names_and_types_fini(&nt));
  ASSERT_EQ(RMW_RET_OK, rmw_get_service_names_and_types(node, &alloc, &nt));
  EXPECT_EQ(1u, names_of(nt).count("/fib/_action/send_goal test_msgs/action/Fibonacci_SendGoal"));
  EXPECT_EQ(RMW_RET_OK, rmw_names_and_types_fini(&nt));

  EXPECT_EQ(RMW_RET_OK, rmw_destroy_client(node, cli));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_subscription(node, sub));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_publisher(node, pub));
}

TEST_F(ApiBehaviour, shutdown_writes_the_capture)
{
  std::remove(capture_path().c_str());
  ASSERT_EQ(RMW_RET_OK, rmw_shutdown(&context));
  const std::string text = read_file(capture_path());
  ASSERT_FALSE(text.empty());
  EXPECT_NE(std::string::npos, text.find("\"state\": \"shutdown\""));
  EXPECT_NE(std::string::npos, text.find("\"fqn\": \"/ns/fixture_node\""));
  EXPECT_NE(std::string::npos, text.find("\"name\": \"/chatter\""));
  EXPECT_NE(std::string::npos, text.find("\"type\": \"test_msgs/srv/BasicTypes\""));
  EXPECT_NE(
    std::string::npos,
    text.find(
      "\"type_hash\": "
      "\"RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18\""));
  // The earlier tests destroyed their entities while running: they stay, flagged.
  EXPECT_NE(std::string::npos, text.find("\"name\": \"/copied_topic\""));
  const size_t pos = text.find("\"name\": \"/copied_topic\"");
  const size_t flag = text.find("\"destroyed\": true", pos);
  const size_t next = text.find("\"seq\":", pos);
  EXPECT_LT(flag, next);
  // Destruction after shutdown is teardown: the entity leaves the graph but is not flagged.
  rmw_gid_t gid;
  ASSERT_EQ(RMW_RET_OK, rmw_get_gid_for_publisher(publisher, &gid));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_subscription(node, subscription));
  subscription = nullptr;
  ASSERT_EQ(RMW_RET_OK, rmw_shutdown(&context));  // writes again
  const std::string after = read_file(capture_path());
  // This test runs last: its fixture subscription is the last one recorded.
  const size_t sub_pos = after.rfind("\"kind\": \"subscription\"");
  ASSERT_NE(std::string::npos, sub_pos);
  const size_t sub_flag = after.find("\"destroyed\": ", sub_pos);
  EXPECT_EQ(after.find("\"destroyed\": false", sub_pos), sub_flag);
  size_t count = 9;
  EXPECT_EQ(RMW_RET_OK, rmw_count_subscribers(node, "/chatter", &count));
  EXPECT_EQ(0u, count);
  subscription = rmw_create_subscription(node, msg_ts, "/chatter", &qos, &sub_options);
  ASSERT_NE(nullptr, subscription);
  unlink(capture_path().c_str());
}
