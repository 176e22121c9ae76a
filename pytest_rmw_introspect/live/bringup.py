"""A system brought up for real: every process a launch file starts, on the real middleware
(Fast DDS with the wheels), in a ROS_DOMAIN_ID of its own with localhost discovery, stopped
after. What the ``live_system`` fixture and the live tests run, so that a live check has a
running system to read.

The processes are the ones a system capture starts (``run.system_capture.process_spec``: the
launch file's command lines, parameters, parameters files, remappings and environment), with the
recording middleware's activation taken out of their environment. A component container
starts without its components (loading them is a service call of ``ros2 launch`` that needs
launch_ros; a capture hands them to the container's middleware instead): a launch file with
containers is refused.

Domains are handed out by :func:`reserve_domain`: a lock file per id under the temporary
directory, held while the system runs, so that two xdist workers, two sessions or two users on
one machine never share a domain.
"""

from __future__ import annotations

import contextlib
import fcntl
import os
import shutil
import signal
import subprocess
import tempfile
import time
from collections.abc import Collection, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any

from ..errors import LiveGraphError
from ..launch import reader as launch_reader
from ..launch.result import LaunchedNode
from ..run import resolution, ros_env, system_capture
from ..run.target import TargetSpec
from .graph import LiveGraph, LiveSettings, read_graph, without_recording

#: the domain ids handed out (ROS 2 documents 0-101 as safe on Linux; the overlay tier's tests
#: use 57 and 60-99 with hashes of their own)
DOMAINS = range(1, 57)
#: what the processes are started with in place of the recording middleware's library (its
#: activation is taken out again: ``without_recording``)
_NO_LIBRARY = Path("/nonexistent/librmw_introspect_cpp.so")


@dataclass
class Domain:
    """A reserved ROS_DOMAIN_ID: held until :meth:`release`."""

    id: int
    _lock: IO[str] | None = None

    def release(self) -> None:
        if self._lock is not None:
            self._lock.close()
            self._lock = None


def reserve_domain(candidates: range = DOMAINS) -> Domain:
    """The first domain id of ``candidates`` no other process of this machine holds."""
    directory = Path(tempfile.gettempdir()) / f"rmw_introspect_live_domains_{os.getuid()}"
    directory.mkdir(mode=0o700, exist_ok=True)
    for domain in candidates:
        handle = open(directory / f"{domain}.lock", "a", encoding="utf-8")  # noqa: SIM115 (held while reserved)
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            handle.close()
            continue
        return Domain(domain, handle)
    raise LiveGraphError(f"every ROS_DOMAIN_ID from {candidates.start} to {candidates.stop - 1} is in use by a "
                         "live system of this machine")


def isolated_env(domain: int, base: Mapping[str, str] | None = None) -> dict[str, str]:
    """``base`` (default: this process's environment) in ``domain`` with localhost discovery,
    without the recording middleware's activation."""
    env = without_recording(dict(os.environ if base is None else base))
    env["ROS_DOMAIN_ID"] = str(domain)
    env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    env.pop("ROS_LOCALHOST_ONLY", None)
    env.pop("ROS_STATIC_PEERS", None)
    return env


@dataclass
class RunningSystem:
    """The processes of a launch file running on the real middleware in ``domain``; ``env`` is
    the environment to read it in (``live.graph.read_graph(base_env=...)``)."""

    domain: Domain
    env: dict[str, str]
    processes: list[subprocess.Popen[bytes]] = field(default_factory=list)
    workdir: Path | None = None
    logs: list[Path] = field(default_factory=list)
    #: the node each process is named by the launch file (None: the program names it)
    expected: list[str | None] = field(default_factory=list)
    #: the domain was reserved for this system (released when it stops); False: the caller's
    owns_domain: bool = True

    @property
    def domain_id(self) -> int:
        return self.domain.id

    def exited(self) -> list[str]:
        """The processes that ended on their own, with the tail of their output."""
        out = []
        for process, log in zip(self.processes, self.logs, strict=False):
            if process.poll() is not None:
                tail = log.read_text(encoding="utf-8", errors="replace")[-800:] if log.exists() else ""
                out.append(f"{process.args!s} exited with {process.returncode}: {tail}")
        return out

    def wait_until_up(self, timeout: float = 30.0, settle: float = 1.0, nodes: Collection[str] = (),
                      expect: Collection[str] = ()) -> LiveGraph:
        """Read the graph until every node the launch file names is in it (but those of processes
        that have ended), and ``nodes``, at most ``timeout`` seconds; the last graph read (raises
        LiveGraphError). The reader also waits a while for ``expect`` (the nodes a contract names,
        which may be absent: that is the check's finding, ``LiveSettings.expect``)."""
        deadline = time.monotonic() + timeout
        while True:
            left = max(settle + 0.5, deadline - time.monotonic())
            running = [name for name, process in zip(self.expected, self.processes, strict=True)
                       if name is not None and process.poll() is None]
            wanted = set(running) | set(nodes)
            graph = read_graph(LiveSettings(settle=settle, timeout=left, expect=tuple(sorted(wanted | set(expect)))),
                               base_env=self.env)
            missing = sorted(wanted - set(graph.capture.nodes))
            if not missing:
                return graph
            if time.monotonic() >= deadline:
                raise LiveGraphError(f"the system in ROS_DOMAIN_ID {self.domain_id} did not show {', '.join(missing)} "
                                     f"within {timeout:g} s; {'; '.join(self.exited()) or 'every process runs'}")

    def stop(self, grace: float = 5.0) -> None:
        """SIGINT to every process (as ``ros2 launch`` ends them), SIGKILL after ``grace`` seconds;
        the domain is released (when it reserved it) and the working directory removed."""
        for process in self.processes:
            if process.poll() is None:
                with contextlib.suppress(ProcessLookupError):
                    os.killpg(process.pid, signal.SIGINT)
        deadline = time.monotonic() + grace
        for process in self.processes:
            try:
                process.wait(timeout=max(0.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                with contextlib.suppress(ProcessLookupError):
                    os.killpg(process.pid, signal.SIGKILL)
                process.wait()
        if self.owns_domain:
            self.domain.release()
        if self.workdir is not None:
            shutil.rmtree(self.workdir, ignore_errors=True)
            self.workdir = None


def bring_up(launch: Mapping[str, Any], *, base_dir: str | Path, ros: ros_env.RosEnvironment | None = None,
             domain: Domain | None = None, env: Mapping[str, str] | None = None) -> RunningSystem:
    """Start every process of the ``launch:`` block ``launch`` (relative paths to ``base_dir``) on
    the real middleware in a domain of its own (``domain``, default: :func:`reserve_domain`);
    raises LaunchError / LiveGraphError / TargetConfigError (nothing is left running then)."""
    ros = ros or ros_env.detect()
    prefixes = system_capture.ament_prefixes(ros)
    spec = system_capture.resolve_launch(launch, base_dir=base_dir, source="live bring-up", prefixes=prefixes)
    launched = launch_reader.read(spec.path, spec.arguments, prefixes=prefixes)
    if not spec.allow_unsupported:
        launched.require_supported()
    containers = [n for n in launched.nodes if n.components]
    if containers:
        raise LiveGraphError(f"{spec.path} loads components into a container ({containers[0].where}): a live bring-up "
                             "without launch_ros cannot load them; start it with `ros2 launch` and check it with "
                             "`rmw-introspect check --live`")
    return start(launched.nodes, ros=ros, domain=domain, env=env)


def start(processes: Sequence[LaunchedNode | TargetSpec], *, ros: ros_env.RosEnvironment | None = None, domain: Domain | None = None,
          env: Mapping[str, str] | None = None) -> RunningSystem:
    """Start ``processes`` (a launch file's, or targets of node contracts) on the real middleware
    in a domain of their own (``domain``, default: :func:`reserve_domain`); nothing is left
    running when starting one fails."""
    ros = ros or ros_env.detect()
    owns = domain is None
    domain = domain or reserve_domain()
    system = RunningSystem(domain=domain, env=isolated_env(domain.id, env), owns_domain=owns)
    system.workdir = Path(tempfile.mkdtemp(prefix="rmw_introspect_live_"))
    try:
        for index, node in enumerate(processes):
            directory = system.workdir / str(index)
            directory.mkdir()
            process = node if isinstance(node, TargetSpec) else system_capture.process_spec(node, TargetSpec(), directory)
            resolved = resolution.resolve(process, workdir=directory, library=_NO_LIBRARY, ros=ros,
                                             cold_note="a live bring-up")
            process_env = isolated_env(domain.id, {**resolved.env, **{k: v for k, v in system.env.items()
                                                                      if k == "RMW_IMPLEMENTATION"}})
            process_env["ROS_LOG_DIR"] = str(directory / "log")
            log = directory / "output.log"
            with open(log, "wb") as out:
                system.processes.append(subprocess.Popen(resolved.argv, env=process_env, cwd=resolved.cwd,
                                                         stdin=subprocess.DEVNULL, stdout=out,
                                                         stderr=subprocess.STDOUT, start_new_session=True))
            system.logs.append(log)
            system.expected.append(None if isinstance(node, TargetSpec) else node.expected_fqn)
    except BaseException:
        system.stop()
        raise
    return system


@contextlib.contextmanager
def running(launch: Mapping[str, Any], *, base_dir: str | Path, ros: ros_env.RosEnvironment | None = None) -> Iterator[RunningSystem]:
    """:func:`bring_up` for a ``with`` block: stopped at its end, whatever happens."""
    system = bring_up(launch, base_dir=base_dir, ros=ros)
    try:
        yield system
    finally:
        system.stop()
