"""Live systems in pytest (issue 52 item 4): the ``live_system`` fixture and the ``live=True``
keyword of the ``system_contract`` marker.

::

    def test_robot(live_system):
        robot = live_system("launch/robot.launch.xml", launch_arguments={"use_lidar": "true"})
        robot.check("contracts/robot.system.yaml")   # fails the test on drift, as `check --live` would
        assert "/robot1/lidar" in robot.read().capture.nodes

    @pytest.mark.system_contract("contracts/robot.system.yaml", live=True)
    def test_robot_live(system_capture):              # the live graph's Capture
        assert "/robot1/lidar" in system_capture.nodes

A system a test brings up runs on the real middleware (Fast DDS with the wheels) in a
ROS_DOMAIN_ID of its own with localhost discovery (``live.bringup``), and is stopped when the test
ends. The live check is ``check --live``'s (``live.check``): the same rules, thresholds,
``accept:`` entries and notes; its outcome goes through ``verdict`` like every contract test.
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

from ..errors import RmwIntrospectError
from . import verdict
from .session import SessionState, state

if TYPE_CHECKING:  # the live check and the launch readers: imported by the first live test
    from ..live.bringup import RunningSystem
    from ..live.check import LiveCheckResult
    from ..live.graph import LiveGraph


@dataclass
class LiveSystem:
    """A system a test brought up (``system``), and how to check it."""

    item: pytest.Item
    session_state: SessionState
    system: RunningSystem
    graphs: list[LiveGraph] = field(default_factory=list)

    @property
    def domain_id(self) -> int:
        return self.system.domain_id

    def read(self, *, settle: float = 1.0, timeout: float = 30.0, expect: Collection[str] = ()) -> LiveGraph:
        """The running graph, once every node the launch file names is in it (and, for a while,
        ``expect``: the nodes a contract names)."""
        graph = self.system.wait_until_up(timeout=timeout, settle=settle, expect=expect)
        self.graphs.append(graph)
        return graph

    def check(self, contract: str | Path, **options: Any) -> LiveCheckResult:
        """Check ``contract`` (relative to the test file) against the running system with the
        comparison ``options`` on top of the contract's; a failure fails the test with the report."""
        from ..live import check as live_check

        path = Path(contract)
        if not path.is_absolute():
            path = Path(self.item.path).parent / path
        layers = self.session_state.layers(strong_options=[(options, f"live_system().check() of {self.item.nodeid}")])
        graph = self.graphs[-1] if self.graphs else self.read(expect=_named_by(path))
        result = live_check.check_contract(path, graph, layers=layers, shown=self.session_state.display(path))
        verdict.apply(self.item, result, self.session_state)
        return result


def _named_by(path: Path) -> tuple[str, ...]:
    """The nodes the contract at ``path`` names, to wait for (none when it cannot be read: the
    check says why)."""
    from ..live import check as live_check

    try:
        return live_check.expected_nodes([live_check.load(path)])
    except RmwIntrospectError:
        return ()


#: What ``live_system`` returns: call it with a launch file to bring the system up.
BringUp = Callable[..., LiveSystem]


@pytest.fixture
def live_system(request: pytest.FixtureRequest) -> Iterator[BringUp]:
    """A function that brings up a launch file on the real middleware in a domain of its own:
    ``live_system("launch/robot.launch.xml")`` (relative to the test file), or
    ``live_system(package="my_robot", file="robot.launch.xml", launch_arguments={...})``; every
    system it started is stopped when the test ends."""
    from ..live import bringup

    started: list[RunningSystem] = []
    base_dir = Path(request.node.path).parent

    def _bring_up(path: str | Path | None = None, *, package: str | None = None, file: str | None = None,
                  launch_arguments: Mapping[str, Any] | None = None) -> LiveSystem:
        block: dict[str, Any] = {"path": str(path)} if path is not None else {"package": package, "file": file}
        if launch_arguments:
            block["arguments"] = {str(k): v for k, v in launch_arguments.items()}
        try:
            system = bringup.bring_up(block, base_dir=base_dir, ros=state(request.config).ros())
        except RmwIntrospectError as exc:
            verdict.fail_with(request.node, exc)
        started.append(system)
        return LiveSystem(request.node, state(request.config), system)

    yield _bring_up
    for system in started:
        system.stop()


@dataclass
class LiveMarkerState:
    """The ``system_contract(..., live=True)`` marker's running system and the graph read."""

    system: RunningSystem
    graph: LiveGraph
    layers: Any


def bring_up_for_marker(request: pytest.FixtureRequest, path: Path, launch: Mapping[str, Any], base_dir: Path,
                        layers: Any) -> LiveMarkerState:
    """Bring up the marker's contract's launch file (stopped when the test ends) and read it
    (raises an RmwIntrospectError)."""
    from ..live import bringup

    system = bringup.bring_up(launch, base_dir=base_dir, ros=state(request.config).ros())
    request.addfinalizer(system.stop)
    return LiveMarkerState(system=system, graph=system.wait_until_up(expect=_named_by(path)), layers=layers)


def check_marker(item: pytest.Item, path: Path, live: LiveMarkerState, session_state: SessionState) -> None:
    """The marker's live check, as a contract test's outcome."""
    from ..live import check as live_check

    result = live_check.check_contract(path, live.graph, layers=live.layers, shown=session_state.display(path))
    verdict.apply(item, result, session_state)
