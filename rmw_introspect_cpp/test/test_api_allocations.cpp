// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// The entry points test_rmw_implementation runs under osrf_testing_tools_cpp's
// EXPECT_NO_MEMORY_OPERATIONS (matched and graph counts) allocate nothing. This binary replaces
// malloc & co. to count the calls its own thread makes inside a window.

#include <gtest/gtest.h>

#include <cstddef>

#include "api_fixture.hpp"

extern "C"
{
void * __libc_malloc(size_t size);
void * __libc_calloc(size_t count, size_t size);
void * __libc_realloc(void * ptr, size_t size);
void __libc_free(void * ptr);
}

namespace
{
thread_local bool counting = false;
thread_local size_t operations = 0;

void note()
{
  if (counting) {
    ++operations;
  }
}

/// Memory operations of this thread while `fn` runs.
template<typename Fn>
size_t memory_operations(Fn fn)
{
  operations = 0;
  counting = true;
  fn();
  counting = false;
  return operations;
}
}  // namespace

extern "C"
{
void * malloc(size_t size)
{
  note();
  return __libc_malloc(size);
}

void * calloc(size_t count, size_t size)
{
  note();
  return __libc_calloc(count, size);
}

void * realloc(void * ptr, size_t size)
{
  note();
  return __libc_realloc(ptr, size);
}

void free(void * ptr)
{
  if (ptr != nullptr) {
    note();
  }
  __libc_free(ptr);
}
}

using ApiAllocations = ApiFixture;

TEST_F(ApiAllocations, the_counter_sees_allocations)
{
  void * (* volatile allocate)(size_t) = malloc;  // volatile: not optimised away
  EXPECT_EQ(2u, memory_operations([&]() {free(allocate(16));}));
  // The publisher's count once allocated: a std::function too large for its inline storage.
  rmw_subscription_t * sub2 = rmw_create_subscription(node, msg_ts, "/chatter", &qos, &sub_options);
  ASSERT_NE(nullptr, sub2);
  EXPECT_GT(
    memory_operations(
      [&]() {
        rmw_subscription_t * sub3 =
        rmw_create_subscription(node, msg_ts, "/chatter", &qos, &sub_options);
        EXPECT_EQ(RMW_RET_OK, rmw_destroy_subscription(node, sub3));
      }), 0u);
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_subscription(node, sub2));
}

TEST_F(ApiAllocations, matched_and_graph_counts_allocate_nothing)
{
  size_t count = 99;
  // Warm up: first calls may set up what lives for the process (rcutils error state, ...).
  ASSERT_EQ(RMW_RET_OK, rmw_publisher_count_matched_subscriptions(publisher, &count));
  ASSERT_EQ(RMW_RET_OK, rmw_subscription_count_matched_publishers(subscription, &count));
  EXPECT_EQ(
    0u, memory_operations(
      [&]() {
        EXPECT_EQ(RMW_RET_OK, rmw_publisher_count_matched_subscriptions(publisher, &count));
      }));
  EXPECT_EQ(1u, count);
  EXPECT_EQ(
    0u, memory_operations(
      [&]() {
        EXPECT_EQ(RMW_RET_OK, rmw_subscription_count_matched_publishers(subscription, &count));
      }));
  EXPECT_EQ(1u, count);
  EXPECT_EQ(
    0u, memory_operations(
      [&]() {
        EXPECT_EQ(RMW_RET_OK, rmw_count_publishers(node, "/chatter", &count));
        EXPECT_EQ(RMW_RET_OK, rmw_count_subscribers(node, "/chatter", &count));
        EXPECT_EQ(RMW_RET_OK, rmw_count_services(node, "/basic", &count));
        EXPECT_EQ(RMW_RET_OK, rmw_count_clients(node, "/basic", &count));
      }));
  EXPECT_EQ(1u, count);
}
