"""The runner's process handling, without ROS: fake targets write the capture file themselves.

Each fake target is a small Python script that behaves like a process on the recording
middleware (writes ``RMW_INTROSPECT_OUTPUT``), crashes, hangs or writes nothing.
"""

from __future__ import annotations

import ast
import json
import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from pytest_rmw_introspect.errors import (
    ExecutableNotFound,
    LifecycleTransitionFailed,
    NoNodeCreated,
    StimulusFailed,
    TargetConfigError,
    TargetExited,
    TargetTimeout,
)
from pytest_rmw_introspect.model.capture import Capture
from pytest_rmw_introspect.model.capture_diagnoses import stimulus_problems
from pytest_rmw_introspect.run import api, executables, process, resolution, runner
from pytest_rmw_introspect.run import target as target_module
from pytest_rmw_introspect.run.ros_env import RosEnvironment
from pytest_rmw_introspect.run.target import TargetSpec

CAPTURE = {
    "format": "rmw_introspect_capture",
    "format_version": 1,
    "rmw_implementation": "rmw_introspect_cpp",
    "pid": 1,
    "argv": [],
    "state": "settled",
    "settle_ms": 10,
    "time_to_settle_ms": 1.0,
    "elapsed_ms": 1.0,
    "nodes": [{"id": 1, "seq": 1, "name": "fake", "namespace": "/", "fqn": "/fake", "enclave": "/", "destroyed": False}],
    "endpoints": [
        {"seq": 2, "kind": "subscription", "node_id": 1, "node": "/fake", "name": "/cmd", "type": "std_msgs/msg/String",
         "type_hash": None, "typesupport": "rosidl_typesupport_c",
         "qos": {"history": "KEEP_LAST", "depth": 7, "reliability": "RELIABLE", "durability": "VOLATILE",
                 "liveliness": "SYSTEM_DEFAULT", "deadline_ns": 0, "lifespan_ns": 0,
                 "liveliness_lease_duration_ns": 0, "avoid_ros_namespace_conventions": False},
         "destroyed": False}
    ],
}


@pytest.fixture
def ros(tmp_path) -> RosEnvironment:
    prefix = tmp_path / "ros"
    (prefix / "lib").mkdir(parents=True)
    return RosEnvironment(kind="system", prefix=prefix, distro="jazzy", ament_prefixes=(prefix,), library_dirs=())


@pytest.fixture
def library(tmp_path) -> Path:
    lib = tmp_path / "mw" / "lib" / "librmw_introspect_cpp.so"
    lib.parent.mkdir(parents=True)
    lib.write_bytes(b"")
    return lib


def fake(tmp_path: Path, body: str, name: str = "fake_node.py") -> Path:
    script = tmp_path / name
    script.write_text(
        "import json, os, sys, time\n"
        f"CAPTURE = {json.dumps(CAPTURE)!r}\n"
        "def write(state='settled', nodes=True, teardown=False, **extra):\n"
        "    doc = json.loads(CAPTURE)\n"
        "    doc['state'] = state\n"
        "    doc.update(extra)\n"
        "    for entity in (doc['nodes'] + doc['endpoints']) if teardown else ():\n"
        "        entity.update(destroyed=True, in_teardown=True)\n"
        "    doc['pid'] = os.getpid()\n"
        "    doc['argv'] = sys.argv\n"
        "    if not nodes:\n"
        "        doc['nodes'] = []; doc['endpoints'] = []\n"
        "    out = os.environ['RMW_INTROSPECT_OUTPUT'].replace('<pid>', str(os.getpid()))\n"
        "    tmp = out + '.tmp.' + str(os.getpid())\n"
        "    open(tmp, 'w').write(json.dumps(doc))\n"
        "    os.rename(tmp, out)\n"
        + textwrap.dedent(body)
    )
    return script


def run(tmp_path, ros, library, body, **options):
    spec = TargetSpec.from_mapping({"script": str(fake(tmp_path, body)), **options})
    return runner.run(spec, library=library, ros=ros)


def test_settled_capture_is_read_and_the_files_are_removed(tmp_path, ros, library):
    body = """
    assert os.environ['RMW_INTROSPECT_EXIT'] == '1'
    assert os.environ['RMW_INTROSPECT_SETTLE_MS'] == '250'
    assert os.environ['RMW_IMPLEMENTATION'] == 'rmw_introspect_cpp'
    assert os.environ['MY_VAR'] == 'x'
    write()
    """
    cap = run(tmp_path, ros, library, body, settle=0.25, env={"MY_VAR": "x"}, arguments=["--flag"])
    assert cap.node_names == ["/fake"]
    assert cap["/fake"].subscriptions[0].qos["depth"] == 7
    assert cap.returncode == 0 and cap.wall_time is not None
    assert cap.command[-1] == "--flag" and cap.argv[-1] == "--flag"
    assert cap.path is None  # temporary files removed


def test_each_capture_gets_its_own_output_file(tmp_path, ros, library):
    body = """
    print(os.environ['RMW_INTROSPECT_OUTPUT'], file=sys.stderr)
    write()
    """
    spec = TargetSpec.from_mapping({"script": str(fake(tmp_path, body))})
    a = runner.run(spec, library=library, ros=ros)
    b = runner.run(spec, library=library, ros=ros)
    assert a.stderr.strip() != b.stderr.strip()
    assert Path(a.stderr.strip()).name == "capture.<pid>.json"  # each process of the target its own file


def test_keep_files_keeps_the_capture(tmp_path, ros, library):
    spec = TargetSpec.from_mapping({"script": str(fake(tmp_path, "write()\n"))})
    cap = runner.run(spec, library=library, ros=ros, keep_files=True)
    assert cap.path is not None and cap.path.exists()


def test_nonzero_exit_reports_status_stderr_and_partial_capture(tmp_path, ros, library):
    body = """
    write(state='running')
    print('starting up', file=sys.stderr)
    raise RuntimeError('boom: the sensor is unplugged')
    """
    with pytest.raises(TargetExited) as info:
        run(tmp_path, ros, library, body)
    err = info.value
    assert err.status == 1
    assert "boom: the sensor is unplugged" in err.stderr_tail
    assert err.partial is not None and err.partial.node_names == ["/fake"]
    msg = str(err)
    assert "crashed: it exited with status 1 while it was captured" in msg
    assert "RuntimeError: boom" in msg
    assert "Captured so far:" in msg and "/fake" in msg and "subscriptions: /cmd" in msg


def test_killed_by_signal(tmp_path, ros, library):
    with pytest.raises(TargetExited, match="was killed by signal 9"):
        run(tmp_path, ros, library, "os.kill(os.getpid(), 9)\n")


def test_exit_without_capture_is_no_node_created(tmp_path, ros, library):
    with pytest.raises(NoNodeCreated) as info:
        run(tmp_path, ros, library, "print('no ros here', file=sys.stderr)\n")
    msg = str(info.value)
    assert "created no ROS node" in msg and "wrote no capture" in msg and "no ros here" in msg


def test_capture_without_nodes_is_no_node_created(tmp_path, ros, library):
    with pytest.raises(NoNodeCreated) as info:
        run(tmp_path, ros, library, "write(nodes=False)\n")
    assert info.value.partial is not None and info.value.partial.nodes == {}


def test_timeout_stops_the_process_and_shows_the_partial_capture(tmp_path, ros, library):
    body = """
    write(state='running')
    while True:
        time.sleep(0.05)
    """
    started = time.monotonic()
    with pytest.raises(TargetTimeout) as info:
        run(tmp_path, ros, library, body, timeout=0.5)
    assert time.monotonic() - started < 3.0  # SIGINT ended it: no long grace period used
    err = info.value
    assert err.partial is not None and err.partial.state == "running"
    msg = str(err)
    assert "did not settle within 0.5 s" in msg and "Captured so far:" in msg and "/fake" in msg
    # the fake target printed a KeyboardInterrupt traceback when our SIGINT stopped it: not its crash
    assert "KeyboardInterrupt" not in msg.replace("the KeyboardInterrupt traceback that printed", "")
    assert "Traceback" not in msg
    assert "The tool stopped it with SIGINT; the KeyboardInterrupt traceback that printed is left out" in msg


def test_timeout_escalates_to_sigkill_when_signals_are_ignored(tmp_path, ros, library, monkeypatch):
    monkeypatch.setattr(process, "SIGINT_GRACE", 0.2)
    monkeypatch.setattr(process, "SIGTERM_GRACE", 0.2)
    body = """
    import signal
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    while True:
        time.sleep(0.05)
    """
    spec = TargetSpec.from_mapping({"script": str(fake(tmp_path, body)), "timeout": 0.3})
    started = time.monotonic()
    with pytest.raises(TargetTimeout) as info:
        runner.run(spec, library=library, ros=ros)
    assert time.monotonic() - started < 5.0
    assert info.value.partial is None
    assert "Nothing was captured" in str(info.value)


def test_stop_uses_the_default_grace_periods(monkeypatch):
    import subprocess

    proc = subprocess.Popen(
        [sys.executable, "-c", "import time; print('ready', flush=True); time.sleep(30)"],
        start_new_session=True,
        stdout=subprocess.PIPE,
    )
    # wait until the interpreter runs the script: a SIGINT during start-up (the wheels'
    # bootstrapper re-execs the interpreter) would end it differently
    assert proc.stdout.readline() == b"ready\n"
    assert runner.stop(proc) == -2  # SIGINT → KeyboardInterrupt → killed by SIGINT
    proc.stdout.close()


def test_missing_script_and_missing_command(tmp_path, ros, library):
    with pytest.raises(ExecutableNotFound, match="does not exist"):
        runner.run(TargetSpec.from_mapping({"script": str(tmp_path / "nope.py")}), library=library, ros=ros)
    with pytest.raises(ExecutableNotFound, match="not found on PATH"):
        runner.run(TargetSpec.from_mapping({"command": ["no-such-program-xyz"]}), library=library, ros=ros)
    with pytest.raises(TargetConfigError, match="No target"):
        runner.run(TargetSpec(), library=library, ros=ros)


def test_package_executable_from_the_ament_index(tmp_path, ros, library):
    index = ros.prefix / "share" / "ament_index" / "resource_index" / "packages"
    index.mkdir(parents=True)
    (index / "demo").write_text("")
    exe = ros.prefix / "lib" / "demo" / "fake"
    exe.parent.mkdir(parents=True)
    script = fake(tmp_path, "write()\n")
    exe.write_text(f"#!{sys.executable}\n" + script.read_text())
    exe.chmod(0o755)
    cap = runner.run(TargetSpec.from_mapping({"package": "demo", "executable": "fake", "namespace": "/r"}),
                     library=library, ros=ros)
    assert cap.command == [str(exe), "--ros-args", "-r", "__ns:=/r"]
    with pytest.raises(ExecutableNotFound, match="The package has these executables: fake"):
        runner.run(TargetSpec.from_mapping({"package": "demo", "executable": "talker"}), library=library, ros=ros)


def test_capture_function_takes_keywords_relative_to_base_dir(tmp_path, ros, library):
    fake(tmp_path, "write()\n", name="n.py")
    cap = api.capture(script="n.py", base_dir=tmp_path, library=library, ros=ros)
    assert cap.node_names == ["/fake"]
    cap = api.capture({"script": "n.py", "timeout": 5}, base_dir=tmp_path, library=library, ros=ros,
                         include_infrastructure=True)
    assert cap.include_infrastructure


def test_cwd_option(tmp_path, ros, library):
    (tmp_path / "work").mkdir()
    body = "assert os.getcwd().endswith('work'), os.getcwd()\nwrite()\n"
    run(tmp_path, ros, library, body, cwd=str(tmp_path / "work"))
    with pytest.raises(ExecutableNotFound, match="Working directory"):
        run(tmp_path, ros, library, "write()\n", cwd=str(tmp_path / "nowhere"))


def test_activation_environment_for_wheels(tmp_path, library):
    ros = RosEnvironment(kind="wheels", prefix=tmp_path, distro="jazzy", ament_prefixes=(tmp_path,),
                         library_dirs=(tmp_path / "lib",))
    spec = TargetSpec.from_mapping({"module": "m", "settle": 0.05, "env": {"RMW_INTROSPECT_VERBOSE": "1"}})
    env = resolution.environment(spec, library, ros, tmp_path / "c.json", base={"PATH": os.environ["PATH"]})
    assert env["LD_PRELOAD"].split()[0] == str(library.resolve())
    assert env["RMW_INTROSPECT_OUTPUT"] == str(tmp_path / "c.json")
    assert env["RMW_INTROSPECT_SETTLE_MS"] == "50"
    assert env["RMW_INTROSPECT_HORIZON_MS"] == "10000"  # virtual time is on by default
    assert env["RMW_INTROSPECT_EXIT"] == "1"
    assert env["RMW_INTROSPECT_VERBOSE"] == "1"


def test_stimuli_reach_the_middleware_only_when_given(tmp_path, library):
    ros = RosEnvironment(kind="wheels", prefix=tmp_path, distro="jazzy", ament_prefixes=(tmp_path,),
                         library_dirs=(tmp_path / "lib",))
    base = {"PATH": os.environ["PATH"]}
    spec = TargetSpec.from_mapping({"module": "m", "stimuli": ["/camera_info", "/calibrate"]})
    env = resolution.environment(spec, library, ros, tmp_path / "c.json", base=base)
    assert env["RMW_INTROSPECT_STIMULI"] == "/camera_info,/calibrate"
    off = resolution.environment(TargetSpec.from_mapping({"module": "m"}), library, ros, tmp_path / "c.json", base=base)
    assert "RMW_INTROSPECT_STIMULI" not in off


def stimulus(name, state="done", error=None, *targets):
    return {"name": name, "state": state, "targets": list(targets), "error": error}


def delivered(result, error=None, kind="subscription", node="/fake"):
    return {"kind": kind, "node": node, "type": "std_msgs/msg/String", "result": result, "error": error}


def problems(raw, returncode):
    """What ``stimulus_problems`` says of the capture document ``raw`` (read by the one reader)."""
    return stimulus_problems(Capture.from_dict({"format": "rmw_introspect_capture", "format_version": 1, **raw}),
                             returncode)


def test_stimuli_that_worked_are_no_problem():
    raw = {"state": "settled", "stimuli": [stimulus("/cmd", "done", None, delivered("taken")),
                                           stimulus("/srv", "done", None, delivered("answered", kind="service"))]}
    assert problems(raw, 0) == []
    assert problems({"state": "settled"}, 0) == []  # an older middleware
    assert problems({"state": "settled", "stimuli": "junk"}, 0) == []


def test_stimulus_problems_are_one_line_each_for_people():
    raw = {"state": "settled", "stimuli": [
        stimulus("/nothing", "no_match", "no subscription or service named /nothing in this process (...)"),
        stimulus("/cmd", "done", None, delivered("not_taken", "the subscription /cmd of /fake did not take the "
                                                              "message within 5000 ms")),
        stimulus("/srv", "done", None, delivered("no_answer", "no answer from /srv of /fake within 5000 ms",
                                                 kind="service")),
        stimulus("/gone", "done", None, delivered("failed", None)),
        stimulus("/late", "skipped", "not delivered: no thread of the process ever waited in rmw_wait"),
    ]}
    assert problems(raw, 0) == [
        "no subscription or service named /nothing in this process (...)",
        "/cmd (subscription of /fake): the subscription /cmd of /fake did not take the message within 5000 ms",
        "/srv (service of /fake): no answer from /srv of /fake within 5000 ms",
        "/gone (subscription of /fake): failed",
        "/late: not delivered: no thread of the process ever waited in rmw_wait",
    ]


def test_a_process_that_fails_after_a_stimulus_is_a_problem_and_one_that_ended_before_its_turn_too():
    crashed = {"state": "exit", "ended": {"before_settle": True},
               "stimuli": [stimulus("/image", "done", None, delivered("pending", node="/fragile")),
                           stimulus("/next", "pending")]}
    first, second = problems(crashed, -11)
    assert first == "/next: not delivered: the process ended before its turn"
    assert second.startswith("the process was killed by signal 11 after the middleware delivered a stimulus (the "
                             "last: a default message or request to the subscription /image of /fragile)")
    # A failure after the final settle, or with nothing delivered, is not the stimuli's.
    settled = {"state": "settled", "stimuli": [stimulus("/image", "done", None, delivered("taken"))]}
    assert problems(settled, 1) == []
    unreached = {"state": "exit", "ended": {"before_settle": True}, "stimuli": [stimulus("/x", "no_match", "no sub")]}
    assert problems(unreached, 1) == ["no sub"]


def test_the_runner_raises_stimulus_failed_with_the_capture(tmp_path, ros, library):
    body = """
    assert os.environ['RMW_INTROSPECT_STIMULI'] == '/nothing'
    write(stimuli=[{'name': '/nothing', 'state': 'no_match', 'targets': [], 'error': 'no subscription or service named /nothing'}])
    """
    with pytest.raises(StimulusFailed) as info:
        run(tmp_path, ros, library, body, stimuli=["/nothing"])
    assert info.value.problems == ["no subscription or service named /nothing"]
    assert info.value.partial is not None and info.value.partial.node_names == ["/fake"]
    message = str(info.value)
    assert message.startswith("The stimuli of the target script ")
    assert "did not work out:\n    - no subscription or service named /nothing\n" in message
    assert "Captured so far:" in message
    # The same capture without stimuli asked for is simply a capture.
    plain = "write(stimuli=[{'name': '/nothing', 'state': 'no_match', 'targets': [], 'error': 'x'}])\n"
    assert run(tmp_path, ros, library, plain).node_names == ["/fake"]


# ---------------------------------------------------------------------------- virtual time


def test_horizon_reaches_the_middleware(tmp_path, ros, library):
    body = """
    assert os.environ['RMW_INTROSPECT_HORIZON_MS'] == '2500', os.environ['RMW_INTROSPECT_HORIZON_MS']
    write()
    """
    assert run(tmp_path, ros, library, body, horizon=2.5).node_names == ["/fake"]
    off = "assert os.environ['RMW_INTROSPECT_HORIZON_MS'] == '0'\nwrite()\n"
    assert run(tmp_path, ros, library, off, horizon=0).node_names == ["/fake"]


# ---------------------------------------------------------------------------- parameters and lifecycle


def test_lifecycle_and_parameter_options_reach_the_middleware(tmp_path, ros, library):
    defaults = """
    assert os.environ['RMW_INTROSPECT_LIFECYCLE'] == 'active', os.environ['RMW_INTROSPECT_LIFECYCLE']
    assert os.environ['RMW_INTROSPECT_PARAMETERS'] == '1'
    write()
    """
    assert run(tmp_path, ros, library, defaults).node_names == ["/fake"]
    chosen = """
    assert os.environ['RMW_INTROSPECT_LIFECYCLE'] == 'unconfigured'
    assert os.environ['RMW_INTROSPECT_PARAMETERS'] == '0'
    write()
    """
    assert run(tmp_path, ros, library, chosen, lifecycle="unconfigured", read_parameters=False).node_names == ["/fake"]


FAILED_CONFIGURE = {
    "target": "active", "initial_state": "unconfigured", "state": "unconfigured",
    "transitions": [{"id": 1, "label": "configure", "result": "failure", "success": False}],
    "error": "transition configure of /fake failed: change_state answered success=false (the callback returned "
             "FAILURE or ERROR, or raised); state now unconfigured",
}


def test_a_failed_lifecycle_transition_fails_the_capture_and_says_what_to_do(tmp_path, ros, library):
    body = f"""
    doc = json.loads(CAPTURE)
    doc['nodes'][0]['lifecycle'] = {FAILED_CONFIGURE!r}
    CAPTURE = json.dumps(doc)
    print('RuntimeError: cannot configure', file=sys.stderr)
    write(format_minor=1)
    """
    with pytest.raises(LifecycleTransitionFailed) as info:
        run(tmp_path, ros, library, body)
    error = info.value
    assert error.failures == [("/fake", "configure", "change_state answered success=false (the callback returned "
                               "FAILURE or ERROR, or raised); state now unconfigured", "unconfigured")]
    text = str(error)
    assert "lifecycle node /fake of the target script" in text
    assert "failed its configure transition: change_state answered success=false" in text
    assert "state now unconfigured. It cannot be captured active as the target asks (`lifecycle: active`)" in text
    assert "fix the node's on_configure" in text and "set `lifecycle: unconfigured` in the target options" in text
    assert "RuntimeError: cannot configure" in text  # its stderr
    assert error.partial is not None and error.partial["/fake"].lifecycle.state == "unconfigured"
    named = error.naming_contract("contracts/fake.interfaces.yaml")
    assert str(named).startswith("contracts/fake.interfaces.yaml: lifecycle node /fake")
    assert "in the `target:` block of contracts/fake.interfaces.yaml" in str(named)


def test_a_capture_stuck_probing_says_how_to_capture_without_it(tmp_path, ros, library):
    body = "write(state='probing', ever_waited=True)\nwhile True:\n    time.sleep(0.05)\n"
    with pytest.raises(TargetTimeout) as info:
        run(tmp_path, ros, library, body, timeout=0.5)
    assert "never finished answering the middleware's questions" in str(info.value)
    assert "`lifecycle: none` or `read_parameters: false`" in str(info.value)


def test_exit_after_settling_is_a_capture_with_a_note(tmp_path, ros, library):
    # settled, then (in the warp) a timeout expired at once and the program gave up
    body = """
    write(state='warping')
    write(state='exit', teardown=True, ended={'before_settle': True})
    sys.exit(1)
    """
    cap = run(tmp_path, ros, library, body)
    assert cap.returncode == 1
    assert cap.node_names == ["/fake"]  # destroyed in its final teardown: still its interface
    assert [s.name for s in cap["/fake"].subscriptions] == ["/cmd"]
    assert not cap.ended_by_itself
    (note,) = cap.notes()
    assert "exited with status 1 after it had settled" in note


def test_a_crash_is_a_failed_target_whether_or_not_it_settled_first(tmp_path, ros, library):
    # a fatal signal, or an uncaught exception, after the first settle: the same failure as
    # before it (whether a crash lands inside the settle window is timing), with the stderr
    with pytest.raises(TargetExited) as killed:
        run(tmp_path, ros, library, "write(state='warping')\nos.kill(os.getpid(), 11)\n")
    assert killed.value.status == -11 and killed.value.crashed
    assert "crashed: it was killed by signal 11 while it was captured" in str(killed.value)
    assert killed.value.partial is not None and killed.value.partial.node_names == ["/fake"]
    body = "write(state='warping')\nraise RuntimeError('sensor driver failed to open /dev/ttyUSB0')\n"
    with pytest.raises(TargetExited) as raised:
        run(tmp_path, ros, library, body)
    message = str(raised.value)
    assert "crashed: it exited with status 1 while it was captured" in message
    assert "Traceback (most recent call last):" in message and "RuntimeError: sensor driver failed" in message
    # a kill that is not a crash (the OOM killer's SIGKILL, an operator) stays a capture with a note
    cap = run(tmp_path, ros, library, "write(state='warping')\nos.kill(os.getpid(), 9)\n")
    assert cap.returncode == -9 and "was killed by signal 9 after it had settled" in cap.notes()[0]


def test_crash_evidence():
    assert runner.crash_evidence(-11, "") and runner.crash_evidence(-6, "")
    assert runner.crash_evidence(1, "Traceback (most recent call last):\n  ...\nValueError: x\n")
    assert runner.crash_evidence(-6, "terminate called after throwing an instance of 'std::runtime_error'")
    assert not runner.crash_evidence(1, "[ERROR] gave up waiting for the server\n")
    assert not runner.crash_evidence(-9, "") and not runner.crash_evidence(-15, "")


def test_program_that_ends_by_itself_before_settling(tmp_path, ros, library):
    body = "write(state='exit', teardown=True, time_to_settle_ms=None, ended={'before_settle': True})\n"
    cap = run(tmp_path, ros, library, body)
    assert cap.ended_by_itself and cap.returncode == 0
    assert cap.node_names == ["/fake"]
    assert cap.raw_nodes[0].destroyed and cap.raw_nodes[0].in_teardown  # the raw capture tells the truth
    assert "ended by itself" in cap.notes()[0]
    assert "ended by itself" in cap.summary()


def test_failure_before_settling_stays_a_failure(tmp_path, ros, library):
    body = "write(state='exit', teardown=True, time_to_settle_ms=None, ended={'before_settle': True})\nsys.exit(3)\n"
    with pytest.raises(TargetExited, match="exited with status 3 before its interfaces settled"):
        run(tmp_path, ros, library, body)


@pytest.mark.parametrize(
    "snapshot, diagnosis",
    [
        ("ever_waited=False, activity_calls=0", "No thread ever waited in an executor (rmw_wait) and it did not keep using"),
        ("ever_waited=False, activity_calls=1", "it is busy or blocked outside ROS"),
        ("ever_waited=True, activity_calls=3", "kept creating or destroying interfaces"),
        ("state='warping', ever_waited=True, time={'horizon_ms': 10000, 'virtual_elapsed_ms': 4000}",
         "virtual time was then advanced (virtual age 4 s) but it never went quiet again"),
        ("nodes=False", "It initialised ROS 2 but created no node yet"),
    ],
)
def test_timeout_says_why_the_capture_did_not_settle(tmp_path, ros, library, snapshot, diagnosis):
    state = "" if "state=" in snapshot else "state='running', "
    body = f"write({state}{snapshot})\nwhile True:\n    time.sleep(0.05)\n"
    with pytest.raises(TargetTimeout) as info:
        run(tmp_path, ros, library, body, timeout=0.5)
    assert diagnosis in str(info.value)


def test_timeout_without_any_capture_says_ros_was_never_initialised(tmp_path, ros, library):
    with pytest.raises(TargetTimeout, match="never initialised ROS 2 on the recording middleware"):
        run(tmp_path, ros, library, "while True:\n    time.sleep(0.05)\n", timeout=0.5)


# ---------------------------------------------------------------------------- other processes, environment, limits


def test_a_ros_process_the_target_starts_writes_its_own_file_and_is_reported(tmp_path, ros, library):
    child = fake(tmp_path, "write()\n", name="child_node.py")
    body = f"""
    import subprocess
    subprocess.run([sys.executable, {str(child)!r}], check=True)   # another ROS process, which settles first
    write()
    """
    cap = run(tmp_path, ros, library, body)
    assert cap.pid == cap.raw["pid"] and cap.argv[-1].endswith("fake_node.py")  # the target's own capture
    (other,) = cap.other_processes
    assert other.argv[-1].endswith("child_node.py") and other.node_names == ["/fake"]
    assert other.pid != cap.pid
    assert any("started other ROS processes" in note and "child_node.py" in note for note in cap.notes())


def test_a_wrapper_that_starts_one_ros_process_is_captured_from_it(tmp_path, ros, library):
    child = fake(tmp_path, "write()\n", name="child_node.py")
    body = f"""
    import subprocess
    sys.exit(subprocess.run([sys.executable, {str(child)!r}]).returncode)   # no ROS in the wrapper itself
    """
    cap = run(tmp_path, ros, library, body)
    assert cap.argv[-1].endswith("child_node.py")
    assert cap.from_child is not None and cap.other_processes == []
    assert any("created no ROS node itself" in note for note in cap.notes())


def test_the_target_env_extends_the_activation_instead_of_replacing_it(tmp_path, library):
    ros = RosEnvironment(kind="wheels", prefix=tmp_path, distro="jazzy", ament_prefixes=(tmp_path,),
                         library_dirs=(tmp_path / "lib",))
    spec = TargetSpec.from_mapping({"module": "m", "env": {
        "LD_PRELOAD": "/opt/libmine.so", "RMW_IMPLEMENTATION": "rmw_fastrtps_cpp", "LD_LIBRARY_PATH": "/mine"}})
    env = resolution.environment(spec, library, ros, tmp_path / "c.json", base={"PATH": os.environ["PATH"]})
    assert env["LD_PRELOAD"].split() == [str(library.resolve()), "/opt/libmine.so"]
    assert env["RMW_IMPLEMENTATION"] == "rmw_introspect_cpp"
    assert env["LD_LIBRARY_PATH"].split(":") == [str(tmp_path / "lib"), "/mine"]


def test_a_user_rmw_implementation_does_not_reach_the_target(tmp_path, ros, library, monkeypatch):
    monkeypatch.setenv("RMW_IMPLEMENTATION", "rmw_fastrtps_cpp")
    body = "assert os.environ['RMW_IMPLEMENTATION'] == 'rmw_introspect_cpp'\nwrite()\n"
    assert run(tmp_path, ros, library, body).node_names == ["/fake"]


def test_a_flood_of_output_keeps_only_a_bounded_tail(tmp_path, ros, library):
    body = """
    chunk = 'x' * 65535 + '\\n'
    for _ in range(400):                       # 26 MB on each stream
        sys.stderr.write(chunk); sys.stdout.write(chunk)
    sys.stderr.write('the last line\\n'); sys.stderr.flush()
    write()
    """
    cap = run(tmp_path, ros, library, body)
    assert cap.stderr.endswith("the last line\n")
    assert len(cap.stderr) <= 16_384


def test_a_missing_module_gets_a_hint_about_the_environment(tmp_path, ros, library):
    body = "import rmwi_no_such_module_anywhere\n"
    with pytest.raises(TargetExited) as info:
        run(tmp_path, ros, library, body)
    message = str(info.value)
    assert "could not import 'rmwi_no_such_module_anywhere'" in message and "PYTHONPATH" in message
    assert "`env:`" in message


def test_stale_working_directories_of_dead_runners_are_swept(tmp_path):
    import subprocess

    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    old = time.time() - 3600
    stale = tmp_path / f"rmw_introspect_{dead.pid}_abc"
    mine = tmp_path / f"rmw_introspect_{os.getpid()}_def"
    recent = tmp_path / f"rmw_introspect_{dead.pid}_ghi"
    for path in (stale, mine, recent):
        path.mkdir()
        (path / "capture.1.json").write_text("{}")
    for path in (stale, mine):
        os.utime(path, (old, old))
    assert runner.sweep_stale_workdirs(tmp_path) == [stale]
    assert not stale.exists() and mine.exists() and recent.exists()


def test_a_hung_target_dies_with_its_runner(tmp_path, ros, library):
    """SIGKILL of the runner (a cancelled CI job) must not leave the target running."""
    import signal
    import subprocess

    pid_file = tmp_path / "target.pid"
    script = fake(tmp_path, f"open({str(pid_file)!r}, 'w').write(str(os.getpid()))\ntime.sleep(60)\n")
    runner_code = textwrap.dedent(f"""
        from pathlib import Path
        from pytest_rmw_introspect.run import process, runner
        from pytest_rmw_introspect.run.ros_env import RosEnvironment
        from pytest_rmw_introspect.run.target import TargetSpec
        ros = RosEnvironment(kind="system", prefix=Path({str(ros.prefix)!r}), distro="jazzy",
                             ament_prefixes=(Path({str(ros.prefix)!r}),), library_dirs=())
        runner.run(TargetSpec.from_mapping({{"script": {str(script)!r}, "timeout": 60}}),
                   library={str(library)!r}, ros=ros)
    """)
    parent = subprocess.Popen([sys.executable, "-c", runner_code])
    deadline = time.monotonic() + 20
    while not pid_file.exists() or not pid_file.read_text():
        assert time.monotonic() < deadline, "the target never started"
        time.sleep(0.05)
    target = int(pid_file.read_text())
    parent.send_signal(signal.SIGKILL)
    parent.wait()
    deadline = time.monotonic() + 10
    while True:
        try:
            os.kill(target, 0)
        except ProcessLookupError:
            break
        # a zombie waiting for init to reap it is dead too
        status = Path(f"/proc/{target}/stat")
        if status.exists() and status.read_text().split(") ", 1)[1].startswith("Z"):
            break
        assert time.monotonic() < deadline, "the target outlived its runner"
        time.sleep(0.05)


#: a program that prints its parent-death signal (prctl PR_GET_PDEATHSIG)
_PRINT_PDEATHSIG = "import ctypes\nv = ctypes.c_int()\nctypes.CDLL('libc.so.6').prctl(2, ctypes.byref(v), 0, 0, 0)\nprint(v.value)"


@pytest.mark.parametrize("wrapped", [True, False], ids=["setpriv", "preexec_fn"])
def test_a_target_starts_with_sigkill_as_its_parent_death_signal(monkeypatch, wrapped):
    """Armed by ``setpriv --pdeathsig`` (which execs the target: vfork and exec instead of a fork
    that runs Python in the child) where it is there, else by a preexec_fn."""
    import signal

    wrapper = process.death_signal_wrapper()
    if wrapped and wrapper is None:
        pytest.skip("no setpriv with --pdeathsig on this machine")
    if not wrapped:
        monkeypatch.setattr(process, "death_signal_wrapper", lambda: None)
    proc = process.start([sys.executable, "-c", _PRINT_PDEATHSIG], env=os.environ, cwd=None)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 0, err
    assert out.decode().strip() == str(int(signal.SIGKILL))
    started_by = list(proc.args)[: len(wrapper or ())]
    assert (started_by == list(wrapper or ()) and bool(wrapper)) == wrapped


def test_a_program_that_cannot_start_is_an_oserror_with_or_without_the_wrapper(tmp_path, monkeypatch):
    plain = tmp_path / "not_executable.sh"
    plain.write_text("#!/bin/sh\n")
    relative = tmp_path / "bin"
    relative.mkdir()
    (relative / "rmwi_here").write_text("#!/bin/sh\n")
    (relative / "rmwi_here").chmod(0o755)
    for argv, error in (([str(tmp_path / "missing")], FileNotFoundError),
                        (["rmwi-no-such-program"], FileNotFoundError),
                        ([str(plain)], PermissionError)):
        with pytest.raises(error):
            process.start(argv, env=os.environ, cwd=None)
    # a relative PATH entry is the child's to resolve, in its own working directory (here the
    # runner's would find it, the target's does not)
    monkeypatch.chdir(tmp_path)
    with pytest.raises(FileNotFoundError):
        process.start(["rmwi_here"], env={**os.environ, "PATH": "bin"}, cwd=tmp_path / "bin")


def test_one_thread_reads_the_tails_of_both_pipes():
    (r1, w1), (r2, w2) = os.pipe(), os.pipe()
    out, err = process.OutputTail.read_together(os.fdopen(r1, "rb"), os.fdopen(r2, "rb"), limit=10)
    os.write(w1, b"0123456789abcdef" * 4)
    os.write(w2, b"error line\n")
    os.close(w2)
    os.write(w1, b"THE END")
    os.close(w1)
    out.finish(5)
    err.finish(5)
    assert out.text() == "cdefTHE END"[-10:] and out.total_bytes == 71
    assert err.text() == "error line\n"[-10:] and err.total_bytes == 11


def _python(code: str) -> process.Process:
    return process.start([sys.executable, "-c", code], env=dict(os.environ), cwd=None)


def test_a_wait_with_a_timeout_is_woken_by_the_end_of_the_process_not_by_polling(monkeypatch):
    # subprocess.Popen.wait(timeout) sleeps between polls, up to 50 ms at a time: a cold
    # capture ended that much after its target
    def no_sleeping(seconds: float) -> None:
        raise AssertionError(f"the wait polled (slept {seconds} s)")

    with _python("import time; time.sleep(0.3); raise SystemExit(3)") as proc:
        monkeypatch.setattr(time, "sleep", no_sleeping)
        assert proc.wait(30) == 3
        assert proc.returncode == 3


def test_a_wait_that_times_out_raises_and_leaves_the_process_running():
    with _python("import time; time.sleep(30)") as proc:
        try:
            with pytest.raises(subprocess.TimeoutExpired):
                proc.wait(0.2)
            assert proc.poll() is None
        finally:
            assert process.stop(proc, 0.5, 0.5) != 0


def test_without_pidfds_a_wait_polls_as_subprocess_does(monkeypatch):
    def unsupported(pid: int) -> int:
        raise OSError(38, "Function not implemented")

    monkeypatch.setattr(os, "pidfd_open", unsupported)
    assert process.wait_for_exit(os.getpid(), 0) is True  # cannot know: the caller's wait decides
    with _python("raise SystemExit(4)") as proc:
        assert proc.wait(30) == 4
    with _python("import time; time.sleep(30)") as proc:
        try:
            with pytest.raises(subprocess.TimeoutExpired):
                proc.wait(0.2)
        finally:
            process.stop(proc, 0.5, 0.5)


def test_waiting_for_the_exit_does_not_reap_the_process():
    with _python("raise SystemExit(5)") as proc:
        assert process.wait_for_exit(proc.pid, 30) is True
        assert process.wait_for_exit(proc.pid, 0) is True  # a zombie still has its pid
        assert proc.returncode is None
        assert proc.wait() == 5  # Popen reaps it and reads its status


def test_the_variables_a_target_env_may_not_set_are_those_the_runner_sets(tmp_path, ros, library):
    spec = TargetSpec.from_mapping({"module": "m", "stimuli": ["/x"]})
    env = resolution.environment(spec, library, ros, tmp_path / "c.json", base={"PATH": os.environ["PATH"]})
    owned = {name for name in env if name.startswith("RMW_INTROSPECT_")}
    assert owned == set(target_module.RUNNER_VARIABLES)


def test_the_log_files_of_a_capture_go_with_its_files_unless_the_user_says_where_logs_go(tmp_path, library):
    ros = RosEnvironment(kind="wheels", prefix=tmp_path, distro="jazzy", ament_prefixes=(tmp_path,))
    output = tmp_path / "work" / "capture.<pid>.json"
    base = {"PATH": os.environ["PATH"], "HOME": "/home/someone"}
    spec = TargetSpec.from_mapping({"module": "m"})
    assert resolution.environment(spec, library, ros, output, base=base)["ROS_LOG_DIR"] == str(tmp_path / "work" / "ros_log")
    for where in ({"ROS_LOG_DIR": "/var/log/ros"}, {"ROS_HOME": "/srv/ros"}):
        # in the environment the check runs in, or in the target's env: the user's choice stands
        env = resolution.environment(spec, library, ros, output, base={**base, **where})
        assert env.get("ROS_LOG_DIR") == where.get("ROS_LOG_DIR"), where
        env = resolution.environment(TargetSpec.from_mapping({"module": "m", "env": where}), library, ros, output,
                                 base=base)
        assert env.get("ROS_LOG_DIR") == where.get("ROS_LOG_DIR"), where


#: a runner process that records which thread imports the capture model, and captures a fake node
_IMPORT_SPY = """
import sys, threading
from pathlib import Path
from pytest_rmw_introspect.run import runner
from pytest_rmw_introspect.run.ros_env import RosEnvironment
from pytest_rmw_introspect.run.target import TargetSpec

importers = []

class Spy:
    def find_spec(self, name, path=None, target=None):
        if name == "pytest_rmw_introspect.model.capture":
            importers.append(threading.current_thread().name)
        return None

assert "pytest_rmw_introspect.model.capture" not in sys.modules
sys.meta_path.insert(0, Spy())
script, library, prefix = sys.argv[1:4]
ros = RosEnvironment(kind="system", prefix=Path(prefix), distro="jazzy", ament_prefixes=(Path(prefix),), library_dirs=())
cap = runner.run(TargetSpec.from_mapping({"script": script}), library=library, ros=ros, cold_note="one capture")
print(cap.node_names, importers)
"""


def test_the_capture_model_is_imported_beside_the_target_not_in_the_main_thread(tmp_path, ros, library):
    """While a target runs, SIGINT or SIGTERM raise in the runner's main thread (KeyboardInterrupt,
    the CLI's Terminated), and one that lands inside an import can come out as another error (a
    RuntimeError from a dataclass field's __set_name__: the CLI then ended with a traceback and
    status 1 instead of stopping the target and ending with 143). So the capture model, imported
    while the first target starts, is imported in a thread of its own."""
    script = fake(tmp_path, "write()\n")
    probe = subprocess.run([sys.executable, "-c", _IMPORT_SPY, str(script), str(library), str(ros.prefix)],
                           capture_output=True, text=True, timeout=60)
    assert probe.returncode == 0, probe.stderr
    assert probe.stdout.strip() == "['/fake'] ['rmw-introspect import']"


def test_a_capture_is_returned_without_waiting_for_its_files_to_be_removed(tmp_path, ros, library, monkeypatch):
    """Removing a capture's working directory waits for the file system (~7 ms a capture on this
    project's machine): the runner returns the capture and a thread of its own removes the files;
    ``flush_removals`` (run at exit) waits for them."""
    import shutil
    import tempfile
    import threading

    temp = tmp_path / "tmp"
    temp.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(temp))
    release = threading.Event()
    real_rmtree = shutil.rmtree

    def slow_rmtree(path, *args, **kwargs):
        if str(path).startswith(str(temp)):  # a file system that takes its time, for this test's files only
            release.wait(30)
        return real_rmtree(path, *args, **kwargs)

    monkeypatch.setattr(shutil, "rmtree", slow_rmtree)
    returned: list[object] = []
    capturing = threading.Thread(target=lambda: returned.append(run(tmp_path, ros, library, "write()\n")))
    capturing.start()
    capturing.join(20)
    try:
        assert returned, "run() waited for its working directory to be removed"
        assert [p.name.startswith("rmw_introspect_") for p in temp.iterdir()] == [True]  # still there
    finally:
        release.set()
        capturing.join(20)
    runner.flush_removals()
    assert list(temp.iterdir()) == []


#: a runner process whose file removals are slow, so that its capture's files are still queued
#: for removal when it exits
_EXIT_WITH_REMOVALS_QUEUED = """
import shutil, sys, time
from pathlib import Path
from pytest_rmw_introspect.run import runner
from pytest_rmw_introspect.run.ros_env import RosEnvironment
from pytest_rmw_introspect.run.target import TargetSpec

real_rmtree = shutil.rmtree
def slow_rmtree(path, *args, **kwargs):
    time.sleep(0.3)
    return real_rmtree(path, *args, **kwargs)
shutil.rmtree = slow_rmtree
script, library, prefix = sys.argv[1:4]
ros = RosEnvironment(kind="system", prefix=Path(prefix), distro="jazzy", ament_prefixes=(Path(prefix),), library_dirs=())
for _ in range(2):
    runner.run(TargetSpec.from_mapping({"script": script}), library=library, ros=ros, cold_note="no server")
print("captured")
"""


def test_the_files_of_captures_are_removed_before_the_runner_exits(tmp_path, ros, library):
    temp = tmp_path / "tmp"
    temp.mkdir()
    script = fake(tmp_path, "write()\n")
    result = subprocess.run([sys.executable, "-c", _EXIT_WITH_REMOVALS_QUEUED, str(script), str(library), str(ros.prefix)],
                            capture_output=True, text=True, timeout=60, env={**os.environ, "TMPDIR": str(temp)})
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "captured"
    assert list(temp.iterdir()) == []


def test_openblas_threads_of_a_target_sleep_at_once_unless_the_user_says_otherwise(tmp_path, library):
    """Spinning OpenBLAS workers (numpy, imported by rclpy) kept a cold target from being proven
    idle for ~40 ms and took a core meanwhile."""
    ros = RosEnvironment(kind="wheels", prefix=tmp_path, distro="jazzy", ament_prefixes=(tmp_path,))
    output = tmp_path / "work" / "capture.<pid>.json"
    base = {"PATH": os.environ["PATH"]}
    spec = TargetSpec.from_mapping({"module": "m"})
    assert resolution.environment(spec, library, ros, output, base=base)["OPENBLAS_THREAD_TIMEOUT"] == "4"
    assert resolution.environment(spec, library, ros, output,
                              base={**base, "OPENBLAS_THREAD_TIMEOUT": "28"})["OPENBLAS_THREAD_TIMEOUT"] == "28"
    own = TargetSpec.from_mapping({"module": "m", "env": {"OPENBLAS_THREAD_TIMEOUT": "30"}})
    assert resolution.environment(own, library, ros, output, base=base)["OPENBLAS_THREAD_TIMEOUT"] == "30"
_TARGET_MODULES = ("target", "executables", "resolution")


def _runtime_imports_from_target(tree: ast.AST) -> list[str]:
    """The names a module imports from ``run.target``, ``run.executables`` and ``run.resolution`` at
    run time (``TYPE_CHECKING`` blocks left out), at any depth; a module itself counts as
    ``<module>``."""
    names: list[str] = []

    def visit(node: ast.AST) -> None:
        if isinstance(node, ast.If) and isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING":
            for child in node.orelse:
                visit(child)
            return
        if isinstance(node, ast.ImportFrom):
            module = ("." * node.level) + (node.module or "")
            if module.rpartition(".")[2] in _TARGET_MODULES and module.lstrip(".").startswith(("run.", "pytest_rmw_introspect.run.", *_TARGET_MODULES)):
                names.extend(alias.name for alias in node.names)
            elif module in (".", "pytest_rmw_introspect.run"):
                names.extend("<module>" for alias in node.names if alias.name in _TARGET_MODULES)
        elif isinstance(node, ast.Import):
            names.extend("<module>" for alias in node.names
                         if alias.name in {f"pytest_rmw_introspect.run.{m}" for m in _TARGET_MODULES})
        for child in ast.iter_child_nodes(node):
            visit(child)

    visit(tree)
    return names


def test_the_runner_imports_only_the_resolution_of_a_target():
    """The runner starts what ``resolution.resolve`` made of a spec and asks the target modules
    nothing else (it once called build_argv, module_main_hint and the spec's queries during a capture)."""
    tree = ast.parse(Path(runner.__file__).read_text(encoding="utf-8"))
    assert _runtime_imports_from_target(tree) == ["resolve"]
    # the check itself sees every way of importing from the target module
    probe = ast.parse("from .target import TargetSpec\nfrom .resolution import resolve\nfrom . import target\n"
                      "def f():\n    from pytest_rmw_introspect.run.executables import build_argv\n"
                      "if TYPE_CHECKING:\n    from .resolution import ResolvedTarget\n")
    assert _runtime_imports_from_target(probe) == ["TargetSpec", "resolve", "<module>", "build_argv"]


def test_a_capture_calls_into_the_target_module_once(tmp_path, ros, library):
    """A trace of one capture (a module target that created no node: the path that asked the
    target modules the most) enters ``run/target.py``, ``run/executables.py`` and
    ``run/resolution.py`` from the runner once, to resolve it."""
    script = fake(tmp_path, "write(nodes=False)\n")
    (tmp_path / "fake_pkg").mkdir()
    (tmp_path / "fake_pkg" / "__init__.py").write_text("")
    (tmp_path / "fake_pkg" / "node.py").write_text(script.read_text())
    spec = TargetSpec.from_mapping({"module": "fake_pkg.node", "cwd": str(tmp_path),
                                    "env": {"PYTHONPATH": str(tmp_path)}})
    calls: list[str] = []

    def profile(frame, event, arg):
        if (event == "call" and frame.f_code.co_filename in (target_module.__file__, resolution.__file__,
                                                             executables.__file__)
                and frame.f_back is not None and frame.f_back.f_code.co_filename == runner.__file__):
            calls.append(frame.f_code.co_name)

    sys.setprofile(profile)
    try:
        with pytest.raises(NoNodeCreated):
            runner.run(spec, library=library, ros=ros, cold_note="one capture")
    finally:
        sys.setprofile(None)
    assert calls == ["resolve"]
