// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// RMW_INTROSPECT_LOAD_NODES: the requests file (parsed into LoadNode requests, bad lines
// warned about and their request left out) and the ComponentLoadPlan on made-up graphs.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "detail/component_loads.hpp"
#include "detail/recorder.hpp"

using rmw_introspect::ComponentLoad;
using rmw_introspect::ComponentLoadPlan;
using rmw_introspect::ComponentLoadRecord;
using rmw_introspect::DynValue;
using rmw_introspect::EndpointKind;

namespace
{

const char * const kTwoLoads =
  "# for /cam/container\n"
  "load\t/cam/container/_container/load_node\n"
  "package_name\tcam\n"
  "plugin_name\tcam::Driver\n"
  "node_name\tdriver\n"
  "node_namespace\t/cam\n"
  "log_level\t0\n"
  "remap_rule\timage:=image_raw\n"
  "parameter\tframe\t4\ta\\tb\\\\c\n"
  "parameter\tfps\t3\t5.5\n"
  "parameter\tids\t7\t1\t-2\n"
  "extra_argument\tuse_intra_process_comms\t1\ttrue\n"
  "end\n"
  "load\t/cam/container/_container/load_node\n"
  "plugin_name\tcam::Rectifier\n"
  "end\n";

}  // namespace

TEST(ComponentLoads, parses_requests_with_escapes_and_typed_parameters)
{
  std::vector<std::string> warnings;
  const std::vector<ComponentLoad> loads =
    rmw_introspect::parse_component_loads(kTwoLoads, &warnings);
  EXPECT_TRUE(warnings.empty());
  ASSERT_EQ(loads.size(), 2u);
  const ComponentLoad & talker = loads[0];
  EXPECT_EQ(talker.service, "/cam/container/_container/load_node");
  EXPECT_EQ(talker.plugin, "cam::Driver");
  EXPECT_EQ(talker.node, "driver");
  EXPECT_EQ(talker.request.field("node_namespace")->s, "/cam");
  ASSERT_EQ(talker.request.field("remap_rules")->items.size(), 1u);
  EXPECT_EQ(talker.request.field("remap_rules")->items[0].s, "image:=image_raw");
  const auto & parameters = talker.request.field("parameters")->items;
  ASSERT_EQ(parameters.size(), 3u);
  EXPECT_EQ(parameters[0].field("value")->field("string_value")->s, "a\tb\\c");
  EXPECT_EQ(parameters[1].field("name")->s, "fps");
  EXPECT_EQ(parameters[1].field("value")->field("type")->as_uint(), 3u);
  EXPECT_DOUBLE_EQ(parameters[1].field("value")->field("double_value")->d, 5.5);
  const auto & ids = parameters[2].field("value")->field("integer_array_value")->items;
  ASSERT_EQ(ids.size(), 2u);
  EXPECT_EQ(ids[1].i, -2);
  const auto & extras = talker.request.field("extra_arguments")->items;
  ASSERT_EQ(extras.size(), 1u);
  EXPECT_TRUE(extras[0].field("value")->field("bool_value")->b);
  EXPECT_EQ(loads[1].node, "");
  EXPECT_EQ(loads[1].request.field("node_name"), nullptr);  // the component's own name
}

TEST(ComponentLoads, a_bad_line_leaves_its_request_out_with_a_warning)
{
  std::vector<std::string> warnings;
  const std::string text = std::string(
    "load\t/c/_container/load_node\nplugin_name\tdemo::A\nparameter\tx\t2\tnot-a-number\nend\n"
    "load\t/c/_container/load_node\nplugin_name\tdemo::B\nend\n"
    "stray\tline\n"
    "load\t/c/_container/load_node\nplugin_name\tdemo::C\n");
  const std::vector<ComponentLoad> loads = rmw_introspect::parse_component_loads(text, &warnings);
  ASSERT_EQ(loads.size(), 1u);
  EXPECT_EQ(loads[0].plugin, "demo::B");
  ASSERT_EQ(warnings.size(), 3u);
  EXPECT_EQ(
    warnings[0],
    "RMW_INTROSPECT_LOAD_NODES line 3: cannot read the parameter (NAME, TYPE 1-4 or 6-9, "
    "then its values)");
  EXPECT_NE(warnings[1].find("line 8: `stray` outside a request"), std::string::npos);
  EXPECT_NE(warnings[2].find("the last request has no `end`"), std::string::npos);
  std::vector<std::string> missing;
  EXPECT_TRUE(rmw_introspect::read_component_loads("/nonexistent/loads.txt", &missing).empty());
  ASSERT_EQ(missing.size(), 1u);
  EXPECT_NE(missing[0].find("cannot read the file"), std::string::npos);
}

TEST(ComponentLoads, the_plan_sends_each_request_to_its_service_and_records_the_answers)
{
  std::vector<std::string> warnings;
  std::vector<ComponentLoad> loads = rmw_introspect::parse_component_loads(kTwoLoads, &warnings);
  loads.push_back(loads[1]);
  loads.back().service = "/elsewhere/_container/load_node";
  ComponentLoadPlan plan(loads);
  rmw_introspect::Recorder recorder;
  const uint64_t node = recorder.add_node("container", "/cam", "/");
  rmw_introspect::EndpointRecord e;
  e.kind = EndpointKind::Service;
  e.node_id = node;
  e.name = "/cam/container/_container/load_node";
  e.type = "composition_interfaces/srv/LoadNode";
  const uint64_t service = recorder.add_endpoint(e);

  uint64_t id = 0;
  const ComponentLoad * load = nullptr;
  ASSERT_TRUE(plan.next(recorder.snapshot(), &id, &load));
  EXPECT_EQ(id, service);
  EXPECT_EQ(load->plugin, "cam::Driver");
  DynValue answer = DynValue::structure();
  answer.set("success", DynValue::boolean(true));
  answer.set("full_node_name", DynValue::string("/cam/driver"));
  plan.on_answer(answer);
  ASSERT_TRUE(plan.next(recorder.snapshot(), &id, &load));
  DynValue refused = DynValue::structure();
  refused.set("success", DynValue::boolean(false));
  refused.set(
    "error_message", DynValue::string("Failed to find class with the requested plugin name."));
  plan.on_answer(refused);
  EXPECT_FALSE(plan.next(recorder.snapshot(), &id, &load));  // the third has no service here

  const auto & records = plan.records();
  ASSERT_EQ(records.size(), 3u);
  EXPECT_EQ(records[0].result, ComponentLoadRecord::Result::kLoaded);
  EXPECT_EQ(records[0].full_node_name, "/cam/driver");
  EXPECT_EQ(records[1].result, ComponentLoadRecord::Result::kRefused);
  EXPECT_EQ(records[1].error, "Failed to find class with the requested plugin name.");
  EXPECT_EQ(records[2].result, ComponentLoadRecord::Result::kNoService);
  EXPECT_EQ(
    records[2].error,
    "the process has no service /elsewhere/_container/load_node (its component "
    "containers' are: /cam/container/_container/load_node)");
  EXPECT_STREQ(rmw_introspect::component_load_result_name(records[2].result), "no_service");
}
