"""Warm starts: Python targets forked from a server that has imported rclpy already.

Starting Python, importing rclpy and creating the first ``rclpy.node.Node`` (which imports numpy
and the parameter and type-description service types) is most of a capture's time, and the same
for every target. A warm start server (:mod:`.server`) pays it once per interpreter and
import-relevant environment: the runner asks it to fork a child per capture, and the child becomes
the target (see the server's module for what the child sets up). This module is the runner's side:

* :mod:`.plan` decides whether a command can start warm (:func:`.plan.plan`) and which server
  it needs (:func:`.plan.server_key`): nothing there starts a process;
* :class:`Pool` keeps the servers of this process (a pytest session, an xdist worker, one CLI run),
  started in the background: a capture that finds its server still starting runs cold; runners
  given the same scope (:meth:`Pool.share_within`: the xdist workers of a run) share them, the
  first one starting a server and the others attaching to it;
* :class:`WarmChild` is the forked target as the runner sees it: it behaves like the
  ``subprocess.Popen`` of a cold start (pid = process group, ``poll``, ``wait``, ``send_signal``), so
  timeouts and the SIGINT → SIGTERM → SIGKILL escalation of :mod:`.process` apply unchanged.

No process is left behind: a server has the parent-death signal SIGKILL tied to the runner, its
children have it tied to the server, and a server exits (killing its children's groups) as soon as
its control socket closes: at :func:`shutdown`, at the end of the runner process, or when it dies.
A shared server exits once its owner and every attached runner closed their sockets (the owner
waits for that at its shutdown); a runner that goes away takes its own children with it.
"""

from __future__ import annotations

import atexit
import functools
import hashlib
import io
import json
import os
import queue
import select
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import IO, Any

from ...errors import WarmStartFailed
from .. import process
from .plan import Plan, server_environment, server_key

#: at most this many servers per process, counting those still ending: a target whose environment
#: needs another one starts cold, unless the least recently used server has been idle for
#: IDLE_BEFORE_EVICTION seconds (it is then ended first, and the new one started)
MAX_SERVERS = 4
#: seconds a server must have gone unused before a server for another environment replaces it:
#: targets that cycle over more environments than MAX_SERVERS would otherwise start a server for
#: nearly every capture (23 for 36 captures over six PYTHONPATH variants), each costing more than
#: the cold start it saves
IDLE_BEFORE_EVICTION = 10.0
#: a server that ended this often (killed, or by a target) is not started again for its key
MAX_DEATHS = 3
#: seconds a server may take to import everything and say it is ready
READY_TIMEOUT = 60.0
#: seconds a capture waits for a server that is still starting (it usually is ready in ~0.3 s,
#: less than a cold start takes) before it starts its target cold instead
DEFAULT_WAIT = 3.0
#: what :meth:`ServerPool.server` answers while the server is not ready yet
STILL_STARTING = "the warm start server is still starting"
#: seconds the server may take to answer a spawn request with the child's pid
SPAWN_TIMEOUT = 10.0
#: seconds a server may take to report the end of a child that ended (it does at once: longer means
#: it is stopped or hung, and the target runs again cold)
REPORT_WAIT = 5.0
#: seconds the owner of a shared server waits, at its end, for the runners still attached to it
#: to finish their captures (each is bounded by its own target's timeout); then it ends the server
#: (their targets die with it, and they run them again cold)
SERVE_OTHERS_WAIT = 300.0
_BOOTSTRAP = (
    "import sys\n"
    "sys.path.insert(0, {package_parent!r})\n"
    "from pytest_rmw_introspect.run.warm import server as warm_server\n"
    "del sys.path[0]\n"
    "_job = warm_server.main(*map(int, sys.argv[1:3]))\n"
    "if _job is None:\n"
    "    warm_server.exit_server()\n"
    "warm_server.run(_job)\n"
)
_PACKAGE_PARENT = str(Path(__file__).resolve().parents[3])  # the directory holding pytest_rmw_introspect/


def server_command(fd: int, python: str | None = None, listen_fd: int | None = None) -> list[str]:
    command = [python or sys.executable, "-c", _BOOTSTRAP.format(package_parent=_PACKAGE_PARENT), str(fd)]
    return command if listen_fd is None else [*command, str(listen_fd)]


def shared_address(scope: str, key: tuple[Any, ...]) -> bytes:
    """The Unix socket address (abstract namespace) of the shared server for ``key`` in ``scope``."""
    digest = hashlib.sha256(repr(key).encode()).hexdigest()[:24]
    return f"\0rmw-introspect-warm/{os.getuid()}/{scope}/{digest}".encode()[:107]


def _connect(address: bytes) -> socket.socket | None:
    """A connection to the shared server at ``address`` (run by this user), or None."""
    from .server import peer_uid  # only runners that share servers need it

    sock = socket.socket(socket.AF_UNIX, socket.SOCK_SEQPACKET)
    try:
        sock.connect(address)
    except OSError:
        sock.close()
        return None
    if peer_uid(sock) != os.getuid():
        sock.close()
        return None
    return sock


def _bind(address: bytes) -> socket.socket | None:
    """A listening socket bound to ``address``, or None when another runner holds it."""
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_SEQPACKET)
    try:
        sock.bind(address)
        sock.listen(64)
    except OSError:
        sock.close()
        return None
    return sock


def _umask() -> int:
    try:
        with open("/proc/self/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


# ---------------------------------------------------------------------------------- the child


class WarmChild:
    """A target forked by a server, with the parts of ``subprocess.Popen`` the runner uses."""

    def __init__(self, pid: int, reply: socket.socket, args: Sequence[str],
                 stdout: IO[bytes], stderr: IO[bytes], on_release: Callable[[], None] | None = None,
                 on_silence: Callable[[], None] | None = None) -> None:
        self.pid = pid
        self._on_release = on_release  # told once, when the runner is done with the child
        self._on_silence = on_silence  # told when the server did not report the child's end
        self.args = list(args)
        self.stdout: IO[bytes] = stdout
        self.stderr: IO[bytes] = stderr
        self.returncode: int | None = None
        #: the server died while the child ran (the child died with it), or did not report the
        #: child's end (``server_silent``): start the target cold
        self.server_lost = False
        self.server_silent = False
        self._reply: socket.socket | None = reply
        self._lock = threading.Lock()
        try:  # readable when the child ends: a server that stopped answering cannot hide that
            self._pidfd: int | None = os.pidfd_open(pid)
        except (AttributeError, OSError):
            self._pidfd = None

    def _receive(self, timeout: float | None) -> None:
        with self._lock:
            if self.returncode is not None or self._reply is None:
                return
            watched: list[Any] = [self._reply] if self._pidfd is None else [self._reply, self._pidfd]
            ready, _, _ = select.select(watched, [], [], timeout)
            if not ready:
                return
            if self._reply not in ready:  # the child ended: its server reports that at once ...
                ready, _, _ = select.select([self._reply], [], [], REPORT_WAIT)
                if not ready:  # ... unless it is stopped or hung: the capture runs again, cold
                    self.server_lost = self.server_silent = True
                    self.returncode = -signal.SIGKILL
                    if self._on_silence is not None:
                        self._on_silence()
                    return
            try:
                data = self._reply.recv(65536)
            except OSError:
                data = b""
            if not data:
                self.server_lost = True
                self.returncode = -signal.SIGKILL
                return
            try:
                message = json.loads(data)
                self.returncode = int(message["returncode"])
            except (ValueError, KeyError, TypeError):
                self.server_lost = True
                self.returncode = -signal.SIGKILL

    def poll(self) -> int | None:
        self._receive(0)
        return self.returncode

    def wait(self, timeout: float | None = None) -> int:
        deadline = None if timeout is None else time.monotonic() + timeout
        while self.returncode is None:
            remaining = None if deadline is None else deadline - time.monotonic()
            if remaining is not None and remaining <= 0:
                raise subprocess.TimeoutExpired(self.args, timeout or 0.0)
            self._receive(remaining)
        return self.returncode

    def send_signal(self, sig: int) -> None:
        # the server reaps the child only after release(): until then its pid cannot be reused
        if self.poll() is None:
            try:
                os.kill(self.pid, sig)
            except ProcessLookupError:
                pass

    def kill(self) -> None:
        self.send_signal(signal.SIGKILL)

    def terminate(self) -> None:
        self.send_signal(signal.SIGTERM)

    def server_stopped_answering(self) -> None:
        """The server did not report this child's end within seconds of its SIGKILL (the server is
        stopped, or hangs): no later target starts on that server."""
        if self._on_silence is not None:
            self._on_silence()

    def release(self) -> None:
        """The runner is done with the child (and its group): the server may reap it (or, if it
        still runs, kills its group)."""
        with self._lock:
            if self._reply is not None:
                self._reply.close()
                self._reply = None
            if self._pidfd is not None:
                os.close(self._pidfd)
                self._pidfd = None
            on_release, self._on_release = self._on_release, None
        if on_release is not None:
            on_release()


# ---------------------------------------------------------------------------------- the server


class _Launcher:
    """Starts server processes from a thread that lives as long as this process. A server's
    parent-death signal fires when the *thread* that forked it ends: a server started by a
    capture running in a short-lived thread (a contract item capturing ahead, a system capture's
    thread pool) would die with that thread. The main thread starts servers itself; any other
    thread hands the start to this launcher's daemon thread (which ends only with the process)."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._jobs: queue.SimpleQueue[tuple[Callable[[], Any], queue.SimpleQueue[tuple[bool, Any]]]] | None = None

    def call(self, job: Callable[[], Any]) -> Any:
        if threading.current_thread() is threading.main_thread():
            return job()
        with self._lock:
            if self._jobs is None:
                self._jobs = queue.SimpleQueue()
                threading.Thread(target=self._serve, args=(self._jobs,), name="rmw-introspect warm launcher",
                                 daemon=True).start()
            jobs = self._jobs
        answer: queue.SimpleQueue[tuple[bool, Any]] = queue.SimpleQueue()
        jobs.put((job, answer))
        try:
            ok, value = answer.get(timeout=READY_TIMEOUT)  # a fork and exec: milliseconds
        except queue.Empty:
            raise WarmStartFailed(f"the warm start launcher thread did not start a server within {READY_TIMEOUT:g} s") from None
        if not ok:
            raise value
        return value

    @staticmethod
    def _serve(jobs: queue.SimpleQueue[tuple[Callable[[], Any], queue.SimpleQueue[tuple[bool, Any]]]]) -> None:
        while True:
            job, answer = jobs.get()
            try:
                answer.put((True, job()))
            except BaseException as exc:  # noqa: BLE001  # raised again in the calling thread
                answer.put((False, exc))


_LAUNCHER = _Launcher()


class WarmServer:
    """One server process and its control socket, seen from the runner: a server this runner
    started (its owner), or one it is attached to (a shared server another runner started)."""

    proc: subprocess.Popen[bytes] | None  # None: attached to another runner's server
    log: IO[bytes]

    def __init__(self, env: Mapping[str, str], cwd: str, python: str | None = None, *,
                 listener: socket.socket | None = None) -> None:
        """Start a server; ``listener``: a bound, listening socket that makes it a shared one."""
        mine, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        self._init(mine, python, tempfile.TemporaryFile(prefix="rmw_introspect_warm_"))
        fds = (theirs.fileno(),) if listener is None else (theirs.fileno(), listener.fileno())
        try:
            self.proc = _LAUNCHER.call(functools.partial(
                process.Process,
                server_command(theirs.fileno(), self.python, None if listener is None else listener.fileno()),
                env=dict(env), cwd=cwd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=self.log,
                pass_fds=fds, start_new_session=True,
                preexec_fn=functools.partial(process.die_with_parent, os.getpid()),
            ))
        except (OSError, WarmStartFailed) as exc:
            self.control.close()
            self.log.close()
            raise WarmStartFailed(f"cannot start a warm start server: {exc}") from None
        finally:
            theirs.close()

    @classmethod
    def attached(cls, sock: socket.socket, python: str | None = None) -> WarmServer:
        """The shared server at the other end of ``sock`` (a connection to its listening socket)."""
        server = cls.__new__(cls)
        server._init(sock, python, io.BytesIO())  # its stderr is its owner's to keep
        return server

    def _init(self, control: socket.socket, python: str | None, log: IO[bytes]) -> None:
        self.python = python or sys.executable
        self.started_at = time.monotonic()
        self.control = control
        self.proc = None
        self.log = log  # the server's stderr
        self._lock = threading.Lock()
        self.info: dict[str, Any] | None = None
        self.failure: str | None = None
        #: why a ready server is given up (it stopped answering: SIGSTOP, a hang); the pool ends
        #: it and counts it as a death (a failure to start instead breaks its key for good)
        self.unresponsive: str | None = None
        self._told: set[str] = set()  # the type names sent to learn()
        self._told_lock = threading.Lock()  # not _lock: wait_ready holds that while it waits
        #: children of this runner the server runs now, and when it was last asked for (the pool's)
        self.running = 0
        self.last_used = time.monotonic()

    @property
    def pid(self) -> int:
        if self.proc is not None:
            return self.proc.pid
        return int((self.info or {}).get("pid", -1))

    def log_tail(self, limit: int = 2000) -> str:
        try:
            self.log.seek(0)
            return self.log.read().decode("utf-8", "replace")[-limit:]
        except (OSError, ValueError):
            return ""

    def wait_ready(self, timeout: float | None) -> bool:
        """Whether the server is ready (waiting up to ``timeout`` seconds for it; 0: just look)."""
        with self._lock:
            if self.info is not None:
                return True
            if self.failure is not None:
                return False
            deadline = None if timeout is None else time.monotonic() + timeout
            while True:
                remaining = None if deadline is None else max(0.0, deadline - time.monotonic())
                ready, _, _ = select.select([self.control], [], [], remaining)
                if ready:
                    break
                if remaining == 0.0 or (deadline is not None and time.monotonic() >= deadline):
                    if time.monotonic() - self.started_at > READY_TIMEOUT:
                        self.failure = f"the warm start server was not ready after {READY_TIMEOUT:g} s"
                    return False
            try:
                data = self.control.recv(65536)
                info = json.loads(data) if data else None
            except (OSError, ValueError):
                info = None
            if not isinstance(info, dict) or not info.get("ready"):
                status = self.proc.poll() if self.proc is not None else None
                self.failure = ("the warm start server ended before it was ready"
                                + (f" (status {status})" if status is not None else "")
                                + (": " + self.log_tail().strip() if self.log_tail().strip() else ""))
                return False
            self.info = info
            return True

    def alive(self) -> bool:
        if self.failure is not None or self.unresponsive is not None:
            return False
        if self.proc is not None:
            return self.proc.poll() is None
        if self.info is None:
            return True  # its ready message (or its end) is wait_ready's to read
        # attached: the server sends nothing after its ready message, so a readable socket is its end
        try:
            readable, _, _ = select.select([self.control], [], [], 0)
        except (OSError, ValueError):
            return False
        return not readable

    def spawn(self, plan: Plan, *, env: Mapping[str, str], cwd: str) -> WarmChild:
        """Fork the target; raises :class:`WarmStartFailed` (the runner then starts it cold)."""
        mine, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        out_r, out_w = os.pipe()
        err_r, err_w = os.pipe()
        stdin = os.open(os.devnull, os.O_RDONLY | os.O_CLOEXEC)
        request = {
            "op": "spawn", "kind": plan.kind, "target": plan.target, "argv": list(plan.argv),
            "orig_argv": list(plan.orig_argv), "executable": plan.executable,
            "env": dict(env), "cwd": cwd, "umask": _umask(),
        }
        try:
            try:
                # never blocks: a stopped or hung server stops reading, and its socket fills up
                socket.send_fds(self.control, [json.dumps(request).encode()],
                                [theirs.fileno(), stdin, out_w, err_w], socket.MSG_DONTWAIT)
            except BlockingIOError:
                raise WarmStartFailed(f"the warm start server (pid {self.pid}, {process.process_state(self.pid)}) "
                                      "does not read its requests") from None
            except OSError as exc:
                raise WarmStartFailed(f"the warm start server is gone ({exc})") from None
            finally:
                for fd in (stdin, out_w, err_w):
                    os.close(fd)
                theirs.close()
            ready, _, _ = select.select([mine], [], [], SPAWN_TIMEOUT)
            data = mine.recv(65536) if ready else b""
            try:
                answer = json.loads(data) if data else {}
            except ValueError:
                answer = {}
            if not ready:  # stopped or hung: no later target is sent to it (the pool ends it)
                self.unresponsive = (f"the warm start server (pid {self.pid}, {process.process_state(self.pid)}) did "
                                     f"not answer a request to start a target within {SPAWN_TIMEOUT:g} s")
                raise WarmStartFailed(self.unresponsive)
            if "pid" not in answer:
                raise WarmStartFailed(answer.get("error") or "the warm start server did not start the target")
        except BaseException:
            mine.close()
            os.close(out_r)
            os.close(err_r)
            raise
        with self._told_lock:
            self.running += 1
        return WarmChild(int(answer["pid"]), mine, [*plan.orig_argv],
                         os.fdopen(out_r, "rb", buffering=0), os.fdopen(err_r, "rb", buffering=0),
                         on_release=self._child_released, on_silence=self._stopped_answering)

    def _stopped_answering(self) -> None:
        self.unresponsive = (f"the warm start server (pid {self.pid}, {process.process_state(self.pid)}) stopped "
                        "answering: it did not report the end of a target it had forked")

    def _child_released(self) -> None:
        with self._told_lock:
            self.running -= 1
        self.last_used = time.monotonic()

    def idle_for(self) -> float:
        """Seconds since it was last used (0 while it runs a child of this runner)."""
        with self._told_lock:
            return 0.0 if self.running else time.monotonic() - self.last_used

    def ended(self) -> bool:
        """Whether a server this runner let go of is gone (an attached one is, once let go of)."""
        return self.proc is None or self.proc.poll() is not None

    def learn(self, type_names: Sequence[str]) -> None:
        """Ask the server to import these types' packages (and type supports) for later targets
        (only those it was not told of before: most captures use no new type)."""
        with self._told_lock:
            new = sorted(set(type_names) - self._told)
            self._told.update(new)
        if not new or not self.alive():
            return
        try:  # a hint: dropped rather than waited for when the server does not read (stopped, hung)
            self.control.send(json.dumps({"op": "preload", "types": new}).encode(), socket.MSG_DONTWAIT)
        except OSError:
            pass

    def close(self, timeout: float = 2.0) -> None:
        """Let go of the server (:meth:`begin_close`, then :meth:`finish_close`)."""
        self.begin_close()
        self.finish_close(timeout)

    def begin_close(self) -> None:
        """An attached runner closes its connection (the server ends that runner's children).
        The owner half-closes its control socket: the server kills what it still runs for the
        owner and exits, or, shared, goes on serving the runners still connected (they may have
        captures to go) and says how many there are. Never blocks: runners that own one shared
        server and are attached to another's begin closing all before waiting for any."""
        if self.proc is None:
            self.control.close()
            return
        try:
            self.control.shutdown(socket.SHUT_WR)
        except OSError:
            pass

    def finish_close(self, timeout: float = 2.0) -> None:
        """The owner waits for the server to end (as long as it reports runners still connected)
        and kills one that neither exits nor answers within ``timeout`` seconds."""
        try:
            if self.proc is not None:
                self._wait_for_exit(self.proc, timeout)
        finally:
            self.control.close()
            self.log.close()

    def _wait_for_exit(self, proc: subprocess.Popen[bytes], timeout: float) -> None:
        """Wait on the control socket (the server's reports, then its end) rather than polling
        the process: the owner is done the moment the server is."""
        serving = False  # the server said runners are still connected
        deadline = time.monotonic() + timeout
        serving_until = time.monotonic() + SERVE_OTHERS_WAIT
        while True:
            remaining = max(0.0, serving_until - time.monotonic()) if serving else deadline - time.monotonic()
            if remaining is not None and remaining <= 0:
                break  # neither exited nor answered: stuck
            try:
                readable, _, _ = select.select([self.control], [], [], remaining)
            except (OSError, ValueError):
                break
            if not readable:
                continue
            clients, ended = self._reports()
            if ended:
                try:
                    proc.wait(timeout)
                    return
                except subprocess.TimeoutExpired:
                    break
            if clients is not None:
                serving = clients > 0
                deadline = time.monotonic() + timeout
                serving_until = time.monotonic() + SERVE_OTHERS_WAIT
            if serving and time.monotonic() >= serving_until:
                break  # runners attached for longer than any capture of theirs can take: stuck
        proc.kill()
        try:
            proc.wait(process.KILL_WAIT)
        except subprocess.TimeoutExpired:
            pass  # not reaped yet (a zombie of ours until this process ends); nothing is waited for

    def _reports(self) -> tuple[int | None, bool]:
        """The last number of connected runners the server reported since the last call (None:
        no report), and whether its end of the control socket is closed."""
        clients = None
        while True:
            try:
                data = self.control.recv(65536, socket.MSG_DONTWAIT)
            except (BlockingIOError, InterruptedError):
                return clients, False
            except OSError:
                return clients, True
            if not data:
                return clients, True
            try:
                message = json.loads(data)
            except ValueError:
                continue
            if isinstance(message, dict) and isinstance(message.get("clients"), int):
                clients = message["clients"]


# ---------------------------------------------------------------------------------- the pool


class Pool:
    """The warm start servers of this process, by :func:`server_key`."""

    def __init__(self) -> None:
        self._servers: dict[tuple[Any, ...], WarmServer] = {}
        self._broken: dict[tuple[Any, ...], str] = {}
        self._closing: list[WarmServer] = []  # let go of, not waited for yet (see close)
        self._deaths: dict[tuple[Any, ...], int] = {}
        self._lock = threading.Lock()
        self._owner = os.getpid()
        #: why this process starts every target cold (None: Python targets start warm)
        self.disabled: str | None = None
        #: runners with the same scope share their servers (None: this process's own servers)
        self.scope: str | None = None

    def share_within(self, scope: str | None) -> None:
        """Share servers with the other runners (processes of this user) that give the same
        ``scope``: the first one that needs a server for a key starts it, the others attach to it
        (pytest-xdist workers of one run: one server instead of one per worker)."""
        self.scope = scope or None

    def disable(self, reason: str) -> None:
        """Start every target of this process cold, for ``reason`` (a run with one capture: a
        server only pays off from the second)."""
        self.disabled = reason

    def server(self, env: Mapping[str, str], cwd: str, python: str | None = None, *,
               wait: float = 0.0) -> WarmServer | str:
        """The ready server for targets with environment ``env``, or why there is none (yet):
        a server not started yet is started in the background and this capture runs cold, unless
        ``wait`` gives it that many seconds to become ready."""
        key = server_key(env, cwd, python)
        with self._lock:
            if self.disabled is not None:
                return self.disabled
            if os.getpid() != self._owner:  # a forked copy of the runner: its parent owns the servers
                return "the runner process was forked"
            broken = self._broken.get(key)
            if broken is not None:
                return broken
            server = self._servers.pop(key, None)
            if server is not None and not server.alive():
                self._deaths[key] = self._deaths.get(key, 0) + 1
                if server.failure is not None:
                    self._broken[key] = server.failure
                elif self._deaths[key] >= MAX_DEATHS:
                    self._broken[key] = f"the warm start server ended {self._deaths[key]} times"
                server.close(0.5)
                server = None
                if key in self._broken:
                    return self._broken[key]
            if server is None:
                full = self._make_room()
                if full is not None:
                    return full
                try:
                    server = self._start_or_attach(key, env, cwd, python)
                except WarmStartFailed as exc:
                    self._broken[key] = str(exc)
                    return str(exc)
            server.last_used = time.monotonic()
            self._servers[key] = server  # most recently used last
        if server.wait_ready(wait):
            return server
        if server.failure is not None:
            with self._lock:
                self._broken[key] = server.failure
                if self._servers.get(key) is server:
                    del self._servers[key]
            server.close(0.5)
            return server.failure
        return STILL_STARTING

    def _make_room(self) -> str | None:
        """Room for one more server (called with the lock held): None when there is, after ending
        the least recently used one if it has been idle long enough, else why the target starts
        cold. Servers let go of count until they are gone, so no more than MAX_SERVERS ever run."""
        for server in [s for s in self._closing if s.ended()]:
            self._closing.remove(server)
            server.finish_close(0.0)
        if len(self._servers) + len(self._closing) < MAX_SERVERS:
            return None
        if self._servers:
            key, oldest = next(iter(self._servers.items()))
            if oldest.idle_for() >= IDLE_BEFORE_EVICTION:
                del self._servers[key]
                oldest.begin_close()
                if oldest.proc is not None and oldest.proc.poll() is None and self.scope is None:
                    oldest.finish_close()  # it runs nothing of ours: it ends at once
                else:
                    self._closing.append(oldest)  # shared: it may still serve other runners
                return self._make_room()
        return (f"{MAX_SERVERS} warm start servers for other environments are in use (the most a runner keeps, "
                "warm.MAX_SERVERS)")

    def _start_or_attach(self, key: tuple[Any, ...], env: Mapping[str, str], cwd: str,
                         python: str | None) -> WarmServer:
        if self.scope is not None:
            address = shared_address(self.scope, key)
            for _attempt in range(5):
                sock = _connect(address)
                if sock is not None:
                    return WarmServer.attached(sock, python)
                listener = _bind(address)
                if listener is not None:
                    try:
                        return WarmServer(server_environment(env), cwd, python, listener=listener)
                    finally:
                        listener.close()  # the server has its own copy
                time.sleep(0.01)  # another runner bound it and is about to listen
        return WarmServer(server_environment(env), cwd, python)

    def learn(self, env: Mapping[str, str], cwd: str, type_names: Sequence[str], python: str | None = None) -> None:
        """Tell the server for targets with environment ``env`` (if there is one, started or
        starting) the message types a target used: it imports their packages for the next ones."""
        with self._lock:
            server = self._servers.get(server_key(env, cwd, python))
        if server is not None:
            server.learn(type_names)

    def servers(self) -> list[WarmServer]:
        with self._lock:
            return list(self._servers.values())

    def close(self) -> None:
        """End every server of this process (and what they still run): let go of all of them
        first, then wait for those it owns (runners that each own a shared server and are
        attached to the other's never wait for each other)."""
        with self._lock:
            servers = [*self._servers.values(), *self._closing] if os.getpid() == self._owner else []
            self._servers.clear()
            self._closing.clear()
            self._broken.clear()
            self._deaths.clear()
        for server in servers:
            server.begin_close()
        for server in servers:
            server.finish_close()


POOL = Pool()


def shutdown() -> None:
    """End this process's warm start servers (also done at interpreter exit)."""
    POOL.close()


atexit.register(shutdown)
