// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Capture rendering (JSON / YAML, exact text for a known model) and atomic writing.

#include <gtest/gtest.h>
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "rmw/qos_profiles.h"

#include "detail/capture_writer.hpp"
#include "detail/json_writer.hpp"
#include "detail/recorder.hpp"
#include "reference_capture_writer.hpp"

using rmw_introspect::CaptureHeader;
using rmw_introspect::RecorderSnapshot;

namespace
{
RecorderSnapshot sample()
{
  rmw_introspect::Recorder recorder;
  const uint64_t n = recorder.add_node("talker", "/", "/", {0.5, 0.5});
  rmw_introspect::EndpointRecord e;
  e.kind = rmw_introspect::EndpointKind::Publisher;
  e.node_id = n;
  e.name = "/chatter";
  e.type = "std_msgs/msg/String";
  e.type_hash = "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18";
  e.typesupport = "rosidl_typesupport_c";
  e.qos = rmw_qos_profile_default;
  e.created = {3000.25, 30.125};
  recorder.add_endpoint(e);
  e.kind = rmw_introspect::EndpointKind::Subscription;
  e.name = "/odd \"name\"\\\n";
  e.type_hash.clear();
  e.qos = rmw_qos_profile_sensor_data;
  e.qos.lifespan = RMW_DURATION_INFINITE;
  e.qos.deadline = {1, 5};
  const uint64_t id = recorder.add_endpoint(e);
  recorder.destroy_endpoint(id, false, {8000.5, 40.25});
  return recorder.snapshot();
}

CaptureHeader header()
{
  CaptureHeader h;
  h.pid = 4242;
  h.argv = {"/usr/bin/python3", "talker.py"};
  h.state = "settled";
  h.settle_ms = 10;
  h.has_time_to_settle = true;
  h.time_to_settle_ms = 31.75;
  h.elapsed_ms = 31.9;
  h.settled_by = "wait";
  h.ever_waited = true;
  h.activity_calls = 3;
  h.idle_detect = true;
  h.idle_settles = 2;
  h.window_settles = 1;
  h.horizon_ms = 10000;
  h.virtual_elapsed_ms = 3031.9;
  h.real_elapsed_ms = 31.9;
  h.jumps = 1;
  h.warp_ms = 3000.0;
  return h;
}

std::string read_file(const std::string & path)
{
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::string temp_dir()
{
  char tmpl[] = "/tmp/rmwi_capture_test_XXXXXX";
  const char * dir = mkdtemp(tmpl);
  return dir ? dir : "/tmp";
}

int count_entries(const std::string & dir)
{
  int n = 0;
  DIR * d = opendir(dir.c_str());
  if (!d) {
    return -1;
  }
  while (dirent * e = readdir(d)) {
    if (std::string(e->d_name) != "." && std::string(e->d_name) != "..") {
      ++n;
    }
  }
  closedir(d);
  return n;
}
}  // namespace

TEST(CaptureWriter, json_exact)
{
  const std::string expected = R"({
  "format": "rmw_introspect_capture",
  "format_version": 1,
  "format_minor": 4,
  "rmw_implementation": "rmw_introspect_cpp",
  "pid": 4242,
  "argv": ["/usr/bin/python3", "talker.py"],
  "state": "settled",
  "settle_ms": 10,
  "time_to_settle_ms": 31.750,
  "elapsed_ms": 31.900,
  "settled_by": "wait",
  "ever_waited": true,
  "activity_calls": 3,
  "quiescence": {
    "detect": true,
    "detected": 2,
    "window": 1,
    "polls": 0,
    "not_idle": null
  },
  "time": {
    "horizon_ms": 10000,
    "virtual_elapsed_ms": 3031.900,
    "real_elapsed_ms": 31.900,
    "jumps": 1,
    "warp_ms": 3000.000,
    "horizon_reached": false,
    "warp_budget_exhausted": false,
    "warp_stalled": false,
    "warp_real_waits": false,
    "warp_real_ms": 0.000,
    "warp_polls": 0,
    "warp_activity": 0
  },
  "probe": {
    "state": "off",
    "parameters": false,
    "lifecycle": "none",
    "answer_timeout_ms": 0,
    "requests": 0,
    "unanswered": 0
  },
  "stimuli": [],
  "nodes": [
    {
      "id": 1,
      "seq": 1,
      "name": "talker",
      "namespace": "/",
      "fqn": "/talker",
      "enclave": "/",
      "destroyed": false,
      "in_teardown": false,
      "created_virtual_ms": 0.500,
      "created_real_ms": 0.500,
      "destroyed_virtual_ms": null,
      "destroyed_real_ms": null,
      "parameters": null,
      "parameters_error": null,
      "lifecycle": null
    }
  ],
  "endpoints": [
    {
      "seq": 2,
      "kind": "publisher",
      "node_id": 1,
      "node": "/talker",
      "name": "/chatter",
      "type": "std_msgs/msg/String",
      "type_hash": "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18",
      "typesupport": "rosidl_typesupport_c",
      "qos": {
        "history": "KEEP_LAST",
        "depth": 10,
        "reliability": "RELIABLE",
        "durability": "VOLATILE",
        "liveliness": "SYSTEM_DEFAULT",
        "deadline_ns": 0,
        "lifespan_ns": 0,
        "liveliness_lease_duration_ns": 0,
        "avoid_ros_namespace_conventions": false
      },
      "destroyed": false,
      "in_teardown": false,
      "created_virtual_ms": 3000.250,
      "created_real_ms": 30.125,
      "destroyed_virtual_ms": null,
      "destroyed_real_ms": null,
      "created_in": null
    },
    {
      "seq": 3,
      "kind": "subscription",
      "node_id": 1,
      "node": "/talker",
      "name": "/odd \"name\"\\\n",
      "type": "std_msgs/msg/String",
      "type_hash": null,
      "typesupport": "rosidl_typesupport_c",
      "qos": {
        "history": "KEEP_LAST",
        "depth": 5,
        "reliability": "BEST_EFFORT",
        "durability": "VOLATILE",
        "liveliness": "SYSTEM_DEFAULT",
        "deadline_ns": 1000000005,
        "lifespan_ns": -1,
        "liveliness_lease_duration_ns": 0,
        "avoid_ros_namespace_conventions": false
      },
      "destroyed": true,
      "in_teardown": false,
      "created_virtual_ms": 3000.250,
      "created_real_ms": 30.125,
      "destroyed_virtual_ms": 8000.500,
      "destroyed_real_ms": 40.250,
      "created_in": null
    }
  ],
  "types": {}
}
)";
  EXPECT_EQ(expected, rmw_introspect::render_capture_json(header(), sample()));
}

TEST(CaptureWriter, parameters_lifecycle_and_created_in)
{
  rmw_introspect::Recorder recorder;
  const uint64_t n = recorder.add_node("lc", "/", "/", {0.5, 0.5});
  rmw_introspect::NodeProbe probe;
  probe.has_parameters = true;
  rmw_introspect::ParameterRecord p;
  p.name = "gain";
  p.descriptor_type = rmw_introspect::kParameterDouble;
  p.value.type = rmw_introspect::kParameterDouble;
  p.value.double_value = 1.0;
  p.read_only = true;
  p.description = "loop gain";
  p.has_floating_point_range = true;
  p.floating_point_range = {0.0, 2.5, 0.1};
  probe.parameters.push_back(p);
  p = rmw_introspect::ParameterRecord();
  p.name = "ids";
  p.value.type = rmw_introspect::kParameterIntegerArray;
  p.value.integer_array_value = {1, -2};
  p.has_integer_range = true;
  p.integer_range = {-5, 5, 1};
  p.declared_in = "configure";
  probe.parameters.push_back(p);
  p = rmw_introspect::ParameterRecord();
  p.name = "unset";
  p.descriptor_type = rmw_introspect::kParameterString;
  p.dynamic_typing = true;
  probe.parameters.push_back(p);
  p = rmw_introspect::ParameterRecord();
  p.name = "odd";
  p.value.type = rmw_introspect::kParameterDoubleArray;
  p.value.double_array_value = {0.1, std::numeric_limits<double>::quiet_NaN(), -HUGE_VAL, 1e300};
  probe.parameters.push_back(p);
  p = rmw_introspect::ParameterRecord();
  p.name = "bytes";
  p.value.type = rmw_introspect::kParameterByteArray;
  p.value.byte_array_value = {0, 255};
  probe.parameters.push_back(p);
  probe.has_lifecycle = true;
  probe.lifecycle.target = "active";
  probe.lifecycle.initial_state = "unconfigured";
  probe.lifecycle.state = "inactive";
  rmw_introspect::LifecycleTransitionRecord t;
  t.id = 1;
  t.label = "configure";
  t.result = rmw_introspect::LifecycleTransitionRecord::Result::kSuccess;
  probe.lifecycle.transitions.push_back(t);
  t.id = 3;
  t.label = "activate";
  t.result = rmw_introspect::LifecycleTransitionRecord::Result::kFailure;
  probe.lifecycle.transitions.push_back(t);
  probe.lifecycle.error = "transition activate of /lc failed";
  recorder.set_node_probe(n, probe);
  recorder.set_node_transition(n, "configure");
  rmw_introspect::EndpointRecord e;
  e.kind = rmw_introspect::EndpointKind::Publisher;
  e.node_id = n;
  e.name = "/lc_chatter";
  e.type = "std_msgs/msg/String";
  recorder.add_endpoint(e);
  CaptureHeader h = header();
  h.probe_state = "done";
  h.probe_parameters = true;
  h.probe_lifecycle = "active";
  h.answer_timeout_ms = 5000;
  h.probe_requests = 12;
  const std::string text = rmw_introspect::render_capture_json(h, recorder.snapshot());
  const std::string expected_node = R"(      "parameters": [
        {
          "name": "gain",
          "type": "double",
          "value": 1.0,
          "read_only": true,
          "dynamic_typing": false,
          "description": "loop gain",
          "additional_constraints": "",
          "integer_range": null,
          "floating_point_range": {
            "from_value": 0.0,
            "to_value": 2.5,
            "step": 0.1
          },
          "declared_in": null
        },
        {
          "name": "ids",
          "type": "integer_array",
          "value": [1, -2],
          "read_only": false,
          "dynamic_typing": false,
          "description": "",
          "additional_constraints": "",
          "integer_range": {
            "from_value": -5,
            "to_value": 5,
            "step": 1
          },
          "floating_point_range": null,
          "declared_in": "configure"
        },
        {
          "name": "unset",
          "type": "string",
          "value": null,
          "read_only": false,
          "dynamic_typing": true,
          "description": "",
          "additional_constraints": "",
          "integer_range": null,
          "floating_point_range": null,
          "declared_in": null
        },
        {
          "name": "odd",
          "type": "double_array",
          "value": [0.1, "nan", "-inf", 1e+300],
          "read_only": false,
          "dynamic_typing": false,
          "description": "",
          "additional_constraints": "",
          "integer_range": null,
          "floating_point_range": null,
          "declared_in": null
        },
        {
          "name": "bytes",
          "type": "byte_array",
          "value": [0, 255],
          "read_only": false,
          "dynamic_typing": false,
          "description": "",
          "additional_constraints": "",
          "integer_range": null,
          "floating_point_range": null,
          "declared_in": null
        }
      ],
      "parameters_error": null,
      "lifecycle": {
        "target": "active",
        "initial_state": "unconfigured",
        "state": "inactive",
        "transitions": [
          {
            "id": 1,
            "label": "configure",
            "result": "success",
            "success": true
          },
          {
            "id": 3,
            "label": "activate",
            "result": "failure",
            "success": false
          }
        ],
        "error": "transition activate of /lc failed"
      }
    }
)";
  EXPECT_NE(std::string::npos, text.find(expected_node)) << text;
  EXPECT_NE(std::string::npos, text.find("      \"created_in\": \"configure\"\n")) << text;
  EXPECT_NE(std::string::npos, text.find(R"(  "probe": {
    "state": "done",
    "parameters": true,
    "lifecycle": "active",
    "answer_timeout_ms": 5000,
    "requests": 12,
    "unanswered": 0
  },
)")) << text;
  // YAML: the same tree.
  const std::string yaml = rmw_introspect::render_capture_yaml(h, recorder.snapshot());
  EXPECT_NE(
    std::string::npos,
    yaml.find("  parameters:\n  - name: \"gain\"\n    type: \"double\"\n    value: 1.0\n"))
    << yaml;
  EXPECT_NE(std::string::npos, yaml.find("    value:\n    - 1\n    - -2\n")) << yaml;
  EXPECT_NE(
    std::string::npos, yaml.find("    transitions:\n    - id: 1\n      label: \"configure\"\n"))
    << yaml;
}

TEST(CaptureWriter, stimuli_and_what_their_nodes_created_after_them)
{
  rmw_introspect::Recorder recorder;
  const uint64_t n = recorder.add_node("cam", "/", "/", {0.5, 0.5});
  recorder.set_cause(rmw_introspect::stimulus_label("/camera_info"));
  rmw_introspect::EndpointRecord e;
  e.kind = rmw_introspect::EndpointKind::Publisher;
  e.node_id = n;
  e.name = "/image";
  e.type = "sensor_msgs/msg/Image";
  recorder.add_endpoint(e);
  CaptureHeader h = header();
  rmw_introspect::StimulusRecord taken;
  taken.name = "/camera_info";
  taken.state = rmw_introspect::StimulusRecord::State::kDone;
  rmw_introspect::StimulusTargetRecord target;
  target.kind = rmw_introspect::EndpointKind::Subscription;
  target.node = "/cam";
  target.type = "sensor_msgs/msg/CameraInfo";
  target.result = rmw_introspect::StimulusTargetRecord::Result::kTaken;
  taken.targets.push_back(target);
  rmw_introspect::StimulusRecord missing;
  missing.name = "/nothing";
  missing.state = rmw_introspect::StimulusRecord::State::kNoMatch;
  missing.error = "no subscription or service named /nothing";
  h.stimuli = {taken, missing};
  const std::string text = rmw_introspect::render_capture_json(h, recorder.snapshot());
  EXPECT_NE(std::string::npos, text.find(R"(  "stimuli": [
    {
      "name": "/camera_info",
      "state": "done",
      "targets": [
        {
          "kind": "subscription",
          "node": "/cam",
          "type": "sensor_msgs/msg/CameraInfo",
          "result": "taken",
          "error": null
        }
      ],
      "error": null
    },
    {
      "name": "/nothing",
      "state": "no_match",
      "targets": [],
      "error": "no subscription or service named /nothing"
    }
  ],
  "nodes": [)"))
    << text;
  EXPECT_NE(std::string::npos, text.find("      \"created_in\": \"stimulus:/camera_info\"\n"))
    << text;
  const std::string yaml = rmw_introspect::render_capture_yaml(h, recorder.snapshot());
  EXPECT_NE(std::string::npos, yaml.find("stimuli:\n- name: \"/camera_info\"\n  state: \"done\"\n"))
    << yaml;
}

TEST(CaptureWriter, json_null_time_to_settle_and_empty_lists)
{
  CaptureHeader h = header();
  h.state = "running";
  h.has_time_to_settle = false;
  const std::string text = rmw_introspect::render_capture_json(h, RecorderSnapshot{});
  EXPECT_NE(std::string::npos, text.find("\"time_to_settle_ms\": null,"));
  EXPECT_NE(std::string::npos, text.find("\"nodes\": [],"));
  EXPECT_NE(std::string::npos, text.find("\"endpoints\": [],\n"));
  EXPECT_NE(std::string::npos, text.find("\"types\": {}\n}"));
}

namespace
{
// pkg/srv/Plan as describe_service_type makes it: the service, its request (constants
// unknown) and its response, which name pkg/msg/Point and pkg/msg/Path (not included)
struct PlanService
{
  rmw_introspect::TypeDescription service, request, response;
};

PlanService plan_service()
{
  using rmw_introspect::FieldArray;
  PlanService plan;
  plan.service.name = "pkg/srv/Plan";
  plan.service.is_service = true;
  plan.service.constants_known = true;
  plan.service.request = "pkg/srv/Plan_Request";
  plan.service.response = "pkg/srv/Plan_Response";
  plan.request.name = "pkg/srv/Plan_Request";
  plan.request.fields = {{"goal", "pkg/msg/Point", FieldArray::None, 0, 0}};
  plan.response.name = "pkg/srv/Plan_Response";
  plan.response.fields = {{"path", "pkg/msg/Path", FieldArray::None, 0, 0}};
  plan.response.constants_known = true;
  return plan;
}

// Two endpoint types that share a nested type, as describe_*_type makes them.
RecorderSnapshot sample_with_types()
{
  using rmw_introspect::FieldArray;
  using rmw_introspect::TypeDescription;
  using rmw_introspect::TypeDescriptions;
  TypeDescription point;
  point.name = "pkg/msg/Point";
  point.fields = {
    {"x", "float64", FieldArray::None, 0, 0}, {"y", "float64", FieldArray::None, 0, 0}};
  point.constants_known = true;
  TypeDescription path;
  path.name = "pkg/msg/Path";
  path.fields = {
    {"points", "pkg/msg/Point", FieldArray::Bounded, 100, 0},
    {"names", "string", FieldArray::Fixed, 2, 8},
    {"tags", "wstring", FieldArray::Unbounded, 0, 0}};
  path.constants_known = true;
  path.constants = {{"MAX", "uint8", "100"}};
  const PlanService plan = plan_service();

  rmw_introspect::Recorder recorder;
  const uint64_t n = recorder.add_node("planner", "/", "/");
  rmw_introspect::EndpointRecord e;
  e.node_id = n;
  e.kind = rmw_introspect::EndpointKind::Publisher;
  e.name = "/path";
  e.type = "pkg/msg/Path";
  e.types = std::make_shared<const TypeDescriptions>(TypeDescriptions{path, point});
  e.qos = rmw_qos_profile_default;
  recorder.add_endpoint(e);
  e.kind = rmw_introspect::EndpointKind::Service;
  e.name = "/plan";
  e.type = "pkg/srv/Plan";
  e.types = std::make_shared<const TypeDescriptions>(
    TypeDescriptions{plan.service, plan.request, point, plan.response, path});
  recorder.add_endpoint(e);
  e.name = "/undescribed";
  e.types = nullptr;
  recorder.add_endpoint(e);
  return recorder.snapshot();
}
}  // namespace

TEST(CaptureWriter, types_table_once_per_type_sorted_by_name)
{
  const std::string text = rmw_introspect::render_capture_json(header(), sample_with_types());
  const std::string expected = R"(  "types": {
    "pkg/msg/Path": {
      "kind": "message",
      "fields": [
        {
          "name": "points",
          "type": "pkg/msg/Point",
          "array": "bounded",
          "array_size": 100
        },
        {
          "name": "names",
          "type": "string",
          "array": "fixed",
          "array_size": 2,
          "string_bound": 8
        },
        {
          "name": "tags",
          "type": "wstring",
          "array": "unbounded"
        }
      ],
      "constants": [
        {
          "name": "MAX",
          "type": "uint8",
          "value": "100"
        }
      ]
    },
    "pkg/msg/Point": {
      "kind": "message",
      "fields": [
        {
          "name": "x",
          "type": "float64"
        },
        {
          "name": "y",
          "type": "float64"
        }
      ],
      "constants": []
    },
    "pkg/srv/Plan": {
      "kind": "service",
      "request": "pkg/srv/Plan_Request",
      "response": "pkg/srv/Plan_Response"
    },
    "pkg/srv/Plan_Request": {
      "kind": "message",
      "fields": [
        {
          "name": "goal",
          "type": "pkg/msg/Point"
        }
      ]
    },
    "pkg/srv/Plan_Response": {
      "kind": "message",
      "fields": [
        {
          "name": "path",
          "type": "pkg/msg/Path"
        }
      ],
      "constants": []
    }
  }
}
)";
  ASSERT_NE(std::string::npos, text.find("  \"types\": {"));
  EXPECT_EQ(expected, text.substr(text.find("  \"types\": {")));
  // YAML: the same table, keys as plain scalars
  const std::string yaml = rmw_introspect::render_capture_yaml(header(), sample_with_types());
  EXPECT_NE(
    std::string::npos,
    yaml.find(
      "\ntypes:\n  pkg/msg/Path:\n    kind: \"message\"\n    fields:\n    - name: \"points\"\n"));
}

TEST(CaptureWriter, invalid_utf8_is_replaced)
{
  CaptureHeader h = header();
  h.argv = {std::string("bad\xff\xfe", 5), "ok\xc3\xa9"};
  const std::string text = rmw_introspect::render_capture_json(h, RecorderSnapshot{});
  EXPECT_NE(std::string::npos, text.find("\"bad\\ufffd\\ufffd\""));
  EXPECT_NE(std::string::npos, text.find("\"ok\xc3\xa9\""));
}

TEST(CaptureWriter, yaml_layout)
{
  const std::string text = rmw_introspect::render_capture_yaml(header(), sample());
  EXPECT_EQ(0u, text.find("# rmw_introspect capture"));
  EXPECT_NE(std::string::npos, text.find("\nformat: \"rmw_introspect_capture\"\n"));
  EXPECT_NE(std::string::npos, text.find("\nargv:\n- \"/usr/bin/python3\"\n- \"talker.py\"\n"));
  EXPECT_NE(std::string::npos, text.find("\nnodes:\n- id: 1\n  seq: 1\n  name: \"talker\"\n"));
  EXPECT_NE(std::string::npos, text.find("  qos:\n    history: \"KEEP_LAST\"\n    depth: 10\n"));
  EXPECT_NE(std::string::npos, text.find("  type_hash: null\n"));
  EXPECT_NE(std::string::npos, text.find("time_to_settle_ms: 31.750\n"));
}

TEST(CaptureWriter, atomic_write_replaces_and_leaves_no_temp_file)
{
  const std::string dir = temp_dir();
  const std::string path = dir + "/capture.json";
  std::string error;
  ASSERT_TRUE(rmw_introspect::write_file_atomically(path, "first\n", &error)) << error;
  EXPECT_EQ("first\n", read_file(path));
  ASSERT_TRUE(rmw_introspect::write_file_atomically(path, "second\n", &error)) << error;
  EXPECT_EQ("second\n", read_file(path));
  EXPECT_EQ(1, count_entries(dir));  // no <path>.tmp.<pid> left behind
  // A failing write (the target is a directory) leaves nothing half-written.
  const std::string sub = dir + "/sub";
  ASSERT_EQ(0, mkdir(sub.c_str(), 0755));
  EXPECT_FALSE(rmw_introspect::write_file_atomically(sub, "x", &error));
  EXPECT_FALSE(error.empty());
  EXPECT_EQ(2, count_entries(dir));
  EXPECT_FALSE(rmw_introspect::write_file_atomically(dir + "/missing/capture.json", "x", &error));
  rmdir(sub.c_str());
  unlink(path.c_str());
  rmdir(dir.c_str());
}

TEST(CaptureWriter, argv_of_this_process)
{
  const auto argv = rmw_introspect::read_process_argv();
  ASSERT_FALSE(argv.empty());
  EXPECT_NE(std::string::npos, argv[0].find("test_capture_writer"));
}

TEST(CaptureWriter, ended_only_in_end_captures_with_teardown_marks)
{
  CaptureHeader h = header();
  h.state = "exit";
  h.has_ended = true;
  h.ended_before_settle = true;
  h.settled_by.clear();
  rmw_introspect::Recorder recorder;
  const uint64_t n = recorder.add_node("n", "/", "/");
  rmw_introspect::EndpointRecord e;
  e.node_id = n;
  e.name = "/p";
  e.type = "std_msgs/msg/String";
  e.typesupport = "rosidl_typesupport_c";
  e.qos = rmw_qos_profile_default;
  recorder.add_endpoint(e);
  recorder.destroy_node(n);
  const std::string text = rmw_introspect::render_capture_json(h, recorder.snapshot(true));
  EXPECT_NE(std::string::npos, text.find("\"settled_by\": null,"));
  EXPECT_NE(std::string::npos, text.find("\"ended\": {\n    \"before_settle\": true\n  },"));
  EXPECT_EQ(std::string::npos, text.find("\"in_teardown\": false"));
  h.has_ended = false;
  EXPECT_EQ(
    std::string::npos, rmw_introspect::render_capture_json(h, recorder.snapshot()).find("ended"));
}

namespace
{
using rmw_introspect::FieldArray;
using rmw_introspect::TypeDescription;
using rmw_introspect::TypeDescriptions;

// Every kind of byte a string can hold: quotes, backslash, control characters, DEL, valid
// and invalid UTF-8 (truncated, overlong, surrogate lead, past U+10FFFF, stray continuation).
const std::string kOdd = std::string(
                           "q\"b\\n\nt\tr\r\x01\x1f\x7f \xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80 "
                           "\xc3 \xc0\xaf \xe2\x82 \xf5\x80\x80\x80 \x80 \xff") +
  std::string(1, '\0') + "end";

std::shared_ptr<const TypeDescriptions> path_types(const std::string & constant_value)
{
  TypeDescription point;
  point.name = "pkg/msg/Point";
  point.fields = {
    {"x", "float64", FieldArray::None, 0, 0}, {"y", "float64", FieldArray::None, 0, 0}};
  point.constants_known = true;
  TypeDescription path;
  path.name = "pkg/msg/Path";
  path.fields = {
    {"points", "pkg/msg/Point", FieldArray::Bounded, 100, 0},
    {"names", "string", FieldArray::Fixed, 2, 8},
    {"tags", "wstring", FieldArray::Unbounded, 0, 0},
    {"label", "string", FieldArray::None, 0, 16}};
  path.constants_known = true;
  path.constants = {{"MAX", "uint8", constant_value}, {"ODD", "string", kOdd}};
  TypeDescription empty;
  empty.name = "pkg/msg/Empty";
  empty.constants_known = false;
  return std::make_shared<const TypeDescriptions>(TypeDescriptions{path, point, empty});
}

std::shared_ptr<const TypeDescriptions> service_types()
{
  const PlanService plan = plan_service();
  TypeDescription point;  // nested, listed again (the first listing wins)
  point.name = "pkg/msg/Point";
  point.fields = {{"different", "int8", FieldArray::None, 0, 0}};
  return std::make_shared<const TypeDescriptions>(
    TypeDescriptions{plan.service, plan.request, plan.response, point});
}

rmw_introspect::NodeProbe full_probe()
{
  using rmw_introspect::ParameterRecord;
  rmw_introspect::NodeProbe probe;
  probe.has_parameters = true;
  probe.parameters_error = kOdd;
  const uint8_t kinds[] = {
    rmw_introspect::kParameterNotSet,
    rmw_introspect::kParameterBool,
    rmw_introspect::kParameterInteger,
    rmw_introspect::kParameterDouble,
    rmw_introspect::kParameterString,
    rmw_introspect::kParameterByteArray,
    rmw_introspect::kParameterBoolArray,
    rmw_introspect::kParameterIntegerArray,
    rmw_introspect::kParameterDoubleArray,
    rmw_introspect::kParameterStringArray,
    42};
  for (uint8_t kind : kinds) {
    ParameterRecord p;
    p.name = "p" + std::to_string(kind);
    p.descriptor_type = kind;
    p.value.type = kind;
    p.value.bool_value = true;
    p.value.integer_value = std::numeric_limits<int64_t>::min();
    p.value.double_value = -0.0;
    p.value.string_value = kOdd;
    p.value.byte_array_value = {0, 127, 255};
    p.value.bool_array_value = {true, false};
    p.value.integer_array_value = {std::numeric_limits<int64_t>::max(), -1, 0};
    p.value.double_array_value = {
      0.1,
      1.0 / 3.0,
      1e300,
      5e-324,
      -2.5,
      100.0,
      1e21,
      123456789012345678.0,
      std::numeric_limits<double>::quiet_NaN(),
      HUGE_VAL,
      -HUGE_VAL};
    p.value.string_array_value = {"", kOdd, "plain"};
    p.description = kOdd;
    p.read_only = kind % 2 == 0;
    p.dynamic_typing = kind % 3 == 0;
    p.has_integer_range = kind % 2 == 1;
    p.integer_range = {-7, 7, 3};
    p.has_floating_point_range = kind % 2 == 0;
    p.floating_point_range = {-0.5, 0.1 + 0.2, std::numeric_limits<double>::infinity()};
    p.declared_in = kind == 3 ? "configure" : "";
    probe.parameters.push_back(p);
  }
  ParameterRecord empty_arrays;
  empty_arrays.name = "empty";
  empty_arrays.value.type = rmw_introspect::kParameterStringArray;
  probe.parameters.push_back(empty_arrays);
  probe.has_lifecycle = true;
  probe.lifecycle.target = "active";
  probe.lifecycle.initial_state = "unconfigured";
  using Result = rmw_introspect::LifecycleTransitionRecord::Result;
  const Result results[] = {
    Result::kSuccess, Result::kFailure, Result::kNoAnswer, Result::kPending};
  uint8_t id = 1;
  for (Result result : results) {
    rmw_introspect::LifecycleTransitionRecord t;
    t.id = id++;
    t.label = "t" + std::to_string(t.id);
    t.result = result;
    probe.lifecycle.transitions.push_back(t);
  }
  probe.lifecycle.error = kOdd;
  return probe;
}

// A capture with every kind of field the document has.
struct FullCapture
{
  CaptureHeader header;
  rmw_introspect::Recorder recorder;
  uint64_t node = 0;
};

void fill(FullCapture & c)
{
  CaptureHeader & h = c.header;
  h = header();
  h.argv = {kOdd, "", "--ros-args"};
  h.state = "exit";
  h.has_time_to_settle = false;
  h.settled_by.clear();
  h.elapsed_ms = 1e12 + 0.0005;
  h.virtual_elapsed_ms = -0.0;
  h.real_elapsed_ms = 2.0005;
  h.horizon_ms = std::numeric_limits<int64_t>::max();
  h.activity_calls = std::numeric_limits<uint64_t>::max() / 2;
  h.horizon_reached = true;
  h.warp_budget_exhausted = true;
  h.probe_state = "done";
  h.probe_parameters = true;
  h.probe_lifecycle = "active";
  h.answer_timeout_ms = -1;
  h.has_ended = true;
  h.ended_before_settle = false;
  rmw_introspect::StimulusRecord stimulus;
  stimulus.name = kOdd;
  stimulus.state = rmw_introspect::StimulusRecord::State::kDone;
  rmw_introspect::StimulusTargetRecord target;
  target.kind = rmw_introspect::EndpointKind::Service;
  target.node = "/n";
  target.type = "pkg/srv/Plan";
  target.result = rmw_introspect::StimulusTargetRecord::Result::kFailed;
  target.error = kOdd;
  stimulus.targets = {target, target};
  rmw_introspect::StimulusRecord skipped;
  skipped.name = "/skipped";
  skipped.state = rmw_introspect::StimulusRecord::State::kSkipped;
  h.stimuli = {stimulus, skipped};

  c.node = c.recorder.add_node("n", "/ns", kOdd.c_str(), {1.0005, -3.25});
  c.recorder.set_node_probe(c.node, full_probe());
  const uint64_t bare = c.recorder.add_node("bare", "/", "/");
  rmw_introspect::NodeProbe no_parameters;
  no_parameters.has_parameters = true;
  c.recorder.set_node_probe(c.recorder.add_node("empty_probe", "/", "/"), no_parameters);
  rmw_introspect::EndpointRecord e;
  e.node_id = c.node;
  e.kind = rmw_introspect::EndpointKind::Publisher;
  e.name = "/path";
  e.type = "pkg/msg/Path";
  e.type_hash = "RIHS01_00";
  e.typesupport = "rosidl_typesupport_cpp";
  e.types = path_types("100");
  e.qos = rmw_qos_profile_sensor_data;
  e.qos.deadline = {1, 5};
  e.qos.lifespan = RMW_DURATION_INFINITE;
  e.qos.avoid_ros_namespace_conventions = true;
  e.created = {0.0005, 1e9};
  c.recorder.add_endpoint(e);
  e.kind = rmw_introspect::EndpointKind::Service;
  e.name = kOdd;
  e.type = "pkg/srv/Plan";
  e.type_hash.clear();
  e.types = service_types();
  e.qos = rmw_qos_profile_services_default;
  c.recorder.add_endpoint(e);
  e.kind = rmw_introspect::EndpointKind::Client;
  e.types = nullptr;
  c.recorder.set_cause("stimulus:" + kOdd);
  const uint64_t client = c.recorder.add_endpoint(e);
  c.recorder.set_cause("");
  e.node_id = bare;
  e.kind = rmw_introspect::EndpointKind::Subscription;
  e.name = "/shared";
  e.types = path_types("100");  // the same types again, another list
  c.recorder.add_endpoint(e);
  c.recorder.destroy_endpoint(client);
  c.recorder.destroy_node(bare, true);
}
}  // namespace

TEST(CaptureWriter, json_and_yaml_equal_the_reference_renderer_for_every_field)
{
  FullCapture c;
  fill(c);
  for (bool teardown : {false, true}) {
    const RecorderSnapshot snapshot = c.recorder.snapshot(teardown);
    const std::string json = rmw_introspect::render_capture_json(c.header, snapshot);
    EXPECT_EQ(rmwi_reference::render_capture_json(c.header, snapshot), json);
    EXPECT_EQ(
      rmwi_reference::render_capture_yaml(c.header, snapshot),
      rmw_introspect::render_capture_yaml(c.header, snapshot));
    // It has what the test means it to have.
    EXPECT_NE(std::string::npos, json.find("\\u0001\\u001f\\u007f")) << json;
    EXPECT_NE(std::string::npos, json.find("\\ufffd \\ufffd\\ufffd")) << json;
    EXPECT_NE(std::string::npos, json.find("end\"")) << json;
    EXPECT_NE(std::string::npos, json.find("\"value\": [],")) << json;
    EXPECT_NE(std::string::npos, json.find("\"nan\", \"inf\", \"-inf\"]")) << json;
    EXPECT_NE(std::string::npos, json.find("\"value\": -0.0,")) << json;
    EXPECT_NE(
      std::string::npos,
      json.find(
        "\"pkg/msg/Empty\": {\n      \"kind\": \"message\",\n"
        "      \"fields\": []\n    },"))
      << json;
    EXPECT_NE(std::string::npos, json.find("\"parameters\": [],")) << json;
  }
  CaptureHeader running = c.header;
  running.state = "running";
  running.has_ended = false;
  running.has_time_to_settle = true;
  running.settled_by = "activity";
  running.stimuli.clear();
  running.argv.clear();
  const RecorderSnapshot snapshot = c.recorder.snapshot();
  EXPECT_EQ(
    rmwi_reference::render_capture_json(running, snapshot),
    rmw_introspect::render_capture_json(running, snapshot));
  EXPECT_EQ(
    rmwi_reference::render_capture_yaml(running, snapshot),
    rmw_introspect::render_capture(rmw_introspect::CaptureFormat::Yaml, running, snapshot));
  EXPECT_EQ(
    rmwi_reference::render_capture_json(running, RecorderSnapshot{}),
    rmw_introspect::render_capture(
      rmw_introspect::CaptureFormat::Json, running, RecorderSnapshot{}));
  EXPECT_EQ(
    rmwi_reference::render_capture_yaml(running, RecorderSnapshot{}),
    rmw_introspect::render_capture_yaml(running, RecorderSnapshot{}));
}

TEST(CaptureWriter, strings_and_doubles_are_written_as_the_reference_writes_them)
{
  // Every byte after plain text, and every pair of bytes (escapes, UTF-8 leads and tails).
  std::vector<std::string> inputs = {"", "plain"};
  for (int a = 0; a < 256; ++a) {
    inputs.push_back("ab" + std::string(1, static_cast<char>(a)));
    for (int b = 0; b < 256; ++b) {
      inputs.push_back(std::string{static_cast<char>(a), static_cast<char>(b)});
    }
  }
  inputs.push_back("\xf0\x9f\x98\x80x\xf0\x9f\x98");
  inputs.push_back("\xe2\x82\xac\xe2\x82\xac\xe2");
  for (const auto & in : inputs) {
    std::string out = "prefix";
    rmw_introspect::append_json_string(out, in);
    ASSERT_EQ("prefix" + rmwi_reference::quote_string(in), out) << in;
  }
  const double doubles[] = {
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.1,
    0.2,
    0.1 + 0.2,
    1.0 / 3.0,
    2.0 / 3.0,
    1e15,
    1e16,
    1e17,
    1e21,
    1e22,
    1e-5,
    1e-7,
    123.456,
    5e-324,
    2.2250738585072014e-308,
    std::numeric_limits<double>::max(),
    std::numeric_limits<double>::lowest(),
    9007199254740993.0,
    4.35,
    0.3,
    std::numeric_limits<double>::quiet_NaN(),
    HUGE_VAL,
    -HUGE_VAL};
  for (double d : doubles) {
    std::string out;
    rmw_introspect::append_exact_double(out, d);
    EXPECT_EQ(rmwi_reference::exact_double_text(d), out) << d;
  }
}

TEST(CaptureWriter, a_renderer_gives_the_same_text_each_time_and_renders_each_type_once)
{
  FullCapture c;
  fill(c);
  const RecorderSnapshot snapshot = c.recorder.snapshot();
  const std::string expected = rmwi_reference::render_capture_json(c.header, snapshot);
  rmw_introspect::CaptureRenderer renderer;
  EXPECT_EQ(expected, renderer.render_json(c.header, snapshot));
  const uint64_t renders = renderer.type_cache().renders();
  EXPECT_EQ(3u + 4u + 3u, renders);  // per list: path, service, path again
  EXPECT_EQ(expected, renderer.render_json(c.header, snapshot));
  EXPECT_EQ(expected, renderer.render_json(c.header, c.recorder.snapshot()));  // a new snapshot
  EXPECT_EQ(renders, renderer.type_cache().renders());
  // The YAML output does not go through the cache and stays as it was.
  EXPECT_EQ(
    rmwi_reference::render_capture_yaml(c.header, snapshot),
    renderer.render(rmw_introspect::CaptureFormat::Yaml, c.header, snapshot));
  EXPECT_EQ(expected, renderer.render(rmw_introspect::CaptureFormat::Json, c.header, snapshot));
}

TEST(CaptureWriter, a_type_added_between_writes_shows_up)
{
  rmw_introspect::Recorder recorder;
  const uint64_t n = recorder.add_node("n", "/", "/");
  rmw_introspect::EndpointRecord e;
  e.node_id = n;
  e.name = "/plan";
  e.kind = rmw_introspect::EndpointKind::Service;
  e.type = "pkg/srv/Plan";
  e.types = service_types();
  recorder.add_endpoint(e);
  rmw_introspect::CaptureRenderer renderer;
  const CaptureHeader h = header();
  const std::string first = renderer.render_json(h, recorder.snapshot());
  EXPECT_EQ(rmwi_reference::render_capture_json(h, recorder.snapshot()), first);
  EXPECT_EQ(std::string::npos, first.find("\"pkg/msg/Path\": {"));
  EXPECT_NE(std::string::npos, first.find("\"different\""));  // the service's Point
  // A new endpoint with new types: they show up; Point stays the first listed one.
  e.kind = rmw_introspect::EndpointKind::Publisher;
  e.name = "/path";
  e.type = "pkg/msg/Path";
  e.types = path_types("7");
  recorder.add_endpoint(e);
  const std::string second = renderer.render_json(h, recorder.snapshot());
  EXPECT_EQ(rmwi_reference::render_capture_json(h, recorder.snapshot()), second);
  EXPECT_NE(std::string::npos, second.find("\"pkg/msg/Path\": {"));
  EXPECT_NE(std::string::npos, second.find("\"value\": \"7\""));
  EXPECT_NE(std::string::npos, second.find("\"different\""));
  EXPECT_EQ(4u + 3u, renderer.type_cache().renders());
  // A snapshot made of other lists (same names, other contents) shows those.
  RecorderSnapshot other = recorder.snapshot();
  other.endpoints.erase(other.endpoints.begin());
  other.endpoints[0].types = path_types("8");
  const std::string third = renderer.render_json(h, other);
  EXPECT_EQ(rmwi_reference::render_capture_json(h, other), third);
  EXPECT_NE(std::string::npos, third.find("\"value\": \"8\""));
  EXPECT_EQ(std::string::npos, third.find("\"value\": \"7\""));
  EXPECT_EQ(std::string::npos, third.find("\"different\""));
}
