"""The warm start server's failure modes, fallbacks and life (issue 12): children that crash,
hang or ignore signals never harm it; targets it cannot start warm start cold and say why; the
middleware reads each capture's settings after the fork; no process outlives its runner."""

from __future__ import annotations

import os
import shutil
import signal
import stat
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
import warm_helpers as w
from rmwi_processes import wait_gone

from pytest_rmw_introspect.errors import TargetExited, TargetTimeout
from pytest_rmw_introspect.run import process, runner
from pytest_rmw_introspect.run.resolution import LOG_DIR
from pytest_rmw_introspect.run.target import TargetSpec
from pytest_rmw_introspect.run.warm import client as warm

TALKER = str(w.NODES / "talker.py")


def capture(**options):
    return runner.run(TargetSpec.from_mapping(options), warm_wait=60.0)


@pytest.fixture(autouse=True)
def _room_for_servers_of_their_own():
    """Tests here start servers for environments of their own (``LC_RMWI_TEST=...``), and a runner
    keeps at most warm.MAX_SERVERS, ending one only after it idled IDLE_BEFORE_EVICTION: the servers
    other tests of this worker started seconds before would leave no room, and the test's target
    would start cold (CI's Jazzy-on-3.12 selection ran four such tests in a row on one worker).
    End them when fewer than two more would fit."""
    if len(warm.POOL.servers()) > warm.MAX_SERVERS - 2:
        warm.shutdown()


def test_each_capture_reads_its_own_settings_after_the_fork():
    server = w.server_for()
    fast = capture(script=TALKER, settle=0.05, horizon=0)
    slow = capture(script=TALKER, settle=0.2, horizon=2)
    assert (fast.started, slow.started) == ("warm", "warm")
    assert (fast.settle_ms, slow.settle_ms) == (50, 200)
    assert fast.virtual_time is not None and slow.virtual_time is not None
    assert (fast.virtual_time.horizon_ms, slow.virtual_time.horizon_ms) == (0, 2000)
    assert fast.pid != slow.pid and server.pid not in (fast.pid, slow.pid)
    assert w.server_for() is server and server.alive()


@pytest.mark.parametrize("env, status", [
    ({"WARM_CRASH_SIGNAL": "SIGSEGV"}, -signal.SIGSEGV),
    ({"WARM_CRASH_SIGNAL": "SIGABRT"}, -signal.SIGABRT),
    ({"WARM_EXIT_STATUS": "3"}, 3),
])
def test_a_crashing_child_does_not_harm_the_server(env, status):
    server = w.server_for()
    with pytest.raises(TargetExited) as failed:
        capture(script=str(w.WARM_NODES / "warm_crasher.py"), env=env)
    assert failed.value.started == "warm" and failed.value.status == status
    assert server.alive() and w.server_for() is server
    assert capture(script=TALKER).started == "warm"


def test_a_child_that_ignores_sigint_and_sigterm_is_killed_and_the_server_lives_on(monkeypatch):
    monkeypatch.setattr(process, "SIGINT_GRACE", 0.3)
    monkeypatch.setattr(process, "SIGTERM_GRACE", 0.3)
    server = w.server_for()
    started = time.monotonic()
    with pytest.raises(TargetTimeout) as failed:
        capture(script=str(w.WARM_NODES / "warm_ignores_signals.py"), timeout=1.5)
    assert failed.value.started == "warm"
    assert time.monotonic() - started < 10
    partial = failed.value.partial
    assert partial is not None and partial.node_names == ["/stubborn"]
    assert wait_gone([partial.pid], 2.0) == []
    assert server.alive() and capture(script=TALKER).started == "warm"


def test_what_a_warm_target_starts_in_its_process_group_is_killed_with_it(tmp_path):
    pids = tmp_path / "pids.txt"
    cap = capture(script=str(w.WARM_NODES / "warm_pid.py"), env={"WARM_PID_FILE": str(pids), "WARM_CHILD": "1"})
    assert cap.started == "warm"
    child = int(pids.read_text().split("child ")[1].split()[0])
    assert wait_gone([child], 5.0) == []


def _write(path: Path, text: str, executable: bool = False) -> Path:
    path.write_text(text)
    if executable:
        path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return path


def test_targets_that_cannot_start_warm_start_cold_and_say_why(tmp_path):
    w.server_for()
    body = (w.NODES / "talker.py").read_text()
    with_options = _write(tmp_path / "with_options", f"#!{sys.executable} -u\n{body}", executable=True)
    shell = _write(tmp_path / "wrapper.sh", f"#!/bin/sh\nexec {sys.executable} {TALKER} \"$@\"\n", executable=True)
    cases = {
        "cold_start asked for it": {"script": TALKER, "cold_start": True},
        "a compiled executable": {"package": w.EXAMPLES, "executable": "c_talker"},
        "its #! line passes options to the interpreter (-u)": {"command": [str(with_options)]},
        "its #! line names another interpreter (/bin/sh)": {"command": [str(shell)]},
        "interpreter option '-u'": {"command": [sys.executable, "-u", TALKER]},
    }
    for note, options in cases.items():
        cap = capture(**options)
        assert (cap.started, cap.start_note) == ("cold", note)
        assert cap.node_names in (["/talker"], ["/c_talker"])


def test_an_environment_that_changes_imports_gets_a_server_of_its_own(tmp_path):
    default = w.server_for()
    (tmp_path / "warm_extra_mod.py").write_text("TOPIC = 'from_pythonpath'\n")
    node = _write(tmp_path / "node.py", textwrap.dedent("""
        import rclpy
        from rclpy.node import Node
        from std_msgs.msg import String
        import warm_extra_mod
        rclpy.init()
        node = Node("extra")
        node.create_publisher(String, warm_extra_mod.TOPIC, 10)
        rclpy.spin(node)
    """))
    other_dir = tmp_path / "elsewhere"
    other_dir.mkdir()
    options = {"script": str(other_dir / "node.py"), "env": {"PYTHONPATH": str(tmp_path)}}
    node.rename(other_dir / "node.py")
    other = w.server_for(options)
    assert other is not default and other.pid != default.pid
    cap = capture(**options)
    assert cap.started == "warm" and cap["/extra"].publishers[0].name == "/from_pythonpath"
    # an environment variable that changes nothing imported shares the default server
    assert w.server_for({"env": {"SOME_NODE_SETTING": "1"}}) is default


def test_the_server_learns_the_message_packages_targets_use():
    server = w.server_for()

    def loaded() -> bool:
        with open(f"/proc/{server.pid}/maps", encoding="utf-8", errors="replace") as maps:
            return "std_srvs__rosidl_typesupport_c" in maps.read()

    assert capture(script=str(w.NODES / "service_server.py")).started == "warm"
    deadline = time.monotonic() + 10
    while not loaded() and time.monotonic() < deadline:
        time.sleep(0.05)
    assert loaded()


def test_a_server_that_dies_during_a_capture_is_replaced_by_a_cold_start():
    env = {"LC_RMWI_TEST": "killed once"}  # a server of this test's own (LC_* is part of the key)
    server = w.server_for({"env": env})
    cap = capture(script=str(w.WARM_NODES / "warm_kills_server.py"), env=env)
    assert (cap.started, cap.start_note) == ("cold", "the warm start server ended during the capture")
    assert cap.node_names == ["/survivor"]
    assert wait_gone([server.pid], 5.0) == []
    # the next capture gets a new server
    assert w.server_for({"env": env}) is not server
    assert capture(script=TALKER, env=env).started == "warm"


def test_a_server_that_keeps_dying_is_not_started_again():
    env = {"LC_RMWI_TEST": "killed often"}
    for _ in range(warm.MAX_DEATHS):
        w.server_for({"env": env})
        cap = capture(script=str(w.WARM_NODES / "warm_kills_server.py"), env=env)
        assert cap.start_note == "the warm start server ended during the capture"
    cap = capture(script=TALKER, env=env)
    assert (cap.started, cap.start_note) == ("cold", f"the warm start server ended {warm.MAX_DEATHS} times")
    assert capture(script=TALKER).started == "warm"  # other environments are not affected


# ---------------------------------------------------------------------------- nothing left behind

_RUNNER = """
import sys
from pytest_rmw_introspect.run import runner
from pytest_rmw_introspect.run.target import TargetSpec
runner.run(TargetSpec.from_mapping({{"script": {script!r}, "timeout": 120,
           "env": {{"WARM_PID_FILE": {pids!r}, "WARM_HANG": "1"}}}}), warm_wait=60.0)
"""


def _wait_for_pids(pids: Path, proc: subprocess.Popen, count: int = 1) -> list[tuple[int, int]]:
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        if pids.exists():
            lines = [line.split() for line in pids.read_text().splitlines() if not line.startswith("child")]
            if len(lines) >= count:
                return [(int(a), int(b)) for a, b in lines]
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.05)
    raise AssertionError("the target never started")


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGINT, signal.SIGTERM])
def test_no_process_outlives_a_runner_that_is_killed_or_interrupted(tmp_path, sig):
    pids = tmp_path / "pids.txt"
    code = _RUNNER.format(script=str(w.WARM_NODES / "warm_pid.py"), pids=str(pids))
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        ((target, server),) = _wait_for_pids(pids, proc)
        assert server != proc.pid  # forked by the warm start server, not by the runner
        with open(f"/proc/{server}/cmdline", "rb") as f:
            assert b"warm_server" in f.read()
        proc.send_signal(sig)
        proc.wait(30)
        assert wait_gone([target, server], 10.0) == []
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def test_shutdown_ends_the_servers():
    server = w.server_for()
    warm.shutdown()
    assert wait_gone([server.pid], 5.0) == []
    assert warm.POOL.servers() == []
    assert os.getpid() != server.pid


# ---------------------------------------------------------------------------- settings after the fork

_PROBE_SETTINGS = {"RMW_INTROSPECT_PARAMETERS": "0", "RMW_INTROSPECT_LIFECYCLE": "inactive",
                   "RMW_INTROSPECT_ANSWER_TIMEOUT_MS": "1234"}


def test_the_probe_settings_are_read_after_the_fork_too():
    """RMW_INTROSPECT_PARAMETERS, _LIFECYCLE (the runner sets them from the target options
    `read_parameters` and `lifecycle`) and _ANSWER_TIMEOUT_MS (target env) are no part of the
    server's key: targets with different values share the server, and each child reads its own."""
    server = w.server_for()
    lifecycle = str(w.NODES / "lc_managed.py")
    default = capture(script=lifecycle)
    options = {"script": lifecycle, "read_parameters": False, "lifecycle": "inactive",
               "env": {"RMW_INTROSPECT_ANSWER_TIMEOUT_MS": "1234"}}
    cold, warm_result = w.cold_and_warm(options)
    assert w.server_for({k: v for k, v in options.items() if k != "script"}) is server
    assert (default.started, warm_result["started"]) == ("warm", "warm")
    assert w.comparable(warm_result) == w.comparable(cold)
    probe = warm_result["capture"]["rest"]["probe"]
    assert (probe["parameters"], probe["lifecycle"], probe["answer_timeout_ms"]) == (False, "inactive", 1234)
    assert default.raw["probe"]["lifecycle"] == "active" and default.raw["probe"]["parameters"] is True
    (node,) = warm_result["capture"]["entities"]["nodes"]
    assert node["lifecycle"]["state"] == "inactive" and node["parameters"] is None


def test_a_process_forked_before_rmw_init_reads_its_own_configuration(middleware_library, tmp_path):
    """The middleware makes its runtime on first use; a warm start server may reach it before it
    forks (a ROS log line at import reads the time through the middleware). The child's runtime
    must still be made from the child's environment, after the fork."""
    import rmwi_helpers as h

    parent_output, child_output = tmp_path / "parent.json", tmp_path / "child.json"
    child_env = {"CHILD_RMW_INTROSPECT_OUTPUT": str(child_output), "CHILD_RMW_INTROSPECT_SETTLE_MS": "37",
                 **{f"CHILD_{k}": v for k, v in _PROBE_SETTINGS.items()}}
    result = h.run_on_middleware(middleware_library, [sys.executable, str(w.WARM_NODES / "warm_fork_before_init.py")],
                                 tmp_path, output=parent_output, settle_ms=500, env=child_env)
    assert result.returncode == 0, result
    child_pid = int(result.stdout.split()[1])
    assert "status 0" in result.stdout, result
    assert not parent_output.exists()  # the parent never initialized: it writes nothing
    cap = h.load_capture(child_output)
    assert cap is not None and cap["pid"] == child_pid and cap["state"] == "settled"
    assert cap["settle_ms"] == 37
    assert (cap["probe"]["parameters"], cap["probe"]["lifecycle"], cap["probe"]["answer_timeout_ms"]) == (
        False, "inactive", 1234)
    assert [n["fqn"] for n in cap["nodes"]] == ["/forked_talker"]


def test_a_server_started_by_a_short_lived_thread_outlives_it():
    """A contract item capturing ahead (or a system capture's thread pool) may be the first to
    need a server: the server must not die with that thread (its parent-death signal follows the
    thread that forked it)."""
    import threading

    env = {"LC_RMWI_TEST": "started by a thread"}
    started: dict = {}
    thread = threading.Thread(target=lambda: started.update(server=w.server_for({"env": env})))
    thread.start()
    thread.join()
    server = started["server"]
    assert wait_gone([server.pid], 1.0) == [server.pid]  # still alive after the thread ended
    assert server.alive() and w.server_for({"env": env}) is server
    assert capture(script=TALKER, env=env).started == "warm"


def test_the_least_recently_used_server_is_ended_when_too_many_run_and_it_is_idle(monkeypatch):
    monkeypatch.setattr(warm, "MAX_SERVERS", 1)
    monkeypatch.setattr(warm, "IDLE_BEFORE_EVICTION", 0.0)
    first = w.server_for({"env": {"LC_RMWI_TEST": "evicted"}})
    second = w.server_for({"env": {"LC_RMWI_TEST": "evicting"}})
    assert second is not first and warm.POOL.servers() == [second]
    assert first.proc is not None and first.proc.poll() is not None  # ended before the second started
    assert capture(script=TALKER, env={"LC_RMWI_TEST": "evicting"}).started == "warm"
    warm.shutdown()
    assert wait_gone([second.pid], 5.0) == []


def _warm_servers_alive() -> set[int]:
    """The warm start servers this process runs now (its children running warm_server)."""
    found = set()
    for entry in os.listdir("/proc"):
        try:
            stat_fields = Path(f"/proc/{entry}/stat").read_text().rsplit(")", 1)[1].split()
            cmdline = Path(f"/proc/{entry}/cmdline").read_bytes()
        except (OSError, IndexError):
            continue
        if stat_fields[1] == str(os.getpid()) and stat_fields[0] != "Z" and b"warm_server" in cmdline:
            found.add(int(entry))
    return found


def test_targets_over_more_environments_than_the_cap_never_run_more_servers(monkeypatch):
    """Six environments cycled through by three threads, two servers allowed: there were up to
    nine servers alive at once (the cap was 4) and one started for nearly every capture. Now at
    most MAX_SERVERS run, counting those still ending; targets that find no room start cold,
    saying why, and a server is replaced only once it has been idle a while."""
    import threading
    from concurrent.futures import ThreadPoolExecutor

    monkeypatch.setattr(warm, "MAX_SERVERS", 2)
    warm.shutdown()
    seen: set[int] = set()
    peak = [0]
    done = threading.Event()

    def watch() -> None:
        while not done.is_set():
            alive = _warm_servers_alive()
            seen.update(alive)
            peak[0] = max(peak[0], len(alive))
            time.sleep(0.01)

    watcher = threading.Thread(target=watch, daemon=True)
    watcher.start()
    variants = [{"LC_RMWI_TEST": f"variant {n % 6}"} for n in range(18)]
    try:
        with ThreadPoolExecutor(max_workers=3) as pool:
            captures = list(pool.map(lambda env: runner.run(TargetSpec.from_mapping({"script": TALKER, "env": env}),
                                                            warm_wait=60.0), variants))
    finally:
        done.set()
        watcher.join()
        warm.shutdown()
    assert peak[0] <= 2 and len(seen) <= 2, (peak[0], len(seen))
    assert {c.started for c in captures} == {"warm", "cold"}
    assert all("warm start servers for other environments are in use" in (c.start_note or "")
               for c in captures if c.started == "cold")


@pytest.mark.parametrize("cold_start", [False, True], ids=["warm", "cold"])
def test_a_capture_keeps_its_log_file_with_its_files_not_in_the_users_log_directory(tmp_path, cold_start):
    """rcl opens a log file per process at rclpy.init (`ros2 run` too): a capture's goes to its
    own files (kept with keep_files, removed without), unless the target says where logs go."""
    if not cold_start:
        w.server_for()
    kept = runner.run(TargetSpec.from_mapping({"script": TALKER, "cold_start": cold_start}), warm_wait=60.0,
                      keep_files=True)
    assert kept.started == ("cold" if cold_start else "warm")
    assert kept.path is not None
    try:
        assert list((kept.path.parent / LOG_DIR).glob("python_*.log"))
    finally:
        shutil.rmtree(kept.path.parent, ignore_errors=True)
    mine = tmp_path / "my_logs"
    chosen = capture(script=TALKER, cold_start=cold_start, env={"ROS_LOG_DIR": str(mine)})
    assert chosen.started == ("cold" if cold_start else "warm")
    assert list(mine.glob("python_*.log"))
