// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Capture rendering (JSON / YAML, exact text for a known model) and atomic writing.

#include <gtest/gtest.h>
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>

#include "rmw/qos_profiles.h"

#include "detail/capture_writer.hpp"
#include "detail/recorder.hpp"

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
  recorder.destroy_endpoint(id);
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
  if (!d) {return -1;}
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
  "format_minor": 2,
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
  "time": {
    "horizon_ms": 10000,
    "virtual_elapsed_ms": 3031.900,
    "real_elapsed_ms": 31.900,
    "jumps": 1,
    "warp_ms": 3000.000,
    "horizon_reached": false,
    "warp_budget_exhausted": false
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
  EXPECT_NE(std::string::npos, yaml.find("  parameters:\n  - name: \"gain\"\n    type: \"double\"\n    value: 1.0\n")) << yaml;
  EXPECT_NE(std::string::npos, yaml.find("    value:\n    - 1\n    - -2\n")) << yaml;
  EXPECT_NE(std::string::npos, yaml.find("    transitions:\n    - id: 1\n      label: \"configure\"\n")) << yaml;
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
  "nodes": [)")) << text;
  EXPECT_NE(std::string::npos, text.find("      \"created_in\": \"stimulus:/camera_info\"\n")) << text;
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
// Two endpoint types that share a nested type, as describe_*_type makes them.
RecorderSnapshot sample_with_types()
{
  using rmw_introspect::FieldArray;
  using rmw_introspect::TypeDescription;
  using rmw_introspect::TypeDescriptions;
  TypeDescription point;
  point.name = "pkg/msg/Point";
  point.fields = {{"x", "float64", FieldArray::None, 0, 0}, {"y", "float64", FieldArray::None, 0, 0}};
  point.constants_known = true;
  TypeDescription path;
  path.name = "pkg/msg/Path";
  path.fields = {
    {"points", "pkg/msg/Point", FieldArray::Bounded, 100, 0},
    {"names", "string", FieldArray::Fixed, 2, 8},
    {"tags", "wstring", FieldArray::Unbounded, 0, 0}};
  path.constants_known = true;
  path.constants = {{"MAX", "uint8", "100"}};
  TypeDescription service;
  service.name = "pkg/srv/Plan";
  service.is_service = true;
  service.constants_known = true;
  service.request = "pkg/srv/Plan_Request";
  service.response = "pkg/srv/Plan_Response";
  TypeDescription request;
  request.name = "pkg/srv/Plan_Request";
  request.fields = {{"goal", "pkg/msg/Point", FieldArray::None, 0, 0}};  // constants unknown
  TypeDescription response;
  response.name = "pkg/srv/Plan_Response";
  response.fields = {{"path", "pkg/msg/Path", FieldArray::None, 0, 0}};
  response.constants_known = true;

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
    TypeDescriptions{service, request, point, response, path});
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
    yaml.find("\ntypes:\n  pkg/msg/Path:\n    kind: \"message\"\n    fields:\n    - name: \"points\"\n"));
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
  EXPECT_NE(
    std::string::npos,
    text.find("  qos:\n    history: \"KEEP_LAST\"\n    depth: 10\n"));
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
  EXPECT_FALSE(
    rmw_introspect::write_file_atomically(dir + "/missing/capture.json", "x", &error));
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
