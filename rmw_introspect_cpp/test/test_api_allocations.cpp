// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Every entry point the rmw API documents as "Allocates Memory: No" (rmw/rmw.h; real-time
// executors call them), and the get_actual_qos family and take that test_rmw_implementation
// checks the same way, makes no memory operation. This binary replaces malloc, calloc, realloc
// and free with counting wrappers around glibc's own (the interposition technique of
// osrf_testing_tools_cpp's memory tools, written here from scratch) and counts the calls the
// calling thread makes inside a window.
//
// Each call runs first on a thread that never called the middleware before: what a thread sets
// up lazily on its first call (a map entry keyed by its id, a thread_local with dynamic TLS) is
// the regression this catches (a 48-byte std::map node in rmw_publisher_count_matched_subscriptions
// took test_rmw_implementation's memcheck configuration to 130/132 on 2026-11-28).

#include <gtest/gtest.h>

#include <cstddef>
#include <functional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "api_fixture.hpp"

extern "C" {
void * __libc_malloc(size_t size);
void * __libc_calloc(size_t count, size_t size);
void * __libc_realloc(void * ptr, size_t size);
void __libc_free(void * ptr);
}

namespace
{
struct Operations
{
  size_t allocations = 0;  // malloc, calloc, realloc
  size_t frees = 0;
};

thread_local bool counting = false;
thread_local Operations counted;

void note_allocation()
{
  if (counting) {
    ++counted.allocations;
  }
}

/// Memory operations of this thread while `fn` runs.
template<typename Fn>
Operations memory_operations(Fn fn)
{
  counted = Operations{};
  counting = true;
  fn();
  counting = false;
  return counted;
}

/// Memory operations of a new thread while `fn` runs in it (the thread's first middleware call).
Operations memory_operations_on_new_thread(const std::function<void()> & fn)
{
  Operations result;
  std::thread([&]() { result = memory_operations(fn); }).join();
  return result;
}

/// A named call and the return code it must give (checked outside the counting window: a
/// failing gtest assertion allocates its message).
struct Call
{
  std::string name;
  std::function<rmw_ret_t()> run;
};

/// Each call, on a fresh thread and then again on this one: no allocation and no free.
void expect_no_memory_operations(const std::vector<Call> & calls)
{
  for (const Call & call : calls) {
    rmw_ret_t ret = RMW_RET_ERROR;
    const Operations fresh = memory_operations_on_new_thread([&]() { ret = call.run(); });
    EXPECT_EQ(RMW_RET_OK, ret) << call.name << ": " << rmw_get_error_string().str;
    EXPECT_EQ(0u, fresh.allocations) << call.name << " allocated on a thread's first call";
    EXPECT_EQ(0u, fresh.frees) << call.name << " freed on a thread's first call";
    const Operations again = memory_operations([&]() { ret = call.run(); });
    EXPECT_EQ(RMW_RET_OK, ret) << call.name;
    EXPECT_EQ(0u, again.allocations) << call.name << " allocated";
    EXPECT_EQ(0u, again.frees) << call.name << " freed";
  }
}
}  // namespace

extern "C" {
void * malloc(size_t size)
{
  note_allocation();
  return __libc_malloc(size);
}

void * calloc(size_t count, size_t size)
{
  note_allocation();
  return __libc_calloc(count, size);
}

void * realloc(void * ptr, size_t size)
{
  note_allocation();
  return __libc_realloc(ptr, size);
}

void free(void * ptr)
{
  if (ptr != nullptr && counting) {
    ++counted.frees;
  }
  __libc_free(ptr);
}
}

using ApiAllocations = ApiFixture;

TEST_F(ApiAllocations, the_counter_sees_allocations_and_frees_on_any_thread)
{
  void * (*volatile allocate)(size_t) = malloc;  // volatile: not optimised away
  const Operations here = memory_operations([&]() { free(allocate(16)); });
  EXPECT_EQ(1u, here.allocations);
  EXPECT_EQ(1u, here.frees);
  const Operations there = memory_operations_on_new_thread([&]() { free(allocate(16)); });
  EXPECT_EQ(1u, there.allocations);
  EXPECT_EQ(1u, there.frees);
  // A call that does allocate is seen: creating a subscription (and destroying it frees).
  rmw_ret_t destroyed = RMW_RET_ERROR;
  const Operations create = memory_operations_on_new_thread([&]() {
    rmw_subscription_t * sub =
      rmw_create_subscription(node, msg_ts, "/chatter", &qos, &sub_options);
    destroyed = rmw_destroy_subscription(node, sub);
  });
  EXPECT_EQ(RMW_RET_OK, destroyed);
  EXPECT_GT(create.allocations, 0u);
  EXPECT_GT(create.frees, 0u);
}

TEST_F(ApiAllocations, matched_and_graph_counts_make_no_memory_operation)
{
  // No warm-up on purpose: test_rmw_implementation's first call of a test is counted.
  size_t count = 99;
  expect_no_memory_operations({
    {"rmw_publisher_count_matched_subscriptions",
     [&]() { return rmw_publisher_count_matched_subscriptions(publisher, &count); }},
    {"rmw_subscription_count_matched_publishers",
     [&]() { return rmw_subscription_count_matched_publishers(subscription, &count); }},
    {"rmw_count_publishers", [&]() { return rmw_count_publishers(node, "/chatter", &count); }},
    {"rmw_count_subscribers", [&]() { return rmw_count_subscribers(node, "/chatter", &count); }},
    {"rmw_count_services", [&]() { return rmw_count_services(node, "/basic", &count); }},
    {"rmw_count_clients", [&]() { return rmw_count_clients(node, "/basic", &count); }},
  });
  size_t matched = 0;
  ASSERT_EQ(RMW_RET_OK, rmw_publisher_count_matched_subscriptions(publisher, &matched));
  EXPECT_EQ(1u, matched);
  ASSERT_EQ(RMW_RET_OK, rmw_subscription_count_matched_publishers(subscription, &matched));
  EXPECT_EQ(1u, matched);
  ASSERT_EQ(RMW_RET_OK, rmw_count_clients(node, "/basic", &matched));
  EXPECT_EQ(1u, matched);
}

TEST_F(ApiAllocations, gids_actual_qos_and_queries_make_no_memory_operation)
{
  rmw_gid_t pub_gid{};
  rmw_gid_t client_gid{};
  bool equal = false;
  bool available = false;
  rmw_qos_profile_t actual{};
  ASSERT_EQ(RMW_RET_OK, rmw_get_gid_for_publisher(publisher, &pub_gid));
  expect_no_memory_operations({
    {"rmw_get_gid_for_publisher", [&]() { return rmw_get_gid_for_publisher(publisher, &pub_gid); }},
    {"rmw_get_gid_for_client", [&]() { return rmw_get_gid_for_client(client, &client_gid); }},
    {"rmw_compare_gids_equal",
     [&]() { return rmw_compare_gids_equal(&pub_gid, &pub_gid, &equal); }},
    {"rmw_publisher_get_actual_qos",
     [&]() { return rmw_publisher_get_actual_qos(publisher, &actual); }},
    {"rmw_subscription_get_actual_qos",
     [&]() { return rmw_subscription_get_actual_qos(subscription, &actual); }},
    {"rmw_client_request_publisher_get_actual_qos",
     [&]() { return rmw_client_request_publisher_get_actual_qos(client, &actual); }},
    {"rmw_client_response_subscription_get_actual_qos",
     [&]() { return rmw_client_response_subscription_get_actual_qos(client, &actual); }},
    {"rmw_service_request_subscription_get_actual_qos",
     [&]() { return rmw_service_request_subscription_get_actual_qos(service, &actual); }},
    {"rmw_service_response_publisher_get_actual_qos",
     [&]() { return rmw_service_response_publisher_get_actual_qos(service, &actual); }},
    {"rmw_publisher_assert_liveliness",
     [&]() { return rmw_publisher_assert_liveliness(publisher); }},
    {"rmw_node_get_graph_guard_condition",
     [&]() { return rmw_node_get_graph_guard_condition(node) ? RMW_RET_OK : RMW_RET_ERROR; }},
    {"rmw_service_server_is_available",
     [&]() { return rmw_service_server_is_available(node, client, &available); }},
  });
  EXPECT_TRUE(equal);
}

TEST_F(ApiAllocations, take_without_message_info_makes_no_memory_operation)
{
  std_msgs__msg__String message;
  ASSERT_TRUE(std_msgs__msg__String__init(&message));
  bool taken = true;
  expect_no_memory_operations({
    {"rmw_take", [&]() { return rmw_take(subscription, &message, &taken, nullptr); }},
  });
  EXPECT_FALSE(taken);
  std_msgs__msg__String__fini(&message);
}

TEST_F(ApiAllocations, destroying_an_entity_allocates_nothing)
{
  // The destroy functions are "Allocates Memory: No" too: freeing is what they are for, so only
  // allocations are counted.
  const rmw_qos_profile_t services_qos = rmw_qos_profile_services_default;
  rmw_publisher_t * pub = rmw_create_publisher(node, msg_ts, "/other", &qos, &pub_options);
  rmw_subscription_t * sub = rmw_create_subscription(node, msg_ts, "/other", &qos, &sub_options);
  rmw_service_t * srv = rmw_create_service(node, srv_ts, "/other_srv", &services_qos);
  rmw_client_t * cli = rmw_create_client(node, srv_ts, "/other_srv", &services_qos);
  rmw_wait_set_t * ws = rmw_create_wait_set(&context, 4);
  ASSERT_TRUE(pub && sub && srv && cli && ws) << rmw_get_error_string().str;
  const std::vector<std::pair<std::string, std::function<rmw_ret_t()>>> destroys{
    {"rmw_destroy_publisher", [&]() { return rmw_destroy_publisher(node, pub); }},
    {"rmw_destroy_subscription", [&]() { return rmw_destroy_subscription(node, sub); }},
    {"rmw_destroy_service", [&]() { return rmw_destroy_service(node, srv); }},
    {"rmw_destroy_client", [&]() { return rmw_destroy_client(node, cli); }},
    {"rmw_destroy_wait_set", [&]() { return rmw_destroy_wait_set(ws); }},
  };
  for (const auto & destroy : destroys) {
    rmw_ret_t ret = RMW_RET_ERROR;
    const Operations fresh = memory_operations_on_new_thread([&]() { ret = destroy.second(); });
    EXPECT_EQ(RMW_RET_OK, ret) << destroy.first;
    EXPECT_EQ(0u, fresh.allocations) << destroy.first << " allocated";
  }
}
