// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// The Prober on made-up graphs and answers: which request comes next, what the answers
// become (parameters with descriptors and values, lifecycle states and transitions), the
// per-name fallback, failed and unanswered requests, the settings.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "detail/prober.hpp"
#include "detail/recorder.hpp"

using rmw_introspect::DynValue;
using rmw_introspect::LifecycleTarget;
using rmw_introspect::LifecycleTransitionRecord;
using rmw_introspect::Prober;
using rmw_introspect::ProbeRequest;
using rmw_introspect::ProbeSettings;

namespace
{

struct Graph
{
  rmw_introspect::Recorder recorder;

  uint64_t node(const char * name, bool parameters, bool lifecycle)
  {
    const uint64_t id = recorder.add_node(name, "/ns", "/");
    const std::string fqn = std::string("/ns/") + name;
    if (parameters) {
      service(id, fqn + "/describe_parameters", "rcl_interfaces/srv/DescribeParameters");
      service(id, fqn + "/get_parameters", "rcl_interfaces/srv/GetParameters");
      service(id, fqn + "/list_parameters", "rcl_interfaces/srv/ListParameters");
      service(id, fqn + "/set_parameters", "rcl_interfaces/srv/SetParameters");
    }
    if (lifecycle) {
      service(id, fqn + "/change_state", "lifecycle_msgs/srv/ChangeState");
      service(id, fqn + "/get_state", "lifecycle_msgs/srv/GetState");
    }
    return id;
  }

  uint64_t service(uint64_t node, const std::string & name, const std::string & type)
  {
    rmw_introspect::EndpointRecord e;
    e.kind = rmw_introspect::EndpointKind::Service;
    e.node_id = node;
    e.name = name;
    e.type = type;
    return recorder.add_endpoint(e);
  }
};

DynValue names_of(const DynValue & request)
{
  const DynValue * names = request.field("names");
  return names != nullptr ? *names : DynValue();
}

std::vector<std::string> strings(const DynValue & seq)
{
  std::vector<std::string> out;
  for (const auto & item : seq.items) {
    out.push_back(item.s);
  }
  return out;
}

DynValue list_answer(const std::vector<std::string> & names)
{
  DynValue result = DynValue::structure();
  result.set("names", rmw_introspect::string_sequence(names));
  result.set("prefixes", DynValue::sequence());
  return DynValue::structure().set("result", result);
}

DynValue descriptor(const std::string & name, uint8_t type)
{
  DynValue d = DynValue::structure();
  d.set("name", DynValue::string(name)).set("type", DynValue::uinteger(type));
  d.set("description", DynValue::string("about " + name));
  d.set("additional_constraints", DynValue::string(""));
  d.set("read_only", DynValue::boolean(false)).set("dynamic_typing", DynValue::boolean(false));
  d.set("floating_point_range", DynValue::sequence()).set("integer_range", DynValue::sequence());
  return d;
}

DynValue describe_answer(std::vector<DynValue> descriptors)
{
  return DynValue::structure().set("descriptors", DynValue::sequence(std::move(descriptors)));
}

DynValue integer_value(int64_t v)
{
  DynValue p = DynValue::structure();
  p.set("type", DynValue::uinteger(2)).set("integer_value", DynValue::integer(v));
  return p;
}

DynValue get_answer(std::vector<DynValue> values)
{
  return DynValue::structure().set("values", DynValue::sequence(std::move(values)));
}

DynValue state_answer(const std::string & label)
{
  DynValue state = DynValue::structure();
  state.set("id", DynValue::uinteger(label == "active" ? 3 : label == "inactive" ? 2 : 1));
  state.set("label", DynValue::string(label));
  return DynValue::structure().set("current_state", state);
}

DynValue change_answer(bool success)
{
  return DynValue::structure().set("success", DynValue::boolean(success));
}

// Expect the next request to go to `/ns/<node>/<service>`.
ProbeRequest expect_next(Prober & prober, Graph & graph, const std::string & service)
{
  ProbeRequest r;
  EXPECT_TRUE(prober.next(graph.recorder.snapshot(), &r)) << "expected " << service;
  EXPECT_EQ(service, r.service_name);
  EXPECT_NE(0u, r.service_id);
  return r;
}

// Run one whole parameter round of names `names` (all integers = index).
void answer_parameter_round(
  Prober & prober, Graph & graph, const std::string & node, const std::vector<std::string> & listed,
  const std::vector<std::string> & expected_new)
{
  expect_next(prober, graph, node + "/list_parameters");
  prober.on_answer(list_answer(listed));
  if (expected_new.empty()) {
    return;
  }
  ProbeRequest r = expect_next(prober, graph, node + "/describe_parameters");
  EXPECT_EQ(expected_new, strings(names_of(r.request)));
  std::vector<DynValue> ds, vs;
  for (size_t k = 0; k < expected_new.size(); ++k) {
    ds.push_back(descriptor(expected_new[k], 2));
    vs.push_back(integer_value(static_cast<int64_t>(k)));
  }
  prober.on_answer(describe_answer(ds));
  r = expect_next(prober, graph, node + "/get_parameters");
  EXPECT_EQ(expected_new, strings(names_of(r.request)));
  prober.on_answer(get_answer(vs));
}

}  // namespace

TEST(Prober, reads_every_parameter_with_its_descriptor_and_value)
{
  Graph graph;
  const uint64_t id = graph.node("talker", true, false);
  Prober prober{ProbeSettings()};
  ProbeRequest r = expect_next(prober, graph, "/ns/talker/list_parameters");
  EXPECT_EQ("rcl_interfaces/srv/ListParameters", r.service_type);
  EXPECT_FALSE(r.changes_node);
  EXPECT_EQ(0u, r.request.field("depth")->u);  // DEPTH_RECURSIVE: every name, any depth
  EXPECT_TRUE(r.request.field("prefixes")->items.empty());
  prober.on_answer(list_answer({"gain", "limits.max"}));

  r = expect_next(prober, graph, "/ns/talker/describe_parameters");
  EXPECT_EQ((std::vector<std::string>{"gain", "limits.max"}), strings(names_of(r.request)));
  DynValue gain = descriptor("gain", 3);
  gain.set("read_only", DynValue::boolean(true));
  gain.set("additional_constraints", DynValue::string("positive"));
  DynValue range = DynValue::structure();
  range.set("from_value", DynValue::real(0.0))
    .set("to_value", DynValue::real(2.5))
    .set("step", DynValue::real(0.5));
  gain.set("floating_point_range", DynValue::sequence({range}));
  DynValue max = descriptor("limits.max", 2);
  DynValue irange = DynValue::structure();
  irange.set("from_value", DynValue::integer(-3))
    .set("to_value", DynValue::integer(30))
    .set("step", DynValue::uinteger(3));
  max.set("integer_range", DynValue::sequence({irange}));
  max.set("dynamic_typing", DynValue::boolean(true));
  prober.on_answer(describe_answer({gain, max}));

  expect_next(prober, graph, "/ns/talker/get_parameters");
  DynValue gv = DynValue::structure();
  gv.set("type", DynValue::uinteger(3)).set("double_value", DynValue::real(1.5));
  DynValue sv = DynValue::structure();
  sv.set("type", DynValue::uinteger(9));
  sv.set("string_array_value", rmw_introspect::string_sequence({"a", "b"}));
  prober.on_answer(get_answer({gv, sv}));

  ProbeRequest none;
  EXPECT_FALSE(prober.next(graph.recorder.snapshot(), &none));
  const auto * result = prober.result(id);
  ASSERT_NE(nullptr, result);
  EXPECT_TRUE(result->has_parameters);
  EXPECT_FALSE(result->has_lifecycle);
  EXPECT_EQ("", result->parameters_error);
  ASSERT_EQ(2u, result->parameters.size());
  const auto & p0 = result->parameters[0];
  EXPECT_EQ("gain", p0.name);
  EXPECT_EQ(3, p0.type());
  EXPECT_DOUBLE_EQ(1.5, p0.value.double_value);
  EXPECT_TRUE(p0.read_only);
  EXPECT_EQ("about gain", p0.description);
  EXPECT_EQ("positive", p0.additional_constraints);
  ASSERT_TRUE(p0.has_floating_point_range);
  EXPECT_DOUBLE_EQ(2.5, p0.floating_point_range.to_value);
  EXPECT_FALSE(p0.has_integer_range);
  EXPECT_EQ("", p0.declared_in);
  const auto & p1 = result->parameters[1];
  EXPECT_EQ("limits.max", p1.name);
  EXPECT_EQ(9, p1.type());  // a dynamically typed parameter has the type of its value
  EXPECT_EQ(2, p1.descriptor_type);
  EXPECT_TRUE(p1.dynamic_typing);
  EXPECT_EQ((std::vector<std::string>{"a", "b"}), p1.value.string_array_value);
  ASSERT_TRUE(p1.has_integer_range);
  EXPECT_EQ(-3, p1.integer_range.from_value);
  EXPECT_EQ(3u, p1.integer_range.step);
  EXPECT_EQ(3u, prober.requests());
  EXPECT_EQ(0u, prober.unanswered());
}

TEST(Prober, a_short_batch_answer_is_asked_again_one_name_at_a_time)
{
  Graph graph;
  const uint64_t id = graph.node("n", true, false);
  Prober prober{ProbeSettings()};
  expect_next(prober, graph, "/ns/n/list_parameters");
  prober.on_answer(list_answer({"a", "unset", "b"}));
  expect_next(prober, graph, "/ns/n/describe_parameters");
  prober.on_answer(
    describe_answer({descriptor("a", 2), descriptor("unset", 4), descriptor("b", 2)}));
  expect_next(prober, graph, "/ns/n/get_parameters");
  prober.on_answer(get_answer({}));  // rclpy: one parameter without a value empties the answer
  for (const char * name : {"a", "unset", "b"}) {
    ProbeRequest r = expect_next(prober, graph, "/ns/n/get_parameters");
    EXPECT_EQ(std::vector<std::string>{name}, strings(names_of(r.request)));
    prober.on_answer(
      std::string(name) == "unset" ? get_answer({}) : get_answer({integer_value(7)}));
  }
  ProbeRequest none;
  EXPECT_FALSE(prober.next(graph.recorder.snapshot(), &none));
  const auto & params = prober.result(id)->parameters;
  ASSERT_EQ(3u, params.size());
  EXPECT_EQ(7, params[0].value.integer_value);
  EXPECT_EQ(0, params[1].value.type);  // declared with a type, no value
  EXPECT_EQ(4, params[1].type());
  EXPECT_EQ(7, params[2].value.integer_value);
}

TEST(Prober, describe_falls_back_too_and_drops_names_gone_meanwhile)
{
  Graph graph;
  const uint64_t id = graph.node("n", true, false);
  Prober prober{ProbeSettings()};
  expect_next(prober, graph, "/ns/n/list_parameters");
  prober.on_answer(list_answer({"a", "gone"}));
  expect_next(prober, graph, "/ns/n/describe_parameters");
  prober.on_answer(describe_answer({}));
  expect_next(prober, graph, "/ns/n/describe_parameters");
  prober.on_answer(describe_answer({descriptor("a", 2)}));
  expect_next(prober, graph, "/ns/n/describe_parameters");
  prober.on_answer(describe_answer({}));
  ProbeRequest r = expect_next(prober, graph, "/ns/n/get_parameters");
  prober.on_answer(get_answer({integer_value(1), integer_value(2)}));
  ProbeRequest none;
  EXPECT_FALSE(prober.next(graph.recorder.snapshot(), &none));
  ASSERT_EQ(1u, prober.result(id)->parameters.size());
  EXPECT_EQ("a", prober.result(id)->parameters[0].name);
}

TEST(Prober, drives_a_lifecycle_node_to_active_and_reads_parameters_after_each_transition)
{
  Graph graph;
  const uint64_t id = graph.node("lc", true, true);
  Prober prober{ProbeSettings()};
  ProbeRequest r = expect_next(prober, graph, "/ns/lc/get_state");
  EXPECT_FALSE(r.changes_node);
  prober.on_answer(state_answer("unconfigured"));
  answer_parameter_round(prober, graph, "/ns/lc", {"use_sim_time"}, {"use_sim_time"});

  r = expect_next(prober, graph, "/ns/lc/change_state");
  EXPECT_TRUE(r.changes_node);
  EXPECT_EQ("configure", r.transition);
  EXPECT_EQ(1u, r.request.field("transition")->field("id")->u);
  EXPECT_EQ("configure", r.request.field("transition")->field("label")->s);
  EXPECT_EQ(
    LifecycleTransitionRecord::Result::kPending,
    prober.result(id)->lifecycle.transitions.back().result);
  prober.on_answer(change_answer(true));
  expect_next(prober, graph, "/ns/lc/get_state");
  prober.on_answer(state_answer("inactive"));
  answer_parameter_round(prober, graph, "/ns/lc", {"use_sim_time", "rate"}, {"rate"});

  r = expect_next(prober, graph, "/ns/lc/change_state");
  EXPECT_EQ("activate", r.transition);
  EXPECT_EQ(3u, r.request.field("transition")->field("id")->u);
  prober.on_answer(change_answer(true));
  expect_next(prober, graph, "/ns/lc/get_state");
  prober.on_answer(state_answer("active"));
  answer_parameter_round(prober, graph, "/ns/lc", {"use_sim_time", "rate"}, {});
  ProbeRequest none;
  EXPECT_FALSE(prober.next(graph.recorder.snapshot(), &none));

  const auto * result = prober.result(id);
  EXPECT_TRUE(result->has_lifecycle);
  EXPECT_EQ("active", result->lifecycle.target);
  EXPECT_EQ("unconfigured", result->lifecycle.initial_state);
  EXPECT_EQ("active", result->lifecycle.state);
  EXPECT_EQ("", result->lifecycle.error);
  ASSERT_EQ(2u, result->lifecycle.transitions.size());
  EXPECT_EQ("configure", result->lifecycle.transitions[0].label);
  EXPECT_EQ(LifecycleTransitionRecord::Result::kSuccess, result->lifecycle.transitions[0].result);
  EXPECT_EQ(3, result->lifecycle.transitions[1].id);
  ASSERT_EQ(2u, result->parameters.size());
  EXPECT_EQ("", result->parameters[0].declared_in);
  EXPECT_EQ("rate", result->parameters[1].name);
  EXPECT_EQ("configure", result->parameters[1].declared_in);
}

TEST(Prober, a_failed_transition_stops_the_driving_with_an_error_naming_node_and_transition)
{
  Graph graph;
  const uint64_t id = graph.node("bad", false, true);
  Prober prober{ProbeSettings()};
  expect_next(prober, graph, "/ns/bad/get_state");
  prober.on_answer(state_answer("unconfigured"));
  expect_next(prober, graph, "/ns/bad/change_state");
  prober.on_answer(change_answer(false));
  expect_next(prober, graph, "/ns/bad/get_state");
  prober.on_answer(state_answer("unconfigured"));
  ProbeRequest none;
  EXPECT_FALSE(prober.next(graph.recorder.snapshot(), &none));  // no activate
  const auto & lc = prober.result(id)->lifecycle;
  ASSERT_EQ(1u, lc.transitions.size());
  EXPECT_EQ(LifecycleTransitionRecord::Result::kFailure, lc.transitions[0].result);
  EXPECT_EQ("unconfigured", lc.state);
  EXPECT_NE(std::string::npos, lc.error.find("transition configure of /ns/bad failed")) << lc.error;
  EXPECT_NE(std::string::npos, lc.error.find("state now unconfigured")) << lc.error;
}

TEST(Prober, targets_inactive_unconfigured_none_and_nodes_already_there)
{
  struct Case
  {
    LifecycleTarget target;
    const char * state;
    std::vector<std::string> transitions;
  };
  const std::vector<Case> cases = {
    {LifecycleTarget::kInactive, "unconfigured", {"configure"}},
    {LifecycleTarget::kInactive, "active", {}},
    {LifecycleTarget::kActive, "inactive", {"activate"}},
    {LifecycleTarget::kActive, "active", {}},
    {LifecycleTarget::kActive, "finalized", {}},
    {LifecycleTarget::kUnconfigured, "unconfigured", {}},
  };
  for (const auto & c : cases) {
    Graph graph;
    const uint64_t id = graph.node("lc", false, true);
    ProbeSettings settings;
    settings.lifecycle = c.target;
    Prober prober{settings};
    expect_next(prober, graph, "/ns/lc/get_state");
    prober.on_answer(state_answer(c.state));
    std::vector<std::string> driven;
    ProbeRequest r;
    while (prober.next(graph.recorder.snapshot(), &r)) {
      if (r.changes_node) {
        driven.push_back(r.transition);
        prober.on_answer(change_answer(true));
      } else {
        prober.on_answer(state_answer(c.state));
      }
    }
    EXPECT_EQ(c.transitions, driven)
      << rmw_introspect::lifecycle_target_name(c.target) << " from " << c.state;
    EXPECT_EQ(rmw_introspect::lifecycle_target_name(c.target), prober.result(id)->lifecycle.target);
  }
  // none: no transition is driven, but the state is asked (with the parameters) and recorded
  Graph graph;
  const uint64_t id = graph.node("lc", true, true);
  ProbeSettings settings;
  settings.lifecycle = LifecycleTarget::kNone;
  Prober prober{settings};
  expect_next(prober, graph, "/ns/lc/get_state");
  prober.on_answer(state_answer("active"));
  answer_parameter_round(prober, graph, "/ns/lc", {"x"}, {"x"});
  ProbeRequest none;
  EXPECT_FALSE(prober.next(graph.recorder.snapshot(), &none));
  EXPECT_TRUE(prober.result(id)->has_lifecycle);
  EXPECT_EQ("none", prober.result(id)->lifecycle.target);
  EXPECT_EQ("active", prober.result(id)->lifecycle.state);
  EXPECT_TRUE(prober.result(id)->lifecycle.transitions.empty());
  EXPECT_EQ(1u, prober.result(id)->parameters.size());
  // none without parameters: nothing is asked at all (state unknown)
  Graph quiet_graph;
  const uint64_t quiet_id = quiet_graph.node("lc", true, true);
  settings.parameters = false;
  Prober quiet{settings};
  EXPECT_FALSE(quiet.next(quiet_graph.recorder.snapshot(), &none));
  EXPECT_EQ("", quiet.result(quiet_id)->lifecycle.state);
}

TEST(Prober, parameters_off_and_nodes_without_services)
{
  Graph graph;
  const uint64_t c_node = graph.node("c_node", false, false);
  const uint64_t lc = graph.node("lc", true, true);
  ProbeSettings settings;
  settings.parameters = false;
  Prober prober{settings};
  expect_next(prober, graph, "/ns/lc/get_state");
  prober.on_answer(state_answer("active"));
  ProbeRequest none;
  EXPECT_FALSE(prober.next(graph.recorder.snapshot(), &none));
  ASSERT_NE(nullptr, prober.result(c_node));
  EXPECT_FALSE(prober.result(c_node)->has_parameters);
  EXPECT_FALSE(prober.result(c_node)->has_lifecycle);
  EXPECT_FALSE(prober.result(lc)->has_parameters);
  EXPECT_EQ("active", prober.result(lc)->lifecycle.state);
  EXPECT_EQ(nullptr, prober.result(12345));
}

TEST(Prober, a_node_that_does_not_answer_is_left_and_the_next_node_asked)
{
  Graph graph;
  const uint64_t mute = graph.node("mute", true, true);
  const uint64_t other = graph.node("other", true, false);
  Prober prober{ProbeSettings()};
  expect_next(prober, graph, "/ns/mute/get_state");
  prober.on_answer(state_answer("unconfigured"));
  answer_parameter_round(prober, graph, "/ns/mute", {}, {});
  expect_next(prober, graph, "/ns/mute/change_state");
  prober.on_no_answer("no answer within 5000 ms");
  answer_parameter_round(prober, graph, "/ns/other", {"p"}, {"p"});
  ProbeRequest none;
  EXPECT_FALSE(prober.next(graph.recorder.snapshot(), &none));
  const auto & lc = prober.result(mute)->lifecycle;
  EXPECT_EQ(LifecycleTransitionRecord::Result::kNoAnswer, lc.transitions.at(0).result);
  EXPECT_EQ("transition configure of /ns/mute: no answer within 5000 ms", lc.error);
  EXPECT_EQ(1u, prober.result(other)->parameters.size());
  EXPECT_EQ(1u, prober.unanswered());

  // A parameter request without an answer is a parameters error.
  Graph g2;
  const uint64_t n = g2.node("n", true, false);
  Prober p2{ProbeSettings()};
  expect_next(p2, g2, "/ns/n/list_parameters");
  p2.on_no_answer("no answer");
  EXPECT_FALSE(p2.next(g2.recorder.snapshot(), &none));
  EXPECT_EQ("no answer", p2.result(n)->parameters_error);
  EXPECT_FALSE(p2.result(n)->has_parameters);
}

TEST(Prober, services_or_nodes_destroyed_meanwhile)
{
  Graph graph;
  const uint64_t a = graph.node("a", true, false);
  const uint64_t b = graph.node("b", true, false);
  Prober prober{ProbeSettings()};
  expect_next(prober, graph, "/ns/a/list_parameters");
  prober.on_answer(list_answer({"x"}));
  // /ns/a/describe_parameters goes away: a's probe ends with an error, b is next.
  for (const auto & e : graph.recorder.snapshot().endpoints) {
    if (e.name == "/ns/a/describe_parameters") {
      graph.recorder.destroy_endpoint(e.id);
    }
  }
  graph.recorder.destroy_node(b);
  const uint64_t c = graph.node("c", true, false);
  expect_next(prober, graph, "/ns/c/list_parameters");
  EXPECT_EQ(
    "the node has no service /ns/a/describe_parameters (any more)",
    prober.result(a)->parameters_error);
  EXPECT_EQ(nullptr, prober.result(b));  // destroyed before its turn: not probed
  prober.on_answer(list_answer({}));
  ProbeRequest none;
  EXPECT_FALSE(prober.next(graph.recorder.snapshot(), &none));
  EXPECT_TRUE(prober.result(c)->has_parameters);
  EXPECT_FALSE(prober.next(graph.recorder.snapshot(), nullptr));
}

TEST(Prober, lifecycle_target_names)
{
  LifecycleTarget t = LifecycleTarget::kNone;
  EXPECT_TRUE(rmw_introspect::parse_lifecycle_target("Inactive", &t));
  EXPECT_EQ(LifecycleTarget::kInactive, t);
  EXPECT_TRUE(rmw_introspect::parse_lifecycle_target("unconfigured", &t));
  EXPECT_EQ(LifecycleTarget::kUnconfigured, t);
  EXPECT_FALSE(rmw_introspect::parse_lifecycle_target("finalized", &t));
  EXPECT_EQ(LifecycleTarget::kUnconfigured, t);
  EXPECT_STREQ("active", rmw_introspect::lifecycle_target_name(LifecycleTarget::kActive));
  EXPECT_STREQ("integer_array", rmw_introspect::parameter_type_name(7));
  EXPECT_EQ(nullptr, rmw_introspect::parameter_type_name(0));
  EXPECT_EQ(nullptr, rmw_introspect::parameter_type_name(10));
}
