"""Parameters and lifecycle (issue 10): after the first settle the middleware asks each node's
own parameter and lifecycle services in process (rmw_take_request / rmw_send_response, no
network) and records the answers. Real rclpy nodes on the raw middleware."""

import pytest
import rmwi_helpers as h
from rmwi_helpers import ep, node
from rmwi_helpers import rclpy_node_infrastructure as infra

RCLPY_PARAMETERS = [
    {"name": "use_sim_time", "type": "bool", "value": False},
    {"name": "start_type_description_service", "type": "bool", "value": True, "read_only": True,
     "description": "If enabled, start the ~/get_type_description service."},
]


def param(name, type_, value, *, read_only=False, dynamic_typing=False, description="",
          additional_constraints="", integer_range=None, floating_point_range=None, declared_in=None):
    return {"name": name, "type": type_, "value": value, "read_only": read_only,
            "dynamic_typing": dynamic_typing, "description": description,
            "additional_constraints": additional_constraints, "integer_range": integer_range,
            "floating_point_range": floating_point_range, "declared_in": declared_in}


def rclpy_parameters(declared_in=None):
    return [param(p["name"], p["type"], p["value"], read_only=p.get("read_only", False),
                  description=p.get("description", ""), declared_in=declared_in) for p in RCLPY_PARAMETERS]


def by_name(capture):
    return {e["name"]: e for e in capture["endpoints"]}


def the_node(capture, fqn):
    return next(n for n in capture["nodes"] if n["fqn"] == fqn)


def assert_probed(result):
    h.assert_settled_process(result)
    assert result.capture["format_minor"] == 4
    probe = result.capture["probe"]
    assert probe["state"] == "done", probe
    assert probe["unanswered"] == 0, probe
    return probe


# ----------------------------------------------------------------------------- parameters
def test_every_parameter_type_with_descriptors_file_and_command_line_overrides(run, tmp_path):
    params_file = tmp_path / "params.yaml"
    params_file.write_text("params_node:\n  ros__parameters:\n    count: 64\n    limits:\n      max_speed: 3.5\n")
    result = run(h.python_node("params_node.py", "--ros-args", "--params-file", params_file,
                               "-p", "frame:=odom", "-p", "anything:=hello"))
    probe = assert_probed(result)
    # list, describe, get; rclpy answers the batch get empty (typed_only has no value): then
    # one get per name.
    assert probe["parameters"] is True and probe["requests"] == 3 + 15
    n = "/params_node"
    # The injected requests are invisible: exactly the node's own entities, settled by its wait.
    h.assert_capture(result.capture, [node("params_node")], infra(n) + [ep("publisher", n, "/chatter", "std_msgs/msg/String")])
    assert result.capture["settled_by"] == "wait"
    assert all(e["created_in"] is None for e in result.capture["endpoints"])
    record = the_node(result.capture, n)
    assert record["parameters_error"] is None
    assert record["lifecycle"] is None
    assert record["parameters"] == rclpy_parameters() + [
        param("flag", "bool", True),
        param("count", "integer", 64, description="how many",
              integer_range={"from_value": 0, "to_value": 100, "step": 2}),
        param("gain", "double", 0.5, additional_constraints="tuned on the robot",
              floating_point_range={"from_value": 0.0, "to_value": 1.0, "step": 0.0}),
        param("frame", "string", "odom", read_only=True, description="TF frame"),
        param("blob", "byte_array", [0, 1, 255]),
        param("flags", "bool_array", [True, False, True]),
        param("ids", "integer_array", [1, -2, 3]),
        param("weights", "double_array", [0.25, 1.0, -1e300]),
        param("names", "string_array", ["a", "b c", "ü"]),
        param("limits.max_speed", "double", 3.5),
        param("limits.nested.deep", "integer", 7),
        param("anything", "string", "hello", dynamic_typing=True),
        param("typed_only", "string", None),
    ]
    # Doubles stay doubles for a JSON reader, even when whole.
    assert isinstance(record["parameters"][4]["floating_point_range"]["to_value"], float)


def test_parameters_off(run):
    result = run(h.python_node("params_node.py"), env={"RMW_INTROSPECT_PARAMETERS": "0"})
    probe = assert_probed(result)
    assert probe["parameters"] is False and probe["requests"] == 0
    record = the_node(result.capture, "/params_node")
    assert record["parameters"] is None and record["parameters_error"] is None


def test_nothing_to_ask_is_off(run):
    result = run(h.python_node("talker.py"),
                 env={"RMW_INTROSPECT_PARAMETERS": "0", "RMW_INTROSPECT_LIFECYCLE": "none"})
    h.assert_settled_process(result)
    assert result.capture["probe"]["state"] == "off"
    assert result.capture["probe"]["lifecycle"] == "none"


def test_a_node_no_executor_serves_is_reported_not_waited_for(run):
    result = run(h.python_node("unspun_node.py"), timeout=20)
    h.assert_settled_process(result)
    assert result.wall_s < 5, str(result)  # no answer timeout spent on it
    spun, idle = the_node(result.capture, "/spun"), the_node(result.capture, "/idle")
    assert [p["name"] for p in spun["parameters"]][-1] == "here"
    assert idle["parameters"] is None
    assert "no executor serves /idle/list_parameters" in idle["parameters_error"]
    assert result.capture["probe"]["unanswered"] == 1


def test_c_node_without_parameter_services_has_none(run, c_node):
    result = run([c_node])
    h.assert_settled_process(result)
    for record in result.capture["nodes"]:
        assert record["parameters"] is None and record["parameters_error"] is None
        assert record["lifecycle"] is None
    assert result.capture["probe"]["requests"] == 0


# ----------------------------------------------------------------------------- lifecycle
def lifecycle_endpoints(n, *extra):
    return infra(n) + h.lifecycle_infrastructure(n) + list(extra)


def test_lifecycle_node_is_configured_and_activated_and_its_parameters_read_again(run):
    # A horizon: the timer created on activate fires 0.5 s later, in virtual time.
    result = run(h.python_node("lc_managed.py"), env={"RMW_INTROSPECT_HORIZON_MS": "2000"})
    probe = assert_probed(result)
    assert probe["lifecycle"] == "active"
    n = "/managed"
    h.assert_capture(result.capture, [node("managed")], lifecycle_endpoints(
        n,
        ep("publisher", n, "/status", "std_msgs/msg/String", h.qos(depth=5)),
        ep("subscription", n, "/cmd", "std_msgs/msg/String"),
        ep("service", n, "/reset", "std_srvs/srv/Trigger", h.QOS_SERVICES),
        ep("publisher", n, "/late_status", "std_msgs/msg/String"),
    ))
    created_in = {name: e["created_in"] for name, e in by_name(result.capture).items()}
    assert created_in["/status"] == "configure"
    assert created_in["/cmd"] == created_in["/reset"] == "activate"
    assert created_in["/late_status"] == "activate"  # by the timer created in on_activate
    assert created_in["/rosout"] is None and created_in[f"{n}/change_state"] is None
    record = the_node(result.capture, n)
    assert record["lifecycle"] == {
        "target": "active", "initial_state": "unconfigured", "state": "active",
        "transitions": [
            {"id": 1, "label": "configure", "result": "success", "success": True},
            {"id": 3, "label": "activate", "result": "success", "success": True},
        ],
        "error": None,
    }
    assert record["parameters"] == rclpy_parameters() + [
        param("rate", "double", 10.0, description="Hz"),
        param("topic", "string", "status", description="where to publish", declared_in="configure"),
        param("depth", "integer", 5, integer_range={"from_value": 1, "to_value": 10, "step": 1},
              declared_in="configure"),
    ]
    assert result.capture["time"]["jumps"] >= 1


@pytest.mark.parametrize("target, state, transitions, created", [
    ("inactive", "inactive", ["configure"], ["/status"]),
    ("unconfigured", "unconfigured", [], []),
])
def test_lifecycle_targets(run, target, state, transitions, created):
    result = run(h.python_node("lc_managed.py"), env={"RMW_INTROSPECT_LIFECYCLE": target})
    assert_probed(result)
    record = the_node(result.capture, "/managed")
    assert record["lifecycle"]["target"] == target
    assert record["lifecycle"]["initial_state"] == "unconfigured"
    assert record["lifecycle"]["state"] == state
    assert [t["label"] for t in record["lifecycle"]["transitions"]] == transitions
    assert record["lifecycle"]["error"] is None
    own = [e["name"] for e in result.capture["endpoints"] if not e["name"].startswith(("/managed", "/rosout", "/parameter_events"))]
    assert own == created
    names = [p["name"] for p in record["parameters"]]
    assert ("topic" in names) == (target == "inactive")


def test_lifecycle_none_leaves_the_node_alone_and_records_its_state(run):
    result = run(h.python_node("lc_managed.py"), env={"RMW_INTROSPECT_LIFECYCLE": "none"})
    probe = assert_probed(result)
    assert probe["requests"] == 4  # get_state, then the parameters: no change_state
    record = the_node(result.capture, "/managed")
    assert record["lifecycle"] == {"target": "none", "initial_state": "unconfigured", "state": "unconfigured",
                                   "transitions": [], "error": None}
    h.assert_capture(result.capture, [node("managed")], lifecycle_endpoints("/managed"))


def test_lifecycle_none_records_the_state_a_self_driving_node_reached(run):
    # lifecycle_node.py configures and activates itself: asked, not driven
    result = run(h.python_node("lifecycle_node.py"), env={"RMW_INTROSPECT_LIFECYCLE": "none"})
    record = the_node(result.capture, "/lc_node")
    assert record["lifecycle"]["state"] == "active"
    assert record["lifecycle"]["transitions"] == []


@pytest.mark.parametrize("mode", ["fail", "raise"])
def test_a_failing_configure_is_a_clear_failure(run, mode):
    result = run(h.python_node("lc_managed.py", mode))
    h.assert_settled_process(result)  # the process goes on; the capture says what failed
    record = the_node(result.capture, "/managed")
    lifecycle = record["lifecycle"]
    assert lifecycle["state"] == "unconfigured"
    assert lifecycle["transitions"] == [{"id": 1, "label": "configure", "result": "failure", "success": False}]
    assert "transition configure of /managed failed" in lifecycle["error"]
    assert "state now unconfigured" in lifecycle["error"]
    h.assert_capture(result.capture, [node("managed")], lifecycle_endpoints("/managed"))
    assert [p["name"] for p in record["parameters"]] == ["use_sim_time", "start_type_description_service", "rate"]


def test_a_lifecycle_node_that_activates_itself_is_not_driven(run):
    result = run(h.python_node("lifecycle_node.py"))
    probe = assert_probed(result)
    assert probe["requests"] == 4  # get_state + list, describe, get
    record = the_node(result.capture, "/lc_node")
    assert record["lifecycle"]["initial_state"] == record["lifecycle"]["state"] == "active"
    assert record["lifecycle"]["transitions"] == []
    assert all(e["created_in"] is None for e in result.capture["endpoints"])


def test_yaml_capture_carries_the_same_fields(run):
    result = run(h.python_node("lc_managed.py"), fmt="yaml")
    assert_probed(result)
    record = the_node(result.capture, "/managed")
    assert record["lifecycle"]["state"] == "active"
    assert [p["declared_in"] for p in record["parameters"]][-2:] == ["configure", "configure"]
