"""What `rmw-introspect` does with an error (issue 41): a problem the user can fix is one of the
project's errors (errors.py), printed as one line naming the file, option or interface, exit
status 2; anything else is a bug of the tool, and its traceback shows (a ValueError is no longer
taken for a user error). No node is started: these inputs fail before any capture."""

from __future__ import annotations

import pytest

from pytest_rmw_introspect import cli
from pytest_rmw_introspect.check import diff

GOOD = """contract_version: 1
nodes:
  /talker:
    publishers:
      - name: /chatter
        type: std_msgs/msg/String
"""


@pytest.fixture
def contract(tmp_path):
    path = tmp_path / "talker.interfaces.yaml"
    path.write_text(GOOD)
    return path


@pytest.mark.parametrize(("shard", "said"), [
    ("3/2", "rmw-introspect: --shard 3/2: I must be between 1 and N (N >= 1), e.g. 1/2 to 2/2"),
    ("x", "rmw-introspect: --shard 'x' is not of the form I/N (this job's number I of N jobs, e.g. 2/4)"),
])
def test_a_bad_shard_is_a_usage_error(contract, capsys, shard, said):
    assert cli.main(["check", "--shard", shard, str(contract)]) == 2
    assert capsys.readouterr().err.strip() == said


def test_a_malformed_contract_names_the_file_line_and_key(contract, capsys):
    bad = contract.with_name("bad.interfaces.yaml")
    bad.write_text(GOOD.replace("nodes:", "options:\n  ignore_qos: [reliabilty]\nnodes:"))
    assert cli.main(["diff", str(contract), str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"rmw-introspect: invalid contract {bad}:3: at options.ignore_qos[0]: 'reliabilty' is not one of")
    assert "Traceback" not in err


def test_a_launch_file_the_reader_cannot_follow_names_its_line(tmp_path, capsys):
    launch = tmp_path / "bad.launch.xml"
    launch.write_text('<launch><node pkg="a" exec="b"/><bogus/></launch>\n')
    assert cli.main(["capture", "--launch", str(launch)]) == 2
    err = capsys.readouterr().err
    assert "bad.launch.xml:1: <bogus>: this tag is not supported" in err and "allow_unsupported" in err


def test_a_usage_error_of_the_command_line_says_what_goes_together(capsys):
    assert cli.main(["capture", "--launch-arg", "x:=1", "--script", "node.py"]) == 2
    assert capsys.readouterr().err.strip() == (
        "rmw-introspect: --launch-arg and --allow-unsupported need a launch file: --launch FILE or "
        "--launch-package P --launch-file F (or, for `check`, a system contract)")


def test_a_programming_error_is_not_reported_as_a_user_error(contract, monkeypatch, capsys):
    """A ValueError inside a command is a bug: it propagates (its traceback shows) instead of
    becoming exit status 2 with a message that would blame the user's input."""
    def broken(*args, **kwargs):
        raise ValueError("an internal invariant broke")

    monkeypatch.setattr(diff, "diff_contracts", broken)
    with pytest.raises(ValueError, match="an internal invariant broke"):
        cli.main(["diff", str(contract), str(contract)])
    assert "rmw-introspect: an internal invariant broke" not in capsys.readouterr().err


def test_every_exception_class_of_the_package_is_defined_in_errors_py():
    """One place to look for what can go wrong (issue 41): a class deriving from an exception
    (BaseException, Exception, ValueError, an error of ours) anywhere else fails here."""
    import ast
    import builtins
    from pathlib import Path

    import pytest_rmw_introspect
    from pytest_rmw_introspect import errors

    package = Path(pytest_rmw_introspect.__file__).parent
    ours = {name for name, value in vars(errors).items() if isinstance(value, type) and issubclass(value, BaseException)}
    assert {"RmwIntrospectError", "UsageError", "InputError", "LockTimeout", "Terminated"} <= ours
    elsewhere = []
    for path in sorted(package.rglob("*.py")):
        if path == package / "errors.py" or "rmw_introspect_cpp" in path.parts:
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ClassDef):
                bases = [ast.unparse(base).rsplit(".", 1)[-1] for base in node.bases]
                if any(b in ours or isinstance(getattr(builtins, b, None), type) and issubclass(getattr(builtins, b), BaseException)
                       for b in bases):
                    elsewhere.append(f"{path.relative_to(package)}: class {node.name}({', '.join(bases)})")
    assert elsewhere == [], f"define these in pytest_rmw_introspect/errors.py: {elsewhere}"


def test_a_system_capture_error_lists_each_process_and_proposes_stand_ins_for_missing_devices(tmp_path, monkeypatch):
    """SystemCaptureError carries its message only; run/system_capture words it: every process that
    failed, under its label and where the launch file starts it, then the stand_ins: block for the
    one that lacks a device."""
    from pytest_rmw_introspect.errors import SystemCaptureError, TargetError
    from pytest_rmw_introspect.launch.result import LaunchedNode, LaunchParameter, Where
    from pytest_rmw_introspect.run import system_capture

    monkeypatch.chdir(tmp_path)  # paths are shown relative to the working directory
    launch = tmp_path / "robot.launch.xml"
    lidar = LaunchedNode(executable="lidar_node", package="drivers", where=Where(launch, 3), name="lidar",
                         parameters=(LaunchParameter(name="port", value="/dev/ttyNOSUCH0"),))
    planner = LaunchedNode(executable="planner", package="nav", where=Where(launch, 7), name="planner")
    failures = [(system_capture.ProcessCapture(lidar, "drivers/lidar_node"), TargetError("cannot open /dev/ttyNOSUCH0")),
                (system_capture.ProcessCapture(planner, "nav/planner"), TargetError("exited with status 1"))]
    error = system_capture._capture_failed(system_capture.LaunchSpec(launch), failures, 5)
    assert isinstance(error, SystemCaptureError) and error.target == "launch robot.launch.xml"
    text = str(error)
    assert text.startswith("2 of the 5 processes of `launch robot.launch.xml` could not be captured:\n")
    assert "[drivers/lidar_node] started at robot.launch.xml:3:\n    cannot open /dev/ttyNOSUCH0" in text
    assert "[nav/planner] started at robot.launch.xml:7:\n    exited with status 1" in text
    assert system_capture.STAND_IN_ADVICE in text and "/dev/ttyNOSUCH0" in text.split(system_capture.STAND_IN_ADVICE)[1]
    assert "planner" not in text.split(system_capture.STAND_IN_ADVICE)[1]  # it lacks no device
