// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// rmw_wait semantics: blocks up to its timeout, wakes on a triggered guard condition of its
// set, remembers triggers until waited on, NULLs every entry that is not ready.

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "rmw/types.h"

#include "api_fixture.hpp"

using Clock = std::chrono::steady_clock;
using WaitTest = ApiFixture;

namespace
{
double ms_since(Clock::time_point t0)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
}  // namespace

TEST_F(WaitTest, poll_returns_timeout_and_clears_everything)
{
  void * gcs_storage[1] = {guard_condition->data};
  rmw_guard_conditions_t gcs{1, gcs_storage};
  void * subs_storage[1] = {subscription->data};
  rmw_subscriptions_t subs{1, subs_storage};
  void * srv_storage[1] = {service->data};
  rmw_services_t srvs{1, srv_storage};
  void * cli_storage[1] = {client->data};
  rmw_clients_t clis{1, cli_storage};
  void * ev_storage[2] = {&pub_event, &sub_event};
  rmw_events_t evs{2, ev_storage};
  rmw_time_t zero{0, 0};
  const auto t0 = Clock::now();
  EXPECT_EQ(RMW_RET_TIMEOUT, rmw_wait(&subs, &gcs, &srvs, &clis, &evs, wait_set, &zero));
  EXPECT_LT(ms_since(t0), 50.0);
  EXPECT_EQ(nullptr, gcs_storage[0]);
  EXPECT_EQ(nullptr, subs_storage[0]);
  EXPECT_EQ(nullptr, srv_storage[0]);
  EXPECT_EQ(nullptr, cli_storage[0]);
  EXPECT_EQ(nullptr, ev_storage[0]);
  EXPECT_EQ(nullptr, ev_storage[1]);
}

TEST_F(WaitTest, blocks_for_the_timeout)
{
  void * gcs_storage[1] = {guard_condition->data};
  rmw_guard_conditions_t gcs{1, gcs_storage};
  rmw_time_t timeout{0, 150000000};  // 150 ms
  const auto t0 = Clock::now();
  EXPECT_EQ(
    RMW_RET_TIMEOUT, rmw_wait(nullptr, &gcs, nullptr, nullptr, nullptr, wait_set, &timeout));
  const double elapsed = ms_since(t0);
  EXPECT_GE(elapsed, 145.0);
  EXPECT_LT(elapsed, 1000.0);
  EXPECT_EQ(nullptr, gcs_storage[0]);
}

TEST_F(WaitTest, trigger_is_remembered_until_waited_on)
{
  ASSERT_EQ(RMW_RET_OK, rmw_trigger_guard_condition(guard_condition));
  rmw_guard_condition_t * other = rmw_create_guard_condition(&context);
  ASSERT_NE(nullptr, other);
  void * subs_storage[1] = {subscription->data};
  rmw_subscriptions_t subs{1, subs_storage};
  void * gcs_storage[2] = {other->data, guard_condition->data};
  rmw_guard_conditions_t gcs{2, gcs_storage};
  rmw_time_t timeout{5, 0};
  const auto t0 = Clock::now();
  EXPECT_EQ(RMW_RET_OK, rmw_wait(&subs, &gcs, nullptr, nullptr, nullptr, wait_set, &timeout));
  EXPECT_LT(ms_since(t0), 100.0);
  EXPECT_EQ(nullptr, gcs_storage[0]);  // not triggered
  EXPECT_EQ(guard_condition->data, gcs_storage[1]);  // triggered: kept
  EXPECT_EQ(nullptr, subs_storage[0]);  // never ready

  // The trigger was consumed by that wait.
  void * again_storage[1] = {guard_condition->data};
  rmw_guard_conditions_t again{1, again_storage};
  rmw_time_t zero{0, 0};
  EXPECT_EQ(RMW_RET_TIMEOUT, rmw_wait(nullptr, &again, nullptr, nullptr, nullptr, wait_set, &zero));
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_guard_condition(other));
}

TEST_F(WaitTest, trigger_from_another_thread_wakes_an_infinite_wait)
{
  for (bool use_null_timeout : {true, false}) {
    void * gcs_storage[1] = {guard_condition->data};
    rmw_guard_conditions_t gcs{1, gcs_storage};
    rmw_time_t infinite = RMW_DURATION_INFINITE;
    std::thread trigger([this]() {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      EXPECT_EQ(RMW_RET_OK, rmw_trigger_guard_condition(guard_condition));
    });
    const auto t0 = Clock::now();
    EXPECT_EQ(
      RMW_RET_OK,
      rmw_wait(
        nullptr, &gcs, nullptr, nullptr, nullptr, wait_set,
        use_null_timeout ? nullptr : &infinite));
    const double elapsed = ms_since(t0);
    trigger.join();
    EXPECT_GE(elapsed, 90.0);
    EXPECT_LT(elapsed, 2000.0);
    EXPECT_EQ(guard_condition->data, gcs_storage[0]);
  }
}

TEST_F(WaitTest, a_trigger_outside_the_set_does_not_wake)
{
  rmw_guard_condition_t * other = rmw_create_guard_condition(&context);
  ASSERT_NE(nullptr, other);
  void * gcs_storage[1] = {guard_condition->data};
  rmw_guard_conditions_t gcs{1, gcs_storage};
  std::thread trigger([other]() {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_EQ(RMW_RET_OK, rmw_trigger_guard_condition(other));
  });
  rmw_time_t timeout{0, 200000000};
  const auto t0 = Clock::now();
  EXPECT_EQ(
    RMW_RET_TIMEOUT, rmw_wait(nullptr, &gcs, nullptr, nullptr, nullptr, wait_set, &timeout));
  EXPECT_GE(ms_since(t0), 195.0);
  trigger.join();
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_guard_condition(other));
}

TEST_F(WaitTest, graph_guard_condition_fires_on_local_graph_change)
{
  const rmw_guard_condition_t * graph = rmw_node_get_graph_guard_condition(node);
  ASSERT_NE(nullptr, graph);
  // Drain whatever the fixture's own creations left.
  void * drain_storage[1] = {graph->data};
  rmw_guard_conditions_t drain{1, drain_storage};
  rmw_time_t zero{0, 0};
  const rmw_ret_t drained = rmw_wait(nullptr, &drain, nullptr, nullptr, nullptr, wait_set, &zero);
  EXPECT_TRUE(drained == RMW_RET_OK || drained == RMW_RET_TIMEOUT);
  rmw_publisher_t * pub = rmw_create_publisher(node, msg_ts, "/graph_change", &qos, &pub_options);
  ASSERT_NE(nullptr, pub);
  void * gcs_storage[1] = {graph->data};
  rmw_guard_conditions_t gcs{1, gcs_storage};
  EXPECT_EQ(RMW_RET_OK, rmw_wait(nullptr, &gcs, nullptr, nullptr, nullptr, wait_set, &zero));
  EXPECT_EQ(graph->data, gcs_storage[0]);
  EXPECT_EQ(RMW_RET_OK, rmw_destroy_publisher(node, pub));
}
