"""System captures: every process a launch file starts, captured on the recording middleware.

:func:`resolve_launch` turns a system contract's ``launch:`` block (or the command line's
``--launch``) into a :class:`LaunchSpec`; :func:`capture_system` reads the launch file
(``launch.reader``), runs every process it starts through the runner (``runner.run``: its own
capture file, settle, virtual time, timeout), in parallel with at most as many processes at a
time as the machine has cores, each with the command line, parameters, remappings and
environment the launch file gives it, and returns a :class:`SystemCapture`.

A process that runs but creates no node is part of the result (the compatibility rule
``LAUNCHED_NODE_NOT_CREATED`` reports it); a process that cannot be captured (not found,
crashes, hangs) makes the whole capture a :class:`SystemCaptureError` listing every such
process, with a ``stand_ins:`` block to add for those that failed for lack of a device
(:func:`device_of`). A process a stand-in names (``model.stand_ins``: a driver that needs
hardware) is not started: its nodes are the stand-in's. No data moves between the processes, so capturing them apart is the same as
capturing them together.
"""

from __future__ import annotations

import copy
import os
import shlex
import shutil
import tempfile
import threading
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, cast

from ..errors import Cancelled, InputError, LaunchError, NoNodeCreated, SystemCaptureError, TargetConfigError, TargetError
from ..launch import component_loads
from ..launch import reader as launch_reader
from ..launch.result import LaunchedNode, LaunchParameter, LaunchResult
from ..model import stand_ins as stand_in_model
from ..model import untrusted
from ..model.capture import Capture
from ..model.contract_shapes import ContractNode, ContractNodes, LaunchBlock, ProcessEntry, TargetBlock
from ..model.paths import shown
from ..model.portable import device_paths_in
from ..model.stand_ins import StoodIn
from ..model.unstable_names import NODE_KEY as UNSTABLE_NAME
from ..model.unstable_names import NameRules, contract_keys
from ..model.vocabulary import DESTROYED_AT, LIFECYCLE, PARAMETERS
from . import middleware, progress, ros_env, runner
from .target import TargetSpec

#: keys of a ``launch:`` block
LAUNCH_KEYS = ("package", "file", "path", "arguments", "allow_unsupported")


@dataclass(frozen=True)
class LaunchSpec:
    """A launch file to start, with its arguments."""

    path: Path
    arguments: Mapping[str, str] = field(default_factory=dict)
    allow_unsupported: bool = False
    package: str | None = None
    file: str | None = None

    def describe(self) -> str:
        where = f"{self.package} {self.file}" if self.package else shown(self.path)
        args = " ".join(f"{k}:={shlex.quote(v)}" for k, v in self.arguments.items())
        return f"launch {where}" + (f" {args}" if args else "")

    def to_block(self, base: Path | None = None) -> LaunchBlock:
        """The ``launch:`` block of a system contract (``path`` relative to ``base``)."""
        block = LaunchBlock()
        if self.package:
            block["package"] = self.package
            if self.file is not None:
                block["file"] = self.file
        else:
            block["path"] = os.path.relpath(self.path, base) if base is not None else str(self.path)
        if self.arguments:
            block["arguments"] = dict(self.arguments)
        if self.allow_unsupported:
            block["allow_unsupported"] = True
        return block


def ament_prefixes(ros: ros_env.RosEnvironment | None = None) -> list[Path]:
    """The prefixes ``$(find-pkg-share)`` and ``ros2 launch PACKAGE`` search: AMENT_PREFIX_PATH,
    then those of the detected install."""
    return ros_env.ament_prefixes(tuple(getattr(ros, "ament_prefixes", ()) or ()))


def resolve_launch(block: Mapping[str, Any], *, base_dir: str | Path | None, source: str,
                   prefixes: Sequence[Path]) -> LaunchSpec:
    """A ``launch:`` block → :class:`LaunchSpec` (raises TargetConfigError / LaunchError)."""
    unknown = sorted(set(block) - set(LAUNCH_KEYS))
    if unknown:
        raise TargetConfigError(f"{source}: unknown launch key(s) {', '.join(unknown)}; known: {', '.join(LAUNCH_KEYS)}")
    arguments = block.get("arguments") or {}
    if not isinstance(arguments, Mapping):
        raise TargetConfigError(f"{source}: `arguments` must be a mapping of launch argument names to values")
    args = {str(k): launch_reader.argument_text(v) for k, v in arguments.items()}
    allow = bool(block.get("allow_unsupported", False))
    if block.get("path") is not None:
        path = Path(os.path.expanduser(str(block["path"])))
        if not path.is_absolute() and base_dir is not None:
            path = Path(base_dir) / path
        return LaunchSpec(path=path.absolute(), arguments=args, allow_unsupported=allow)
    package, file = block.get("package"), block.get("file")
    if not package or not file:
        raise TargetConfigError(f"{source}: name the launch file with `package` and `file` (like ros2 launch) "
                                "or with `path`")
    path = launch_reader.launch_file_of_package(str(package), str(file), prefixes)
    return LaunchSpec(path=path, arguments=args, allow_unsupported=allow, package=str(package), file=str(file))


@dataclass
class ProcessCapture:
    """One process of a system: what the launch file says, and its capture (None when it
    created no node: ``no_node`` says how it ended)."""

    launched: LaunchedNode
    label: str
    capture: Capture | None = None
    no_node: NoNodeCreated | None = None
    #: not run here: its nodes come from this stand-in (``model.stand_ins``)
    stood_in: StoodIn | None = None

    @property
    def node_names(self) -> list[str]:
        if self.stood_in is not None:
            return sorted(self.stood_in.nodes)
        return self.capture.node_names if self.capture is not None else []

    @property
    def named_by_launch(self) -> frozenset[str]:
        """The node name the launch file gives this process (stable by construction: never a
        pattern of ``model.unstable_names``)."""
        return frozenset({self.launched.expected_fqn} if self.launched.expected_fqn else ())

    def contract_nodes(self, *, with_type_hash: bool = True, with_qos: bool = True) -> ContractNodes:
        if self.stood_in is not None:
            return _without(self.stood_in.nodes, () if with_type_hash else ("type_hash",),
                            () if with_qos else ("qos",))
        if self.capture is None:
            return {}
        return self.capture.to_contract_nodes(with_type_hash=with_type_hash, with_qos=with_qos,
                                              names=NameRules(stable=self.named_by_launch))

    def entry(self, node_keys: Sequence[str] | None = None) -> ProcessEntry:
        """This process in a system contract's ``processes:`` block (``node_keys``: its nodes'
        keys in the contract; default their names)."""
        launched = self.launched
        nodes = sorted(node_keys) if node_keys is not None else self.node_names
        if launched.package:
            return {"package": launched.package, "executable": launched.executable, "name": launched.expected_fqn,
                    "nodes": nodes}
        return {"executable": launched.executable, "name": launched.expected_fqn, "nodes": nodes}


@dataclass
class SystemCapture:
    """Every process of a system and what it created."""

    spec: LaunchSpec
    launch: LaunchResult
    processes: list[ProcessCapture]

    def keyed_nodes(self, *, with_type_hash: bool = True, with_qos: bool = True,
                    names: NameRules | None = None) -> list[list[tuple[str, ContractNode]]]:
        """Per process, each of its nodes with its key in the contract (``unstable_names``: a
        name that changes every run under its pattern, the nodes of one pattern in all processes
        compared as a set; the names the launch file gives are kept)."""
        named: list[tuple[str, ContractNode, int | None]] = []
        owners: list[int] = []
        for index, process in enumerate(self.processes):
            if process.capture is not None:
                found = process.capture.named_contract_nodes(with_type_hash=with_type_hash, with_qos=with_qos)
                named += found
                owners += [index] * len(found)
        rules = names or NameRules()
        rules = replace(rules, stable=rules.stable.union(*(p.named_by_launch for p in self.processes)))
        out: list[list[tuple[str, ContractNode]]] = [[] for _ in self.processes]
        for owner, keyed in zip(owners, contract_keys(named, rules), strict=True):
            out[owner].append(keyed)
        for index, process in enumerate(self.processes):
            if process.stood_in is not None:  # a stand-in's contract names its nodes as they are
                out[index] = sorted(process.contract_nodes(with_type_hash=with_type_hash, with_qos=with_qos).items())
        return out

    def to_contract_nodes(self, *, with_type_hash: bool = True, with_qos: bool = True,
                          names: NameRules | None = None) -> ContractNodes:
        """All nodes of the system (a node name held by several processes: the union of their
        interfaces and parameters, the first one's lifecycle state, and ``destroyed_at`` only when
        every holder destroyed it: the latest, since the name lived until then)."""
        merged: dict[str, dict[str, Any]] = {}
        for process_nodes in self.keyed_nodes(with_type_hash=with_type_hash, with_qos=with_qos, names=names):
            for fqn, node in process_nodes:
                first = fqn not in merged
                into = merged.setdefault(fqn, {})
                keys: Mapping[str, Any] = node  # merged key by key, whatever the key
                if not first and DESTROYED_AT not in keys:  # this holder lived on
                    into.pop(DESTROYED_AT, None)
                for key, value in keys.items():
                    if key == DESTROYED_AT:
                        if first or DESTROYED_AT in into:
                            into[key] = max(value, into.get(key, value))
                    elif key in (LIFECYCLE, UNSTABLE_NAME):
                        into.setdefault(key, value)
                    elif key == PARAMETERS:
                        have = {e["name"] for e in into.setdefault(key, [])}
                        into[key] = sorted([*into[key], *(e for e in value if e["name"] not in have)],
                                           key=lambda e: e["name"])
                    else:
                        for entry in value:
                            if entry not in into.setdefault(key, []):
                                into[key].append(entry)
        # the union of contract nodes is a contract node
        return {fqn: cast(ContractNode, merged[fqn]) for fqn in sorted(merged)}

    def process_entries(self, names: NameRules | None = None) -> list[ProcessEntry]:
        return [p.entry([key for key, _node in keyed]) for p, keyed in zip(self.processes, self.keyed_nodes(names=names), strict=True)]

    @property
    def node_names(self) -> list[str]:
        return sorted({n for p in self.processes for n in p.node_names})

    @property
    def stood_in(self) -> list[ProcessCapture]:
        """The processes not run here, their nodes taken from a stand-in."""
        return [p for p in self.processes if p.stood_in is not None]

    def notes(self) -> list[str]:
        notes = [f"not captured ({u.where}): {u.what}" for u in self.launch.unsupported]
        for process in self.processes:
            if process.stood_in is not None:
                notes.append(f"{process.label} ({process.launched.where}) stood in for: {process.stood_in.note()}")
            elif process.capture is not None:
                notes += [f"{process.label}: {note}" for note in process.capture.notes()]
            elif process.no_node is not None:
                stderr = process.no_node.stderr_tail.strip().splitlines()
                device = device_of(process.launched, str(process.no_node))
                notes.append(f"{process.label} ({process.launched.where}) created no node"
                             + (f"; the end of its stderr: {stderr[-1]}" if stderr else "")
                             + (f"; it needs {device}, which this machine lacks: stand in for it (`stand_ins:`, "
                                "docs/system-contracts.md, \"Hardware processes\")" if device else ""))
        return notes

    def stand_in_proposal(self) -> str:
        """The ``stand_ins:`` block for the processes that created no node for lack of a device."""
        return _stand_in_proposal([(p, p.no_node) for p in self.processes if p.no_node is not None])

    def summary(self) -> str:
        lines = [f"{self.spec.describe()}: {len(self.processes)} process(es), {len(self.node_names)} node(s)"]
        lines += [f"note: {note}" for note in self.notes()]
        for process in self.processes:
            lines.append(f"{process.label} ({process.launched.where}): {', '.join(process.node_names) or 'no node'}")
        return "\n".join(lines)


def _capture_failed(spec: LaunchSpec, failures: Sequence[tuple[ProcessCapture, TargetError]], total: int) -> SystemCaptureError:
    """The error of a system capture some of whose processes could not be captured: each one's
    error under its label and where it was started, then the ``stand_ins:`` block for those that
    failed for lack of a device."""
    parts = [f"{len(failures)} of the {total} processes of `{spec.describe()}` could not be captured:"]
    for process, error in failures:
        parts.append(f"\n[{process.label}] started at {process.launched.where}:\n" + _indent(str(error)))
    proposal = _stand_in_proposal(failures)
    if proposal:
        parts.append("\n" + STAND_IN_ADVICE + "\n" + _indent(proposal.rstrip("\n")))
    return SystemCaptureError("\n".join(parts), target=spec.describe())


#: what to do with a ``stand_ins:`` proposal
STAND_IN_ADVICE = (
    "A process that needs hardware this machine lacks can be stood in for (docs/system-contracts.md, \"Hardware "
    "processes\"): capture it once where the hardware is (`rmw-introspect capture ... -o FILE` on the robot, FILE "
    "as named below), then add this block to the system contract above `processes:` (no contract yet: write one "
    "with `system_version: 1`, the `launch:` block and this block, and run `rmw-introspect check FILE --update`):")

def device_of(process: LaunchedNode, error_text: str) -> str | None:
    """The device a process that failed probably lacks: a ``/dev/...`` path that is not on this
    machine, named in its error output or in the parameters the launch file gives it."""
    candidates = device_paths_in(error_text)
    for parameter in process.parameters:
        candidates += device_paths_in(str(parameter.value)) if parameter.value is not None else []
        candidates += device_paths_in(parameter.file_text or "")
        if parameter.file is not None:
            try:
                candidates += device_paths_in(untrusted.read_text(Path(parameter.file)))
            except (OSError, InputError):
                pass
    candidates += [m for word in process.ros_arguments for m in device_paths_in(word)]
    return next((c for c in candidates if not os.path.exists(c)), None)


def _stand_in_proposal(failures: Sequence[tuple[ProcessCapture, Exception]]) -> str:
    """The ``stand_ins:`` block for the processes of ``failures`` (with their errors) that lack a
    device ("" when none does)."""
    lacking = []
    for process, error in failures:
        device = device_of(process.launched, str(error))
        if device is not None:
            launched = process.launched
            lacking.append((launched.package, launched.executable, launched.expected_fqn, device))
    return stand_in_model.proposal(lacking) if lacking else ""


def _without(nodes: ContractNodes, *dropped: Sequence[str]) -> ContractNodes:
    """A copy of ``nodes`` without the ``dropped`` keys of their interface entries."""
    keys = {key for group in dropped for key in group}
    out: dict[str, Any] = copy.deepcopy(dict(nodes))
    if keys:
        for node in out.values():
            for value in node.values():
                if isinstance(value, list):
                    for entry in value:
                        if isinstance(entry, dict):
                            for key in keys:
                                entry.pop(key, None)
    return cast(ContractNodes, out)


def _indent(text: str) -> str:
    return "\n".join("    " + line for line in text.splitlines())


def labels(processes: Sequence[tuple[str | None, str]]) -> list[str]:
    """A short unique label per process from its (package, executable): ``package/executable``
    (``#2``, ``#3`` when repeated)."""
    out: list[str] = []
    seen: dict[str, int] = {}
    for package, executable in processes:
        base = f"{package}/{executable}" if package else os.path.basename(executable)
        seen[base] = seen.get(base, 0) + 1
        out.append(base if seen[base] == 1 else f"{base} #{seen[base]}")
    return out


def process_spec(node: LaunchedNode, base: TargetSpec, params_dir: Path) -> TargetSpec:
    """The target of one launched process: the launch file's command line on top of the
    system's process-wide options (``base``: settle, timeout, horizon, lifecycle, read_parameters, env)."""
    counter = [0]

    def params_file(parameter: LaunchParameter) -> Path:
        counter[0] += 1
        path = params_dir / f"params_{counter[0]}.yaml"
        path.write_text(parameter.file_text or "", encoding="utf-8")
        return path

    env = {**base.env, **node.env}
    if node.components:  # the container's middleware loads them (component_loads)
        counter[0] += 1
        requests = params_dir / f"component_loads_{counter[0]}.txt"
        requests.write_text(component_loads.requests_text(node.expected_fqn or "", node.components), encoding="utf-8")
        env[component_loads.VARIABLE] = str(requests)
    options: TargetBlock = {"env": env} if env else {}
    if node.cwd is not None:
        options["cwd"] = str(node.cwd)
    if node.command is not None:
        options["command"] = list(node.command)
    elif node.package:
        options["package"] = node.package
        options["executable"] = node.executable
        options["arguments"] = [*node.arguments, *node.ros_argument_list(params_file)]
    else:
        options["command"] = [node.executable, *node.arguments, *node.ros_argument_list(params_file)]
    spec = TargetSpec(settle=base.settle, timeout=base.timeout, horizon=base.horizon, lifecycle=base.lifecycle,
                      read_parameters=base.read_parameters)
    return spec.merged(options, source=f"launch file {node.where}")


#: seconds between two lines of a long system capture's progress
PROGRESS_EVERY = 5.0
#: a system capture is said on the terminal once it has lasted this long (most take less: silence)
SAID_AFTER = 2.0


def _results(pool: ThreadPoolExecutor, run_one: Callable[[int], TargetError | None], count: int,
             step: progress.LateStep) -> list[TargetError | None]:
    """Each process's error (or None), in the launch file's order; ``step`` says the capture if it
    lasts (:data:`SAID_AFTER`), then how many processes are captured every few seconds."""
    futures = [pool.submit(run_one, i) for i in range(count)]
    pending = set(futures)
    while pending:
        _, pending = wait(pending, timeout=step.wait_for(), return_when=FIRST_COMPLETED)
        if pending:  # (the last one is said by the step's end line)
            step.tick(f"captured {count - len(pending)} of {count} processes, "
                      f"{progress.seconds(step.elapsed())} so far")
    return [future.result() for future in futures]


def capture_system(
    spec: LaunchSpec,
    *,
    target: TargetSpec | None = None,
    library: str | Path | None = None,
    ros: ros_env.RosEnvironment | None = None,
    include_infrastructure: bool = False,
    jobs: int | None = None,
    launch: LaunchResult | None = None,
    stand_ins: Sequence[StoodIn] = (),
) -> SystemCapture:
    """Read ``spec``'s launch file and capture every process it starts (raises LaunchError,
    SystemCaptureError, SetupError). ``target``: process-wide options (settle, timeout,
    horizon, env); ``jobs``: processes at a time (default: the number of cores);
    ``stand_ins``: processes not to start, their nodes taken from the stand-in instead."""
    ros = ros or ros_env.detect()
    if library is None:
        library = middleware.ensure_library(ros)
    if launch is None:
        launch = launch_reader.read(spec.path, spec.arguments, prefixes=ament_prefixes(ros))
    if not spec.allow_unsupported:
        launch.require_supported()
    if not launch.nodes:
        raise LaunchError(f"{shown(spec.path)} starts no node (with the arguments given: "
                                        f"{dict(spec.arguments) or 'none'})")
    base = target or TargetSpec()
    names = labels([(n.package, n.executable) for n in launch.nodes])
    processes = [ProcessCapture(node, label) for node, label in zip(launch.nodes, names, strict=True)]
    _stand_in_for(processes, stand_ins, spec)
    params_dir = Path(tempfile.mkdtemp(prefix="rmw_introspect_params_"))
    try:
        specs = []
        for i, process in enumerate(processes):
            directory = params_dir / str(i)
            directory.mkdir()
            specs.append(process_spec(process.launched, base, directory))

        cancel = threading.Event()

        def run_one(index: int) -> TargetError | None:
            if processes[index].stood_in is not None:
                return None
            try:
                processes[index].capture = runner.run(specs[index], library=library, ros=ros,
                                                      include_infrastructure=include_infrastructure, cancel=cancel)
            except NoNodeCreated as exc:
                processes[index].no_node = exc
            except TargetError as exc:
                return exc
            except Cancelled:
                return None  # the capture as a whole is being abandoned
            return None

        workers = max(1, min(len(processes) - len([p for p in processes if p.stood_in]) or 1,
                             jobs or os.cpu_count() or 2))
        pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="rmw-introspect-system")
        step = progress.LateStep(f"capturing the {len(processes)} processes of {shown(spec.path)}, {workers} at a time",
                                 f"captured the {len(processes)} processes of {shown(spec.path)} in {{time}}",
                                 f"capturing the processes of {shown(spec.path)} ended",
                                 after=SAID_AFTER, every=PROGRESS_EVERY)
        try:
            errors = _results(pool, run_one, len(processes), step)
            step.end(ok=True)
        except BaseException:
            # Ctrl-C or SIGTERM (the CLI's Terminated) reaches this thread only: the workers' targets
            # are stopped now and the processes not started yet never start, instead of each
            # running until its timeout while the pool is shut down
            step.end(ok=False)
            cancel.set()
            raise
        finally:
            pool.shutdown(wait=True, cancel_futures=True)
    finally:
        shutil.rmtree(params_dir, ignore_errors=True)
    failures = [(p, e) for p, e in zip(processes, errors, strict=True) if e is not None]
    if failures:
        raise _capture_failed(spec, failures, len(processes))
    return SystemCapture(spec=spec, launch=launch, processes=processes)


def _stand_in_for(processes: Sequence[ProcessCapture], stand_ins: Sequence[StoodIn], spec: LaunchSpec) -> None:
    """Give each process a stand-in names its stand-in (raises TargetConfigError for a stand-in
    that names no process the launch file starts)."""
    for stood_in in stand_ins:
        wanted = stood_in.stand_in
        matched = [p for p in processes
                   if wanted.matches(p.launched.package, p.launched.executable, p.launched.expected_fqn)]
        if not matched:
            started = "; ".join(f"{p.label} ({p.launched.expected_fqn or 'its own node name'})" for p in processes)
            raise TargetConfigError(
                f"the stand-in for {wanted.describe()} ({stood_in.shown}) names no process that `{spec.describe()}` "
                f"starts; it starts: {started}. Fix `package`, `executable` or `name` of the `stand_ins:` entry")
        for process in matched:
            process.stood_in = stood_in
