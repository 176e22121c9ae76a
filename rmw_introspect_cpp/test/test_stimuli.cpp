// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// RMW_INTROSPECT_STIMULI: parsing (and its warnings through Config::from_environment), and
// the StimulusPlan on made-up graphs: which endpoint gets the next delivery, names matched
// when their turn comes, no match, endpoints destroyed meanwhile, outcomes, skipping.

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "detail/config.hpp"
#include "detail/recorder.hpp"
#include "detail/stimuli.hpp"

using rmw_introspect::EndpointKind;
using rmw_introspect::StimulusPlan;
using rmw_introspect::StimulusRecord;
using rmw_introspect::StimulusRequest;
using rmw_introspect::StimulusTargetRecord;

namespace
{

std::vector<std::string> parse(const char * text, std::vector<std::string> * warnings = nullptr)
{
  std::vector<std::string> ignored;
  return rmw_introspect::parse_stimuli(text, warnings != nullptr ? warnings : &ignored);
}

struct Graph
{
  rmw_introspect::Recorder recorder;

  uint64_t node(const char * name) { return recorder.add_node(name, "/", "/"); }

  uint64_t endpoint(uint64_t node, EndpointKind kind, const std::string & name, const char * type)
  {
    rmw_introspect::EndpointRecord e;
    e.kind = kind;
    e.node_id = node;
    e.name = name;
    e.type = type;
    return recorder.add_endpoint(e);
  }
};

class ScopedEnv
{
public:
  ScopedEnv(const char * name, const char * value)
  : name_(name)
  {
    setenv(name, value, 1);
  }
  ~ScopedEnv() { unsetenv(name_); }

private:
  const char * name_;
};

}  // namespace

TEST(Stimuli, parses_names_in_order_trimmed_once_each)
{
  std::vector<std::string> warnings;
  EXPECT_EQ(
    parse(" /camera_info, /reset ,/ns/cmd_vel,", &warnings),
    (std::vector<std::string>{"/camera_info", "/reset", "/ns/cmd_vel"}));
  EXPECT_TRUE(warnings.empty());
  EXPECT_TRUE(parse(nullptr).empty());
  EXPECT_TRUE(parse("").empty());
  EXPECT_TRUE(parse(" , ,").empty());
  // Hidden names (action parts) are names like any other.
  EXPECT_EQ(parse("/fib/_action/send_goal"), (std::vector<std::string>{"/fib/_action/send_goal"}));
}

TEST(Stimuli, bad_and_repeated_names_are_left_out_with_a_warning_naming_them)
{
  std::vector<std::string> warnings;
  const auto names = parse("camera_info,/ok,/bad name,/ok,/trailing/,//double,/9lives", &warnings);
  EXPECT_EQ(names, (std::vector<std::string>{"/ok"}));
  ASSERT_EQ(warnings.size(), 6u);
  EXPECT_NE(
    warnings[0].find("'camera_info' is not a fully qualified topic or service name"),
    std::string::npos)
    << warnings[0];
  EXPECT_NE(warnings[0].find("e.g. /camera_info"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[1].find("'/bad name'"), std::string::npos) << warnings[1];
  EXPECT_NE(warnings[2].find("'/ok' is named twice"), std::string::npos) << warnings[2];
  EXPECT_NE(warnings[3].find("'/trailing/'"), std::string::npos) << warnings[3];
  EXPECT_NE(warnings[4].find("'//double'"), std::string::npos) << warnings[4];
  EXPECT_NE(warnings[5].find("'/9lives'"), std::string::npos) << warnings[5];
  for (const auto & w : warnings) {
    EXPECT_EQ(w.rfind("RMW_INTROSPECT_STIMULI: ", 0), 0u) << w;
  }
}

TEST(Stimuli, config_reads_the_variable_and_is_off_without_it)
{
  unsetenv("RMW_INTROSPECT_STIMULI");
  EXPECT_TRUE(rmw_introspect::Config::from_environment(1).stimuli.empty());
  ScopedEnv env("RMW_INTROSPECT_STIMULI", "/camera_info,relative");
  const auto config = rmw_introspect::Config::from_environment(1);
  EXPECT_EQ(config.stimuli, (std::vector<std::string>{"/camera_info"}));
  ASSERT_EQ(config.warnings.size(), 1u);
  EXPECT_NE(config.warnings[0].find("'relative'"), std::string::npos) << config.warnings[0];
}

TEST(Stimuli, labels_and_names)
{
  EXPECT_EQ(rmw_introspect::stimulus_label("/camera_info"), "stimulus:/camera_info");
  EXPECT_STREQ(rmw_introspect::stimulus_state_name(StimulusRecord::State::kNoMatch), "no_match");
  EXPECT_STREQ(
    rmw_introspect::stimulus_result_name(StimulusTargetRecord::Result::kNotTaken), "not_taken");
  EXPECT_STREQ(
    rmw_introspect::stimulus_result_name(StimulusTargetRecord::Result::kNoAnswer), "no_answer");
}

TEST(Stimuli, every_subscription_and_service_of_a_name_once_in_creation_order)
{
  Graph g;
  const uint64_t cam = g.node("cam");
  const uint64_t viewer = g.node("viewer");
  g.endpoint(cam, EndpointKind::Publisher, "/camera_info", "sensor_msgs/msg/CameraInfo");
  const uint64_t sub1 =
    g.endpoint(cam, EndpointKind::Subscription, "/camera_info", "sensor_msgs/msg/CameraInfo");
  const uint64_t srv = g.endpoint(viewer, EndpointKind::Service, "/reset", "std_srvs/srv/Trigger");
  const uint64_t sub2 =
    g.endpoint(viewer, EndpointKind::Subscription, "/camera_info", "sensor_msgs/msg/CameraInfo");
  g.endpoint(viewer, EndpointKind::Client, "/reset", "std_srvs/srv/Trigger");

  StimulusPlan plan({"/reset", "/camera_info"});
  ASSERT_EQ(plan.records().size(), 2u);
  EXPECT_EQ(plan.records()[0].state, StimulusRecord::State::kPending);

  StimulusRequest r;
  ASSERT_TRUE(plan.next(g.recorder.snapshot(), &r));
  EXPECT_EQ(r.name, "/reset");
  EXPECT_EQ(r.kind, EndpointKind::Service);
  EXPECT_EQ(r.endpoint_id, srv);
  EXPECT_EQ(r.node_id, viewer);
  EXPECT_EQ(r.node, "/viewer");
  plan.on_delivered();

  ASSERT_TRUE(plan.next(g.recorder.snapshot(), &r));
  EXPECT_EQ(r.endpoint_id, sub1);
  EXPECT_EQ(r.kind, EndpointKind::Subscription);
  EXPECT_EQ(r.node, "/cam");
  plan.on_delivered();
  ASSERT_TRUE(plan.next(g.recorder.snapshot(), &r));
  EXPECT_EQ(r.endpoint_id, sub2);
  plan.on_failed("the subscription /camera_info of /viewer did not take the message", true);
  EXPECT_FALSE(plan.next(g.recorder.snapshot(), &r));

  const auto & records = plan.records();
  EXPECT_EQ(records[0].state, StimulusRecord::State::kDone);
  ASSERT_EQ(records[0].targets.size(), 1u);
  EXPECT_EQ(records[0].targets[0].result, StimulusTargetRecord::Result::kAnswered);
  EXPECT_EQ(records[0].targets[0].type, "std_srvs/srv/Trigger");
  EXPECT_EQ(records[1].state, StimulusRecord::State::kDone);
  ASSERT_EQ(records[1].targets.size(), 2u);  // the publisher of that name is no target
  EXPECT_EQ(records[1].targets[0].result, StimulusTargetRecord::Result::kTaken);
  EXPECT_EQ(records[1].targets[1].result, StimulusTargetRecord::Result::kNotTaken);
  EXPECT_EQ(records[1].targets[1].node, "/viewer");
  EXPECT_NE(records[1].targets[1].error.find("did not take"), std::string::npos);
}

TEST(Stimuli, a_name_is_matched_when_its_turn_comes)
{
  Graph g;
  const uint64_t n = g.node("relay");
  g.endpoint(n, EndpointKind::Subscription, "/in", "std_msgs/msg/String");
  StimulusPlan plan({"/in", "/later"});
  StimulusRequest r;
  ASSERT_TRUE(plan.next(g.recorder.snapshot(), &r));
  EXPECT_EQ(r.name, "/in");
  // The node answers the first stimulus with a new subscription: the second name finds it.
  const uint64_t later = g.endpoint(n, EndpointKind::Subscription, "/later", "std_msgs/msg/Empty");
  plan.on_delivered();
  ASSERT_TRUE(plan.next(g.recorder.snapshot(), &r));
  EXPECT_EQ(r.name, "/later");
  EXPECT_EQ(r.endpoint_id, later);
  plan.on_delivered();
  EXPECT_FALSE(plan.next(g.recorder.snapshot(), &r));
}

TEST(Stimuli, a_name_matching_nothing_says_so_and_lists_what_there_is)
{
  Graph g;
  const uint64_t n = g.node("cam");
  g.endpoint(n, EndpointKind::Subscription, "/camera_info", "sensor_msgs/msg/CameraInfo");
  g.endpoint(n, EndpointKind::Service, "/cam/get_parameters", "rcl_interfaces/srv/GetParameters");
  g.endpoint(n, EndpointKind::Service, "/cam/calibrate", "std_srvs/srv/Trigger");
  g.endpoint(n, EndpointKind::Publisher, "/camera_inf", "std_msgs/msg/String");
  StimulusPlan plan({"/camera_inf", "/camera_info"});
  StimulusRequest r;
  ASSERT_TRUE(plan.next(g.recorder.snapshot(), &r));
  EXPECT_EQ(r.name, "/camera_info");  // the first name matched nothing: the next one's turn
  const auto & miss = plan.records()[0];
  EXPECT_EQ(miss.state, StimulusRecord::State::kNoMatch);
  EXPECT_TRUE(miss.targets.empty());
  EXPECT_NE(
    miss.error.find("no subscription or service named /camera_inf in this process"),
    std::string::npos)
    << miss.error;
  EXPECT_NE(miss.error.find("subscriptions: /camera_info;"), std::string::npos) << miss.error;
  // Node-owned standard services are left out of the listing; the node's own ones are there.
  EXPECT_NE(miss.error.find("services: /cam/calibrate)"), std::string::npos) << miss.error;
  EXPECT_EQ(miss.error.find("get_parameters"), std::string::npos) << miss.error;
  // A publisher of that very name is pointed out: the name was right, the direction wrong.
  EXPECT_NE(
    miss.error.find(
      "There is a publisher /camera_inf (of /cam), but stimuli go to "
      "subscriptions and services."),
    std::string::npos)
    << miss.error;
}

TEST(Stimuli, endpoints_destroyed_before_their_turn_fail_and_the_rest_go_on)
{
  Graph g;
  const uint64_t n = g.node("cam");
  const uint64_t a = g.endpoint(n, EndpointKind::Subscription, "/x", "std_msgs/msg/Empty");
  const uint64_t b = g.endpoint(n, EndpointKind::Subscription, "/x", "std_msgs/msg/Empty");
  StimulusPlan plan({"/x"});
  StimulusRequest r;
  ASSERT_TRUE(plan.next(g.recorder.snapshot(), &r));
  EXPECT_EQ(r.endpoint_id, a);
  plan.on_failed("the subscription /x was destroyed before it took the message", false);
  ASSERT_TRUE(g.recorder.destroy_endpoint(b));
  EXPECT_FALSE(plan.next(g.recorder.snapshot(), &r));
  const auto & targets = plan.records()[0].targets;
  ASSERT_EQ(targets.size(), 2u);
  EXPECT_EQ(targets[0].result, StimulusTargetRecord::Result::kFailed);
  EXPECT_EQ(targets[1].result, StimulusTargetRecord::Result::kFailed);
  EXPECT_NE(targets[1].error.find("destroyed before its turn"), std::string::npos);
  // A destroyed endpoint is no match for a name whose turn comes later.
  StimulusPlan later({"/x"});
  ASSERT_TRUE(g.recorder.destroy_endpoint(a));
  EXPECT_FALSE(later.next(g.recorder.snapshot(), &r));
  EXPECT_EQ(later.records()[0].state, StimulusRecord::State::kNoMatch);
}

TEST(Stimuli, skipping_marks_what_was_not_delivered)
{
  Graph g;
  const uint64_t n = g.node("cam");
  g.endpoint(n, EndpointKind::Service, "/a", "std_srvs/srv/Trigger");
  StimulusPlan plan({"/a", "/b"});
  StimulusRequest r;
  ASSERT_TRUE(plan.next(g.recorder.snapshot(), &r));
  plan.skip_remaining("not delivered: no thread ever waited");
  EXPECT_FALSE(plan.next(g.recorder.snapshot(), &r));
  EXPECT_EQ(plan.records()[0].targets[0].result, StimulusTargetRecord::Result::kFailed);
  EXPECT_EQ(plan.records()[1].state, StimulusRecord::State::kSkipped);
  EXPECT_EQ(plan.records()[1].error, "not delivered: no thread ever waited");
  // Outcomes reported with nothing in flight change nothing.
  plan.on_delivered();
  EXPECT_EQ(plan.records()[0].targets[0].result, StimulusTargetRecord::Result::kFailed);
  EXPECT_TRUE(StimulusPlan({}).empty());
}
