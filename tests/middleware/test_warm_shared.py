"""Warm start servers shared by the runners of one scope (pytest-xdist workers of one run,
issue 12): the first runner that needs a server starts it, the others attach to it; each runner's
children are its own; the server outlives its owner's shutdown as long as runners are attached,
and never outlives them all."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
import uuid
from pathlib import Path

import pytest
import warm_helpers as w
from rmwi_processes import alive, wait_gone

from pytest_rmw_introspect.run import ros_env
from pytest_rmw_introspect.run.resolution import environment
from pytest_rmw_introspect.run.target import TargetSpec
from pytest_rmw_introspect.run.warm import client as warm
from pytest_rmw_introspect.run.warm import plan as warm_plan

TALKER = str(w.NODES / "talker.py")

# A runner process: shares servers within SCOPE, then reads commands from stdin, one per line:
# "capture SCRIPT [ENV_JSON]" prints {"started", "server", "owner", "pid"}; "quit" shuts down.
_RUNNER = """
import json, sys
from pytest_rmw_introspect.run import runner
from pytest_rmw_introspect.run.warm import client as warm
from pytest_rmw_introspect.run.target import TargetSpec
warm.POOL.share_within(sys.argv[1])
for line in sys.stdin:
    words = line.split(maxsplit=2)
    if words[0] == "quit":
        break
    env = json.loads(words[2]) if len(words) > 2 else {}
    cap = runner.run(TargetSpec.from_mapping({"script": words[1], "env": env, "timeout": 60}), warm_wait=60.0)
    server = warm.POOL.servers()[-1]  # the one this capture used: the most recently used is last
    print(json.dumps({"started": cap.started, "note": cap.start_note, "server": server.pid,
                      "owner": server.proc is not None, "pid": cap.pid}), flush=True)
warm.shutdown()
"""


class Runner:
    def __init__(self, scope: str) -> None:
        self.proc = subprocess.Popen([sys.executable, "-c", _RUNNER, scope], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def send(self, line: str) -> None:
        assert self.proc.stdin is not None
        self.proc.stdin.write(line + "\n")
        self.proc.stdin.flush()

    def capture(self, script: str = TALKER, env: dict | None = None) -> dict:
        self.send(f"capture {script} {json.dumps(env or {})}")
        assert self.proc.stdout is not None
        line = self.proc.stdout.readline()
        assert line, self.proc.communicate()
        return json.loads(line)

    def quit(self) -> None:
        self.send("quit")

    def end(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
        self.proc.communicate()


def _first_pid(pids: Path) -> int:
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        if pids.exists() and pids.read_text().strip():
            return int(pids.read_text().split()[0])
        time.sleep(0.05)
    raise AssertionError("the target never started")


@pytest.fixture
def runners():
    made: list[Runner] = []
    scope = uuid.uuid4().hex

    def make() -> Runner:
        made.append(Runner(scope))
        return made[-1]

    yield make
    for runner_ in made:
        runner_.end()


def test_runners_of_one_scope_share_one_server(runners):
    first, second = runners(), runners()
    a = first.capture()
    b = second.capture()
    assert (a["started"], b["started"]) == ("warm", "warm")
    assert a["server"] == b["server"]
    assert sorted([a["owner"], b["owner"]]) == [False, True]  # one started it, the other attached
    assert a["pid"] != b["pid"]


def test_runners_of_other_scopes_have_servers_of_their_own(runners):
    ours = runners().capture()
    theirs = Runner(uuid.uuid4().hex)
    try:
        other = theirs.capture()
    finally:
        theirs.end()
    assert other["server"] != ours["server"] and other["owner"] and ours["owner"]


def test_the_owner_waits_for_the_attached_runners_before_the_server_ends(runners):
    owner = runners()
    server = owner.capture()["server"]
    attached = runners()
    assert attached.capture()["server"] == server
    owner.quit()
    with pytest.raises(subprocess.TimeoutExpired):
        owner.proc.wait(1.0)  # it waits: a runner is still attached
    again = attached.capture()  # still served by the same server
    assert (again["started"], again["server"]) == ("warm", server)
    attached.quit()
    assert attached.proc.wait(10) == 0 and owner.proc.wait(10) == 0
    assert wait_gone([server], 5.0) == []


def test_runners_that_own_a_server_each_and_use_the_other_s_end_together(runners):
    """Each runner owns the server of one environment and is attached to the other's: at their
    end each lets go of the other's before waiting for its own (no runner waits for the other)."""
    first, second = runners(), runners()
    other_env = {"LC_RMWI_TEST": "the second environment"}  # LC_*: a server key of its own
    own_first = first.capture()
    own_second = second.capture(env=other_env)
    assert own_first["owner"] and own_second["owner"]
    assert first.capture(env=other_env)["server"] == own_second["server"]
    assert second.capture()["server"] == own_first["server"]
    first.quit()
    second.quit()
    assert first.proc.wait(30) == 0 and second.proc.wait(30) == 0
    assert wait_gone([own_first["server"], own_second["server"]], 5.0) == []


def test_an_attached_runner_that_is_killed_takes_only_its_own_children(runners, tmp_path):
    owner = runners()
    server = owner.capture()["server"]
    attached = runners()
    pids = tmp_path / "pids.txt"
    attached.send(f"capture {w.WARM_NODES / 'warm_pid.py'} "
                  + json.dumps({"WARM_PID_FILE": str(pids), "WARM_HANG": "1"}))
    target = _first_pid(pids)  # the hanging target, forked by the shared server
    assert alive(target)
    attached.proc.send_signal(signal.SIGKILL)
    attached.proc.wait(10)
    assert wait_gone([target], 10.0) == []
    assert alive(server)
    after = owner.capture()
    assert (after["started"], after["server"]) == ("warm", server)


def test_when_the_owner_dies_an_attached_runner_starts_a_server_of_its_own(runners):
    owner, attached = runners(), runners()
    server = owner.capture()["server"]
    assert attached.capture()["server"] == server
    owner.proc.send_signal(signal.SIGKILL)
    owner.proc.wait(10)
    assert wait_gone([server], 10.0) == []  # it was tied to its owner
    # a capture that meets the server while its last threads exit starts cold (and succeeds)
    first = attached.capture()
    assert first["started"] == "warm" or first["note"].startswith("the warm start server"), first
    after = attached.capture()
    assert after["started"] == "warm", after
    assert after["owner"] and after["server"] != server


@pytest.mark.skipif(os.getuid() != 0, reason="needs to run a process as another user")
def test_a_runner_of_another_user_is_refused(runners, middleware_library):
    owner = runners()
    owner.capture()
    scope = owner.proc.args[-1]
    env = environment(TargetSpec.from_mapping({"script": TALKER}), middleware_library,
                             ros_env.detect(), Path("/unused"))
    address = warm.shared_address(scope, warm_plan.server_key(env, os.getcwd()))
    read_end, write_end = os.pipe()
    pid = os.fork()
    if pid == 0:  # as user nobody: connect, and report what the server says
        try:
            os.setgid(65534)
            os.setuid(65534)
            sock = socket.socket(socket.AF_UNIX, socket.SOCK_SEQPACKET)
            sock.connect(address)
            sock.settimeout(10)
            os.write(write_end, b"said: " + sock.recv(65536))
        except BaseException as exc:  # noqa: BLE001
            os.write(write_end, repr(exc).encode())
        finally:
            os._exit(0)
    os.close(write_end)
    os.waitpid(pid, 0)
    with os.fdopen(read_end, "rb") as said:
        assert said.read() == b"said: "  # connected, then closed without a word
