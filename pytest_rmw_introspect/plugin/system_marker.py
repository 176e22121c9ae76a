"""System contracts in pytest: the ``system_contract`` marker, the ``system_capture`` fixture,
and ``*.system.yaml`` files collected as test items.

::

    @pytest.mark.system_contract("contracts/robot.system.yaml", launch_arguments={"use_lidar": False})
    def test_robot(system_capture):
        assert "/robot1/status_reporter" in system_capture.node_names

The marker's first argument is the system contract (relative to the test file); keyword
arguments: ``launch_arguments`` (on top of the contract's ``launch: arguments``), the
target and comparison options a system contract takes (``model.option_tables``, the rows with
``FrontEnd.SYSTEM``, ``system_fail_on`` among them). Every process of the launch file is captured when the test sets
up; after the test body the system is compared with the contract and the compatibility rules run
(``check.system_pipeline``), with the same outcomes as an ``interfaces`` test:
``--update-golden`` writes the contract, drift or system problems at or above their thresholds
fail the test.

A system contract file collected as a test item (default pattern ``*.system.yaml``) is one
item, ``robot.system.yaml::system``, that does the same without Python.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import pytest

from ..errors import OptionError, RmwIntrospectError
from ..model import system_contract
from ..model.option_tables import COMPARISON, FrontEnd
from ..model.system_contract import SYSTEM_TARGET_KEYS
from . import live_fixtures, verdict
from .fixtures import UnavailableCapture
from .session import SessionState, state

if TYPE_CHECKING:  # the system pipeline and launch readers: imported by the first system test that runs
    from ..check.system_pipeline import SystemPrepared
    from ..model.capture import Capture
    from ..run.system_capture import SystemCapture
    from .live_fixtures import LiveMarkerState

MARKER = "system_contract"
OPTION_KEYS = COMPARISON.names(FrontEnd.SYSTEM)
MARKER_DOC = (
    f"{MARKER}(contract, **options): capture every process the system contract's launch file starts and "
    "compare the system with the contract (path relative to the test file); run the compatibility rules. Keyword "
    f"arguments: launch_arguments, target options ({', '.join(SYSTEM_TARGET_KEYS)}), comparison options "
    f"({', '.join(OPTION_KEYS)}); live=True: bring the launch file up on the real middleware in a domain of its "
    "own and check the running graph instead (`check --live`)."
)
ITEM_NAME = "system"


@dataclass
class SystemItemState:
    prepared: SystemPrepared | None = None
    capture: SystemCapture | Capture | None = None
    error: RmwIntrospectError | None = None
    #: ``live=True`` (issue 52): the system brought up on the real middleware and its graph
    live: LiveMarkerState | None = None


ITEM = pytest.StashKey[SystemItemState]()


def source(item: pytest.Item) -> str:
    return f"@pytest.mark.{MARKER} of {item.nodeid}"


def parse(item: pytest.Item) -> tuple[Path, dict[str, Any], dict[str, Any], dict[str, Any]]:
    """The marker's contract path, launch arguments, target options and comparison options
    (``system_fail_on`` among them; raises OptionError)."""
    marker = item.get_closest_marker(MARKER)
    assert marker is not None
    kwargs = dict(marker.kwargs)
    kwargs.pop("live", None)  # is_live
    where = source(item)
    args = list(marker.args)
    contract = kwargs.pop("contract", None)
    if len(args) + (contract is not None) != 1:
        raise OptionError(f"{where}: give one system contract path, e.g. "
                          f"@pytest.mark.{MARKER}(\"contracts/robot.system.yaml\")")
    contract = args[0] if args else contract
    if not isinstance(contract, (str, os.PathLike)) or not str(contract):
        raise OptionError(f"{where}: the first argument must be the path of the system contract")
    launch_arguments = kwargs.pop("launch_arguments", None) or {}
    if not isinstance(launch_arguments, Mapping):
        raise OptionError(f"{where}: launch_arguments must be a mapping of launch argument names to values")
    unknown = sorted(set(kwargs) - set(SYSTEM_TARGET_KEYS) - set(OPTION_KEYS))
    if unknown:
        raise OptionError(f"{where}: unknown keyword argument(s) {', '.join(unknown)}; known: launch_arguments, "
                          f"{', '.join(SYSTEM_TARGET_KEYS)}, {', '.join(OPTION_KEYS)}")
    path = Path(os.path.expanduser(str(contract)))
    if not path.is_absolute():
        path = Path(item.path).parent / path
    target = {k: v for k, v in kwargs.items() if k in SYSTEM_TARGET_KEYS}
    options = {k: v for k, v in kwargs.items() if k in OPTION_KEYS}
    return path, dict(launch_arguments), target, options


def is_live(item: pytest.Item) -> bool:
    """``live=True``: the launch file runs on the real middleware and is checked live (issue 52)."""
    marker = item.get_closest_marker(MARKER)
    return marker is not None and bool(marker.kwargs.get("live", False))


def prepare(item: pytest.Item, session_state: SessionState,
            request: pytest.FixtureRequest | None = None) -> SystemItemState:
    """Load the marker's system contract and capture every process of its launch file (with
    ``live=True``: bring it up on the real middleware and read its graph)."""
    from ..check import system_pipeline

    st = SystemItemState()
    try:
        path, launch_arguments, target, options = parse(item)
        layers = session_state.layers(strong_target=[(target, Path(item.path).parent, source(item))],
                                      strong_options=[(options, source(item))])
        st.prepared = system_pipeline.prepare(path, layers=layers, launch_arguments=launch_arguments,
                                              shown=session_state.display(path),
                                              ros=session_state.ros)
        if request is not None and is_live(item):  # issue 52 item 4
            launch = st.prepared.launch
            block = {"path": str(launch.path), "arguments": dict(launch.arguments),
                     "allow_unsupported": launch.allow_unsupported}
            st.live = live_fixtures.bring_up_for_marker(request, path, block, Path(item.path).parent, layers)
            st.capture = st.live.graph.capture
        else:
            st.capture = system_pipeline.run_capture(st.prepared, library=session_state.library(),
                                                     ros=session_state.ros())
    except RmwIntrospectError as exc:
        st.error = exc
    return st


def check_system_marker_item(item: pytest.Item, st: SystemItemState, session_state: SessionState) -> None:
    """Compare the test's system capture with its contract and apply the outcome."""
    from ..check import system_pipeline

    assert st.prepared is not None and st.capture is not None
    if st.live is not None:  # live=True (issue 52)
        live_fixtures.check_marker(item, st.prepared.path, st.live, session_state)
        return
    verdict.apply(item, system_pipeline.compare(st.prepared, cast("SystemCapture", st.capture)), session_state)


@pytest.fixture
def system_capture(request: pytest.FixtureRequest) -> SystemCapture | Capture | UnavailableCapture:
    """The :class:`~pytest_rmw_introspect.run.system_capture.SystemCapture` of the test's
    ``@pytest.mark.system_contract(...)``: every process of the launch file and what it created
    (with ``live=True``: the :class:`~pytest_rmw_introspect.model.capture.Capture` of the live graph)."""
    item = request.node
    if item.get_closest_marker(MARKER) is None:
        pytest.fail(f"the `system_capture` fixture needs an @pytest.mark.{MARKER}(\"robot.system.yaml\") marker",
                    pytrace=False)
    existing = item.stash.get(ITEM, None)
    if existing is None:
        existing = prepare(item, state(request.config), request)
        item.stash[ITEM] = existing
    if existing.error is not None:
        return UnavailableCapture(existing.error)
    assert existing.capture is not None
    return existing.capture


@pytest.fixture(autouse=True)
def rmw_introspect_system_marker_check(request: pytest.FixtureRequest) -> None:
    """Tests with the marker are captured and checked even when they do not ask for ``system_capture``."""
    if request.node.get_closest_marker(MARKER) is not None and "system_capture" not in request.fixturenames:
        request.getfixturevalue("system_capture")


# ---------------------------------------------------------------------------- contract files


class SystemContractFile(pytest.File):
    """A system contract file: one :class:`SystemContractItem`."""

    def collect(self) -> Iterator[pytest.Item]:
        try:
            system_contract.load(self.path)
        except RmwIntrospectError as exc:
            yield SystemContractItem.from_parent(self, name="invalid", load_error=exc)
            return
        yield SystemContractItem.from_parent(self, name=ITEM_NAME)


class SystemContractItem(pytest.Item):
    """Captures every process of the system contract's launch file and checks the system."""

    def __init__(self, *, load_error: RmwIntrospectError | None = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.load_error = load_error

    def runtest(self) -> None:
        from ..check import system_pipeline

        if self.load_error is not None:
            verdict.fail_with(self, self.load_error)
        session_state = state(self.config)
        error: RmwIntrospectError | None = None
        try:
            prepared = system_pipeline.prepare(self.path, layers=session_state.layers(),
                                               shown=session_state.display(self.path), ros=session_state.ros)
            capture = system_pipeline.run_capture(prepared, library=session_state.library(), ros=session_state.ros())
        except RmwIntrospectError as exc:
            error = exc
        if error is not None:
            verdict.fail_with(self, error)
        verdict.apply(self, system_pipeline.compare(prepared, capture), session_state)

    def reportinfo(self) -> tuple[Path, int, str]:
        return self.path, 0, f"system contract {self.path.name}"
