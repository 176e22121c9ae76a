"""`rmw-introspect capture` with virtual time (--horizon) and --partial, on real rclpy nodes."""

from __future__ import annotations

from pathlib import Path

from cli_helpers import NODES

VT_NODES = Path(__file__).parent.parent / "middleware" / "nodes"


def test_late_publisher_is_captured_by_default_and_missed_with_horizon_zero(cli):
    script = str(VT_NODES / "vt_oneshot_timer.py")
    default = cli("capture", "--script", script, "--format", "json")
    assert default.returncode == 0, default
    assert '"/late3"' in default.stdout
    off = cli("capture", "--script", script, "--format", "json", "--horizon", "0")
    assert off.returncode == 0, off
    assert '"/late3"' not in off.stdout


def test_horizon_is_validated(cli_nodes_only):
    result = cli_nodes_only("capture", "--script", "x.py", "--horizon", "-1")
    assert result.returncode == 2
    assert "`horizon` must be a number of seconds from 0 to 86400" in result.stderr
    assert "Traceback" not in result.stderr


def test_notes_on_a_program_that_ended_by_itself_go_to_stderr(cli):
    result = cli("capture", "--script", str(VT_NODES / "vt_finishes.py"))
    assert result.returncode == 0, result
    assert "note: the program ended by itself (status 0)" in result.stderr
    assert "/short_lived:" in result.stdout and "- name: /short" in result.stdout


def test_partial_writes_what_a_hanging_target_created(cli):
    result = cli("capture", "--script", str(NODES / "hanging_node.py"), "--timeout", "1.5", "--partial",
                 "-o", "hanging.interfaces.yaml")
    assert result.returncode == 2, result
    assert "did not settle within 1.5 s" in result.stderr
    assert "No thread ever waited in an executor" in result.stderr
    text = cli.read("hanging.interfaces.yaml")
    assert text.startswith("# PARTIAL capture (not a complete interface): The target script")
    assert "/sleeper:" in text and "- name: /snore" in text


def test_without_partial_a_hanging_target_writes_nothing(cli):
    result = cli("capture", "--script", str(NODES / "hanging_node.py"), "--timeout", "1.5", "-o", "h.interfaces.yaml")
    assert result.returncode == 2, result
    assert not (cli.path / "h.interfaces.yaml").exists()
    assert "Captured so far:" in result.stderr and "/snore" in result.stderr
