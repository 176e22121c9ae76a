"""Drift fails the test itself (a failure, not an error) with the drift report as its message."""

from __future__ import annotations

import pytest
from sample_contracts import STRING_HASH, talker_contract

TALKER_CONTRACT = talker_contract(complete=False)


def drift_test(project, marker_kwargs: str = "", contract: str = TALKER_CONTRACT, body: str = "pass"):
    """The marker test of a golden; the golden is a contract file by its content, so its own item is
    collected and skipped (the marker test checks it: every run counts one skipped)."""
    project.write("contracts/talker.yaml", contract)
    project.test(f"""
        @pytest.mark.interfaces("contracts/talker.yaml", script=NODES + "/talker.py"{', ' + marker_kwargs if marker_kwargs else ''})
        def test_talker(interfaces):
            {body}
    """)


def test_matching_capture_passes(project):
    drift_test(project)
    result = project.run()
    result.assert_outcomes(passed=1, skipped=1)


def test_passing_test_body_can_assert_more(project):
    drift_test(project, body='assert interfaces["/talker"].get("publishers", "/chatter").qos["depth"] == 10')
    project.run().assert_outcomes(passed=1, skipped=1)


@pytest.mark.parametrize(
    "marker_kwargs, expected_lines",
    [
        pytest.param(
            'parameters={"topic": "chat"}',
            ["BREAKING (1)", "    publisher /chatter",
             "*[[]PUB_RENAMED[]] publisher /chatter looks renamed to /chat (same type std_msgs/msg/String)*"],
            id="topic-renamed",
        ),
        pytest.param(
            'parameters={"msg_type": "Int32"}',
            ["BREAKING (1)", "*[[]TYPE_CHANGED[]] type changed from std_msgs/msg/String to std_msgs/msg/Int32*"],
            id="type-changed",
        ),
        pytest.param(
            'parameters={"reliability": "best_effort"}',
            ["BREAKING (1)", "    publisher /chatter", "*[[]QOS_RELIABILITY_WEAKENED[]]*RELIABLE*BEST_EFFORT*"],
            id="qos-reliability",
        ),
        pytest.param(
            'parameters={"depth": 3}',
            ["RISKY (1)", "*[[]QOS_DEPTH_DECREASED[]] depth 10 -> 3*"],
            id="qos-depth",
        ),
        pytest.param(
            'parameters={"listen": "/commands"}',
            ["RISKY (1)", "    subscription /commands", "*[[]SUB_ADDED[]] new subscription to /commands*"],
            id="subscription-added",
        ),
        pytest.param(
            'node_name="talker2"',
            ["BREAKING (2)", "  /talker", "*[[]NODE_REMOVED[]] node removed*", "SAFE (2)", "  /talker2",
             "*[[]NODE_ADDED[]] new node /talker2*"],
            id="node-renamed",
        ),
    ],
)
def test_each_kind_of_drift_fails_with_the_report(project, marker_kwargs, expected_lines):
    drift_test(project, marker_kwargs)
    result = project.run()
    result.assert_outcomes(failed=1, errors=0, skipped=1)
    result.stdout.fnmatch_lines(
        [
            "*_ test_talker _*",
            "Interface drift of script */talker.py against contracts/talker.yaml: *",
            "Result: FAIL (fail on: any)",
            *expected_lines,
            "To accept these changes as the new contract, run:",
            "  pytest --update-golden test_nodes.py::test_talker",
        ]
    )
    out = result.stdout.str()
    assert "Traceback" not in out and "_pytest" not in out and "pytest_rmw_introspect" not in out


def test_type_hash_drift_and_ignore_type_hash(project):
    wrong = TALKER_CONTRACT.replace(STRING_HASH, "RIHS01_" + "0" * 64)
    drift_test(project, contract=wrong)
    result = project.run()
    result.assert_outcomes(failed=1, skipped=1)
    result.stdout.fnmatch_lines(["*[[]TYPE_HASH_CHANGED[]]*"])
    project.run("--rmw-introspect-ignore-type-hash").assert_outcomes(passed=1, skipped=1)


def test_qos_drift_can_be_ignored_per_field(project):
    drift_test(project, 'parameters={"depth": 3}, ignore_qos=["depth"]')
    project.run().assert_outcomes(passed=1, skipped=1)
    drift_test(project, 'parameters={"depth": 3, "reliability": "best_effort"}, ignore_qos=["depth"]')
    result = project.run()
    result.assert_outcomes(failed=1, skipped=1)
    assert "QOS_DEPTH" not in result.stdout.str()
    result.stdout.fnmatch_lines(["*QOS_RELIABILITY_WEAKENED*"])
    drift_test(project, 'parameters={"depth": 3, "reliability": "best_effort"}, ignore_qos=True')
    project.run().assert_outcomes(passed=1, skipped=1)


def test_allow_extra_accepts_new_interfaces_but_not_removed_ones(project):
    drift_test(project, 'parameters={"listen": "/commands"}, allow_extra=True')
    project.run().assert_outcomes(passed=1, skipped=1)
    drift_test(project, 'parameters={"topic": "chat"}, allow_extra=True')
    result = project.run()
    result.assert_outcomes(failed=1, skipped=1)
    result.stdout.fnmatch_lines(["*PUB_REMOVED*"])


def test_below_threshold_drift_passes_with_a_warning(project):
    drift_test(project, 'parameters={"depth": 3}, fail_on="breaking"')
    result = project.run()
    result.assert_outcomes(passed=1, warnings=1, skipped=1)
    result.stdout.fnmatch_lines(["*1 interface change(s) against contracts/talker.yaml below the fail threshold (breaking)*"])
    drift_test(project, 'parameters={"reliability": "best_effort"}, fail_on="breaking"')
    result = project.run()
    result.assert_outcomes(failed=1, skipped=1)
    result.stdout.fnmatch_lines(["Result: FAIL (fail on: breaking)"])


def test_test_without_interfaces_argument_is_still_checked(project):
    project.write("contracts/talker.yaml", TALKER_CONTRACT)
    project.test("""
        @pytest.mark.interfaces("contracts/talker.yaml", script=NODES + "/talker.py", parameters={"topic": "x"})
        def test_talker():
            pass
    """)
    result = project.run()
    result.assert_outcomes(failed=1, skipped=1)
    result.stdout.fnmatch_lines(["*PUB_RENAMED*"])


def test_marker_on_a_class_applies_to_its_tests(project):
    project.write("contracts/talker.yaml", TALKER_CONTRACT)
    project.test("""
        @pytest.mark.interfaces("contracts/talker.yaml", script=NODES + "/talker.py")
        class TestTalker:
            def test_one(self, interfaces):
                assert interfaces.node_names == ["/talker"]

            def test_two(self):
                pass
    """)
    project.run().assert_outcomes(passed=2, skipped=1)


def test_include_infrastructure_compares_parameter_services_and_rosout(project):
    project.test("""
        @pytest.mark.interfaces("contracts/full.yaml", script=NODES + "/talker.py", include_infrastructure=True)
        def test_talker(interfaces):
            names = interfaces["/talker"].names("service_servers")
            assert "/talker/get_parameters" in names and "/talker/get_type_description" in names
    """)
    project.run("--update-golden").assert_outcomes(passed=1)
    text = project.read("contracts/full.yaml")
    assert "- name: /rosout\n" in text and "- name: /parameter_events\n" in text
    assert "- name: /talker/set_parameters_atomically\n" in text
    project.run().assert_outcomes(passed=1, skipped=1)
