"""Stand-ins: processes of a system that are not run where the system is checked.

A robot's bring-up starts drivers that need hardware the CI machine does not have (a lidar on
``/dev/ttyUSB0``, a flight controller on ``/dev/ttyACM0``): there they crash or block. A system
contract names such a process under ``stand_ins:`` and says where its interfaces come from
instead: a node contract captured once on the robot (``rmw-introspect capture``, which runs the
driver for real) or a NoDL document::

    stand_ins:
      - package: my_robot_drivers          # which launched process: package (optional),
        executable: lidar_driver           # executable (required)
        name: /robot1/lidar                # and the node name the launch file gives (optional)
        contract: contracts/lidar.interfaces.yaml   # relative to the system contract
        reason: needs the lidar on /dev/ttyUSB0     # optional, shown by `check`

The system capture does not start that process and takes its nodes from the stand-in
(``run.system_capture``); the system rules treat them as present. The stand-in contract is
loaded and validated like any node contract, and checked on its own where the hardware is.
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from ..errors import ContractError
from . import contract as contract_module
from . import untrusted
from .contract_shapes import ContractNodes, StandInEntry
from .paths import shown

SECTION_KEY = "stand_ins"
KEYS = ("package", "executable", "name", "contract", "reason")

SCHEMA: dict[str, Any] = {
    "description": "Processes of the launch file that are not run where the system is checked (drivers that "
                   "need hardware), and the node contract or NoDL document their interfaces come from instead.",
    "type": ["array", "null"],
    "items": {
        "type": "object",
        "additionalProperties": False,
        "required": ["executable", "contract"],
        "properties": {
            "package": {"type": ["string", "null"], "minLength": 1},
            "executable": {"type": "string", "minLength": 1},
            "name": {"type": ["string", "null"], "pattern": "^/"},
            "contract": {"type": "string", "minLength": 1},
            "reason": {"type": "string", "minLength": 1},
        },
    },
}


@dataclass(frozen=True)
class StandIn:
    """One ``stand_ins:`` entry: which launched process, and the file that stands in for it."""

    executable: str
    contract: str  # as written, relative to the system contract
    package: str | None = None
    name: str | None = None
    reason: str | None = None
    line: int | None = None  # of the entry in the system contract

    def matches(self, package: str | None, executable: str, name: str | None) -> bool:
        """Whether the launched process (``package``, ``executable``, the node name the launch
        file gives) is this one."""
        return (executable == self.executable or Path(executable).name == self.executable) \
            and (self.package is None or package == self.package) and (self.name is None or name == self.name)

    def describe(self) -> str:
        what = f"{self.package}/{self.executable}" if self.package else self.executable
        return f"{what} ({self.name})" if self.name else what


@dataclass(frozen=True)
class StoodIn:
    """A stand-in with the nodes its file describes."""

    stand_in: StandIn
    path: Path
    nodes: ContractNodes = field(default_factory=dict)

    @property
    def shown(self) -> str:
        return shown(self.path)

    def note(self) -> str:
        why = f" ({self.stand_in.reason})" if self.stand_in.reason else ""
        return f"not run here{why}: its nodes {', '.join(sorted(self.nodes)) or 'none'} are taken from {self.shown}"


def from_entries(entries: Sequence[StandInEntry] | None,
                 line_of: Callable[[int], int | None] = lambda i: None) -> tuple[StandIn, ...]:
    """The validated ``stand_ins:`` entries (the schema checked their keys and types)."""
    return tuple(StandIn(executable=str(e["executable"]), contract=str(e["contract"]), package=e.get("package"),
                         name=e.get("name"), reason=e.get("reason"), line=line_of(i))
                 for i, e in enumerate(entries or ()))


def load(stand_in: StandIn, index: int, system_path: Path | None) -> StoodIn:
    """Read and validate the file that stands in for a process (raises one ContractError that
    names the system contract, the entry and the stand-in file)."""
    base = system_path.absolute().parent if system_path is not None else Path.cwd()
    path = Path(stand_in.contract).expanduser()
    path = path if path.is_absolute() else base / path
    location = f"{SECTION_KEY}[{index}].contract"
    problem = untrusted.file_problem(path)  # a FIFO or a directory is said as such (issue 50, N27)
    if problem == "does not exist":
        raise ContractError(system_path, location, (
            f"the stand-in for {stand_in.describe()}, {shown(path)}, does not exist: capture it where the hardware "
            f"is (`rmw-introspect capture ... -o {stand_in.contract}` on the robot), or write it as a NoDL document"),
            line=stand_in.line)
    if problem is not None:
        raise ContractError(system_path, location, (
            f"the stand-in for {stand_in.describe()}, {shown(path)}, {problem}: point `contract:` at the node "
            f"contract (.interfaces.yaml) or NoDL document of that process, or replace {shown(path)} with one"),
            line=stand_in.line)
    try:
        contract = contract_module.load(path)
        nodes = contract.nodes
        if contract.nodl is not None and contract.nodl.unnamed and stand_in.name:
            nodes = contract_module.normalize_nodes(contract.nodl.nodes(bound=stand_in.name))
    except ContractError as exc:
        inner = shown(path) + (f":{exc.line}" if exc.line else "") + (f": at {exc.location}" if exc.location else "")
        raise ContractError(system_path, location, (
            f"the stand-in for {stand_in.describe()}, {shown(path)}, is not a valid node contract or NoDL "
            f"document: {inner}: {exc.reason}"), line=stand_in.line) from None
    if not nodes:
        raise ContractError(system_path, location, (
            f"the stand-in for {stand_in.describe()}, {shown(path)}, describes no node: a stand-in gives the "
            "process's nodes"), line=stand_in.line)
    return StoodIn(stand_in, path, copy.deepcopy(nodes))


def load_all(stand_ins: Sequence[StandIn], system_path: Path | None) -> list[StoodIn]:
    """Every stand-in of a system contract, read and validated."""
    return [load(stand_in, i, system_path) for i, stand_in in enumerate(stand_ins)]


def proposal(processes: Sequence[tuple[str | None, str, str | None, str]]) -> str:
    """A ``stand_ins:`` block for processes that failed for lack of a device: (package,
    executable, node name, the device), as YAML text to paste into the system contract."""
    entries = []
    for package, executable, name, device in processes:
        stem = (name or Path(executable).name).strip("/").replace("/", "_")
        entry = {"package": package, "executable": executable, "name": name,
                 "contract": f"contracts/{stem}.interfaces.yaml", "reason": f"needs {device}"}
        entries.append({key: entry[key] for key in KEYS if entry.get(key) is not None})
    return yaml.safe_dump({SECTION_KEY: entries}, sort_keys=False, default_flow_style=False, allow_unicode=True)
