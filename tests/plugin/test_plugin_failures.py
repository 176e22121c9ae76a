"""Everything a user can get wrong is a clear test failure: target failures, malformed
contracts, bad marker arguments, a missing middleware. Never an internal error or a traceback
into the plugin."""

from __future__ import annotations

from pathlib import Path

import pytest
from sample_contracts import talker_contract

CONTRACT = talker_contract(described=False, complete=False)


def assert_clean_failure(result, failed: int = 1, skipped: int = 0) -> str:
    result.assert_outcomes(failed=failed, errors=0, skipped=skipped)
    out = result.stdout.str()
    assert "INTERNALERROR" not in out
    assert "pytest_rmw_introspect/" not in out  # no traceback into the plugin
    return out


def test_missing_script(project):
    project.test("""
        @pytest.mark.interfaces("c.yaml", script="nodes/does_not_exist.py")
        def test_x():
            pass
    """)
    result = project.run()
    assert_clean_failure(result)
    result.stdout.fnmatch_lines(["*Python script */nodes/does_not_exist.py does not exist.*"])


def test_missing_package_lists_the_prefixes_searched(project):
    project.test("""
        @pytest.mark.interfaces("c.yaml", package="no_such_pkg", executable="talker")
        def test_x():
            pass
    """)
    result = project.run()
    assert_clean_failure(result)
    result.stdout.fnmatch_lines(["*Package 'no_such_pkg' was not found in the ament index. Searched the prefixes*"])


def test_ament_package_executable_is_run_like_ros2_run(project):
    prefix = project.path / "install"
    (prefix / "share" / "ament_index" / "resource_index" / "packages").mkdir(parents=True)
    (prefix / "share" / "ament_index" / "resource_index" / "packages" / "demo_pkg").write_text("")
    exe = prefix / "lib" / "demo_pkg" / "talker"
    exe.parent.mkdir(parents=True)
    import sys

    exe.write_text(f"#!{sys.executable}\n" + Path(project.node("talker.py")).read_text())
    exe.chmod(0o755)
    project.pytester._monkeypatch.setenv("AMENT_PREFIX_PATH", str(prefix))
    project.test("""
        @pytest.mark.interfaces("c.yaml", package="demo_pkg", executable="talker", namespace="/robot")
        def test_x(interfaces):
            assert interfaces.node_names == ["/robot/talker"]
            assert interfaces.command[1:] == ["--ros-args", "-r", "__ns:=/robot"]

        @pytest.mark.interfaces("c.yaml", package="demo_pkg", executable="listener")
        def test_missing_executable():
            pass
    """)
    result = project.run("--update-golden")
    result.assert_outcomes(passed=1, failed=1)
    result.stdout.fnmatch_lines([
        "*Executable 'listener' not found in package 'demo_pkg'*The package has these executables: talker.*"
    ])


def test_crashing_node_shows_status_stderr_and_partial_capture(project):
    project.test("""
        @pytest.mark.interfaces("c.yaml", script=NODES + "/crashing_node.py")
        def test_x():
            pass
    """)
    result = project.run()
    assert_clean_failure(result)
    result.stdout.fnmatch_lines([
        "The target script */crashing_node.py crashed: it exited with status 1 while it was captured*",
        "Command: *crashing_node.py",
        "Last lines of its stderr:",
        "*RuntimeError: sensor driver failed to open /dev/ttyUSB0",
        "Captured so far:",
        "*/crasher",
        "*publishers: /doomed [[]std_msgs/msg/String[]]",
    ])


def test_hanging_node_times_out_and_shows_what_was_captured(project):
    project.test("""
        @pytest.mark.interfaces("c.yaml", script=NODES + "/hanging_node.py", timeout=1.5)
        def test_x():
            pass
    """)
    result = project.run(timeout=60)
    assert_clean_failure(result)
    result.stdout.fnmatch_lines([
        "The target script */hanging_node.py did not settle within 1.5 s and was stopped.*",
        "Captured so far:",
        "*/sleeper",
        "*publishers: /snore [[]std_msgs/msg/String[]]",
    ])
    assert result.duration < 30


def test_node_that_creates_no_node(project):
    project.test("""
        @pytest.mark.interfaces("c.yaml", script=NODES + "/no_node.py")
        def test_x():
            pass
    """)
    result = project.run()
    assert_clean_failure(result)
    result.stdout.fnmatch_lines(["The target script */no_node.py created no ROS node*"])


def test_malformed_contract_names_file_line_path_and_reason(project):
    project.write("contracts/talker.yaml", CONTRACT + "        qos: {reliability: RELIABEL}\n")
    project.test("""
        @pytest.mark.interfaces("contracts/talker.yaml", script=NODES + "/talker.py")
        def test_x():
            pass
    """)
    result = project.run()
    assert_clean_failure(result, skipped=1)  # the golden's own item: skipped for its test
    result.stdout.fnmatch_lines([
        (
            "invalid contract contracts/talker.yaml:7: at nodes./talker.publishers[[]0[]].qos.reliability: "
            "'RELIABEL' is not one of: RELIABLE, BEST_EFFORT*"
        )
    ])


@pytest.mark.parametrize("text, expected", [
    ("contract_version: 1\nnodes:\n  /talker: [\n", "*talker.yaml:4: YAML syntax error*"),
    (("contract_version: 1\nnodes:\n  /talker:\n    publishers:\n      - {name: /a, type: std_msgs/msg/String}\n"
      "      - {name: /a, type: std_msgs/msg/String}\n"),
     "*talker.yaml:6: at nodes./talker.publishers[[]1[]].name: duplicate publisher '/a' in node /talker*"),
    ("contract_version: 1\nnodes: {}\noptions: {fail_on: often}\n", "*at options.fail_on: 'often' is not one of*"),
])
def test_other_contract_errors(project, text, expected):
    project.write("contracts/talker.yaml", text)
    project.test("""
        @pytest.mark.interfaces("contracts/talker.yaml", script=NODES + "/talker.py")
        def test_x():
            pass
    """)
    result = project.run()
    assert_clean_failure(result, skipped=1)  # the golden's own item: skipped for its test
    result.stdout.fnmatch_lines([expected])


def test_missing_golden_without_any_target(project):
    project.test("""
        @pytest.mark.interfaces("contracts/talker.yaml")
        def test_x():
            pass
    """)
    result = project.run("--update-golden")
    assert_clean_failure(result)
    result.stdout.fnmatch_lines([
        "The golden contract contracts/talker.yaml does not exist and the @pytest.mark.interfaces marker names no target*",
        "*pytest --update-golden test_nodes.py::test_x",
    ])


def test_bad_marker_arguments(project):
    project.test("""
        @pytest.mark.interfaces("c.yaml", script=NODES + "/talker.py", namspace="/x")
        def test_unknown_kwarg():
            pass

        @pytest.mark.interfaces(script=NODES + "/talker.py")
        def test_no_contract():
            pass

        @pytest.mark.interfaces("c.yaml", script=NODES + "/talker.py", timeout="soon")
        def test_bad_value():
            pass

        @pytest.mark.interfaces("c.yaml", script=NODES + "/talker.py", fail_on="sometimes")
        def test_bad_option():
            pass

        def test_fixture_without_marker(interfaces):
            pass
    """)
    result = project.run()
    result.assert_outcomes(failed=4, errors=1)  # a fixture used without its marker is a setup error
    assert "pytest_rmw_introspect/" not in result.stdout.str()
    result.stdout.fnmatch_lines_random([
        "*test_unknown_kwarg*: unknown keyword argument(s) namspace; target options: package, *",
        "*test_no_contract: the first argument must be the path of the golden contract*",
        "*`timeout` must be a number of seconds, got 'soon'*",
        "*`fail_on` must be one of any, risky, breaking, got 'sometimes'*",
        "*the `interfaces` fixture needs an @pytest.mark.interfaces(*",
    ])


def test_fixture_depending_on_a_failed_capture_fails_with_the_reason(project):
    project.test("""
        @pytest.fixture
        def publishers(interfaces):
            return interfaces["/crasher"].publishers

        @pytest.mark.interfaces("c.yaml", script=NODES + "/no_node.py")
        def test_x(publishers):
            pass
    """)
    result = project.run()
    result.assert_outcomes(errors=1)
    result.stdout.fnmatch_lines([
        "the interfaces capture is not available:",
        "The target script */no_node.py created no ROS node*",
    ])


def test_missing_middleware_library_is_one_clear_failure(project):
    project.pytester._monkeypatch.setenv("RMW_INTROSPECT_LIBRARY", "/nonexistent/librmw_introspect_cpp.so")
    project.test("""
        @pytest.mark.interfaces("c.yaml", script=NODES + "/talker.py")
        def test_a():
            pass

        def test_b(rmw_introspect_library):
            pass
    """)
    result = project.run()
    result.assert_outcomes(failed=1, errors=1)
    result.stdout.fnmatch_lines_random([
        "*RMW_INTROSPECT_LIBRARY points at /nonexistent/librmw_introspect_cpp.so, which does not exist.*",
        "ERROR test_nodes.py::test_b - Failed: RMW_INTROSPECT_LIBRARY points at*",
    ])
