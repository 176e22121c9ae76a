"""The errors a user of pytest-rmw-introspect can see.

Every error is written for people: it names the file, the node, the interface or the
command involved, and says what to do next. Every error class of the package is defined here
(``rmw-introspect`` reports an RmwIntrospectError as one line, exit status 2; any other
exception is a bug and shows its traceback). The pytest plugin turns them into test
failures (``pytest.fail``) with the message as the failure text, never into internal errors.

Hierarchy::

    RmwIntrospectError
    ├── SetupError          ROS 2 / compiler / CMake / middleware library missing
    ├── ContractError       malformed contract file (YAML, schema, QoS, duplicates)
    ├── CaptureFormatError  a capture file that is not a valid capture
    ├── RecordingError      ``check --bag``: a recording that cannot be read (missing, corrupt, truncated)
    ├── RevisionError       ``diff --against REF``: no git repository, no such revision, a shallow clone
    ├── UsageError          a bad command line or option value (``--shard``, arguments that go together)
    ├── OptionError         a comparison option with a value that makes no sense
    └── TargetError         the target could not be captured
        ├── TargetConfigError   inconsistent target options (no target, two targets...)
        │   └── LaunchError     a launch file that cannot be read (file, line, what to do)
        ├── SystemCaptureError  some processes of a launch file could not be captured
        ├── ExecutableNotFound  package/executable/script not found
        ├── TargetExited        the process exited non-zero before settling
        ├── NoNodeCreated       the process created no ROS node
        ├── TargetTimeout       the process never settled within the timeout
        ├── TargetNotStopped    the process did not end even after SIGKILL (it cannot be reaped)
        ├── LifecycleTransitionFailed  a lifecycle node's transition failed or raised
        └── StimulusFailed      a stimulus (target option ``stimuli``) matched nothing, was not
                                taken or answered, or the node ended after one
"""

from __future__ import annotations

import shlex
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol

__all__ = [
    "CaptureFormatError",
    "ContractError",
    "ExecutableNotFound",
    "LaunchError",
    "LifecycleTransitionFailed",
    "LiveGraphError",
    "NoNodeCreated",
    "OptionError",
    "RecordingError",
    "RevisionError",
    "RmwIntrospectError",
    "SetupError",
    "StimulusFailed",
    "SystemCaptureError",
    "TargetConfigError",
    "TargetError",
    "TargetExited",
    "TargetNotStopped",
    "TargetTimeout",
    "UsageError",
]


class RmwIntrospectError(Exception):
    """Base class of every error this package raises on purpose."""


class SetupError(RmwIntrospectError):
    """Something the plugin needs is missing: ROS 2, a compiler, CMake, the middleware library."""


class ContractError(RmwIntrospectError):
    """A contract file that cannot be used.

    ``path``: the file; ``location``: the place inside it as a dotted path
    (``nodes./talker.publishers[0].qos.reliability``) or ``None`` for the whole file;
    ``reason``: what is wrong; ``line``: 1-based line number when known.
    """

    def __init__(
        self,
        path: str | Path | None,
        location: str | None,
        reason: str,
        line: int | None = None,
        others: Sequence[tuple[str | None, str, int | None]] = (),
    ) -> None:
        self.path = Path(path) if path is not None else None
        self.location = location
        self.reason = reason
        self.line = line
        #: the file's other problems, (location, reason, line) each, by line
        self.others = list(others)
        super().__init__(self._format())

    def shown_from(self, display: Callable[[Path], str]) -> str:
        """The message with the file shown by ``display`` (e.g. relative to where pytest started)."""
        return self._format(display(self.path) if self.path is not None else None)

    def _format(self, where: str | None = None) -> str:
        where = where or (str(self.path) if self.path is not None else "<contract>")
        text = f"invalid contract {self._place(where, self.line, self.location)}: {self.reason}"
        if self.others:
            count = len(self.others)
            text += f"\n{count} more problem{'s' if count > 1 else ''} in the file:"
            for location, reason, line in self.others:
                text += f"\n  {self._place(where, line, location)}: {reason}"
        return text

    @staticmethod
    def _place(where: str, line: int | None, location: str | None) -> str:
        if line is not None:
            where += f":{line}"
        if location:
            where += f": at {location}"
        return where


class CaptureFormatError(RmwIntrospectError):
    """A capture file that is not a capture of a format version this package reads."""

    def __init__(self, path: str | Path | None, reason: str) -> None:
        self.path = Path(path) if path is not None else None
        self.reason = reason
        where = str(self.path) if self.path is not None else "<capture>"
        super().__init__(f"unreadable capture {where}: {reason}")


def _tail(text: str | None, lines: int = 20) -> str:
    if not text:
        return ""
    return "\n".join(text.rstrip().splitlines()[-lines:])


#: the last line of the traceback a Python target prints when the runner's SIGINT stops it
_INTERRUPT_ENDS = ("KeyboardInterrupt", "rclpy.executors.ExternalShutdownException")
_CHAINED = ("During handling of the above exception, another exception occurred:",
            "The above exception was the direct cause of the following exception:")


def without_our_interrupt(stderr: str) -> tuple[str, bool]:
    """``stderr`` without the traceback that ends it when it is the one our own SIGINT caused (the
    runner stops a target that did not settle that way): it reads like the node's own crash.
    Chained tracebacks leading to it go too; anything before them stays. Returns the text and
    whether something was left out."""
    lines = stderr.rstrip().splitlines()
    if not lines or not lines[-1].strip().startswith(_INTERRUPT_ENDS):
        return stderr, False
    headers = [i for i, line in enumerate(lines) if line.strip() == "Traceback (most recent call last):"]
    if not headers:
        return stderr, False
    start = headers[-1]
    while True:  # a chained traceback ("During handling of ...") goes with the one it leads to
        above = start - 1
        while above >= 0 and not lines[above].strip():
            above -= 1
        earlier = [i for i in headers if i < above]
        if above < 0 or lines[above].strip() not in _CHAINED or not earlier:
            break
        start = earlier[-1]
    while start > 0 and not lines[start - 1].strip():
        start -= 1
    return "\n".join(lines[:start]), True


def _indent(text: str, prefix: str = "    ") -> str:
    return "\n".join(prefix + line for line in text.splitlines())


class TargetError(RmwIntrospectError):
    """The target could not be captured. ``target`` describes it (a short string); ``started``
    says how the runner had started it (``"warm"``, ``"cold"``; None when it never started)."""

    started: str | None = None

    def __init__(self, message: str, *, target: str | None = None) -> None:
        self.target = target
        super().__init__(message)


class TargetConfigError(TargetError):
    """The target options are inconsistent or incomplete (e.g. no target at all)."""


class ExecutableNotFound(TargetError):
    """The package, executable, script or command could not be found.

    ``searched``: the places looked at; ``found``: candidates seen (e.g. the executables a
    package does have, or several prefixes that provide it).
    """

    def __init__(
        self,
        message: str,
        *,
        target: str | None = None,
        searched: Sequence[str | Path] = (),
        found: Sequence[str | Path] = (),
    ) -> None:
        self.searched = [str(s) for s in searched]
        self.found = [str(f) for f in found]
        super().__init__(message, target=target)


class PartialCapture(Protocol):
    """What an error shows of the capture a target left before it failed: its summary. It is a
    :class:`~pytest_rmw_introspect.model.capture.Capture` (this base layer imports no model)."""

    def summary(self) -> str: ...


class _WithPartialCapture(TargetError):
    partial: PartialCapture | None
    argv: list[str]
    stderr_tail: str

    def _process_details(self) -> list[str]:
        """The command, the tail of its stderr (if any) and what was captured."""
        parts = []
        if self.argv:
            parts.append("Command: " + shlex.join(self.argv))
        if self.stderr_tail:
            parts.append("Last lines of its stderr:\n" + _indent(self.stderr_tail))
        parts.append(self._partial_summary())
        return parts

    def _partial_summary(self) -> str:
        if self.partial is None:
            return "Nothing was captured (no capture file was written)."
        try:
            return "Captured so far:\n" + _indent(self.partial.summary())
        except Exception:  # noqa: BLE001  # pragma: no cover - never hide the real error
            return "Captured so far: (unprintable capture)"


class TargetExited(_WithPartialCapture):
    """The target process ended with a non-zero status (or a signal) before settling, or
    crashed (an uncaught exception, a fatal signal) at any time before its final settle."""

    def __init__(
        self,
        target: str,
        status: int,
        stderr_tail: str,
        partial: PartialCapture | None = None,
        argv: Sequence[str] = (),
        hint: str | None = None,
        crashed: bool = False,
    ) -> None:
        self.status = status
        self.hint = hint
        self.stderr_tail = _tail(stderr_tail)
        self.partial = partial
        self.argv = list(argv)
        self.crashed = crashed
        if status < 0:
            how = f"was killed by signal {-status}"
        else:
            how = f"exited with status {status}"
        if crashed:  # whether it got past the first settle is timing: a crash is reported as one
            parts = [f"The target {target} crashed: it {how} while it was captured (an uncaught exception or a "
                     "fatal signal), so what it created is not its interface."]
        else:
            parts = [f"The target {target} {how} before its interfaces settled."]
        if self.argv:
            parts.append("Command: " + shlex.join(self.argv))
        if self.stderr_tail:
            parts.append("Last lines of its stderr:\n" + _indent(self.stderr_tail))
        else:
            parts.append("It wrote nothing to stderr.")
        parts.append(self._partial_summary())
        if hint:
            parts.append(hint)
        super().__init__("\n".join(parts), target=target)


#: what a target that created no node is asked, by what it is (``language``: "python" for a Python
#: program, "compiled" for an ELF executable, None when it is not known): a C++ program is not
#: told to check rclpy.init() (issue 50)
_NO_NODE_QUESTION = {
    "python": "call rclpy.init(), create a Node and spin before it exits?",
    "compiled": "call rclcpp::init() (rcl_init in C), create a node and spin before it exits?",
    None: "initialise ROS 2 (rclpy.init() in Python, rclcpp::init() in C++), create a node and spin before it exits?",
}


class NoNodeCreated(_WithPartialCapture):
    """The target ran (and settled or exited) but never created a ROS node."""

    def __init__(
        self,
        target: str,
        stderr_tail: str = "",
        partial: PartialCapture | None = None,
        argv: Sequence[str] = (),
        detail: str | None = None,
        hint: str | None = None,
        language: str | None = None,
    ) -> None:
        self.hint = hint
        self.stderr_tail = _tail(stderr_tail)
        self.partial = partial
        self.argv = list(argv)
        self.detail = detail
        parts = [
            f"The target {target} created no ROS node"
            + (f" ({detail})" if detail else "")
            + f": is it the right executable, and does it {_NO_NODE_QUESTION.get(language, _NO_NODE_QUESTION[None])}"
        ]
        if self.argv:
            parts.append("Command: " + shlex.join(self.argv))
        if self.stderr_tail:
            parts.append("Last lines of its stderr:\n" + _indent(self.stderr_tail))
        if hint:
            parts.append(hint)
        super().__init__("\n".join(parts), target=target)


class TargetTimeout(_WithPartialCapture):
    """The target did not settle within ``timeout`` seconds (it never waited, or kept changing).
    ``diagnosis``: why, told from ``partial``, and what to do (the runner words it:
    ``model.capture_diagnoses.diagnose_unsettled``)."""

    def __init__(
        self,
        target: str,
        timeout: float,
        partial: PartialCapture | None = None,
        stderr_tail: str = "",
        argv: Sequence[str] = (),
        *,
        diagnosis: str = "",
    ) -> None:
        self.timeout = timeout
        self.partial = partial
        #: why it did not settle and what to do (``model.capture_diagnoses.diagnose_unsettled``)
        self.diagnosis = diagnosis
        stderr_tail, self.interrupt_left_out = without_our_interrupt(stderr_tail)
        self.stderr_tail = _tail(stderr_tail)
        self.argv = list(argv)
        parts = [" ".join(filter(None, [f"The target {target} did not settle within {timeout:g} s and was stopped.",
                                        diagnosis]))]
        details = self._process_details()
        if self.interrupt_left_out:
            details.insert(len(details) - 1, "The tool stopped it with SIGINT; the KeyboardInterrupt traceback "
                                             "that printed is left out (it is not the node's own crash).")
        super().__init__("\n".join(parts + details), target=target)


class TargetNotStopped(TargetError):
    """The target was stopped (its timeout passed, or the run was cancelled) and did not end within
    seconds of SIGKILL: it is in uninterruptible sleep (a hung file system or device) or nobody
    reaps it (a warm start server that stopped answering). ``state``: what /proc says of it."""

    def __init__(self, target: str, pid: int, waited: float, state: str, reaper: str) -> None:
        self.pid = pid
        self.state = state
        super().__init__(
            f"The target {target} (pid {pid}) did not end within {waited:g} s of SIGKILL: its state is {state}; "
            f"{reaper}. Nothing more can be done from here: look at that process (`cat /proc/{pid}/stack` as root, "
            "`ps -o pid,stat,wchan -p <pid>`); a process in state D waits for a device or a network file system.",
            target=target)


class StimulusFailed(_WithPartialCapture):
    """A stimulus of the target (option ``stimuli``) did not do what it was asked to: a name matched
    no subscription or service, a delivery was not taken or answered, or the process ended with an
    error after the middleware had delivered one. ``problems``: one line each; ``partial``: the capture."""

    def __init__(
        self,
        target: str,
        problems: Sequence[str],
        partial: PartialCapture | None = None,
        stderr_tail: str = "",
        argv: Sequence[str] = (),
    ) -> None:
        self.problems = list(problems)
        self.partial = partial
        self.stderr_tail = _tail(stderr_tail)
        self.argv = list(argv)
        parts = [f"The stimuli of the target {target} did not work out:"]
        parts += [_indent("- " + problem) for problem in self.problems]
        super().__init__("\n".join(parts + self._process_details()), target=target)


class LifecycleTransitionFailed(_WithPartialCapture):
    """A lifecycle node of the target failed a transition the middleware drove (its callback
    returned FAILURE or ERROR, raised, or never answered): the capture shows it in a state the
    target did not ask for, so it is not compared.

    ``failures``: ``(node, transition, what the middleware recorded, the state to capture it in
    instead)`` per failed node; ``contract``: the contract being checked, when there is one.
    """

    def __init__(
        self,
        target: str,
        failures: Sequence[tuple[str, str, str, str]],
        *,
        wanted: str,
        partial: PartialCapture | None = None,
        stderr_tail: str = "",
        argv: Sequence[str] = (),
        contract: str | None = None,
    ) -> None:
        self.failures = [(node, transition, recorded, instead) for node, transition, recorded, instead in failures]
        self.wanted = wanted
        self.partial = partial
        self.stderr_tail = _tail(stderr_tail)
        self.argv = list(argv)
        self.contract = contract
        where = f"{contract}: " if contract else ""
        parts = []
        for node, transition, recorded, _instead in self.failures:
            parts.append(
                f"{where}lifecycle node {node} of the target {target} failed its {transition} transition: "
                f"{recorded}. It cannot be captured {wanted} as the target asks (`lifecycle: {wanted}`)."
            )
        _node, first_transition, _recorded, first_instead = self.failures[0]
        block = f"the `target:` block of {contract}" if contract else "the target options"
        stderr_note = ("its stderr is below" if self.stderr_tail else
                       "it wrote nothing to stderr; rclpy turns an exception raised in a transition callback "
                       "into ERROR without logging it")
        parts.append(
            f"What to do: fix the node's on_{first_transition} ({stderr_note}), or capture it in the state "
            f"it does reach: set `lifecycle: {first_instead}` in {block} (marker keyword lifecycle=\"{first_instead}\", "
            f"--lifecycle {first_instead}, --rmw-introspect-lifecycle {first_instead}), or `lifecycle: none` to "
            "leave lifecycle nodes alone."
        )
        if self.argv:
            parts.append("Command: " + shlex.join(self.argv))
        if self.stderr_tail:
            parts.append("Last lines of its stderr:\n" + _indent(self.stderr_tail))
        parts.append(self._partial_summary())
        self._target = target
        super().__init__("\n".join(parts), target=target)

    def naming_contract(self, contract: str) -> LifecycleTransitionFailed:
        """The same error, saying which contract was being checked."""
        return LifecycleTransitionFailed(self._target, self.failures, wanted=self.wanted, partial=self.partial,
                                         stderr_tail=self.stderr_tail, argv=self.argv, contract=contract)


class GoldenWriteError(RmwIntrospectError):
    """A contract (or another file the tool writes) could not be written."""

    def __init__(self, path: str | Path, reason: str, advice: str | None = None) -> None:
        self.path = Path(path)
        self.reason = reason
        advice = advice or "Make the file and its directory writable, or write elsewhere."
        super().__init__(f"cannot write {path}: {reason}. {advice}")


class BaselineError(RmwIntrospectError):
    """A baseline file (``--baseline``, ini ``rmw_introspect_baseline``) that cannot be used."""

    def __init__(self, path: str | Path, reason: str) -> None:
        self.path = Path(path)
        self.reason = reason
        super().__init__(
            f"baseline {path}: {reason}. Write it anew with `rmw-introspect check --write-baseline {path} "
            "CONTRACT...` (or `compat --write-baseline`), or leave the baseline out."
        )


class RecordingError(RmwIntrospectError):
    """A recording (``check --bag``: a rosbag2 bag directory, an MCAP or sqlite3 file) that cannot be
    read: the message names the path and what to do."""


class TypeLockError(RmwIntrospectError):
    """A type-hash lockfile (``rmw-introspect lock``) that cannot be written or read."""

    def __init__(self, path: str | Path, reason: str, advice: str | None = None, *, subject: str = "type lock") -> None:
        self.path = Path(path)
        self.reason = reason
        advice = advice or (f"Write it anew with `rmw-introspect lock CONTRACT... -o {path}`, or delete it "
                            "to check without it.")
        super().__init__(f"{subject} {path}: {reason}. {advice}")


class RevisionError(RmwIntrospectError):
    """``diff --against REF`` cannot read the contracts at REF: the directory is not in a git
    repository, REF names no commit, or a shallow clone does not hold it."""


class NoContracts(RevisionError):
    """The gate (``diff --against``, ``pytest --against``) found no contract to compare: an error
    (exit 2) that names where it looked, never a pass on nothing (``check.gate.no_contracts``)."""


class UsageError(RmwIntrospectError):
    """A bad command line or option value (``rmw-introspect``'s arguments, ``--shard``): the
    message says which and what to write; exit status 2."""


class LiveGraphError(RmwIntrospectError):
    """The live check could not read a running graph (``check --live``, ``capture --live``):
    nothing running in the domain, a middleware that is not installed or is the recording one,
    a reader that failed; the message says which and what to do; exit status 2."""


class OptionError(RmwIntrospectError):
    """A comparison option with a value that makes no sense (names where it was set)."""


class LaunchError(TargetConfigError):
    """A launch file that cannot be read: the message names the file and line and what to do."""


class SystemCaptureError(TargetError):
    """Some processes of a system could not be captured: the message lists each one's error under
    its label and where the launch file starts it, then the ``stand_ins:`` block for those that
    failed for lack of a device (``run.system_capture`` words it)."""


# ---------------------------------------------------------------------------- inside the package
# The exceptions below never reach a user as they are: the module that raises one (named in its
# docstring) catches it and says the same in one of the errors above, with the file and what to do
# (or, for Cancelled, Terminated and WarmStartFailed, acts on it).


@dataclass
class InputError(Exception):
    """Untrusted input (a YAML or JSON file, a value) that cannot be read within the limits
    (``model.untrusted``): ``reason``, the ``line`` and ``location`` inside it when known."""

    reason: str
    line: int | None = None
    location: tuple[str | int, ...] = ()

    def __str__(self) -> str:
        return self.reason


@dataclass
class EntryProblem(Exception):
    """A contract parameter entry the JSON Schema lets through but that makes no sense:
    ``location`` inside the node's ``parameters`` list, and the reason."""

    location: list[str | int] = field(default_factory=list)
    reason: str = ""


class UnreadableFile(Exception):
    """Why the file cannot be used (``reason``); the caller names the file and what to do."""

    def __init__(self, reason: str) -> None:
        super().__init__(reason)
        self.reason = reason


class UnhashableType(ValueError):
    """A type whose description is incomplete (a nested type the table lacks) or not a message."""


class SectionError(ValueError):
    """A malformed ``types:`` section: ``location`` is the path inside it (a list)."""

    def __init__(self, location: list[str | int], reason: str) -> None:
        super().__init__(reason)
        self.location = location
        self.reason = reason


class EntityFormatError(Exception):
    """A launch file that is not well-formed; ``line`` when known."""

    def __init__(self, reason: str, line: int | None = None) -> None:
        self.reason = reason
        self.line = line
        super().__init__(reason)


class SubstitutionError(Exception):
    """A substitution that cannot be evaluated (unset variable, unknown package, bad syntax).
    The launch reader adds the file and line."""


class UnsupportedSubstitution(SubstitutionError):
    """A substitution this reader does not evaluate (``$(eval ...)``, ``$(command ...)``, ...)."""

    def __init__(self, name: str, supported: Sequence[str]) -> None:
        self.name = name
        super().__init__(
            f"the substitution $({name} ...) is not supported (supported: "
            + ", ".join(f"$({s})" for s in supported) + ")"
        )


class ComponentParameterError(ValueError):
    """A parameter value a LoadNode request cannot carry (the message says which and why)."""


class WarmStartFailed(Exception):
    """The server could not start the target (it died, or refused): the runner starts it cold."""


class NotEnded(Exception):
    """A process that did not end within KILL_WAIT seconds of SIGKILL (``pid``, its ``state``, and
    who should reap it: ``reaper``)."""

    def __init__(self, pid: int, waited: float, state: str, reaper: str) -> None:
        self.pid, self.waited, self.state, self.reaper = pid, waited, state, reaper
        super().__init__(f"pid {pid} did not end within {waited:g} s of SIGKILL: {state}; {reaper}")


class Cancelled(Exception):
    """The capture was cancelled (its ``cancel`` event was set): its target was stopped."""


class LockTimeout(Exception):
    """A lock (``run.locks``) was not free within the timeout; ``holder``: who holds it, for people
    (``pid 123, T (stopped)``); ``pid``: its pid (None: it wrote none)."""

    def __init__(self, path: Path, timeout: float, holder: str, pid: int | None) -> None:
        self.path, self.timeout, self.holder, self.pid = path, timeout, holder, pid
        super().__init__(f"{path} was held for over {timeout:g} s by {holder}")


class UnsafeLockDirectory(Exception):
    """The lock directory is not one only the calling user can create files in (``args``: the
    reason and the advice of a GoldenWriteError)."""


class Terminated(BaseException):
    """SIGTERM arrived (a CI job cancelled): unwinds like KeyboardInterrupt, so a running target
    is stopped and temporary files are removed on the way out."""
