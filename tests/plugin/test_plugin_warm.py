"""Warm starts in pytest sessions (issue 12): captures start warm, one server per session (the
xdist workers of a run share it); the option and ini value ask for cold starts; the next contract item captures
ahead; no server or target outlives the session, also when pytest is interrupted or terminated
or an xdist worker is killed."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from rmwi_processes import alive, wait_gone

WARM_NODES = Path(__file__).resolve().parents[1] / "middleware" / "nodes_warm"

#: each test records how it was started and which servers its process had (for the outer test)
RECORDING_TESTS = """
import os
from pytest_rmw_introspect.run.warm import client as warm

def record(cap):
    servers = " ".join(str(s.pid) for s in warm.POOL.servers())
    with open("record.txt", "a") as f:
        f.write(f"{os.getpid()} {cap.started} {cap.start_note} servers={servers}\\n")

@pytest.mark.parametrize("ns", ["/a", "/b", "/c", "/d"])
def test_capture(ns, rmw_capture):
    cap = rmw_capture(script=NODES + "/talker.py", namespace=ns, settle=0.02)
    assert cap.node_names == [ns + "/talker"]
    record(cap)

@pytest.mark.interfaces("contracts/talker.yaml", script=NODES + "/talker.py", settle=0.02)
def test_marker(interfaces):
    record(interfaces)
"""


def _records(project) -> list[list[str]]:
    return [line.split(" ", 2) for line in project.read("record.txt").splitlines()]


def _server_pids(records) -> set[int]:
    return {int(p) for r in records for p in r[2].split("servers=")[1].split()}


@pytest.mark.parametrize("workers", [[], ["-n", "2"]], ids=["serial", "xdist"])
def test_captures_start_warm_and_the_servers_end_with_the_session(project, workers):
    project.test(RECORDING_TESTS)
    result = project.run("--update-golden", *workers)
    result.assert_outcomes(passed=5)
    records = _records(project)
    assert len(records) == 5
    assert all(how == "warm" for _pid, how, _rest in records), records
    per_process: dict[str, set[int]] = {}
    for pid, _how, rest in records:
        per_process.setdefault(pid, set()).update(int(p) for p in rest.split("servers=")[1].split())
    assert all(len(servers) == 1 for servers in per_process.values()), per_process
    assert len(_server_pids(records)) == 1, records  # xdist: the workers share it
    assert wait_gone(_server_pids(records)) == []


@pytest.mark.parametrize("how", ["option", "ini"])
def test_cold_starts_on_request(project, how):
    project.test(RECORDING_TESTS)
    if how == "ini":
        project.pytester.makeini("[pytest]\nrmw_introspect_cold_start = true\n")
    result = project.run("--update-golden", *(["--rmw-introspect-cold-start"] if how == "option" else []))
    result.assert_outcomes(passed=5)
    records = _records(project)
    assert {(how_, rest.split(" servers=")[0]) for _pid, how_, rest in records} == {
        ("cold", "cold_start asked for it")}
    assert _server_pids(records) == set()  # no server was started at all


def test_a_marker_can_ask_for_a_cold_start(project):
    project.test("""
        @pytest.mark.interfaces("contracts/talker.yaml", script=NODES + "/talker.py", cold_start=True)
        def test_marker(interfaces):
            assert (interfaces.started, interfaces.start_note) == ("cold", "cold_start asked for it")

        def test_fixture(rmw_capture):
            assert rmw_capture(script=NODES + "/talker.py").started == "warm"
    """)
    project.run("--update-golden").assert_outcomes(passed=2)


HANGING_TEST = f"""
def test_hangs(rmw_capture):
    rmw_capture(script={str(WARM_NODES / 'warm_pid.py')!r}, timeout=120,
                env={{"WARM_PID_FILE": "pids.txt", "WARM_HANG": "1"}})
"""


def _start_pytest(project, *args: str) -> subprocess.Popen:
    env = dict(os.environ)
    return subprocess.Popen([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-q", *args],
                            cwd=project.path, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            start_new_session=True)


def _wait_for_target(project, proc: subprocess.Popen) -> tuple[int, int]:
    pids = project.path / "pids.txt"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        if pids.exists() and pids.read_text().strip():
            target, server = pids.read_text().split()[:2]
            return int(target), int(server)
        assert proc.poll() is None, proc.communicate()[0].decode(errors="replace")
        time.sleep(0.05)
    raise AssertionError("the target never started")


def _parent(pid: int) -> int:
    with open(f"/proc/{pid}/status", encoding="ascii") as f:
        return int(next(line for line in f if line.startswith("PPid:")).split()[1])


#: the slow node sleeps this long before it initializes ROS: a capture of it takes at least this
SLOW = 2.0


def _slow_contracts(project) -> None:
    for name in ("first", "second", "third"):
        project.write(f"contracts/{name}.interfaces.yaml", f"""\
            contract_version: 1
            target:
              script: {WARM_NODES / 'warm_slow_start.py'}
              settle: 0.02
              env: {{WARM_TIMES_FILE: {project.path / 'times.txt'}, WARM_NODE_NAME: {name}, WARM_SLEEP: '{SLOW}'}}
            nodes: {{}}
        """)


def _starts(project) -> list[float]:
    lines = [line.split() for line in project.read("times.txt").splitlines()]
    return [float(t) for _name, _start, t in sorted(lines, key=lambda parts: parts[0])]


@pytest.mark.parametrize(("options", "ahead"), [([], 8), (["--rmw-introspect-capture-ahead", "1"], 1),
                                              (["--rmw-introspect-cold-start"], 1),
                                              (["--rmw-introspect-cold-start", "--rmw-introspect-capture-ahead", "2"], 2),
                                              (["--rmw-introspect-no-capture-ahead"], 0)],
                         ids=["default", "one-ahead", "cold-default", "cold-two-ahead", "one-at-a-time"])
def test_the_next_contract_items_capture_while_the_current_one_runs(project, options, ahead):
    _slow_contracts(project)
    result = project.run("--update-golden", *options)
    result.assert_outcomes(passed=3)
    first, second, third = _starts(project)
    if ahead >= 2:  # every capture started with first's item, before first's could have ended
        assert abs(second - first) < SLOW and abs(third - first) < SLOW
    elif ahead == 1:  # second's with first's item, third's with second's
        assert abs(second - first) < SLOW and third - first >= SLOW
    else:
        assert second - first >= SLOW and third - second >= SLOW
    # the captures are the items' own: each contract got its node
    for name in ("first", "second", "third"):
        assert f"/{name}:" in project.read(f"contracts/{name}.interfaces.yaml")
    project.run().assert_outcomes(passed=3)  # and they match again, captured ahead


#: records, as each file's collection ends, how many warm start servers the session has asked for
COLLECTION_RECORDER = """
from pytest_rmw_introspect.run.warm import client as warm

def pytest_collectreport(report):
    if report.nodeid.endswith(".interfaces.yaml"):
        with open("collected.txt", "a") as f:
            f.write(f"{report.nodeid} {len(warm.POOL.servers())}\\n")
"""


@pytest.mark.parametrize("collect_only", [False, True], ids=["run", "collect-only"])
def test_the_first_contract_file_starts_the_server_while_the_rest_is_collected(project, collect_only):
    """The server imports rclpy while the session collects its other contracts (a collection of
    a hundred takes about as long), instead of after collection, when the first item waits."""
    _slow_contracts(project)
    project.write("conftest.py", COLLECTION_RECORDER)
    result = project.run("--update-golden", *(["--collect-only"] if collect_only else []))
    assert result.ret == 0, result.stdout.str()
    reports = [line.split() for line in project.read("collected.txt").splitlines()]
    assert len(reports) == 3
    assert {int(servers) for _nodeid, servers in reports} == ({0} if collect_only else {1}), reports


def test_capture_ahead_is_an_ini_value_too(project):
    _slow_contracts(project)
    project.pytester.makeini("[pytest]\nrmw_introspect_capture_ahead = false\n")
    project.run("--update-golden").assert_outcomes(passed=3)
    first, second, third = _starts(project)
    assert second - first >= SLOW and third - second >= SLOW


def test_a_bad_capture_ahead_count_is_a_usage_error(project):
    _slow_contracts(project)
    project.pytester.makeini("[pytest]\nrmw_introspect_capture_ahead = many\n")
    result = project.run()
    assert result.ret == pytest.ExitCode.USAGE_ERROR
    result.stderr.fnmatch_lines(["*ini option rmw_introspect_capture_ahead = 'many'*0 to 64*"])


@pytest.mark.parametrize("workers", [[], ["-n", "2"]], ids=["serial", "xdist"])
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_nothing_outlives_an_interrupted_pytest(project, workers, sig):
    project.test(HANGING_TEST)
    proc = _start_pytest(project, *workers)
    try:
        target, server = _wait_for_target(project, proc)
        runner = _parent(server)
        assert runner != os.getpid() and alive(runner)
        # SIGINT: Ctrl-C, the terminal signals the whole foreground group; SIGTERM: a CI job's
        # runner stopping the job's process group
        os.killpg(proc.pid, sig)
        proc.wait(60)
        assert wait_gone([target, server]) == []
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


@pytest.mark.parametrize("workers", [[], ["-n", "2"]], ids=["serial", "xdist"])
def test_nothing_outlives_pytest_terminated_alone(project, workers):
    """SIGTERM to the pytest process only (not its group): its xdist workers, their servers and
    the targets end with it."""
    project.test(HANGING_TEST)
    proc = _start_pytest(project, *workers)
    try:
        target, server = _wait_for_target(project, proc)
        runner = _parent(server)
        proc.send_signal(signal.SIGTERM)
        proc.wait(60)
        assert wait_gone([target, server, runner]) == []
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def test_nothing_outlives_a_killed_xdist_worker(project):
    project.test(HANGING_TEST)
    proc = _start_pytest(project, "-n", "2")
    try:
        target, server = _wait_for_target(project, proc)
        worker = _parent(server)
        assert worker != proc.pid
        os.kill(worker, signal.SIGKILL)
        assert wait_gone([target, server]) == []
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


TWO_HANGING_TESTS = f"""
import pytest

@pytest.mark.parametrize("name", ["one", "two"])
def test_hangs(rmw_capture, name):
    rmw_capture(script={str(WARM_NODES / 'warm_pid.py')!r}, timeout=120,
                env={{"WARM_PID_FILE": "pids.txt", "WARM_HANG": "1", "WARM_NODE_NAME": name}})
"""


def test_a_killed_xdist_worker_takes_its_targets_not_the_shared_server(project):
    """Two workers, one shared server: killing the worker that did not start it ends its own
    target only; the rest ends with pytest."""
    project.test(TWO_HANGING_TESTS)
    proc = _start_pytest(project, "-n", "2")
    try:
        pids = project.path / "pids.txt"
        deadline = time.monotonic() + 120
        while not (pids.exists() and len(pids.read_text().splitlines()) >= 2):
            assert time.monotonic() < deadline and proc.poll() is None, proc.communicate()[0].decode(errors="replace")
            time.sleep(0.05)
        lines = pids.read_text().splitlines()[:2]
        (target_a, server_a), (target_b, server_b) = ([int(p) for p in line.split()[:2]] for line in lines)
        assert server_a == server_b  # both workers' targets were forked by one server
        owner = _parent(server_a)
        workers = {pid for pid in _children(proc.pid) if pid != owner}
        assert len(workers) == 1, workers
        (other,) = workers
        os.kill(other, signal.SIGKILL)
        deadline = time.monotonic() + 10
        while alive(target_a) and alive(target_b) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert [alive(target_a), alive(target_b)].count(True) == 1  # the killed worker's target only
        assert alive(server_a) and alive(owner)
        proc.send_signal(signal.SIGTERM)
        proc.wait(60)
        assert wait_gone([target_a, target_b, server_a, owner]) == []
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def _children(pid: int) -> list[int]:
    with open(f"/proc/{pid}/task/{pid}/children", encoding="ascii") as f:
        return [int(p) for p in f.read().split()]
