"""Reading a running graph: the reader process started on the real middleware, its answer read
into a :class:`LiveGraph` (a :class:`~..model.capture.Capture` and what only a live read knows).

The reader never runs on the recording middleware: ``RMW_IMPLEMENTATION=rmw_introspect_cpp`` is
refused (the user asked for a middleware that sees no other process), an ``LD_PRELOAD`` entry
naming ``librmw_introspect_cpp`` is taken out of the reader's environment (said on stderr), and
the reader itself refuses to read when its middleware identifies as the recording one. A
``RMW_IMPLEMENTATION`` that names a middleware this ROS 2 install does not have is refused
before anything starts (the PyPI wheels have Fast DDS alone).
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from collections.abc import Collection, Generator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import CaptureFormatError, LiveGraphError
from ..model.capture import Capture
from ..run import ros_env
from ..run.ros_env import RosEnvironment
from . import ABSENT_AFTER, DEFAULT_PARAMETER_TIMEOUT, DEFAULT_SETTLE, DEFAULT_TIMEOUT, EXIT_EMPTY, EXIT_WRONG_MIDDLEWARE

#: the middleware of the PyPI wheels (the only one they have: selection is compiled out)
WHEELS_MIDDLEWARE = "rmw_fastrtps_cpp"


@dataclass(frozen=True)
class LiveSettings:
    """How long to wait: ``settle`` seconds of an unchanged graph, at most ``timeout`` seconds;
    ``parameter_timeout``: how long the nodes' parameter and lifecycle services have, together."""

    settle: float = DEFAULT_SETTLE
    timeout: float = DEFAULT_TIMEOUT
    parameter_timeout: float = DEFAULT_PARAMETER_TIMEOUT
    #: the nodes the contracts name: the reader waits for them (:data:`ABSENT_AFTER`)
    expect: tuple[str, ...] = ()


@dataclass
class LiveGraph:
    """What the reader saw: ``capture`` (the graph as a capture of the recording middleware's
    format, infrastructure filtered as asked) and the facts of the read."""

    capture: Capture
    domain_id: int
    rmw_implementation: str
    settled: bool
    waited: float
    settings: LiveSettings
    parameters_unanswered: list[str] = field(default_factory=list)
    lifecycle_unanswered: list[str] = field(default_factory=list)
    #: what was said about the environment (a stripped preload)
    environment_notes: list[str] = field(default_factory=list)
    #: when it was read (seconds since the epoch; 0: not said)
    at: float = 0.0
    #: other live readers that were in the graph (left out of it)
    other_readers: list[str] = field(default_factory=list)
    #: the nodes of `ros2 launch` that were in the graph (left out of it: no part of the system)
    launchers: list[str] = field(default_factory=list)
    #: nodes the contracts name that the graph did not show (waited for, then read without them)
    expected_absent: list[str] = field(default_factory=list)
    #: names that more than one node in the graph has (fully qualified name: how many); the
    #: capture holds each name once, with the interfaces of all of them
    duplicate_nodes: dict[str, int] = field(default_factory=dict)

    def describe(self) -> str:
        return f"the running graph of ROS_DOMAIN_ID {self.domain_id} ({self.rmw_implementation})"

    def notes(self, nodes: Collection[str] | None = None) -> list[str]:
        """What a report's reader should know about the read (not drift); ``nodes``: only about
        these nodes (default: every node)."""
        out = []  # (the environment notes are said on stderr as the read starts)
        parameters = [n for n in self.parameters_unanswered if nodes is None or n in nodes]
        lifecycle = [n for n in self.lifecycle_unanswered if nodes is None or n in nodes]
        if not self.settled:
            out.append(f"the graph was still changing after {self.settings.timeout:g} s (--timeout): it was read as it "
                       "was then")
        absent = [n for n in self.expected_absent if nodes is None or n in nodes]
        if absent and self.settled:
            out.append(f"waited for node(s) the contracts name until the graph had not changed for "
                       f"{max(self.settings.settle, ABSENT_AFTER):g} s; not running: {', '.join(absent)}")
        if self.other_readers:
            out.append(f"other live readers were in the graph, left out of it: {', '.join(self.other_readers)}")
        if self.launchers:
            out.append(f"the node of `ros2 launch` (launch_ros, which drives lifecycle nodes and loads components) was "
                       f"in the graph, left out of it: {', '.join(self.launchers)}")
        duplicates = {n: c for n, c in self.duplicate_nodes.items() if nodes is None or n in nodes}
        if duplicates:
            named = ", ".join(f"{c} nodes named {n}" for n, c in duplicates.items())
            out.append(f"the graph has {named}: their interfaces are read together, as one node's")
        if parameters:
            out.append(f"parameters not read (the node's parameter services did not answer within "
                       f"{self.settings.parameter_timeout:g} s), not compared: {', '.join(parameters)}")
        if lifecycle:
            out.append(f"lifecycle state not read (`get_state` did not answer within "
                       f"{self.settings.parameter_timeout:g} s), not compared: {', '.join(lifecycle)}")
        return out


def installed_middleware(name: str, ros: RosEnvironment) -> bool:
    """Whether the ROS 2 install ``ros`` can run on the middleware ``name``."""
    if ros.kind == ros_env.WHEELS:
        return name == WHEELS_MIDDLEWARE
    return any((Path(prefix) / "share" / "ament_index" / "resource_index" / "packages" / name).exists()
               for prefix in ros.ament_prefixes)


def without_recording(env: dict[str, str]) -> dict[str, str]:
    """``env`` without the recording middleware's activation: its ``LD_PRELOAD`` entry, an
    ``RMW_IMPLEMENTATION`` naming it and the ``RMW_INTROSPECT_*`` variables (changed in place)."""
    preload = env.get("LD_PRELOAD", "").replace(":", " ").split()
    kept = [p for p in preload if not os.path.basename(p).startswith(f"lib{ros_env.MIDDLEWARE_NAME}")]
    if kept:
        env["LD_PRELOAD"] = " ".join(kept)
    else:
        env.pop("LD_PRELOAD", None)
    if env.get("RMW_IMPLEMENTATION") == ros_env.MIDDLEWARE_NAME:
        env.pop("RMW_IMPLEMENTATION")
    for name in [k for k in env if k.startswith("RMW_INTROSPECT_")]:
        env.pop(name)
    return env


def reader_environment(ros: RosEnvironment, base: Mapping[str, str] | None = None) -> tuple[dict[str, str], list[str]]:
    """The reader's environment (the user's, without the recording middleware's activation) and
    what to say about it; raises LiveGraphError for a middleware it must not or cannot run on."""
    env = dict(os.environ if base is None else base)
    notes = []
    chosen = env.get("RMW_IMPLEMENTATION", "")
    if chosen == ros_env.MIDDLEWARE_NAME:
        raise LiveGraphError(
            f"RMW_IMPLEMENTATION={chosen} is the recording middleware, which sees no other process: a live check "
            "reads the middleware the robot runs; unset RMW_IMPLEMENTATION (or name that middleware, e.g. "
            f"{WHEELS_MIDDLEWARE})")
    if chosen and not installed_middleware(chosen, ros):
        have = (f"the PyPI wheels of ROS 2 {ros.distro} have {WHEELS_MIDDLEWARE} only" if ros.kind == ros_env.WHEELS
                else "no package of that name is in the ament index (AMENT_PREFIX_PATH)")
        raise LiveGraphError(f"RMW_IMPLEMENTATION={chosen} names a middleware that is not installed here: {have}; "
                             "install it, or unset RMW_IMPLEMENTATION for the default one")
    preloaded = env.get("LD_PRELOAD", "")
    without_recording(env)
    if env.get("LD_PRELOAD", "") != preloaded:
        notes.append("LD_PRELOAD activated the recording middleware; the live reader runs without it (on the "
                     "middleware the robot runs)")
    if ros.kind == ros_env.WHEELS:  # the wheels' bootstrapper would re-exec the interpreter to set it
        env["LD_LIBRARY_PATH"] = ros.library_path(env.get("LD_LIBRARY_PATH"))
        env["_ROS_WHEELS_BOOTSTRAP_COMPLETE"] = "1"
    package_root = str(Path(__file__).resolve().parents[2])
    env["PYTHONPATH"] = os.pathsep.join([package_root, *filter(None, [env.get("PYTHONPATH")])])
    return env, notes


def _reader_command(settings: LiveSettings) -> list[str]:
    return [sys.executable, "-m", "pytest_rmw_introspect.live.reader", "--settle", f"{settings.settle:g}",
            "--timeout", f"{settings.timeout:g}", "--parameter-timeout", f"{settings.parameter_timeout:g}",
            *(f"--expect={fqn}" for fqn in settings.expect)]


def _nothing_running(domain: str, settings: LiveSettings, env: Mapping[str, str]) -> str:
    where = env.get("ROS_AUTOMATIC_DISCOVERY_RANGE")
    return (f"nothing is running in ROS_DOMAIN_ID {domain}: no node appeared within {settings.timeout:g} s (--timeout)"
            + (f" with ROS_AUTOMATIC_DISCOVERY_RANGE={where}" if where else "")
            + "; start the system, or set ROS_DOMAIN_ID (and ROS_AUTOMATIC_DISCOVERY_RANGE) as the robot has them")


def read_graph(settings: LiveSettings = LiveSettings(), *, ros: RosEnvironment | None = None,
               include_infrastructure: bool = False, base_env: Mapping[str, str] | None = None) -> LiveGraph:
    """Read the running graph (raises LiveGraphError); progress goes to stderr as it comes."""
    ros = ros if ros is not None else ros_env.detect()
    env, notes = reader_environment(ros, base_env)
    for note in notes:
        print(f"rmw-introspect: live: {note}", file=sys.stderr)
    command = _reader_command(settings)
    limit = settings.timeout + 2 * settings.parameter_timeout + 30  # start-up and teardown included
    try:
        done = subprocess.run(command, env=env, stdout=subprocess.PIPE, stderr=None, text=True, timeout=limit,
                              check=False)
    except subprocess.TimeoutExpired:
        raise LiveGraphError(f"the live reader did not finish within {limit:g} s") from None
    domain = env.get("ROS_DOMAIN_ID") or "0"
    if done.returncode == EXIT_EMPTY:
        raise LiveGraphError(_nothing_running(domain, settings, env))
    if done.returncode == EXIT_WRONG_MIDDLEWARE:
        raise LiveGraphError("the live reader found itself on the recording middleware rmw_introspect_cpp: remove its "
                             "activation from the environment (LD_PRELOAD, RMW_IMPLEMENTATION)")
    if done.returncode != 0:
        raise LiveGraphError(f"the live reader failed (exit status {done.returncode}) in ROS_DOMAIN_ID {domain}; its "
                             "error output is above")
    return parse_answer(done.stdout, settings, include_infrastructure=include_infrastructure, notes=notes,
                        domain=domain)


def parse_answer(text: str, settings: LiveSettings, *, include_infrastructure: bool, notes: list[str],
                 domain: str) -> LiveGraph:
    """One answer of the reader (a JSON object) as a :class:`LiveGraph` (raises LiveGraphError);
    an answer without a capture (the graph emptied while watching) is an empty graph."""
    try:
        answer: Any = json.loads(text)
        live: Mapping[str, Any] = answer["live"]
        document = answer.get("capture") or {"format": "rmw_introspect_capture", "format_version": 1, "state": "live"}
        capture = Capture.from_dict(document, include_infrastructure=include_infrastructure)
    except (ValueError, KeyError, TypeError, AttributeError, CaptureFormatError) as exc:
        raise LiveGraphError(f"the live reader's answer could not be read: {exc}") from None
    return LiveGraph(capture=capture, domain_id=int(live.get("domain_id", domain)),
                     rmw_implementation=str(live.get("rmw_implementation")), settled=bool(live.get("settled")),
                     waited=float(live.get("waited_s", 0.0)), settings=settings,
                     parameters_unanswered=list(live.get("parameters_unanswered", [])),
                     lifecycle_unanswered=list(live.get("lifecycle_unanswered", [])),
                     environment_notes=notes, at=float(live.get("at", 0.0)),
                     other_readers=list(live.get("other_readers", [])), launchers=list(live.get("launchers", [])),
                     expected_absent=list(live.get("expected_absent", [])),
                     duplicate_nodes={str(k): int(v) for k, v in (live.get("duplicate_nodes") or {}).items()})


def watch_graph(settings: LiveSettings, duration: float, *, ros: RosEnvironment | None = None,
                base_env: Mapping[str, str] | None = None) -> Generator[LiveGraph, None, None]:
    """The running graph once stable (as :func:`read_graph`), then again at every change, until
    ``duration`` seconds have passed (0: until Ctrl-C or the generator is closed); the reader is
    stopped when the generator ends."""
    ros = ros if ros is not None else ros_env.detect()
    env, notes = reader_environment(ros, base_env)
    for note in notes:
        print(f"rmw-introspect: live: {note}", file=sys.stderr)
    command = [*_reader_command(settings), "--watch", "--duration", f"{duration:g}"]
    domain = env.get("ROS_DOMAIN_ID") or "0"
    process = subprocess.Popen(command, env=env, stdout=subprocess.PIPE, text=True)
    try:
        assert process.stdout is not None
        for number, line in enumerate(process.stdout):
            graph = parse_answer(line, settings, include_infrastructure=True, notes=notes, domain=domain)
            if number == 0 and not graph.capture.nodes:
                raise LiveGraphError(_nothing_running(domain, settings, env))
            yield graph
        if process.wait() not in (0, -signal.SIGINT):
            raise LiveGraphError(f"the live reader failed (exit status {process.returncode}) in ROS_DOMAIN_ID "
                                 f"{domain}; its error output is above")
    finally:
        if process.poll() is None:
            process.send_signal(signal.SIGINT)
            try:
                process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
