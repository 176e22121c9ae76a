// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// The recorder model: creation order, destroyed flags (teardown excluded), copied names,
// unique GIDs, change notifications, thread safety.

#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "detail/recorder.hpp"

using rmw_introspect::EndpointKind;
using rmw_introspect::EndpointRecord;
using rmw_introspect::Recorder;

namespace
{
EndpointRecord endpoint(EndpointKind kind, uint64_t node_id, const char * name)
{
  EndpointRecord r;
  r.kind = kind;
  r.node_id = node_id;
  r.name = name;
  r.type = "std_msgs/msg/String";
  return r;
}
}  // namespace

TEST(Recorder, fqn)
{
  EXPECT_EQ("/talker", rmw_introspect::make_fqn("/", "talker"));
  EXPECT_EQ("/robot/talker", rmw_introspect::make_fqn("/robot", "talker"));
  EXPECT_EQ("/talker", rmw_introspect::make_fqn("", "talker"));
}

TEST(Recorder, creation_order_and_ids)
{
  Recorder recorder;
  const uint64_t n1 = recorder.add_node("a", "/", "/");
  const uint64_t e1 = recorder.add_endpoint(endpoint(EndpointKind::Publisher, n1, "/x"));
  const uint64_t n2 = recorder.add_node("b", "/ns", "/enclave");
  const uint64_t e2 = recorder.add_endpoint(endpoint(EndpointKind::Service, n2, "/ns/b/srv"));
  const uint64_t e3 = recorder.add_endpoint(endpoint(EndpointKind::Client, n1, "/ns/b/srv"));
  EXPECT_EQ(0u, recorder.add_endpoint(endpoint(EndpointKind::Publisher, 99, "/nope")));
  auto snap = recorder.snapshot();
  ASSERT_EQ(2u, snap.nodes.size());
  ASSERT_EQ(3u, snap.endpoints.size());
  EXPECT_EQ(1u, snap.nodes[0].seq);
  EXPECT_EQ(2u, snap.endpoints[0].seq);
  EXPECT_EQ(3u, snap.nodes[1].seq);
  EXPECT_EQ(4u, snap.endpoints[1].seq);
  EXPECT_EQ(5u, snap.endpoints[2].seq);
  EXPECT_EQ("/ns/b", snap.nodes[1].fqn);
  EXPECT_EQ("/enclave", snap.nodes[1].enclave);
  EXPECT_EQ("/ns/b", snap.endpoints[1].node_fqn);
  EXPECT_EQ("b", snap.endpoints[1].node_name);
  EXPECT_EQ("/ns", snap.endpoints[1].node_namespace);
  EXPECT_EQ(n1, snap.endpoints[2].node_id);
  EXPECT_NE(e1, e2);
  EXPECT_NE(e2, e3);
}

TEST(Recorder, names_are_copied)
{
  Recorder recorder;
  char name[] = "talker";
  char ns[] = "/robot";
  const uint64_t n = recorder.add_node(name, ns, "/");
  std::memset(name, 'x', sizeof(name) - 1);
  std::memset(ns + 1, 'x', sizeof(ns) - 2);
  auto snap = recorder.snapshot();
  EXPECT_EQ("talker", snap.nodes[0].name);
  EXPECT_EQ("/robot", snap.nodes[0].namespace_);
  EXPECT_EQ("/robot/talker", snap.nodes[0].fqn);
  (void)n;
}

TEST(Recorder, destroyed_flags_and_teardown)
{
  Recorder recorder;
  const uint64_t n = recorder.add_node("a", "/", "/");
  const uint64_t p = recorder.add_endpoint(endpoint(EndpointKind::Publisher, n, "/p"));
  const uint64_t s = recorder.add_endpoint(endpoint(EndpointKind::Subscription, n, "/s"));
  const uint64_t gen = recorder.generation();
  EXPECT_TRUE(recorder.destroy_endpoint(p));
  EXPECT_FALSE(recorder.destroy_endpoint(p));  // twice
  EXPECT_GT(recorder.generation(), gen);
  const uint64_t gen2 = recorder.generation();
  EXPECT_TRUE(recorder.destroy_endpoint(s, true));  // teardown: not reported
  EXPECT_TRUE(recorder.destroy_node(n, true));
  EXPECT_EQ(gen2, recorder.generation());
  auto snap = recorder.snapshot();
  EXPECT_TRUE(snap.endpoints[0].destroyed);
  EXPECT_FALSE(snap.endpoints[0].alive);
  EXPECT_FALSE(snap.endpoints[1].destroyed);
  EXPECT_FALSE(snap.endpoints[1].alive);
  EXPECT_FALSE(snap.nodes[0].destroyed);
  EXPECT_FALSE(snap.nodes[0].alive);
  EXPECT_FALSE(recorder.destroy_node(12345));
}

TEST(Recorder, gids_are_unique)
{
  Recorder a;
  Recorder b;
  std::set<rmw_introspect::Gid> seen;
  for (int i = 0; i < 100; ++i) {
    EXPECT_TRUE(seen.insert(a.new_gid()).second);
    EXPECT_TRUE(seen.insert(b.new_gid()).second);
  }
}

TEST(Recorder, listener_is_told_of_every_change)
{
  Recorder recorder;
  std::atomic<int> calls{0};
  recorder.set_change_listener([&]() { ++calls; });
  const uint64_t n = recorder.add_node("a", "/", "/");
  const uint64_t p = recorder.add_endpoint(endpoint(EndpointKind::Publisher, n, "/p"));
  recorder.destroy_endpoint(p);
  recorder.destroy_node(n);
  EXPECT_EQ(4, calls.load());
}

TEST(Recorder, concurrent_creation_keeps_a_total_order)
{
  Recorder recorder;
  const uint64_t n = recorder.add_node("a", "/", "/");
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&recorder, n, t]() {
      for (int i = 0; i < 250; ++i) {
        const std::string name = "/t" + std::to_string(t) + "_" + std::to_string(i);
        recorder.add_endpoint(endpoint(EndpointKind::Publisher, n, name.c_str()));
      }
    });
  }
  for (auto & th : threads) {
    th.join();
  }
  auto snap = recorder.snapshot();
  ASSERT_EQ(1000u, snap.endpoints.size());
  for (size_t i = 0; i < snap.endpoints.size(); ++i) {
    EXPECT_EQ(i + 2, snap.endpoints[i].seq);  // seq 1 is the node
    EXPECT_EQ(i + 1, snap.endpoints[i].id);
  }
}

TEST(Recorder, destroying_a_node_destroys_its_endpoints)
{
  Recorder recorder;
  const uint64_t a = recorder.add_node("a", "/", "/");
  const uint64_t b = recorder.add_node("b", "/", "/");
  const uint64_t pa = recorder.add_endpoint(endpoint(EndpointKind::Publisher, a, "/pa"));
  const uint64_t pb = recorder.add_endpoint(endpoint(EndpointKind::Publisher, b, "/pb"));
  EXPECT_TRUE(recorder.destroy_node(a));
  EXPECT_FALSE(recorder.destroy_endpoint(pa));  // already gone with its node
  auto snap = recorder.snapshot();
  EXPECT_TRUE(snap.endpoints[pa - 1].destroyed);
  EXPECT_FALSE(snap.endpoints[pa - 1].alive);
  EXPECT_FALSE(snap.endpoints[pb - 1].destroyed);
  EXPECT_TRUE(snap.endpoints[pb - 1].alive);
  // Teardown destruction of a node: its endpoints leave the graph, unflagged.
  EXPECT_TRUE(recorder.destroy_node(b, true));
  snap = recorder.snapshot();
  EXPECT_FALSE(snap.endpoints[pb - 1].destroyed);
  EXPECT_FALSE(snap.endpoints[pb - 1].alive);
}

TEST(Recorder, teardown_run_is_the_trailing_destructions)
{
  Recorder recorder;
  const uint64_t n = recorder.add_node("n", "/", "/");
  const uint64_t early = recorder.add_endpoint(endpoint(EndpointKind::Publisher, n, "/early"));
  recorder.destroy_endpoint(early);  // destroyed before a later creation: behaviour
  const uint64_t sub = recorder.add_endpoint(endpoint(EndpointKind::Subscription, n, "/s"));
  const uint64_t pub = recorder.add_endpoint(endpoint(EndpointKind::Publisher, n, "/p"));
  const uint64_t other = recorder.add_node("other", "/", "/");
  recorder.destroy_endpoint(pub);
  recorder.destroy_endpoint(sub, true);  // teardown: not an event, not flagged
  recorder.destroy_node(n);
  // Without marking (running/settled captures), nothing is in_teardown.
  for (const auto & e : recorder.snapshot().endpoints) {
    EXPECT_FALSE(e.in_teardown);
  }
  const auto snap = recorder.snapshot(true);
  EXPECT_FALSE(snap.endpoints[early - 1].in_teardown);
  EXPECT_TRUE(snap.endpoints[early - 1].destroyed);
  EXPECT_FALSE(snap.endpoints[sub - 1].in_teardown);
  EXPECT_FALSE(snap.endpoints[sub - 1].destroyed);
  EXPECT_TRUE(snap.endpoints[pub - 1].in_teardown);
  EXPECT_TRUE(snap.nodes[n - 1].in_teardown);
  EXPECT_FALSE(snap.nodes[other - 1].in_teardown);  // alive
}

TEST(Recorder, creation_times_are_kept)
{
  Recorder recorder;
  const uint64_t n = recorder.add_node("n", "/", "/", {3000.5, 12.25});
  auto e = endpoint(EndpointKind::Publisher, n, "/p");
  e.created = {4000.0, 13.0};
  recorder.add_endpoint(e);
  const auto snap = recorder.snapshot();
  EXPECT_DOUBLE_EQ(3000.5, snap.nodes[0].created.virtual_ms);
  EXPECT_DOUBLE_EQ(12.25, snap.nodes[0].created.real_ms);
  EXPECT_DOUBLE_EQ(4000.0, snap.endpoints[0].created.virtual_ms);
  EXPECT_DOUBLE_EQ(13.0, snap.endpoints[0].created.real_ms);
}

TEST(Recorder, destruction_times_are_kept_for_what_the_program_destroyed)
{
  Recorder recorder;
  const uint64_t n = recorder.add_node("n", "/", "/", {1.0, 1.0});
  const uint64_t early = recorder.add_endpoint(endpoint(EndpointKind::Publisher, n, "/early"));
  const uint64_t late = recorder.add_endpoint(endpoint(EndpointKind::Publisher, n, "/late"));
  const uint64_t kept = recorder.add_node("kept", "/", "/", {1.0, 1.0});
  const uint64_t gone = recorder.add_endpoint(endpoint(EndpointKind::Service, kept, "/s"));
  recorder.destroy_endpoint(early, false, {5000.0, 20.0});
  recorder.destroy_node(n, false, {8000.25, 30.5});  // takes /late with it, at its age
  recorder.destroy_endpoint(gone, true, {9000.0, 40.0});  // teardown: no age reported
  const auto snap = recorder.snapshot();
  EXPECT_DOUBLE_EQ(5000.0, snap.endpoints[early - 1].destroyed_at.virtual_ms);
  EXPECT_DOUBLE_EQ(20.0, snap.endpoints[early - 1].destroyed_at.real_ms);
  EXPECT_DOUBLE_EQ(8000.25, snap.endpoints[late - 1].destroyed_at.virtual_ms);
  EXPECT_DOUBLE_EQ(8000.25, snap.nodes[n - 1].destroyed_at.virtual_ms);
  EXPECT_DOUBLE_EQ(30.5, snap.nodes[n - 1].destroyed_at.real_ms);
  EXPECT_FALSE(snap.endpoints[gone - 1].destroyed);
  EXPECT_DOUBLE_EQ(0.0, snap.endpoints[gone - 1].destroyed_at.virtual_ms);
}

TEST(Recorder, created_in_is_the_stimulus_while_it_lasts_then_the_node_transition)
{
  Recorder recorder;
  const uint64_t lc = recorder.add_node("lc", "/", "/");
  const uint64_t other = recorder.add_node("other", "/", "/");
  recorder.set_node_transition(lc, "activate");
  const uint64_t before = recorder.add_endpoint(endpoint(EndpointKind::Publisher, lc, "/a"));
  recorder.set_cause("stimulus:/camera_info");
  // Whatever node the process creates it on, it is the reaction to the stimulus.
  const uint64_t on_lc = recorder.add_endpoint(endpoint(EndpointKind::Publisher, lc, "/b"));
  const uint64_t on_other = recorder.add_endpoint(endpoint(EndpointKind::Client, other, "/c"));
  recorder.set_cause("");
  const uint64_t after = recorder.add_endpoint(endpoint(EndpointKind::Publisher, lc, "/d"));
  const uint64_t plain = recorder.add_endpoint(endpoint(EndpointKind::Publisher, other, "/e"));
  const auto snapshot = recorder.snapshot();
  EXPECT_EQ(snapshot.endpoints[before - 1].created_in, "activate");
  EXPECT_EQ(snapshot.endpoints[on_lc - 1].created_in, "stimulus:/camera_info");
  EXPECT_EQ(snapshot.endpoints[on_other - 1].created_in, "stimulus:/camera_info");
  EXPECT_EQ(snapshot.endpoints[after - 1].created_in, "activate");
  EXPECT_EQ(snapshot.endpoints[plain - 1].created_in, "");
}
