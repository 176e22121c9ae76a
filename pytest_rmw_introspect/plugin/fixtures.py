"""The plugin's fixtures: ``interfaces`` (the marker test's capture), ``rmw_capture`` (capture
any target from a test), and the session's ROS environment and middleware library."""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

import pytest

from ..errors import SetupError
from ..run import runner
from ..run.ros_env import RosEnvironment
from ..run.target import TargetSpec
from . import marker
from .session import state

if TYPE_CHECKING:  # the capture model: imported by the first capture (run.runner)
    from ..model.capture import Capture


@pytest.fixture(scope="session")
def rmw_introspect_ros(pytestconfig: pytest.Config) -> RosEnvironment:
    """The detected ROS 2 environment (``run.ros_env.RosEnvironment``)."""
    try:
        return state(pytestconfig).ros()
    except SetupError as exc:
        pytest.fail(str(exc), pytrace=False)


@pytest.fixture(scope="session")
def rmw_introspect_library(pytestconfig: pytest.Config) -> Path:
    """Path of the recording middleware library (found installed, or built once and cached).

    Fails with one message naming what is missing (ROS 2, a compiler, CMake) and how to
    install it.
    """
    try:
        return state(pytestconfig).library()
    except SetupError as exc:
        pytest.fail(str(exc), pytrace=False)


#: What ``rmw_capture`` returns: call it with target options to capture a target.
CaptureFunction = Callable[..., "Capture"]


@pytest.fixture
def rmw_capture(request: pytest.FixtureRequest) -> CaptureFunction:
    """A function that captures a target: ``rmw_capture(script="node.py", namespace="/a")``.

    Takes the target options as keyword arguments (or a mapping first), relative paths
    being relative to the test file, plus ``include_infrastructure``. Returns a
    :class:`~pytest_rmw_introspect.model.capture.Capture`; raises a ``TargetError`` (which fails
    the test with its message unless the test catches it).
    """
    session_state = state(request.config)
    base_dir = Path(request.node.path).parent

    def _capture(target: TargetSpec | Mapping[str, Any] | None = None, *, include_infrastructure: bool = False,
                 **options: Any) -> Capture:
        if isinstance(target, TargetSpec):
            spec = target.merged(options, base_dir=base_dir, source="rmw_capture()")
        else:
            spec = session_state.layers(strong_target=[(target, base_dir, "rmw_capture()"),
                                                       (options, base_dir, "rmw_capture()")]).target()
        return runner.run(spec, library=session_state.library(), ros=session_state.ros(),
                          include_infrastructure=include_infrastructure)

    return _capture


class UnavailableCapture:
    """Stands in for the capture when capturing failed; the test itself is failed with the
    reason before its body runs. Anything else (a fixture using it) fails with the reason."""

    def __init__(self, error: BaseException) -> None:
        object.__setattr__(self, "_error", error)

    def __getattr__(self, name: str) -> NoReturn:
        pytest.fail(f"the interfaces capture is not available:\n{self._error}", pytrace=False)

    def __getitem__(self, key: object) -> NoReturn:
        self.__getattr__("__getitem__")

    def __contains__(self, key: object) -> bool:
        self.__getattr__("__contains__")

    def __iter__(self) -> Iterator[Any]:
        self.__getattr__("__iter__")

    def __repr__(self) -> str:
        return f"<interfaces capture unavailable: {type(self._error).__name__}>"


@pytest.fixture
def interfaces(request: pytest.FixtureRequest) -> Capture | UnavailableCapture:
    """The :class:`~pytest_rmw_introspect.model.capture.Capture` of the test's target, as named
    by its ``@pytest.mark.interfaces(contract, **options)`` marker. After the test body, the
    capture is compared with the contract (drift fails the test)."""
    item = request.node
    if item.get_closest_marker(marker.MARKER) is None:
        pytest.fail(
            "the `interfaces` fixture needs an @pytest.mark.interfaces(\"contract.yaml\", ...) marker "
            "on the test; to capture without a contract use the `rmw_capture` fixture",
            pytrace=False,
        )
    existing = item.stash.get(marker.ITEM, None)
    if existing is None:
        existing = marker.prepare(item, state(request.config))
        item.stash[marker.ITEM] = existing
    if existing.error is not None:
        return UnavailableCapture(existing.error)
    assert existing.capture is not None
    return existing.capture


@pytest.fixture(autouse=True)
def rmw_introspect_marker_check(request: pytest.FixtureRequest) -> None:
    """Tests with the marker are captured and checked even when they do not ask for ``interfaces``."""
    if request.node.get_closest_marker(marker.MARKER) is not None and "interfaces" not in request.fixturenames:
        request.getfixturevalue("interfaces")
