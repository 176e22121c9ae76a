"""What a reader of a report should know about how a capture came about: its notes.

:func:`notes` is ``Capture.notes()``: the process the capture is of, other ROS processes the
target started, duplicate node names, how the program ended, a warp of virtual time that
stopped before its horizon (and which loop kept it from advancing: :func:`horizon_note`), nodes
on sim time, clients of services of the same process, parameters and lifecycle states that
could not be read. Each note is one sentence for people, with what to do where there is
something to do.

The notes read a capture as :class:`Noted`, the part of
:class:`~pytest_rmw_introspect.model.capture.Capture` they need, so that this module does not
import the capture module that calls it (no import cycle, types included).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import Protocol

from .capture_file import Endpoint, RawNode, VirtualTime
from .capture_view import Node
from .parameters import Probe


class Described(Protocol):
    """Another process of the run (``model.capture.OtherProcess``), as a note names it."""

    def describe(self) -> str: ...


class Noted(Protocol):
    """What the notes read of a capture (``model.capture.Capture`` is one)."""

    @property
    def from_child(self) -> Described | None: ...
    @property
    def other_processes(self) -> Sequence[Described]: ...
    @property
    def duplicate_node_names(self) -> list[str]: ...
    @property
    def raw_nodes(self) -> Sequence[RawNode]: ...
    @property
    def ended_by_itself(self) -> bool: ...
    @property
    def returncode(self) -> int | None: ...
    @property
    def settled_once(self) -> bool: ...
    @property
    def virtual_time(self) -> VirtualTime | None: ...
    @property
    def polls(self) -> int: ...
    @property
    def probe(self) -> Probe | None: ...
    def __iter__(self) -> Iterator[Node]: ...
    def endpoints(self, *, include_destroyed: bool = False) -> list[Endpoint]: ...


def notes(capture: Noted) -> list[str]:
    """What a reader of a report should know about how this capture came about."""
    notes: list[str] = []
    if capture.from_child is not None:
        notes.append(
            "the target created no ROS node itself; this is the capture of the ROS process it started: "
            + capture.from_child.describe()
        )
    if capture.other_processes:
        notes.append(
            "the target started other ROS processes, which are not part of this capture (capture each "
            "as a target of its own): " + "; ".join(p.describe() for p in capture.other_processes)
        )
    for fqn in capture.duplicate_node_names:
        count = sum(1 for raw_node in capture.raw_nodes if raw_node.alive and raw_node.fqn == fqn)
        notes.append(
            f"{count} nodes are named {fqn} in one process: ROS 2 cannot tell them apart (their parameter "
            "services collide); the contract lists their interfaces under one entry. Give each node a "
            "name of its own."
        )
    if capture.ended_by_itself:
        notes.append(
            "the program ended by itself (status 0) before its final settle: the capture is what was "
            "alive just before its own final teardown"
        )
    elif capture.returncode not in (None, 0) and capture.settled_once:
        how = f"was killed by signal {-capture.returncode}" if capture.returncode < 0 else f"exited with status {capture.returncode}"
        notes.append(
            f"the program {how} after it had settled (for example a timeout that expired at once in "
            "virtual time): the capture is what it had created until then"
        )
    vt = capture.virtual_time
    if vt is not None and vt.enabled and not vt.horizon_reached and (
            vt.warp_stalled or vt.warp_budget_exhausted or vt.warp_real_waits):
        notes.append(horizon_note(vt, capture.polls))
    for node in capture:
        if node.uses_sim_time:
            notes.append(
                f"node {node.fqn} uses sim time (use_sim_time): its ROS clock waits for /clock, which never "
                "arrives in a capture, so its ROS-time timers never fire"
            )
    notes.extend(own_service_notes(capture))
    probe = capture.probe
    if probe is not None and probe.state == "skipped":
        notes.append(
            "no thread ever waited in an executor, so the middleware could not ask the nodes' own "
            "services: parameters were not read and lifecycle nodes were not driven"
        )
    for node in capture:
        if node.parameters_error:
            notes.append(f"the parameters of node {node.fqn} could not be read ({node.parameters_error}); "
                         "they are not compared")
        if node.lifecycle is not None and node.lifecycle.error:
            notes.append(f"lifecycle: {node.lifecycle.error}")
    return notes

def own_service_notes(capture: Noted) -> list[str]:
    """A client of a service that a node of this same process serves: in a capture nothing is
    delivered, so a program that waits for the answer (to a request to its own node, say)
    waits for ever, and what it would create after the answer is not captured."""
    servers: dict[str, list[str]] = {}
    for e in capture.endpoints():
        if e.kind == "service":
            servers.setdefault(e.name, []).append(e.node)
    notes = []
    for e in capture.endpoints():
        if e.kind != "client" or e.name not in servers:
            continue
        whose = "its own node" if e.node in servers[e.name] else "node " + ", ".join(sorted(set(servers[e.name])))
        notes.append(
            f"node {e.node} has a client of {e.name}, a service of {whose} in this process: requests to it "
            "are never answered in a capture (nothing is delivered), so a program that waits for the answer "
            "keeps waiting, and what it would create after the answer is not in this capture"
        )
    return notes



# A loop that returns from rmw_wait at least this often (on average) polls without pausing; a
# slower one sleeps between its polls (sleep_for(10ms) is 100 a second, a 2 Hz rate 2).
_BUSY_POLLS_PER_SECOND = 500


def horizon_note(vt: VirtualTime, polls: int) -> str:
    """What a capture says when the warp stopped before the horizon (stalled, or its budget
    spent), and what was seen."""
    where = (f"virtual time stopped at {vt.virtual_elapsed_ms / 1000:.3g} s of the {vt.horizon_ms / 1000:g} s "
             f"horizon after {vt.jumps} jumps")
    later = "; interfaces created later are not in the capture"
    if vt.warp_real_waits and not (vt.warp_stalled or vt.warp_budget_exhausted):
        return (f"{where}: the idle proof ended it while a thread of the program waited on the real clock "
                "until before the horizon (a Rate or WallRate sleep, a timed condition wait, Event.wait with a "
                "timeout), which virtual time does not step: what that thread does after its wait is not in the "
                "capture (a timer of the node, or a longer settle, would cover it)")
    if vt.warp_stalled:
        return f"{where}: the program kept running but never waited with a timeout: {stalled_loop(vt, polls)}" + later
    if vt.jumps >= 1000:
        why = "each jump is one period of a very fast timer"
    elif polls:
        why = (f"the program kept running between its waits: {polls} returns from rmw_wait without waiting (polls, "
               "or a spin_once loop running a task that awaits an answer that never comes)")
    else:
        why = "the program kept running between its waits (a loop that sleeps or polls besides its timers)"
    return f"{where}: the warp used its real-time budget ({why})" + later


def stalled_loop(vt: VirtualTime, polls: int) -> str:
    """Which loop kept a stalled warp from advancing, from what the middleware counted in it."""
    # time.sleep, sleep_for, nanosleep and usleep are the middleware's and stepped by the warp
    # (docs/design.md, "Sleeps"), unless RMW_INTROSPECT_SLEEPS=0 made them real
    sleeps = ("a WallRate or Rate loop, a timed condition wait or select(); or time.sleep / sleep_for with "
              "RMW_INTROSPECT_SLEEPS=0")
    if vt.warp_polls is None or vt.warp_real_ms is None:  # a capture that does not say
        polled = (f" ({polls} zero-timeout polls of its executor, or waits that returned at once on a guard "
                  "condition it had just triggered itself)" if polls else "")
        return (f"it polls{polled} (spin_some, spin_once(timeout_sec=0)), spins a task that awaits an answer that "
                f"never comes (spin_once with a pending call_async), or sleeps on its own clock ({sleeps}), which "
                "virtual time cannot advance")
    seconds = vt.warp_real_ms / 1000
    if vt.warp_polls == 0:
        return (f"in {seconds:.2g} s it made {vt.warp_activity or 0} calls into ROS (publish, take, graph queries) "
                f"and never waited in an executor: a loop that sleeps on its own clock ({sleeps}) without spinning, "
                "which virtual time cannot advance")
    rate = vt.warp_polls / seconds if seconds > 0 else float("inf")
    counted = (f"{vt.warp_polls} zero-timeout poll{'s' if vt.warp_polls != 1 else ''} of its executor in "
               f"{seconds:.2g} s (or waits that returned at once on a guard condition it had just triggered itself)")
    if rate >= _BUSY_POLLS_PER_SECOND:
        return (f"{counted}, without pausing: a busy loop at full CPU that polls its executor (spin_some or "
                "spin_once(timeout_sec=0) until something is done) or spins a task that awaits an answer that "
                "never comes (spin_once with a pending call_async); in a capture no answer or message arrives, so "
                "it never ends, and it has no deadline virtual time could jump to")
    return (f"{counted}, one every {1000 / rate:.3g} ms: between its polls it sleeps on the real clock ({sleeps}), "
            "which virtual time does not advance")
