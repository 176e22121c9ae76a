"""The pytest session of pytest-rmw-introspect: its command-line and ini options, the state
they give (comparison and target option layers, ``--update-golden``), the ROS environment and
middleware library found once per session, and the summary of goldens written."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

from ..check import golden_record, sharding
from ..compare.options import parse_layer
from ..errors import OptionError, SetupError, TargetConfigError, UsageError
from ..model.option_tables import COMPARISON, TARGET, Source
from ..model.paths import shown
from ..run import middleware, ros_env
from ..run.ros_env import RosEnvironment
from ..run.target import TargetSpec
from . import option_flags

if TYPE_CHECKING:
    from ..check.outcome import Checked
    from ..check.pipeline import Layers, OptionLayer, TargetLayer
    from ..compare.baseline import Baseline

#: contract items whose capture starts while the current item runs (a capture is mostly waiting:
#: settle periods, nodes that sleep). 8, not 3: 100 warm items under `pytest -n 2` took a median
#: 5.7 s against 6.1 s (18 and 23 interleaved runs; 16 ahead was no better than 8). An xdist worker
#: knows at most the items its controller sent it, a dozen at the start and two or three later.
DEFAULT_CAPTURE_AHEAD = 8
MAX_CAPTURE_AHEAD = 64


@dataclass
class SessionState:
    update: bool
    cli_options: dict[str, Any]
    ini_options: dict[str, Any]
    cli_target: dict[str, Any]
    ini_target: dict[str, Any]
    golden: golden_record.GoldenSession
    invocation_dir: Path
    rootdir: Path
    #: the processes system checks did not run because a ``stand_ins:`` entry stood in for them:
    #: contract as shown -> "process by stand-in contract" (from test reports: xdist workers too)
    stood_in: dict[str, list[str]] = field(default_factory=dict)
    #: what the checks noted beside their findings (a device this machine lacks, what a NoDL
    #: document cannot state): note -> contracts as shown; said once in the terminal summary
    notes: dict[str, list[str]] = field(default_factory=dict)
    #: how many contract items ahead of the running one have their capture started already
    #: (``items.ContractItem.capture_ahead``); 0: each item captures when it runs
    capture_ahead: int = DEFAULT_CAPTURE_AHEAD
    #: ini ``rmw_introspect_baseline``: findings in this file do not fail (read by the first check)
    baseline_path: Path | None = None
    _baseline: Baseline | None = None
    #: ``--rmw-introspect-shard``: the contract-file items this job runs
    shard: sharding.Shard | None = None
    _ros: RosEnvironment | None = None
    _library: Path | None = None
    _setup_error: SetupError | None = None

    def ros(self) -> RosEnvironment:
        self._setup()
        assert self._ros is not None
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
        try:
            self._ros = ros_env.detect()
            self._library = Path(middleware.ensure_library(self._ros))
        except SetupError as exc:
            self._setup_error = exc
            raise

    def target_layers(self) -> dict[Source, list[TargetLayer]]:
        """The target layers below a contract's ``target:`` block, by source."""
        return {Source.INI: [(self.ini_target, self.rootdir, "ini file")],
                Source.PYTEST: [(self.cli_target, self.rootdir, "command line")]}

    def option_layers(self) -> dict[Source, list[OptionLayer]]:
        """The comparison option layers below a contract's ``options:`` block, by source."""
        return {Source.INI: [(self.ini_options, "ini file")], Source.PYTEST: [(self.cli_options, "command line")]}

    def layers(self, *, strong_target: list[TargetLayer] | None = None,
               strong_options: list[OptionLayer] | None = None) -> Layers:
        """This session's layers, with a test's own (marker, fixture arguments) on top."""
        from ..check.pipeline import Layers  # the pipeline: not in an xdist controller, which runs no test

        return Layers(weak_target=self.target_layers(), strong_target=strong_target or [],
                      weak_options=self.option_layers(), strong_options=strong_options or [])

    def display(self, path: Path) -> str:
        """``path`` as shown in messages: relative to where pytest was started."""
        return shown(path, self.invocation_dir)

    def apply_baseline(self, result: Checked) -> None:
        """Apply the session's baseline (ini ``rmw_introspect_baseline``) to a checked result:
        the findings it holds are reported as accepted and do not fail. Raises BaselineError."""
        if self.baseline_path is None or result.error is not None:
            return
        # the baseline and the pipeline it judges (~40 ms): imported by the first contract check
        from ..check import baselines
        from ..compare import baseline

        if self._baseline is None:
            self._baseline = baseline.load(self.baseline_path, self.display(self.baseline_path))
        baselines.apply(result, self._baseline)


SESSION = pytest.StashKey[SessionState]()


def state(config: pytest.Config) -> SessionState:
    return config.stash[SESSION]


def addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("rmw-introspect", "interface contracts of ROS 2 nodes (pytest-rmw-introspect)")
    group.addoption(
        "--update-golden",
        action="store_true",
        default=False,
        help="rewrite the golden contracts of the selected tests that drifted and create missing "
        "ones (refused when the CI environment variable is set)",
    )
    group.addoption("--rmw-introspect-shard", metavar="I/N", default=None,
                    help="run only this CI job's share of the contract files' items: job I of N (e.g. 2/4); the "
                    "items are sorted by node id and dealt round-robin, the N jobs together run each exactly once "
                    "(tests with the interfaces marker are left to pytest's own sharding plugins)")

    group.addoption("--rmw-introspect-capture-ahead", default=None, metavar="N",
                    help="how many of the next contract items start their capture while the current one "
                    f"runs (default {DEFAULT_CAPTURE_AHEAD}, 1 with cold starts; 0: one capture at a time)")
    group.addoption("--rmw-introspect-no-capture-ahead", action="store_true", default=False,
                    help="capture each contract item's target only when the item runs (--rmw-introspect-capture-ahead 0)")
    group.addoption(
        "--rmw-introspect-contracts",
        default=None,
        metavar="GLOBS",
        help="contract files collected as test items: glob patterns, comma-separated, instead of every YAML "
        "file that is a contract by its content (default: ini rmw_introspect_contracts; 'none' turns it off)",
    )
    parser.addini("rmw_introspect_contracts", "glob patterns of contract files collected as test items (default: "
                  "every YAML file that is a node or system contract by its content; 'none' turns it off)",
                  type="args", default=[])
    parser.addini("rmw_introspect_baseline", "a baseline file (rmw-introspect check --write-baseline FILE): "
                  "findings it holds are reported as accepted and do not fail; relative to the ini file", default="")
    parser.addini("rmw_introspect_capture_ahead", "how many of the next contract items start their capture while "
                  f"the current one runs (default {DEFAULT_CAPTURE_AHEAD}; true: the default; false or 0: one "
                  "capture at a time)", default="")
    option_flags.add(group, parser, COMPARISON)
    option_flags.add(group, parser, TARGET)


def capture_ahead_count(raw: Any, where: str) -> int:
    """``--rmw-introspect-capture-ahead`` / ini ``rmw_introspect_capture_ahead``: a count of items,
    or true (the default count) / false (0)."""
    text = str(raw).strip().lower()
    if text in ("", "true", "yes", "on"):
        return DEFAULT_CAPTURE_AHEAD
    if text in ("false", "no", "off"):
        return 0
    try:
        count = int(text)
    except ValueError:
        count = -1
    if not 0 <= count <= MAX_CAPTURE_AHEAD:
        raise pytest.UsageError(f"{where} = {raw!r}: give how many of the next contract items capture ahead, "
                                f"0 to {MAX_CAPTURE_AHEAD} (0 or false: one capture at a time; "
                                f"true: the default, {DEFAULT_CAPTURE_AHEAD})")
    return count


def _capture_ahead(config: pytest.Config, cold_session: bool) -> int:
    if config.getoption("rmw_introspect_no_capture_ahead", False):
        return 0
    cli = config.getoption("rmw_introspect_capture_ahead", None)
    if cli is not None:
        return capture_ahead_count(cli, "--rmw-introspect-capture-ahead")
    ini = config.getini("rmw_introspect_capture_ahead")
    if str(ini).strip() == "" and cold_session:
        # cold starts keep the CPU busy (starting Python, importing rclpy): more than one
        # capture ahead only adds contention
        return min(DEFAULT_CAPTURE_AHEAD, 1)
    return capture_ahead_count(ini, "ini option rmw_introspect_capture_ahead")


def configure(config: pytest.Config) -> SessionState:
    """Read and validate this session's options (a bad value is a ``pytest.UsageError``)."""
    update = bool(config.getoption("update_golden", False))
    if update:
        refusal = golden_record.ci_refusal()
        if refusal:
            raise pytest.UsageError(refusal)

    try:
        ini_options = parse_layer(option_flags.ini_values(config, COMPARISON), "ini file")
        cli_options = parse_layer(option_flags.flag_values(config, COMPARISON), "command line")
    except OptionError as exc:
        raise pytest.UsageError(str(exc)) from None

    # (cold starts: only ever switched on by these layers; a contract or marker may say false)
    ini_target = option_flags.ini_values(config, TARGET)
    cli_target = option_flags.flag_values(config, TARGET)
    try:
        TargetSpec.from_mapping(ini_target, source="ini file").merged(cli_target, source="command line")
    except TargetConfigError as exc:
        raise pytest.UsageError(str(exc)) from None

    try:
        shard = sharding.parse(config.getoption("rmw_introspect_shard"), "--rmw-introspect-shard") \
            if config.getoption("rmw_introspect_shard", None) else None
    except UsageError as exc:
        raise pytest.UsageError(str(exc)) from None

    return SessionState(
        update=update,
        cli_options=cli_options,
        ini_options=ini_options,
        cli_target=cli_target,
        ini_target=ini_target,
        golden=golden_record.GoldenSession(enabled=update),
        invocation_dir=Path(config.invocation_params.dir),
        rootdir=Path(config.rootpath),
        capture_ahead=_capture_ahead(config, cold_session=bool(ini_target.get("cold_start") or cli_target.get("cold_start"))),
        baseline_path=_baseline_path(config),
        shard=shard,
    )


def _baseline_path(config: pytest.Config) -> Path | None:
    """ini ``rmw_introspect_baseline`` as a path (relative to the ini file's directory)."""
    raw = str(config.getini("rmw_introspect_baseline") or "").strip()
    if not raw:
        return None
    base = Path(config.inipath).parent if config.inipath else Path(config.rootpath)
    return base / raw


#: user property of a system check's item, one per process a ``stand_ins:`` entry stood in for:
#: ``"<contract as shown>\t<process> by <stand-in contract>"``
STOOD_IN_PROPERTY = "rmw_introspect_stood_in"
#: user property of a check's item, one per note of the check (``check_notes``):
#: ``"<contract as shown>\t<note>"``
NOTE_PROPERTY = "rmw_introspect_note"


class SessionReporter:
    """Collects, from test reports (so also those of xdist workers), the goldens written and the
    processes stood in for, and lists them in the terminal summary. Registered per session in
    ``pytest_configure``."""

    def __init__(self, session_state: SessionState) -> None:
        self.state = session_state

    def pytest_runtest_logreport(self, report: pytest.TestReport) -> None:
        if not report.user_properties:
            return
        self.state.golden.record_report(report.user_properties)
        for name, value in report.user_properties:
            if name == STOOD_IN_PROPERTY and isinstance(value, str) and "\t" in value:
                contract, entry = value.split("\t", 1)
                entries = self.state.stood_in.setdefault(contract, [])
                if entry not in entries:
                    entries.append(entry)
            elif name == NOTE_PROPERTY and isinstance(value, str) and "\t" in value:
                contract, note = value.split("\t", 1)
                contracts = self.state.notes.setdefault(note, [])
                if contract not in contracts:
                    contracts.append(contract)


def terminal_summary(terminalreporter: pytest.TerminalReporter, config: pytest.Config) -> None:
    session_state = config.stash.get(SESSION, None)
    if session_state is None:
        return
    if session_state.stood_in:
        # a passing system check that did not run every process must not look like one that did
        terminalreporter.section("rmw-introspect: processes stood in for, not run here (stand_ins:)")
        for contract in sorted(session_state.stood_in):
            terminalreporter.write_line(f"{contract}: {', '.join(session_state.stood_in[contract])}")
    if session_state.notes:
        # once per run, not in every failure report (issue 47)
        terminalreporter.section("rmw-introspect: notes")
        for note, contracts in session_state.notes.items():
            more = f" (and {len(contracts) - 1} more)" if len(contracts) > 1 else ""
            terminalreporter.write_line(f"{contracts[0]}{more}: {note}")
    if session_state.update:
        terminalreporter.section("rmw-introspect: golden contracts")
        for line in session_state.golden.summary_lines(session_state.invocation_dir):
            terminalreporter.write_line(line)
