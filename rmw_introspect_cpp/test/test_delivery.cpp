// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// In-process delivery (RMW_INTROSPECT_DELIVERY=1): messages from publishers to the matching
// subscriptions of the process (C and C++ type supports, QoS, content filters, ignore_local,
// KEEP_LAST, TRANSIENT_LOCAL), requests and responses, matched events, and rmw_wait waking.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

#include "rcutils/allocator.h"
#include "rmw/events_statuses/matched.h"
#include "rmw/serialized_message.h"
#include "rmw/subscription_content_filter_options.h"
#include "rosidl_runtime_c/string_functions.h"
#include "rosidl_typesupport_cpp/message_type_support.hpp"
#include "std_msgs/msg/string.hpp"
#include "test_msgs/msg/basic_types.h"
#include "test_msgs/srv/basic_types.h"

#include "api_fixture.hpp"

namespace
{
struct SetEnvironment
{
  SetEnvironment()
  {
    setenv("RMW_INTROSPECT_DELIVERY", "1", 1);
    setenv("RMW_INTROSPECT_SERVER_AVAILABLE", "0", 1);
    setenv("RMW_INTROSPECT_AUTO_EXPORT", "0", 1);
  }
} set_environment;

class StringMessage
{
public:
  explicit StringMessage(const char * text = "")
  {
    std_msgs__msg__String__init(&msg);
    rosidl_runtime_c__String__assign(&msg.data, text);
  }
  ~StringMessage() { std_msgs__msg__String__fini(&msg); }
  std_msgs__msg__String msg;
};

/// Take one message from `sub` and return its text ("<none>" when nothing was taken).
std::string take_text(rmw_subscription_t * sub, rmw_message_info_t * info = nullptr)
{
  StringMessage out;
  bool taken = false;
  rmw_message_info_t ignored = rmw_get_zero_initialized_message_info();
  EXPECT_EQ(RMW_RET_OK, rmw_take_with_info(sub, &out.msg, &taken, info ? info : &ignored, nullptr));
  return taken ? std::string(out.msg.data.data) : std::string("<none>");
}

const rmw_time_t kZeroTimeout{0, 0};
std::atomic<size_t> callback_calls{0};
void count_callback(const void *, size_t number)
{
  callback_calls += number;
}
}  // namespace

using Delivery = ApiFixture;

TEST_F(Delivery, a_message_reaches_the_matching_subscriptions_of_the_process)
{
  // The fixture's publisher and subscription share /chatter.
  StringMessage hello("hello");
  ASSERT_EQ(RMW_RET_OK, rmw_publish(publisher, &hello.msg, nullptr));
  rmw_message_info_t info = rmw_get_zero_initialized_message_info();
  EXPECT_EQ("hello", take_text(subscription, &info));
  EXPECT_EQ("<none>", take_text(subscription));
  rmw_gid_t gid;
  ASSERT_EQ(RMW_RET_OK, rmw_get_gid_for_publisher(publisher, &gid));
  EXPECT_EQ(0, std::memcmp(gid.data, info.publisher_gid.data, RMW_GID_STORAGE_SIZE));
  EXPECT_GT(info.publication_sequence_number, 0u);
  EXPECT_GT(info.source_timestamp, 0);
  EXPECT_FALSE(info.from_intra_process);

  // A C++ subscription gets what the C publisher sent.
  const rosidl_message_type_support_t * cpp_ts =
    rosidl_typesupport_cpp::get_message_type_support_handle<std_msgs::msg::String>();
  rmw_subscription_t * cpp_sub =
    rmw_create_subscription(node, cpp_ts, "/chatter", &qos, &sub_options);
  ASSERT_NE(nullptr, cpp_sub);
  StringMessage again("again");
  ASSERT_EQ(RMW_RET_OK, rmw_publish(publisher, &again.msg, nullptr));
  std_msgs::msg::String cpp_out;
  bool taken = false;
  ASSERT_EQ(RMW_RET_OK, rmw_take(cpp_sub, &cpp_out, &taken, nullptr));
  EXPECT_TRUE(taken);
  EXPECT_EQ("again", cpp_out.data);
  EXPECT_EQ("again", take_text(subscription));

  // Not to another topic, not across incompatible QoS (BEST_EFFORT pub, RELIABLE sub).
  rmw_qos_profile_t best_effort = qos;
  best_effort.reliability = RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT;
  rmw_publisher_t * lossy =
    rmw_create_publisher(node, msg_ts, "/chatter", &best_effort, &pub_options);
  ASSERT_NE(nullptr, lossy);
  ASSERT_EQ(RMW_RET_OK, rmw_publish(lossy, &again.msg, nullptr));
  EXPECT_EQ("<none>", take_text(subscription));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_publisher(node, lossy));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_subscription(node, cpp_sub));
}

TEST_F(Delivery, history_depth_ignore_local_and_transient_local)
{
  rmw_qos_profile_t two = qos;
  two.depth = 2;
  rmw_subscription_t * shallow =
    rmw_create_subscription(node, msg_ts, "/depth", &two, &sub_options);
  rmw_subscription_options_t ignore = sub_options;
  ignore.ignore_local_publications = true;
  rmw_subscription_t * deaf = rmw_create_subscription(node, msg_ts, "/depth", &qos, &ignore);
  rmw_publisher_t * pub = rmw_create_publisher(node, msg_ts, "/depth", &qos, &pub_options);
  ASSERT_TRUE(shallow && deaf && pub);
  for (const char * text : {"one", "two", "three"}) {
    StringMessage m(text);
    ASSERT_EQ(RMW_RET_OK, rmw_publish(pub, &m.msg, nullptr));
  }
  EXPECT_EQ("two", take_text(shallow));  // KEEP_LAST 2: "one" was dropped
  EXPECT_EQ("three", take_text(shallow));
  EXPECT_EQ("<none>", take_text(deaf));  // same context: local

  // TRANSIENT_LOCAL: a late TRANSIENT_LOCAL subscription gets the last `depth` samples.
  rmw_qos_profile_t latched = qos;
  latched.durability = RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL;
  latched.depth = 2;
  rmw_publisher_t * map = rmw_create_publisher(node, msg_ts, "/map", &latched, &pub_options);
  ASSERT_NE(nullptr, map);
  for (const char * text : {"v1", "v2", "v3"}) {
    StringMessage m(text);
    ASSERT_EQ(RMW_RET_OK, rmw_publish(map, &m.msg, nullptr));
  }
  rmw_subscription_t * late = rmw_create_subscription(node, msg_ts, "/map", &latched, &sub_options);
  rmw_subscription_t * volatile_late =
    rmw_create_subscription(node, msg_ts, "/map", &qos, &sub_options);
  ASSERT_TRUE(late && volatile_late);
  EXPECT_EQ("v2", take_text(late));
  EXPECT_EQ("v3", take_text(late));
  EXPECT_EQ("<none>", take_text(late));
  EXPECT_EQ("<none>", take_text(volatile_late));

  for (rmw_subscription_t * s : {shallow, deaf, late, volatile_late}) {
    EXPECT_EQ(RMW_RET_OK, rmw_destroy_subscription(node, s));
  }
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_publisher(node, map));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_publisher(node, pub));
}

TEST_F(Delivery, content_filters_select_what_arrives)
{
  rcutils_allocator_t alloc = rcutils_get_default_allocator();
  rmw_subscription_content_filter_options_t filter =
    rmw_get_zero_initialized_content_filter_options();
  const char * params[] = {"'keep%'"};
  ASSERT_EQ(
    RMW_RET_OK,
    rmw_subscription_content_filter_options_init("data LIKE %0", 1, params, &alloc, &filter));
  ASSERT_EQ(RMW_RET_OK, rmw_subscription_set_content_filter(subscription, &filter));
  EXPECT_EQ(RMW_RET_OK, rmw_subscription_content_filter_options_fini(&filter, &alloc));
  for (const char * text : {"drop me", "keep me", "drop too", "keep too"}) {
    StringMessage m(text);
    ASSERT_EQ(RMW_RET_OK, rmw_publish(publisher, &m.msg, nullptr));
  }
  EXPECT_EQ("keep me", take_text(subscription));
  EXPECT_EQ("keep too", take_text(subscription));
  EXPECT_EQ("<none>", take_text(subscription));

  // An empty expression resets the filter.
  rmw_subscription_content_filter_options_t reset =
    rmw_get_zero_initialized_content_filter_options();
  ASSERT_EQ(
    RMW_RET_OK, rmw_subscription_content_filter_options_init("", 0, nullptr, &alloc, &reset));
  ASSERT_EQ(RMW_RET_OK, rmw_subscription_set_content_filter(subscription, &reset));
  EXPECT_EQ(RMW_RET_OK, rmw_subscription_content_filter_options_fini(&reset, &alloc));
  EXPECT_FALSE(subscription->is_cft_enabled);
  StringMessage m("anything");
  ASSERT_EQ(RMW_RET_OK, rmw_publish(publisher, &m.msg, nullptr));
  EXPECT_EQ("anything", take_text(subscription));
}

TEST_F(Delivery, serialized_publish_and_take_and_take_sequence)
{
  StringMessage m("serialized");
  rcutils_allocator_t alloc = rcutils_get_default_allocator();
  rmw_serialized_message_t bytes = rmw_get_zero_initialized_serialized_message();
  ASSERT_EQ(RMW_RET_OK, rmw_serialized_message_init(&bytes, 0u, &alloc));
  ASSERT_EQ(RMW_RET_OK, rmw_serialize(&m.msg, msg_ts, &bytes));
  ASSERT_EQ(RMW_RET_OK, rmw_publish_serialized_message(publisher, &bytes, nullptr));
  EXPECT_EQ("serialized", take_text(subscription));

  ASSERT_EQ(RMW_RET_OK, rmw_publish(publisher, &m.msg, nullptr));
  rmw_serialized_message_t got = rmw_get_zero_initialized_serialized_message();
  ASSERT_EQ(RMW_RET_OK, rmw_serialized_message_init(&got, 0u, &alloc));
  bool taken = false;
  ASSERT_EQ(RMW_RET_OK, rmw_take_serialized_message(subscription, &got, &taken, nullptr));
  ASSERT_TRUE(taken);
  ASSERT_EQ(bytes.buffer_length, got.buffer_length);
  EXPECT_EQ(0, std::memcmp(bytes.buffer, got.buffer, got.buffer_length));
  EXPECT_EQ(RMW_RET_OK, rmw_serialized_message_fini(&got));
  EXPECT_EQ(RMW_RET_OK, rmw_serialized_message_fini(&bytes));

  // take_sequence takes up to `count`.
  for (const char * text : {"a", "b", "c"}) {
    StringMessage s(text);
    ASSERT_EQ(RMW_RET_OK, rmw_publish(publisher, &s.msg, nullptr));
  }
  StringMessage out[2];
  rmw_message_sequence_t seq = rmw_get_zero_initialized_message_sequence();
  rmw_message_info_sequence_t infos = rmw_get_zero_initialized_message_info_sequence();
  ASSERT_EQ(RMW_RET_OK, rmw_message_sequence_init(&seq, 2, &alloc));
  ASSERT_EQ(RMW_RET_OK, rmw_message_info_sequence_init(&infos, 2, &alloc));
  seq.data[0] = &out[0].msg;
  seq.data[1] = &out[1].msg;
  size_t n = 0;
  ASSERT_EQ(RMW_RET_OK, rmw_take_sequence(subscription, 2, &seq, &infos, &n, nullptr));
  EXPECT_EQ(2u, n);
  EXPECT_EQ(2u, seq.size);
  EXPECT_STREQ("a", out[0].msg.data.data);
  EXPECT_STREQ("b", out[1].msg.data.data);
  EXPECT_LT(infos.data[0].publication_sequence_number, infos.data[1].publication_sequence_number);
  EXPECT_EQ("c", take_text(subscription));
  EXPECT_EQ(RMW_RET_OK, rmw_message_sequence_fini(&seq));
  EXPECT_EQ(RMW_RET_OK, rmw_message_info_sequence_fini(&infos));
}

TEST_F(Delivery, a_request_reaches_the_service_and_its_response_the_client)
{
  test_msgs__srv__BasicTypes_Request request;
  test_msgs__srv__BasicTypes_Request__init(&request);
  request.int32_value = 21;
  int64_t sequence = 0;
  ASSERT_EQ(RMW_RET_OK, rmw_send_request(client, &request, &sequence));

  rmw_service_info_t header{};
  test_msgs__srv__BasicTypes_Request got;
  test_msgs__srv__BasicTypes_Request__init(&got);
  bool taken = false;
  ASSERT_EQ(RMW_RET_OK, rmw_take_request(service, &header, &got, &taken));
  ASSERT_TRUE(taken);
  EXPECT_EQ(21, got.int32_value);
  EXPECT_EQ(sequence, header.request_id.sequence_number);

  test_msgs__srv__BasicTypes_Response response;
  test_msgs__srv__BasicTypes_Response__init(&response);
  response.int32_value = 42;
  ASSERT_EQ(RMW_RET_OK, rmw_send_response(service, &header.request_id, &response));
  test_msgs__srv__BasicTypes_Response answer;
  test_msgs__srv__BasicTypes_Response__init(&answer);
  rmw_service_info_t answer_header{};
  ASSERT_EQ(RMW_RET_OK, rmw_take_response(client, &answer_header, &answer, &taken));
  ASSERT_TRUE(taken);
  EXPECT_EQ(42, answer.int32_value);
  EXPECT_EQ(sequence, answer_header.request_id.sequence_number);
  ASSERT_EQ(RMW_RET_OK, rmw_take_response(client, &answer_header, &answer, &taken));
  EXPECT_FALSE(taken);

  // A response to a client that is gone is dropped, RMW_RET_OK.
  rmw_client_t * gone =
    rmw_create_client(node, srv_ts, "/basic", &rmw_qos_profile_services_default);
  ASSERT_NE(nullptr, gone);
  ASSERT_EQ(RMW_RET_OK, rmw_send_request(gone, &request, &sequence));
  ASSERT_EQ(RMW_RET_OK, rmw_take_request(service, &header, &got, &taken));
  ASSERT_TRUE(taken);
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_client(node, gone));
  EXPECT_EQ(RMW_RET_OK, rmw_send_response(service, &header.request_id, &response));

  test_msgs__srv__BasicTypes_Response__fini(&answer);
  test_msgs__srv__BasicTypes_Response__fini(&response);
  test_msgs__srv__BasicTypes_Request__fini(&got);
  test_msgs__srv__BasicTypes_Request__fini(&request);
}

TEST_F(Delivery, rmw_wait_wakes_for_data_and_keeps_only_ready_entries)
{
  void * subs_storage[1] = {subscription->data};
  rmw_subscriptions_t subs{1, subs_storage};
  rmw_time_t short_timeout{0, 20000000};
  EXPECT_EQ(
    RMW_RET_TIMEOUT, rmw_wait(&subs, nullptr, nullptr, nullptr, nullptr, wait_set, &short_timeout));
  EXPECT_EQ(nullptr, subs.subscribers[0]);

  // A publish from another thread wakes a wait that would last 10 s.
  std::thread later([this]() {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    StringMessage m("wake up");
    EXPECT_EQ(RMW_RET_OK, rmw_publish(publisher, &m.msg, nullptr));
  });
  subs_storage[0] = subscription->data;
  rmw_time_t long_timeout{10, 0};
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(
    RMW_RET_OK, rmw_wait(&subs, nullptr, nullptr, nullptr, nullptr, wait_set, &long_timeout));
  later.join();
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
  EXPECT_EQ(subscription->data, subs.subscribers[0]);
  EXPECT_EQ("wake up", take_text(subscription));

  // Services and clients likewise.
  test_msgs__srv__BasicTypes_Request request;
  test_msgs__srv__BasicTypes_Request__init(&request);
  int64_t sequence = 0;
  ASSERT_EQ(RMW_RET_OK, rmw_send_request(client, &request, &sequence));
  void * srv_storage[1] = {service->data};
  rmw_services_t srvs{1, srv_storage};
  void * cli_storage[1] = {client->data};
  rmw_clients_t clis{1, cli_storage};
  EXPECT_EQ(RMW_RET_OK, rmw_wait(nullptr, nullptr, &srvs, &clis, nullptr, wait_set, &long_timeout));
  EXPECT_EQ(service->data, srvs.services[0]);
  EXPECT_EQ(nullptr, clis.clients[0]);
  test_msgs__srv__BasicTypes_Request__fini(&request);
}

TEST_F(Delivery, matched_events_follow_the_graph)
{
  rmw_publisher_t * pub = rmw_create_publisher(node, msg_ts, "/matched", &qos, &pub_options);
  ASSERT_NE(nullptr, pub);
  rmw_event_t event = rmw_get_zero_initialized_event();
  ASSERT_EQ(RMW_RET_OK, rmw_publisher_event_init(&event, pub, RMW_EVENT_PUBLICATION_MATCHED));
  callback_calls = 0;
  ASSERT_EQ(RMW_RET_OK, rmw_event_set_callback(&event, count_callback, nullptr));
  rmw_matched_status_t status{};
  bool taken = false;
  ASSERT_EQ(RMW_RET_OK, rmw_take_event(&event, &status, &taken));
  EXPECT_TRUE(taken);
  EXPECT_EQ(0u, status.current_count);

  rmw_subscription_t * a = rmw_create_subscription(node, msg_ts, "/matched", &qos, &sub_options);
  rmw_subscription_t * b = rmw_create_subscription(node, msg_ts, "/matched", &qos, &sub_options);
  rmw_qos_profile_t strict = qos;
  strict.deadline = {1, 0};  // the publisher offers none: incompatible, not matched
  rmw_subscription_t * c = rmw_create_subscription(node, msg_ts, "/matched", &strict, &sub_options);
  ASSERT_TRUE(a && b && c);
  EXPECT_EQ(2u, callback_calls.load());
  void * events_storage[1] = {&event};
  rmw_events_t events{1, events_storage};
  rmw_time_t timeout{1, 0};
  EXPECT_EQ(RMW_RET_OK, rmw_wait(nullptr, nullptr, nullptr, nullptr, &events, wait_set, &timeout));
  EXPECT_EQ(&event, events.events[0]);
  ASSERT_EQ(RMW_RET_OK, rmw_take_event(&event, &status, &taken));
  EXPECT_EQ(2u, status.total_count);
  EXPECT_EQ(2u, status.total_count_change);
  EXPECT_EQ(2u, status.current_count);
  EXPECT_EQ(2, status.current_count_change);

  EXPECT_EQ(RMW_RET_OK, rmw_destroy_subscription(node, a));
  ASSERT_EQ(RMW_RET_OK, rmw_take_event(&event, &status, &taken));
  EXPECT_EQ(2u, status.total_count);
  EXPECT_EQ(0u, status.total_count_change);
  EXPECT_EQ(1u, status.current_count);
  EXPECT_EQ(-1, status.current_count_change);
  events_storage[0] = &event;
  EXPECT_EQ(
    RMW_RET_TIMEOUT,
    rmw_wait(nullptr, nullptr, nullptr, nullptr, &events, wait_set, &kZeroTimeout));
  EXPECT_EQ(nullptr, events.events[0]);

  // The subscription side too.
  rmw_event_t sub_matched = rmw_get_zero_initialized_event();
  ASSERT_EQ(
    RMW_RET_OK, rmw_subscription_event_init(&sub_matched, b, RMW_EVENT_SUBSCRIPTION_MATCHED));
  ASSERT_EQ(RMW_RET_OK, rmw_take_event(&sub_matched, &status, &taken));
  EXPECT_EQ(1u, status.current_count);

  EXPECT_EQ(RMW_RET_OK, rmw_event_fini(&sub_matched));
  EXPECT_EQ(RMW_RET_OK, rmw_event_fini(&event));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_subscription(node, c));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_subscription(node, b));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_publisher(node, pub));
}

TEST_F(Delivery, plain_types_can_loan)
{
  // As on rmw_fastrtps_cpp: plain (fixed-size) types can loan, others cannot.
  EXPECT_FALSE(publisher->can_loan_messages);  // std_msgs/String holds a string
  EXPECT_FALSE(subscription->can_loan_messages);
  const rosidl_message_type_support_t * basic =
    ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, BasicTypes);
  rmw_publisher_t * pub = rmw_create_publisher(node, basic, "/plain", &qos, &pub_options);
  rmw_subscription_t * sub = rmw_create_subscription(node, basic, "/plain", &qos, &sub_options);
  ASSERT_TRUE(pub && sub);
  ASSERT_TRUE(pub->can_loan_messages);
  ASSERT_TRUE(sub->can_loan_messages);

  void * loan = nullptr;
  ASSERT_EQ(RMW_RET_OK, rmw_borrow_loaned_message(pub, basic, &loan));
  ASSERT_NE(nullptr, loan);
  EXPECT_RET_WITH_ERROR(RMW_RET_INVALID_ARGUMENT, rmw_borrow_loaned_message(pub, basic, &loan));
  static_cast<test_msgs__msg__BasicTypes *>(loan)->int64_value = -77;
  ASSERT_EQ(RMW_RET_OK, rmw_publish_loaned_message(pub, loan, nullptr));
  test_msgs__msg__BasicTypes not_loaned;
  test_msgs__msg__BasicTypes__init(&not_loaned);
  EXPECT_RET_WITH_ERROR(
    RMW_RET_INVALID_ARGUMENT, rmw_publish_loaned_message(pub, &not_loaned, nullptr));
  EXPECT_RET_WITH_ERROR(RMW_RET_ERROR, rmw_return_loaned_message_from_publisher(pub, &not_loaned));

  void * taken_loan = nullptr;
  bool taken = false;
  rmw_message_info_t info = rmw_get_zero_initialized_message_info();
  ASSERT_EQ(
    RMW_RET_OK, rmw_take_loaned_message_with_info(sub, &taken_loan, &taken, &info, nullptr));
  ASSERT_TRUE(taken);
  EXPECT_EQ(-77, static_cast<test_msgs__msg__BasicTypes *>(taken_loan)->int64_value);
  EXPECT_GT(info.publication_sequence_number, 0u);
  EXPECT_RET_WITH_ERROR(
    RMW_RET_ERROR, rmw_return_loaned_message_from_subscription(sub, &not_loaned));
  EXPECT_EQ(RMW_RET_OK, rmw_return_loaned_message_from_subscription(sub, taken_loan));
  void * none = nullptr;
  ASSERT_EQ(RMW_RET_OK, rmw_take_loaned_message(sub, &none, &taken, nullptr));
  EXPECT_FALSE(taken);
  EXPECT_EQ(nullptr, none);

  // A loan still out when its publisher goes is freed with it (no leak under ASan).
  void * forgotten = nullptr;
  ASSERT_EQ(RMW_RET_OK, rmw_borrow_loaned_message(pub, basic, &forgotten));
  test_msgs__msg__BasicTypes__fini(&not_loaned);
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_subscription(node, sub));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_publisher(node, pub));
}
