"""The components a launch file loads into a container (launch.component_loads): the requests
file the container's middleware reads, and what a capture says of each load."""

from __future__ import annotations

from pathlib import Path

import pytest

from pytest_rmw_introspect.compare.compatibility import LaunchedProcess, check_launched
from pytest_rmw_introspect.errors import CaptureFormatError
from pytest_rmw_introspect.launch import component_loads
from pytest_rmw_introspect.launch.result import ComponentLoad, Where
from pytest_rmw_introspect.model.capture import Capture

TALKER = ComponentLoad(package="demo", plugin="demo::Talker", where=Where(Path("/ws/robot.launch.py"), 12),
                       name="talker", namespace="/robot", remap_rules=("chatter:=status",),
                       parameters=(("rate_hz", 3, 5.5), ("frame", 4, "a\tb\\c\nd"), ("ids", 7, (1, -2)),
                                   ("on", 1, True)),
                       extra_arguments=(("use_intra_process_comms", 1, False),))
LISTENER = ComponentLoad(package="demo", plugin="demo::Listener", where=Where(Path("/ws/robot.launch.py"), 14))


def test_the_requests_file_the_middleware_reads():
    assert component_loads.requests_text("/robot/container", [TALKER, LISTENER]) == (
        "# LoadNode requests for the component container /robot/container\n"
        "load\t/robot/container/_container/load_node\n"
        "package_name\tdemo\n"
        "plugin_name\tdemo::Talker\n"
        "node_name\ttalker\n"
        "node_namespace\t/robot\n"
        "log_level\t0\n"
        "remap_rule\tchatter:=status\n"
        "parameter\trate_hz\t3\t5.5\n"
        "parameter\tframe\t4\ta\\tb\\\\c\\nd\n"  # tabs, backslashes and newlines escaped
        "parameter\tids\t7\t1\t-2\n"
        "parameter\ton\t1\ttrue\n"
        "extra_argument\tuse_intra_process_comms\t1\tfalse\n"
        "end\n"
        "load\t/robot/container/_container/load_node\n"
        "package_name\tdemo\n"
        "plugin_name\tdemo::Listener\n"
        "log_level\t0\n"
        "end\n")


def records(document):
    """The ``component_loads`` records of a capture document, as the one reader reads them."""
    return Capture.from_dict({"format": "rmw_introspect_capture", "format_version": 1, **document}).component_loads


def test_what_a_capture_says_of_each_load():
    document = {"component_loads": [
        {"service": "/robot/container/_container/load_node", "plugin": "demo::Talker", "node": "talker",
         "result": "loaded", "full_node_name": "/robot/talker", "error": None},
        {"service": "/robot/container/_container/load_node", "plugin": "demo::Listener", "node": "",
         "result": "refused", "full_node_name": "", "error": "Failed to find class with the requested plugin name."},
    ]}
    assert component_loads.problems(records(document), [TALKER, LISTENER]) == [
        (LISTENER, "the container refused it: Failed to find class with the requested plugin name.")]
    assert [why for _, why in component_loads.problems(records({}), [TALKER])] == [
        "the container's middleware never sent the request (it ended first, or read no request: is "
        "RMW_INTROSPECT_LOAD_NODES set?)"]


def test_a_load_record_that_is_not_an_object_is_a_malformed_capture():
    """Each record answers the request at its place, so one that cannot be read cannot be skipped."""
    with pytest.raises(CaptureFormatError, match="`component_loads` is not a list of objects"):
        records({"component_loads": [{"result": "loaded"}, "junk"]})


def test_a_component_that_was_not_loaded_is_a_node_not_created():
    container = LaunchedProcess("rclcpp_components/component_container", "/robot/container",
                                {"/robot/container": {}, "/robot/talker": {}},
                                unloaded=(("demo::Listener", "the launch file loads component demo::Listener ... "
                                                             "the container refused it"),))
    [item] = check_launched([container])
    assert (item.rule, item.severity.name, item.name) == ("LAUNCHED_NODE_NOT_CREATED", "BREAKING", "demo::Listener")
    assert item.message.endswith("the container refused it")


def test_a_component_is_judged_on_what_its_load_request_gives_it():
    from pytest_rmw_introspect.check import launch_settings
    from pytest_rmw_introspect.compare import launch_given

    node = {"parameters": [{"name": "rate_hz", "type": "double", "default_value": 5.5}],
            "publishers": [{"name": "/robot/status"}]}  # its remapping chatter:=status is used
    container = LaunchedProcess("rclcpp_components/component_container", "/robot/container",
                                {"/robot/container": {"parameters": []}, "/robot/talker": node},
                                given=launch_given.Given(where="robot.launch.py:8"),
                                component_given={"/robot/talker": launch_settings.component_given(TALKER)})
    # its own parameters, not the container's (which has none), and rate_hz is declared
    assert sorted((i.rule, i.requester.node, i.name) for i in check_launched([container])) == [
        ("PARAM_NOT_DECLARED", "/robot/talker", "frame"), ("PARAM_NOT_DECLARED", "/robot/talker", "ids"),
        ("PARAM_NOT_DECLARED", "/robot/talker", "on")]
    [frame, *_] = launch_given.given_findings([container])
    assert frame.message.startswith(
        f"parameter `frame` is given ({TALKER.where}) but /robot/talker does not declare it")


def test_a_component_s_own_remappings_are_judged_on_its_own_node():
    from dataclasses import replace

    from pytest_rmw_introspect.check import launch_settings
    from pytest_rmw_introspect.compare import launch_given

    # the scope's rule (first) and the component's own: `chatter:=status` is its own here
    talker = replace(TALKER, parameters=(), remap_rules=("/tf:=tf", "chatter:=status"), scope_remap_rules=1)
    listener = replace(LISTENER, name="listener", namespace="/robot", remap_rules=("/tf:=tf",), scope_remap_rules=1)

    def findings(talker_topic: str) -> list[tuple[str, str, str, str]]:
        nodes = {"/robot/container": {}, "/robot/talker": {"publishers": [{"name": talker_topic}]},
                 "/robot/listener": {"subscriptions": [{"name": "/robot/status"}]}}
        container = LaunchedProcess("rclcpp_components/component_container", "/robot/container", nodes,
                                    given=launch_given.Given(where="robot.launch.py:8"),
                                    component_given={"/robot/talker": launch_settings.component_given(talker),
                                                     "/robot/listener": launch_settings.component_given(listener)})
        return [(f.rule, f.node, f.name, f.message) for f in launch_given.given_findings([container])]

    # used: the talker publishes the remapped name; and the scope's /tf rule, which reaches every
    # node after it and that none of these uses, is never judged against one component
    assert findings("/robot/status") == []
    # unused: the talker's publisher is not named `chatter` (a typo in the component or the rule);
    # the listener's subscription to /robot/status does not count for the talker's own rule
    [(rule, node, name, message)] = findings("/robot/chater")
    assert (rule, node, name) == ("REMAP_NEAR_MISS", "/robot/talker", "chatter:=status")
    assert message.startswith(f"the remapping chatter -> status (at {TALKER.where}) changed none of the names of "
                              "/robot/talker:")
