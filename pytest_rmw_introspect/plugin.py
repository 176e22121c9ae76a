"""pytest entry point of pytest-rmw-introspect: options, the ``interfaces`` marker, fixtures, hooks.

Usage::

    @pytest.mark.interfaces("contracts/talker.yaml", script="nodes/talker.py")
    def test_talker(interfaces):
        assert "/talker" in interfaces          # the test may assert more

The marker's first argument is the golden contract, relative to the test file. Its keyword
arguments are target options (``target.TARGET_KEYS``; they override the contract's
``target:`` block) and comparison options (``options.OPTION_KEYS``). The target is captured
when the test sets up (``interfaces`` fixture). After the test body passed, the capture is
compared with the contract inside the test's *call* phase, so drift is a test failure whose
message is the drift report, ending with the command that accepts the change.

Problems the user can cause (no target, a malformed contract, a target that crashes,
hangs or creates no node, ROS 2 or the middleware missing) fail the test with a message
that says what to do; they are never internal errors.

Precedence of comparison options: marker > contract ``options:`` > command line > ini.
Precedence of target options: marker > contract ``target:`` > command line > ini
(``timeout``/``settle``/``horizon`` only on the command line and in the ini file).
"""

from __future__ import annotations

import json
import os
import shlex
import textwrap
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest

from . import golden as golden_module
from .errors import RmwIntrospectError, SetupError, TargetConfigError
from .options import OPTION_KEYS, ComparisonOptions, OptionError, parse_layer
from .target import TARGET_KEYS, TargetSpec

MARKER = "interfaces"
#: user property with the drift items as JSON (report.to_json + contract), for JUnit XML
DRIFT_PROPERTY = "rmw_introspect_drift"

_MARKER_DOC = (
    f"{MARKER}(contract, **options): capture the test's target on the recording middleware and "
    "compare it with the golden contract (path relative to the test file). Keyword arguments: "
    f"target options ({', '.join(TARGET_KEYS)}) and comparison options ({', '.join(OPTION_KEYS)})."
)


# ---------------------------------------------------------------------------- session state


@dataclass
class _SessionState:
    update: bool
    cli_options: dict[str, Any]
    ini_options: dict[str, Any]
    cli_target: dict[str, Any]
    ini_target: dict[str, Any]
    golden: golden_module.GoldenSession
    _ros: Any = None
    _library: Path | None = None
    _setup_error: SetupError | None = None

    def ros(self) -> Any:
        self._setup()
        return self._ros

    def library(self) -> Path:
        self._setup()
        assert self._library is not None
        return self._library

    def _setup(self) -> None:
        if self._setup_error is not None:
            raise self._setup_error
        if self._library is not None:
            return
        from . import middleware, ros_env

        try:
            self._ros = ros_env.detect()
            self._library = Path(middleware.ensure_library(self._ros))
        except SetupError as exc:
            self._setup_error = exc
            raise


_SESSION = pytest.StashKey[_SessionState]()


@dataclass
class _ItemState:
    contract_path: Path | None = None
    contract: Any = None  # contract.Contract | None (missing golden)
    options: ComparisonOptions = field(default_factory=ComparisonOptions)
    spec: TargetSpec | None = None
    capture: Any = None
    error: RmwIntrospectError | None = None
    prepared: Any = None  # checking.Prepared


_ITEM = pytest.StashKey[_ItemState]()


def _state(config: pytest.Config) -> _SessionState:
    return config.stash[_SESSION]


# ---------------------------------------------------------------------------- options


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("rmw-introspect", "interface contracts of ROS 2 nodes (pytest-rmw-introspect)")
    group.addoption(
        "--update-golden",
        action="store_true",
        default=False,
        help="rewrite the golden contracts of the selected tests that drifted and create missing "
        "ones (refused when the CI environment variable is set)",
    )
    group.addoption(
        "--rmw-introspect-fail-on",
        choices=("any", "risky", "breaking"),
        default=None,
        help="least severe interface drift that fails a test (default: ini rmw_introspect_fail_on, any)",
    )
    group.addoption(
        "--rmw-introspect-ignore-type-hash",
        action="store_true",
        default=None,
        help="do not compare type hashes",
    )
    group.addoption(
        "--rmw-introspect-ignore-qos",
        default=None,
        metavar="FIELDS",
        help="QoS fields not to compare: comma-separated names (depth,history) or 'all'",
    )
    group.addoption(
        "--rmw-introspect-allow-extra",
        action="store_true",
        default=None,
        help="interfaces and nodes the contract does not list are not drift",
    )
    group.addoption(
        "--rmw-introspect-include-infrastructure",
        action="store_true",
        default=None,
        help="also compare /rosout, /parameter_events, parameter and lifecycle services",
    )
    group.addoption("--rmw-introspect-timeout", type=float, default=None, metavar="SECONDS",
                    help="default time a target gets to settle (default 20)")
    group.addoption("--rmw-introspect-settle", type=float, default=None, metavar="SECONDS",
                    help="default settle time of targets (default 0.1)")
    group.addoption("--rmw-introspect-horizon", type=float, default=None, metavar="SECONDS",
                    help="default virtual-time horizon of targets: seconds of a node's life a capture "
                    "observes, timers firing at once (default 10; 0 turns virtual time off)")

    group.addoption(
        "--rmw-introspect-contracts",
        default=None,
        metavar="GLOBS",
        help="contract files collected as test items: glob patterns, comma-separated "
        "(default: ini rmw_introspect_contracts, *.interfaces.yaml; 'none' turns it off)",
    )
    parser.addini("rmw_introspect_contracts", "glob patterns of contract files collected as test items "
                  "('none' turns it off)", type="args", default=["*.interfaces.yaml"])
    parser.addini("rmw_introspect_ignore_type_hash", "do not compare type hashes", type="bool", default=False)
    parser.addini("rmw_introspect_ignore_qos", "QoS fields not to compare (list, or 'all')", type="args", default=[])
    parser.addini("rmw_introspect_allow_extra", "interfaces the contract does not list are not drift",
                  type="bool", default=False)
    parser.addini("rmw_introspect_include_infrastructure", "compare infrastructure endpoints too",
                  type="bool", default=False)
    parser.addini("rmw_introspect_fail_on", "least severe drift that fails: any | risky | breaking", default="any")
    parser.addini("rmw_introspect_timeout", "default target timeout in seconds", default="")
    parser.addini("rmw_introspect_settle", "default target settle time in seconds", default="")
    parser.addini("rmw_introspect_horizon", "default target virtual-time horizon in seconds (0: off)", default="")


def _ini_float(config: pytest.Config, name: str) -> float | None:
    raw = str(config.getini(name) or "").strip()
    if not raw:
        return None
    try:
        return float(raw)
    except ValueError:
        raise pytest.UsageError(f"ini option {name} = {raw!r} is not a number of seconds") from None


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line("markers", _MARKER_DOC)
    update = bool(config.getoption("update_golden", False))
    if update:
        refusal = golden_module.ci_refusal()
        if refusal:
            raise pytest.UsageError(refusal)

    ini_qos = config.getini("rmw_introspect_ignore_qos")
    ini_raw = {
        "ignore_type_hash": config.getini("rmw_introspect_ignore_type_hash"),
        "ignore_qos": (ini_qos[0] if len(ini_qos) == 1 else list(ini_qos)) if ini_qos else None,
        "allow_extra": config.getini("rmw_introspect_allow_extra"),
        "include_infrastructure": config.getini("rmw_introspect_include_infrastructure"),
        "fail_on": config.getini("rmw_introspect_fail_on") or None,
    }
    cli_raw = {
        "ignore_type_hash": config.getoption("rmw_introspect_ignore_type_hash", None),
        "ignore_qos": config.getoption("rmw_introspect_ignore_qos", None),
        "allow_extra": config.getoption("rmw_introspect_allow_extra", None),
        "include_infrastructure": config.getoption("rmw_introspect_include_infrastructure", None),
        "fail_on": config.getoption("rmw_introspect_fail_on", None),
    }
    try:
        ini_options = parse_layer(ini_raw, "ini file")
        cli_options = parse_layer(cli_raw, "command line")
    except OptionError as exc:
        raise pytest.UsageError(str(exc)) from None

    ini_target = {key: _ini_float(config, f"rmw_introspect_{key}") for key in ("timeout", "settle", "horizon")}
    cli_target = {key: config.getoption(f"rmw_introspect_{key}", None) for key in ("timeout", "settle", "horizon")}
    try:
        TargetSpec.from_mapping(ini_target, source="ini file").merged(cli_target, source="command line")
    except TargetConfigError as exc:
        raise pytest.UsageError(str(exc)) from None

    state = _SessionState(
        update=update,
        cli_options=cli_options,
        ini_options=ini_options,
        cli_target={k: v for k, v in cli_target.items() if v is not None},
        ini_target={k: v for k, v in ini_target.items() if v is not None},
        golden=golden_module.GoldenSession(enabled=update),
    )
    config.stash[_SESSION] = state
    config.pluginmanager.register(_GoldenReporter(state), "rmw-introspect-golden-reporter")


def pytest_report_header(config: pytest.Config) -> list[str] | None:
    state = config.stash.get(_SESSION, None)
    if state is not None and state.update:
        return ["rmw-introspect: --update-golden: drifted and missing golden contracts will be written"]
    return None


# ---------------------------------------------------------------------------- fixtures


@pytest.fixture(scope="session")
def rmw_introspect_ros(pytestconfig: pytest.Config) -> Any:
    """The detected ROS 2 environment (``ros_env.RosEnvironment``)."""
    try:
        return _state(pytestconfig).ros()
    except SetupError as exc:
        pytest.fail(str(exc), pytrace=False)


@pytest.fixture(scope="session")
def rmw_introspect_library(pytestconfig: pytest.Config) -> Path:
    """Path of the recording middleware library (found installed, or built once and cached).

    Fails with one message naming what is missing (ROS 2, a compiler, CMake) and how to
    install it.
    """
    try:
        return _state(pytestconfig).library()
    except SetupError as exc:
        pytest.fail(str(exc), pytrace=False)


def _base_spec(state: _SessionState, rootdir: Path) -> TargetSpec:
    spec = TargetSpec.from_mapping(state.ini_target, base_dir=rootdir, source="ini file")
    return spec.merged(state.cli_target, base_dir=rootdir, source="command line")


@pytest.fixture
def rmw_capture(request: pytest.FixtureRequest) -> Callable[..., Any]:
    """A function that captures a target: ``rmw_capture(script="node.py", namespace="/a")``.

    Takes the target options as keyword arguments (or a mapping first), relative paths
    being relative to the test file, plus ``include_infrastructure``. Returns a
    :class:`~pytest_rmw_introspect.capture_model.Capture`; raises a ``TargetError`` (which fails
    the test with its message unless the test catches it).
    """
    state = _state(request.config)
    base_dir = Path(request.node.path).parent

    def _capture(target: Any = None, *, include_infrastructure: bool = False, **options: Any) -> Any:
        from . import runner

        spec = _base_spec(state, request.config.rootpath)
        if isinstance(target, TargetSpec):
            spec = target
        elif target is not None:
            spec = spec.merged(target, base_dir=base_dir, source="rmw_capture()")
        spec = spec.merged(options, base_dir=base_dir, source="rmw_capture()")
        return runner.run(spec, library=state.library(), ros=state.ros(), include_infrastructure=include_infrastructure)

    return _capture


class _UnavailableCapture:
    """Stands in for the capture when capturing failed; the test itself is failed with the
    reason before its body runs. Anything else (a fixture using it) fails with the reason."""

    def __init__(self, error: BaseException) -> None:
        object.__setattr__(self, "_error", error)

    def __getattr__(self, name: str) -> Any:
        pytest.fail(f"the interfaces capture is not available:\n{self._error}", pytrace=False)

    def __getitem__(self, key: Any) -> Any:
        return self.__getattr__("__getitem__")

    def __contains__(self, key: Any) -> bool:
        return self.__getattr__("__contains__")

    def __iter__(self) -> Any:
        return self.__getattr__("__iter__")

    def __repr__(self) -> str:
        return f"<interfaces capture unavailable: {type(self._error).__name__}>"


@pytest.fixture
def interfaces(request: pytest.FixtureRequest) -> Any:
    """The :class:`~pytest_rmw_introspect.capture_model.Capture` of the test's target, as named by
    its ``@pytest.mark.interfaces(contract, **options)`` marker. After the test body, the
    capture is compared with the contract (drift fails the test)."""
    item = request.node
    if item.get_closest_marker(MARKER) is None:
        pytest.fail(
            "the `interfaces` fixture needs an @pytest.mark.interfaces(\"contract.yaml\", ...) marker "
            "on the test; to capture without a contract use the `rmw_capture` fixture",
            pytrace=False,
        )
    existing = item.stash.get(_ITEM, None)
    if existing is None:
        existing = _prepare(item, _state(request.config))
        item.stash[_ITEM] = existing
    if existing.error is not None:
        return _UnavailableCapture(existing.error)
    return existing.capture


@pytest.fixture(autouse=True)
def _rmw_introspect_marker(request: pytest.FixtureRequest) -> None:
    """Tests with the marker are captured and checked even when they do not ask for ``interfaces``."""
    if request.node.get_closest_marker(MARKER) is not None and "interfaces" not in request.fixturenames:
        request.getfixturevalue("interfaces")


# ---------------------------------------------------------------------------- marker → capture


def _marker_source(item: pytest.Item) -> str:
    return f"@pytest.mark.{MARKER} of {item.nodeid}"


def _parse_marker(item: pytest.Item) -> tuple[Path, dict[str, Any], dict[str, Any]]:
    marker = item.get_closest_marker(MARKER)
    assert marker is not None
    kwargs = dict(marker.kwargs)
    contract = kwargs.pop("contract", None)
    args = list(marker.args)
    source = _marker_source(item)
    if args:
        if len(args) > 1 or contract is not None:
            given = args + ([contract] if contract else [])
            raise OptionError(f"{source}: give one contract path (positional or contract=...), got {given}")
        contract = args[0]
    if not contract or not isinstance(contract, (str, os.PathLike)):
        raise OptionError(
            f"{source}: the first argument must be the path of the golden contract, e.g. "
            f"@pytest.mark.{MARKER}(\"contracts/talker.yaml\", script=\"talker.py\")"
        )
    unknown = sorted(set(kwargs) - set(TARGET_KEYS) - set(OPTION_KEYS))
    if unknown:
        raise OptionError(
            f"{source}: unknown keyword argument(s) {', '.join(unknown)}; target options: "
            f"{', '.join(TARGET_KEYS)}; comparison options: {', '.join(OPTION_KEYS)}"
        )
    path = Path(os.path.expanduser(str(contract)))
    if not path.is_absolute():
        path = Path(item.path).parent / path
    target = {k: v for k, v in kwargs.items() if k in TARGET_KEYS}
    options = {k: v for k, v in kwargs.items() if k in OPTION_KEYS}
    return path, target, options


def _target_layers(state: _SessionState, rootdir: Path) -> list[tuple[dict[str, Any], Path, str]]:
    """The target layers below a contract's ``target:`` block (ini file, then command line)."""
    return [(state.ini_target, rootdir, "ini file"), (state.cli_target, rootdir, "command line")]


def _option_layers(state: _SessionState) -> list[tuple[dict[str, Any], str]]:
    """The comparison option layers below a contract's ``options:`` block."""
    return [(state.ini_options, "ini file"), (state.cli_options, "command line")]


def _prepare(item: pytest.Item, state: _SessionState) -> _ItemState:
    from . import checking

    st = _ItemState()
    try:
        path, target_kw, option_kw = _parse_marker(item)
        st.contract_path = path
        shown = _display(path, item.config)

        def no_target(contract: Any, shown: str) -> str:
            if contract is None:
                return (
                    f"The golden contract {shown} does not exist and the @pytest.mark.{MARKER} marker "
                    "names no target, so there is nothing to capture. Name the target in the marker, "
                    f"e.g. @pytest.mark.{MARKER}(\"{path.name}\", package=\"my_pkg\", executable=\"my_node\"), "
                    f"then create the contract with:\n  {_accept_command(item)}"
                )
            return (
                f"No target to run: neither the {MARKER} marker of {item.nodeid} nor the `target:` block "
                f"of {shown} names one (package+executable, command, script or module)."
            )

        prepared = checking.prepare(
            path,
            weak_target=_target_layers(state, item.config.rootpath),
            strong_target=[(target_kw, Path(item.path).parent, _marker_source(item))],
            weak_options=_option_layers(state),
            strong_options=[(option_kw, _marker_source(item))],
            shown=shown,
            allow_missing=True,
            no_target=no_target,
        )
        st.prepared = prepared
        st.contract, st.options, st.spec = prepared.contract, prepared.options, prepared.spec
        st.capture = checking.run_capture(prepared, library=state.library(), ros=state.ros())
    except RmwIntrospectError as exc:
        st.error = exc
    return st


# ---------------------------------------------------------------------------- the check


def _display(path: Path, config: pytest.Config) -> str:
    try:
        rel = os.path.relpath(path, config.invocation_params.dir)
    except ValueError:
        return str(path)
    return str(path) if rel.startswith("../../..") else rel


def _accept_command(item: pytest.Item) -> str:
    file_part = _display(Path(item.path), item.config)
    suffix = item.nodeid.split("::", 1)[1] if "::" in item.nodeid else ""
    node = file_part + (f"::{suffix}" if suffix else "")
    return f"pytest --update-golden {shlex.quote(node)}"


def _record(item: pytest.Item, action: str | None, path: Path) -> None:
    if action is not None:
        item.user_properties.append((golden_module.USER_PROPERTY, golden_module.property_value(action, path)))


def _record_drift(item: pytest.Item, result: Any) -> None:
    """Attach the machine-readable drift to the report (JUnit writes it as a <property>)."""
    if result.items:
        item.user_properties.append((DRIFT_PROPERTY, json.dumps(result.to_json(), sort_keys=True, default=str)))


def _verdict(item: pytest.Item, result: Any, state: _SessionState, accept_command: str) -> None:
    """Turn a compared :class:`checking.CheckResult` into the test outcome: pass, write the
    golden (``--update-golden``), fail with the drift report, or warn below the threshold.
    Shared by marker tests and contract items."""
    assert result.spec is not None
    _record_drift(item, result)
    if result.contract is None:
        if state.update:
            _record(item, result.update(), result.path)
            return
        pytest.fail(
            f"The golden contract {result.shown} does not exist. Create it from the current capture of "
            f"{result.spec.describe()} with:\n  {accept_command}\n\nCaptured:\n"
            + textwrap.indent(result.capture.summary(), "  "),
            pytrace=False,
        )
    if not result.items:
        return
    if state.update:
        _record(item, result.update(), result.path)
        return
    if result.failed:
        pytest.fail(result.render_text(accept_command=accept_command), pytrace=False)
    item.warn(
        pytest.PytestWarning(
            f"{len(result.items)} interface change(s) against {result.shown} below the fail threshold "
            f"({result.options.fail_on}); accept them with {accept_command}"
        )
    )


def _check(item: pytest.Item, st: _ItemState, state: _SessionState) -> None:
    from . import checking

    assert st.prepared is not None
    _verdict(item, checking.compare(st.prepared, st.capture), state, _accept_command(item))


@pytest.hookimpl(wrapper=True)
def pytest_runtest_call(item: pytest.Item) -> Any:
    st = item.stash.get(_ITEM, None)
    if st is not None and st.error is not None:
        pytest.fail(str(st.error), pytrace=False)
    try:
        result = yield
    except RmwIntrospectError as exc:
        # raised in the test body (e.g. by rmw_capture): a failure with the message, no traceback
        pytest.fail(str(exc), pytrace=False)
    if st is not None and st.capture is not None:
        _check(item, st, _state(item.config))
    return result


# ---------------------------------------------------------------------------- contract files


def pytest_collect_file(file_path: Path, parent: pytest.Collector) -> Any:
    """Contract files (``rmw_introspect_contracts``) are test items of their own (collect.py)."""
    from . import collect

    if collect.matches(file_path, parent.config, collect.patterns(parent.config)):
        return collect.ContractFile.from_parent(parent, path=file_path)
    return None


# ---------------------------------------------------------------------------- reporting


class _GoldenReporter:
    """Collects the goldens written (from test reports, so also those of xdist workers) and
    lists them in the terminal summary. Registered per session in ``pytest_configure``."""

    def __init__(self, state: _SessionState) -> None:
        self.state = state

    def pytest_runtest_logreport(self, report: pytest.TestReport) -> None:
        if report.user_properties:
            self.state.golden.record_report(report.user_properties)


def pytest_terminal_summary(terminalreporter: Any, exitstatus: int, config: pytest.Config) -> None:
    state = config.stash.get(_SESSION, None)
    if state is None or not state.update:
        return
    lines = state.golden.summary_lines(config.invocation_params.dir)
    terminalreporter.section("rmw-introspect: golden contracts")
    if lines:
        for line in lines:
            terminalreporter.write_line(line)
        terminalreporter.write_line(f"{len(lines)} golden contract(s) written")
    else:
        terminalreporter.write_line("no golden contract needed changes")
