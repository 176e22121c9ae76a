"""Warm starts without a server: which commands can start warm (and why the others cannot), what
a server is keyed on, the forked child as the runner sees it, the cold_start option."""

from __future__ import annotations

import json
import os
import signal
import socket
import stat
import subprocess
import sys
import threading
import time
import zipfile
from pathlib import Path

import pytest

from pytest_rmw_introspect.errors import TargetConfigError
from pytest_rmw_introspect.run import runner
from pytest_rmw_introspect.run.target import TARGET_KEYS, TargetSpec
from pytest_rmw_introspect.run.warm import client as warm
from pytest_rmw_introspect.run.warm import plan as warm_plan
from pytest_rmw_introspect.run.warm import server as warm_server

PY = sys.executable


def _exe(path: Path, text: str) -> Path:
    path.write_text(text)
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return path


# ---------------------------------------------------------------------------- plan


def test_a_script_run_by_this_interpreter_starts_warm(tmp_path):
    script = tmp_path / "node.py"
    script.write_text("pass\n")
    plan = warm_plan.plan([PY, str(script), "a", "--ros-args", "-r", "__ns:=/x"], {})
    assert plan == warm_plan.Plan("script", str(script), (str(script), "a", "--ros-args", "-r", "__ns:=/x"),
                             (PY, str(script), "a", "--ros-args", "-r", "__ns:=/x"), PY)


def test_a_module_starts_warm_with_argv_as_python_dash_m_gives_it():
    plan = warm_plan.plan([PY, "-m", "pkg.node", "x"], {})
    assert isinstance(plan, warm_plan.Plan)
    assert (plan.kind, plan.target, plan.argv, plan.orig_argv) == ("module", "pkg.node", ("-m", "x"),
                                                                  (PY, "-m", "pkg.node", "x"))


def test_an_executable_whose_shebang_names_this_interpreter_starts_warm(tmp_path):
    exe = _exe(tmp_path / "talker", f"#!{PY}\nimport sys\n")
    plan = warm_plan.plan([str(exe), "--ros-args"], {})
    assert isinstance(plan, warm_plan.Plan)
    # what the kernel makes of it: `interpreter executable args...`
    assert (plan.kind, plan.target, plan.argv, plan.orig_argv) == ("script", str(exe), (str(exe), "--ros-args"),
                                                                  (PY, str(exe), "--ros-args"))


def test_an_env_shebang_is_resolved_on_the_targets_path(tmp_path):
    name = Path(PY).name
    exe = _exe(tmp_path / "talker", f"#!/usr/bin/env {name}\n")
    plan = warm_plan.plan([str(exe)], {"PATH": str(Path(PY).parent)})
    assert isinstance(plan, warm_plan.Plan) and plan.orig_argv == (name, str(exe)) and plan.executable == PY
    assert warm_plan.plan([str(exe)], {"PATH": str(tmp_path)}) == f"its #! line names {name}, which is not on PATH"


@pytest.mark.parametrize("make, reason", [
    (lambda d: [PY, "-u", "x.py"], "interpreter option '-u'"),
    (lambda d: [PY, "-c", "pass"], "interpreter option '-c'"),
    (lambda d: [PY], "no script or module to run"),
    (lambda d: [PY, str(d)], "the script is a directory"),
    (lambda d: [PY, str(d / "missing.py")], "cannot read the script (No such file or directory)"),
    (lambda d: ["/bin/true"], "a compiled executable"),
    (lambda d: [str(_exe(d / "plain", "echo hi\n"))], "not a Python program (no #! line)"),
    (lambda d: [str(_exe(d / "sh", "#!/bin/sh\n"))], "its #! line names another interpreter (/bin/sh)"),
    (lambda d: [str(_exe(d / "opt", f"#!{PY} -E\n"))], "its #! line passes options to the interpreter (-E)"),
    (lambda d: [str(d / "nothing-here")], f"cannot read {'{d}'}/nothing-here"),
    (lambda d: [], "empty command"),
])
def test_commands_that_start_cold_and_why(tmp_path, make, reason):
    assert warm_plan.plan(make(tmp_path), {}) == reason.replace("{d}", str(tmp_path))


def test_zip_archives_and_compiled_python_start_cold(tmp_path):
    archive = tmp_path / "app.pyz"
    with zipfile.ZipFile(archive, "w") as z:
        z.writestr("__main__.py", "pass\n")
    compiled = tmp_path / "node.pyc"
    compiled.write_bytes(b"\xa7\r\r\n" + bytes(12))
    for path in (archive, compiled):
        assert warm_plan.plan([PY, str(path)], {}) == "the script is a zip archive or compiled Python"


def test_another_interpreter_starts_cold(tmp_path):
    other = tmp_path / "python3"
    other.symlink_to(os.path.realpath(PY))  # the same binary, but not this environment's prefix
    assert not warm_plan.same_interpreter(str(other))
    assert warm_plan.plan([str(other), "x.py"], {}) == f"another Python interpreter ({other})"
    assert warm_plan.same_interpreter(PY)
    sibling = Path(PY).parent / "python3"
    if sibling.exists() and os.path.realpath(sibling) == os.path.realpath(PY):
        assert warm_plan.same_interpreter(str(sibling))


# ---------------------------------------------------------------------------- keys


def test_the_server_key_is_the_environment_that_changes_imports():
    base = {"PATH": "/bin", "LD_PRELOAD": "/lib/mw.so", "LD_LIBRARY_PATH": "/venv/lib", "PYTHONPATH": "/ws",
            "AMENT_PREFIX_PATH": "/venv", "ROS_DOMAIN_ID": "3", "RMW_INTROSPECT_OUTPUT": "/tmp/a", "MY_NODE": "x"}
    key = warm_plan.server_key(base, "/here")
    # variables a node reads itself, per-capture middleware settings: same server
    for name, value in (("MY_NODE", "y"), ("ROS_DOMAIN_ID", "4"), ("RMW_INTROSPECT_OUTPUT", "/tmp/b"),
                        ("PATH", "/usr/bin"), ("WARM_FACT", "1")):
        assert warm_plan.server_key({**base, name: value}, "/elsewhere") == key, name
    # what the interpreter, the dynamic loader or the imports read: another server
    for name, value in (("PYTHONPATH", "/other"), ("LD_PRELOAD", "/lib/asan.so /lib/mw.so"), ("LD_LIBRARY_PATH", "/x"),
                        ("AMENT_PREFIX_PATH", "/ws:/venv"), ("PYTHONHASHSEED", "0"), ("LANG", "C"),
                        ("RCUTILS_CONSOLE_OUTPUT_FORMAT", "{message}"), ("OPENBLAS_NUM_THREADS", "1")):
        assert warm_plan.server_key({**base, name: value}, "/here") != key, name
    assert warm_plan.server_key(base, "/here", python="/other/python") != key
    assert warm_plan.server_environment(base) == {"LD_PRELOAD": "/lib/mw.so", "LD_LIBRARY_PATH": "/venv/lib",
                                             "PYTHONPATH": "/ws", "AMENT_PREFIX_PATH": "/venv"}


def test_a_relative_pythonpath_keys_the_server_on_the_working_directory():
    env = {"PYTHONPATH": "src:/abs"}
    assert warm_plan.server_key(env, "/a") != warm_plan.server_key(env, "/b")
    assert warm_plan.server_key({"PYTHONPATH": "/abs"}, "/a") == warm_plan.server_key({"PYTHONPATH": "/abs"}, "/b")


def test_message_types_name_their_python_modules():
    assert warm_server.type_module("std_msgs/msg/String") == ("std_msgs.msg", "String")
    assert warm_server.type_module("std_srvs/srv/SetBool") == ("std_srvs.srv", "SetBool")
    assert warm_server.type_module("test_msgs/action/Fibonacci_SendGoal") == ("test_msgs.action", "Fibonacci")
    assert warm_server.type_module("test_msgs/action/Fibonacci_FeedbackMessage") == ("test_msgs.action", "Fibonacci")
    for bad in ("String", "a/b", "os/msg/X; import", "pkg/idl/X", "../x/msg/Y"):
        assert warm_server.type_module(bad) is None


# ---------------------------------------------------------------------------- the child


@pytest.fixture
def child_and_server():
    ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
    sleeper = subprocess.Popen(["sleep", "30"])
    r1, w1 = os.pipe()
    r2, w2 = os.pipe()
    os.close(w1)
    os.close(w2)
    child = warm.WarmChild(sleeper.pid, ours, ["node"], os.fdopen(r1, "rb"), os.fdopen(r2, "rb"))
    yield child, theirs, sleeper
    sleeper.kill()
    sleeper.wait()
    theirs.close()
    child.release()


def test_a_warm_child_waits_like_popen(child_and_server):
    child, server, _sleeper = child_and_server
    assert child.poll() is None
    with pytest.raises(subprocess.TimeoutExpired):
        child.wait(0.05)
    server.send(json.dumps({"returncode": -signal.SIGTERM}).encode())
    assert child.wait(5) == -signal.SIGTERM and child.poll() == -signal.SIGTERM
    assert not child.server_lost


def test_a_warm_child_signals_its_process_until_it_ended(child_and_server):
    child, server, sleeper = child_and_server
    child.send_signal(signal.SIGTERM)
    assert sleeper.wait(5) == -signal.SIGTERM
    server.send(json.dumps({"returncode": -signal.SIGTERM}).encode())
    child.wait(5)
    child.send_signal(signal.SIGKILL)  # ended: never signalled again (its pid may be reused)


def test_a_server_gone_during_the_capture_is_noticed(child_and_server):
    child, server, _sleeper = child_and_server
    server.close()
    assert child.wait(5) == -signal.SIGKILL and child.server_lost


def test_a_server_is_told_each_message_type_once():
    ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
    sleeper = subprocess.Popen(["sleep", "30"])
    # a WarmServer without its process: learn() only needs the control socket and a live proc
    server = object.__new__(warm.WarmServer)
    server.__dict__.update(control=ours, proc=sleeper, failure=None, unresponsive=None, info=None)
    server.__dict__.update(_told=set(), _told_lock=threading.Lock())
    try:
        theirs.settimeout(5)
        server.learn(["std_msgs/msg/String", "std_srvs/srv/Empty"])
        assert json.loads(theirs.recv(65536)) == {"op": "preload", "types": ["std_msgs/msg/String", "std_srvs/srv/Empty"]}
        server.learn(["std_srvs/srv/Empty", "std_msgs/msg/String"])  # nothing new: nothing sent
        server.learn(["std_msgs/msg/String", "geometry_msgs/msg/Twist"])
        assert json.loads(theirs.recv(65536)) == {"op": "preload", "types": ["geometry_msgs/msg/Twist"]}
        theirs.setblocking(False)
        with pytest.raises(BlockingIOError):
            theirs.recv(65536)
    finally:
        sleeper.kill()
        sleeper.wait()
        ours.close()
        theirs.close()


def test_the_shared_address_names_user_scope_and_key():
    key = warm_plan.server_key({"PYTHONPATH": "/a"}, "/")
    address = warm.shared_address("scope1", key)
    assert address.startswith(b"\0rmw-introspect-warm/") and f"/{os.getuid()}/scope1/".encode() in address
    assert warm.shared_address("scope1", warm_plan.server_key({"PYTHONPATH": "/b"}, "/")) != address
    assert warm.shared_address("scope2", key) != address


def test_one_runner_binds_a_shared_address_the_others_connect_to_it():
    address = warm.shared_address(f"unit-{os.getpid()}", ("key",))
    assert warm._connect(address) is None  # nobody there yet
    listener = warm._bind(address)
    assert listener is not None
    try:
        assert warm._bind(address) is None  # taken
        client = warm._connect(address)
        assert client is not None
        served, _ = listener.accept()
        assert warm_server.peer_uid(served) == os.getuid() == warm_server.peer_uid(client)
        served.close()
        client.close()
    finally:
        listener.close()
    assert warm._connect(address) is None


# ---------------------------------------------------------------------------- option and pool


def test_cold_start_is_a_target_option():
    assert "cold_start" in TARGET_KEYS
    assert TargetSpec.from_mapping({"script": "a.py", "cold_start": True}).cold_start is True
    assert TargetSpec.from_mapping({"script": "a.py"}).cold_start is None
    with pytest.raises(TargetConfigError, match="`cold_start` must be true or false"):
        TargetSpec.from_mapping({"script": "a.py", "cold_start": "yes"})


def test_a_disabled_pool_starts_no_server_and_says_why(monkeypatch):
    monkeypatch.setattr(warm.POOL, "disabled", "because")
    before = warm.POOL.servers()  # this process may have run end-to-end tests (xdist)
    assert warm.POOL.server({"PYTHONPATH": "/x/unique"}, "/") == "because"
    assert warm.POOL.servers() == before


def _fake_target(tmp_path):
    """A script that writes a settled capture of one node the way the middleware would, a library
    file and a ROS environment to run it with (no ROS needed)."""
    script = tmp_path / "fake.py"
    script.write_text(
        "import json, os\n"
        "doc = {'format': 'rmw_introspect_capture', 'format_version': 1, 'pid': os.getpid(), 'argv': [],\n"
        "       'state': 'settled', 'settle_ms': 10, 'time_to_settle_ms': 1.0, 'elapsed_ms': 1.0,\n"
        "       'nodes': [{'id': 1, 'seq': 1, 'name': 'n', 'namespace': '/', 'fqn': '/n', 'enclave': '/',\n"
        "                  'destroyed': False}], 'endpoints': []}\n"
        "out = os.environ['RMW_INTROSPECT_OUTPUT'].replace('<pid>', str(os.getpid()))\n"
        "open(out + '.t', 'w').write(json.dumps(doc)); os.rename(out + '.t', out)\n"
    )
    lib = tmp_path / "librmw_introspect_cpp.so"
    lib.write_bytes(b"")
    from pytest_rmw_introspect.run.ros_env import RosEnvironment

    ros = RosEnvironment(kind="system", prefix=tmp_path, distro="jazzy", ament_prefixes=(tmp_path,))
    return TargetSpec.from_mapping({"script": str(script)}), lib, ros


def test_the_capture_says_how_it_was_started(tmp_path):
    spec, lib, ros = _fake_target(tmp_path)
    cap = runner.run(spec, library=lib, ros=ros)
    assert (cap.started, cap.start_note) == ("cold", "the fast test tier starts targets cold")
    assert "started cold" in cap.summary()


def test_a_capture_given_a_cold_note_never_asks_for_a_server(tmp_path, monkeypatch):
    """`rmw-introspect capture` runs one target: it starts cold, for the reason it gives, without
    the warm start client (which would start a server for a Python target)."""
    monkeypatch.setattr(warm.POOL, "disabled", None)

    def no_server(*args, **kwargs):
        raise AssertionError("a capture given a cold note asked for a warm start server")

    monkeypatch.setattr(warm.POOL, "server", no_server)
    monkeypatch.setattr(warm.POOL, "learn", no_server)
    spec, lib, ros = _fake_target(tmp_path)
    cap = runner.run(spec, library=lib, ros=ros, cold_note="one capture")
    assert (cap.started, cap.start_note) == ("cold", "one capture")


def test_an_attached_server_whose_ready_message_waits_is_alive():
    """An attached runner's server socket becomes readable with the ready message: that is no end
    until wait_ready read it (a capture that found the server still starting ran cold, the
    next one must find it alive, not count a death)."""
    ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
    server = warm.WarmServer.attached(ours)
    try:
        assert not server.wait_ready(0)  # nothing yet: still starting
        theirs.send(json.dumps({"ready": True, "pid": 4242}).encode())
        assert server.alive()  # readable, but with the ready message
        assert server.wait_ready(0) and server.pid == 4242 and server.alive()
        theirs.close()
        assert not server.alive()  # now readable at its end
    finally:
        server.close()


def _owned(proc: subprocess.Popen) -> tuple[warm.WarmServer, socket.socket]:
    """A WarmServer owning ``proc`` (a stand-in for a server process), and the server's end of
    its control socket."""
    ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
    server = warm.WarmServer.attached(ours)
    server.proc = proc
    return server, theirs


def test_the_owner_kills_a_server_that_neither_ends_nor_answers():
    server, theirs = _owned(subprocess.Popen(["sleep", "30"]))
    try:
        server.close(timeout=0.3)
        assert server.proc is not None and server.proc.returncode == -signal.SIGKILL
    finally:
        theirs.close()


def test_the_owner_waits_while_the_server_still_serves_attached_runners():
    proc = subprocess.Popen(["sleep", "0.9"])
    server, theirs = _owned(proc)

    def shared_server() -> None:  # runners stay attached longer than the owner's timeout
        theirs.send(json.dumps({"clients": 1}).encode())
        time.sleep(0.8)
        theirs.send(json.dumps({"clients": 0}).encode())
        theirs.close()

    serving = threading.Thread(target=shared_server)
    serving.start()
    server.close(timeout=0.5)
    serving.join()
    assert proc.returncode == 0  # it ended by itself: not killed after 0.5 s
