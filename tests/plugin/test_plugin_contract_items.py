"""Contract files as pytest items (no Python test file): collection, names, pass/drift/errors,
--update-golden, comparison options, the glob option."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from sample_contracts import talker_contract


def talker(project, *, target: str | None = None, **options) -> str:
    """talker_contract with a target block running nodes/talker.py (``target=""``: none)."""
    return talker_contract(target=f"script: {project.node('talker.py')}" if target is None else target, **options)


TWO_NODES = """\
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from std_msgs.msg import String

rclpy.init()
a, b = Node("camera"), Node("detector")
a.create_publisher(String, "image", 10)
b.create_subscription(String, "image", lambda m: None, 10)
ex = SingleThreadedExecutor()
ex.add_node(a)
ex.add_node(b)
try:
    ex.spin()
except (KeyboardInterrupt, rclpy.executors.ExternalShutdownException):
    pass
"""


def test_contract_files_are_collected_as_one_item_each_named_after_their_nodes(project):
    project.write("contracts/talker.interfaces.yaml", talker(project))
    project.write("contracts/pipeline.interfaces.yaml", "contract_version: 1\nnodes:\n  /camera: {}\n  /detector: {}\n")
    project.write("contracts/empty.interfaces.yaml", "contract_version: 1\nnodes: {}\n")
    project.write("contracts/broken.interfaces.yaml", "contract_version: 1\nnodes: [\n")
    project.write("contracts/other.yaml", talker(project))  # a contract by its content, whatever its name
    project.write("contracts/params.yaml", "/talker:\n  ros__parameters:\n    depth: 10\n")  # not a contract
    result = project.run("--collect-only", "-q")
    result.stdout.fnmatch_lines([
        "contracts/broken.interfaces.yaml::invalid",
        "contracts/empty.interfaces.yaml::no-nodes",
        "contracts/other.yaml::/talker",
        "contracts/pipeline.interfaces.yaml::/camera,/detector",
        "contracts/talker.interfaces.yaml::/talker",
        "5 tests collected*",
    ])
    assert "params.yaml" not in result.stdout.str()


def test_a_matching_contract_passes_and_drift_fails_with_the_report(project):
    project.write("contracts/talker.interfaces.yaml", talker(project))
    project.write("contracts/old.interfaces.yaml", talker(project, depth=3))
    result = project.run("-rA")
    result.assert_outcomes(passed=1, failed=1)
    result.stdout.fnmatch_lines([
        "*_ interface contract old.interfaces.yaml::/talker _*",
        "Interface drift of script */talker.py against contracts/old.interfaces.yaml: 1 change (0 breaking, 0 risky, 1 safe)",
        "Result: FAIL (fail on: any)",
        "*[[]QOS_DEPTH_INCREASED[]] depth 3 -> 10*",
        "To accept these changes as the new contract, run:",
        "  pytest --update-golden contracts/old.interfaces.yaml::/talker",
        "PASSED contracts/talker.interfaces.yaml::/talker",
    ])
    assert "Traceback" not in result.stdout.str()


def test_a_contract_of_several_nodes_is_one_item_with_one_capture(project):
    project.write("nodes/pipeline.py", TWO_NODES)
    project.write("pipeline.interfaces.yaml", (
        "contract_version: 1\ntarget:\n  script: nodes/pipeline.py\nnodes:\n"
        "  /camera:\n    publishers:\n      - {name: /image, type: std_msgs/msg/String}\n"
        "  /detector:\n    subscriptions:\n      - {name: /image, type: std_msgs/msg/String}\n"
        "      - {name: /gone, type: std_msgs/msg/String}\n"
    ))
    result = project.run("-v")
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines([
        "pipeline.interfaces.yaml::/camera,/detector FAILED*",
        "*[[]SUB_REMOVED[]]*",
    ])


def test_update_golden_rewrites_a_drifted_contract_file_and_lists_it(project):
    header = "# Reviewed by the demo team.\n"
    project.write("contracts/talker.interfaces.yaml", talker(project, depth=3, header=header))
    result = project.run("--update-golden")
    result.assert_outcomes(passed=1)
    result.stdout.fnmatch_lines([
        "*rmw-introspect: golden contracts*",
        "updated  contracts/talker.interfaces.yaml",
        "1 golden contract(s) written",
    ])
    assert project.read("contracts/talker.interfaces.yaml") == talker(project, header=header)
    project.run().assert_outcomes(passed=1)


def test_update_golden_fills_a_contract_that_has_only_a_target(project):
    target = f"target:\n  script: {project.node('talker.py')}\n"
    project.write("talker.interfaces.yaml", f"contract_version: 1\n{target}nodes: {{}}\n")
    result = project.run("--update-golden", "-v")
    result.assert_outcomes(passed=1)
    result.stdout.fnmatch_lines(["talker.interfaces.yaml::no-nodes PASSED*", "updated  talker.interfaces.yaml"])
    assert project.read("talker.interfaces.yaml") == talker(project)


def test_a_contract_without_target_or_loadable_yaml_fails_with_a_clear_message(project):
    project.write("notarget.interfaces.yaml", talker(project, target=""))
    project.write("broken.interfaces.yaml", "contract_version: 1\nnodes: [\n")
    result = project.run()
    result.assert_outcomes(failed=2)
    result.stdout.fnmatch_lines([
        "*_ interface contract broken.interfaces.yaml::invalid _*",
        "invalid contract broken.interfaces.yaml:3: YAML syntax error*",  # relative, as pytest's own paths
        "*_ interface contract notarget.interfaces.yaml::/talker _*",
        "The contract notarget.interfaces.yaml has no `target:` block, so there is nothing to run.*",
    ])
    out = result.stdout.str()
    assert "Traceback" not in out
    assert "During handling" not in out


def test_comparison_options_of_the_command_line_ini_and_contract_apply(project):
    project.write("contracts/talker.interfaces.yaml", talker(project, depth=3))
    project.run().assert_outcomes(failed=1)
    below = project.run("--rmw-introspect-fail-on", "breaking")
    below.assert_outcomes(passed=1, warnings=1)
    below.stdout.fnmatch_lines([("*1 interface change(s) against contracts/talker.interfaces.yaml below the fail "
                                "threshold (breaking)*")])
    project.run("--rmw-introspect-ignore-qos", "depth").assert_outcomes(passed=1)
    project.pytester.makeini("[pytest]\nrmw_introspect_ignore_qos = depth\n")
    project.run().assert_outcomes(passed=1)
    # the contract's own options beat the ini file
    project.write("contracts/talker.interfaces.yaml",
                  talker(project, depth=3).replace("nodes:", "options:\n  ignore_qos: []\nnodes:", 1))
    project.run().assert_outcomes(failed=1)


def test_the_contract_glob_is_configurable(project):
    project.write("talker.contract.yaml", talker(project))
    project.write("other.interfaces.yaml", talker(project, depth=3))
    project.pytester.makeini("[pytest]\nrmw_introspect_contracts = *.contract.yaml\n")
    result = project.run("-v")
    result.assert_outcomes(passed=1)
    result.stdout.fnmatch_lines(["talker.contract.yaml::/talker PASSED*"])
    cli = project.run("-v", "--rmw-introspect-contracts", "other.*.yaml")
    cli.assert_outcomes(failed=1)
    cli.stdout.fnmatch_lines(["other.interfaces.yaml::/talker FAILED*"])
    off = project.run("--rmw-introspect-contracts", "none")
    assert off.ret == 5  # no tests collected


def test_a_baseline_in_the_ini_file_fails_only_new_drift_and_accept_entries_are_honoured(project):
    project.write("contracts/old.interfaces.yaml", talker(project, depth=5))
    accept = "accept:\n  - {rule: QOS_DEPTH_INCREASED, name: /chatter, reason: deeper on purpose}\n"
    project.write("contracts/accepted.interfaces.yaml", talker(project, depth=7, header=accept))
    # the baseline as the command line writes it, from another directory than pytest's
    contracts = project.pytester.path / "contracts"
    baseline = project.pytester.path / "ci" / "interfaces.baseline.json"
    baseline.parent.mkdir()
    written = subprocess.run([str(Path(sys.executable).with_name("rmw-introspect")), "check",
                              str(contracts / "old.interfaces.yaml"), "--write-baseline", str(baseline)],
                             capture_output=True, text=True, timeout=120, check=False)
    assert written.returncode == 0, written
    project.pytester.makeini("[pytest]\nrmw_introspect_baseline = ci/interfaces.baseline.json\n")
    result = project.run("-rA")
    result.assert_outcomes(passed=2)
    project.write("contracts/old.interfaces.yaml", talker(project, depth=5).replace("RELIABLE", "BEST_EFFORT"))
    result = project.run()
    result.assert_outcomes(passed=1, failed=1)
    result.stdout.fnmatch_lines(["*QOS_RELIABILITY_STRENGTHENED*", "ACCEPTED (1)*", "*in the baseline*"])
    project.pytester.makeini("[pytest]\nrmw_introspect_baseline = ci/missing.json\n")
    result = project.run()
    result.assert_outcomes(failed=2)
    result.stdout.fnmatch_lines(["*baseline ci/missing.json: the file does not exist*"])


def test_the_shards_of_a_session_run_every_contract_item_exactly_once(project):
    for i in range(3):
        project.write(f"contracts/t{i}.interfaces.yaml", talker(project, depth=10 if i else 3))
    project.write("contracts/empty.interfaces.yaml", "contract_version: 1\nnodes: {}\n")
    whole = project.run("-rA")
    whole.assert_outcomes(passed=2, failed=2)  # t0 drifted, empty has no target
    ran = []
    for i in (1, 2, 3):
        shard = project.run("-rA", f"--rmw-introspect-shard={i}/3")
        ran += [line.split(" ", 1)[1].split(" - ")[0] for line in shard.outlines if line.startswith(("PASSED ", "FAILED "))]
    everything = [line.split(" ", 1)[1].split(" - ")[0] for line in whole.outlines if line.startswith(("PASSED ", "FAILED "))]
    assert len(everything) == 4
    assert sorted(ran) == sorted(everything)  # the union is the unsharded run, nothing twice
    project.run("--rmw-introspect-shard=4/3").stderr.fnmatch_lines(["*--rmw-introspect-shard 4/3: I must be between*"])
