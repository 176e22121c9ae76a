"""Node names that change every run (model/unstable_names.py) on real programs: an rclpy node
with a random suffix and an rcl C node with its process id in the name are captured once, then
checked ten times in a row with no drift; a real rename of the same node still drifts."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

NODES = Path(__file__).parent / "nodes"
CHECKS = 10


@pytest.fixture
def cli(tmp_path: Path, middleware_library: Path):
    """``cli(*args)``: ``rmw-introspect ARGS`` in ``tmp_path`` on the recording middleware."""
    exe = shutil.which("rmw-introspect", path=str(Path(sys.executable).parent))
    assert exe, "the rmw-introspect console script is not installed next to the interpreter"
    env = {k: v for k, v in os.environ.items() if k not in ("CI", "PYTEST_ADDOPTS")}
    env["RMW_INTROSPECT_LIBRARY"] = str(middleware_library)

    def run(*args: object) -> subprocess.CompletedProcess[str]:
        return subprocess.run([exe, *map(str, args)], cwd=tmp_path, env=env, capture_output=True, text=True,
                              timeout=120, check=False)

    return run


def _nodes(path: Path) -> dict:
    return yaml.safe_load(path.read_text())["nodes"]


def _checks_without_drift(cli, contract: str) -> None:
    for attempt in range(CHECKS):
        result = cli("check", contract)
        assert result.returncode == 0, f"check {attempt + 1} of {CHECKS} drifted:\n{result.stdout}{result.stderr}"
        assert result.stdout.startswith(f"{contract}: matches ("), result.stdout


def test_an_rclpy_node_with_a_random_suffix_is_written_as_a_pattern_and_never_drifts(cli, tmp_path):
    captured = cli("capture", "--script", NODES / "anonymous_talker.py", "-o", "anon.interfaces.yaml")
    assert captured.returncode == 0, captured.stderr
    nodes = _nodes(tmp_path / "anon.interfaces.yaml")
    assert list(nodes) == ["/anonymous_talker_*"]
    node = nodes["/anonymous_talker_*"]
    assert "hexadecimal suffix" in node["unstable_name"]
    # the service under the node's own name is written under the pattern, and compared as usual
    assert [(e["name"], e["type"]) for e in node["service_servers"]] == [("/anonymous_talker_*/reset",
                                                                         "std_srvs/srv/Trigger")]
    assert [e["name"] for e in node["publishers"]] == ["/chatter"]

    _checks_without_drift(cli, "anon.interfaces.yaml")

    renamed = cli("check", "anon.interfaces.yaml", "--arg=--name", "--arg=renamed_talker")
    assert renamed.returncode == 1, renamed.stdout + renamed.stderr
    assert "/anonymous_talker_*" in renamed.stdout and "/renamed_talker_*" in renamed.stdout
    assert "NODE_REMOVED" in renamed.stdout or "NODE_RENAMED" in renamed.stdout


def test_two_nodes_of_one_pattern_are_compared_as_a_set(cli, tmp_path):
    captured = cli("capture", "--script", NODES / "anonymous_talker.py", "--arg=--two", "-o", "two.interfaces.yaml")
    assert captured.returncode == 0, captured.stderr
    assert sorted(_nodes(tmp_path / "two.interfaces.yaml")) == ["/anonymous_talker_*", "/anonymous_talker_*#2"]
    _checks_without_drift(cli, "two.interfaces.yaml")
    # one of the two gone: the set lost a member
    contract = tmp_path / "two.interfaces.yaml"
    contract.write_text(contract.read_text().replace("  arguments:\n  - --two\n", "", 1))
    one = cli("check", "two.interfaces.yaml")
    assert one.returncode == 1, one.stdout
    assert "/anonymous_talker_*#2" in one.stdout and "NODE_REMOVED" in one.stdout


def test_a_hand_written_pattern_is_kept_by_an_update_and_a_literal_name_is_not_a_pattern(cli, tmp_path):
    contract = tmp_path / "mine.interfaces.yaml"
    contract.write_text(
        "contract_version: 1\n"
        f"target: {{script: {NODES / 'anonymous_talker.py'}}}\n"
        "unstable_names:\n"
        "  - pattern: /anonymous_*\n"
        "    reason: the talker draws a new name at every start\n"
        "nodes: {}\n")
    updated = cli("check", "--update", contract.name)
    assert updated.returncode == 0, updated.stdout + updated.stderr
    nodes = _nodes(contract)
    assert list(nodes) == ["/anonymous_*"]
    assert nodes["/anonymous_*"]["unstable_name"] == "the talker draws a new name at every start"
    assert "unstable_names:\n  - pattern: /anonymous_*\n" in contract.read_text()
    _checks_without_drift(cli, contract.name)
    again = cli("check", "--update", contract.name)
    assert again.returncode == 0 and "updated" not in again.stderr, again.stderr


def test_a_c_node_with_its_process_id_in_the_name_never_drifts(cli, c_node, tmp_path):
    pid_node = c_node.parent / "rmwi_c_pid_node"
    captured = cli("capture", "-o", "c.interfaces.yaml", "--", pid_node)
    assert captured.returncode == 0, captured.stderr
    nodes = _nodes(tmp_path / "c.interfaces.yaml")
    assert list(nodes) == ["/c/c_talker_*"]
    assert "process id" in nodes["/c/c_talker_*"]["unstable_name"]
    assert [e["name"] for e in nodes["/c/c_talker_*"]["publishers"]] == ["/c/chatter"]

    _checks_without_drift(cli, "c.interfaces.yaml")

    renamed = cli("check", "c.interfaces.yaml", "--arg", "other_talker")
    assert renamed.returncode == 1, renamed.stdout + renamed.stderr
    assert "/c/c_talker_*" in renamed.stdout and "/c/other_talker_*" in renamed.stdout
