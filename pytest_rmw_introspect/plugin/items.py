"""Contract files as pytest items: no Python test file needed.

pytest collects every contract file under the paths it is asked to collect, by its content
(``model.contract_kind``): a ``*.yaml`` / ``*.yml`` file with a top-level ``contract_version:``
(a node contract, or a marker test's golden) or ``system_version:`` (a system contract; those
are ``system_marker``'s items), whatever its name; any other YAML file (parameters, launch, CI)
is not collected. Only the top-level keys of the text are looked at, no YAML is parsed, so
collecting a large repository stays cheap. The ini option ``rmw_introspect_contracts`` or the
command-line option ``--rmw-introspect-contracts`` replaces that with glob patterns (several,
separated by spaces; a pattern with a ``/`` is matched against the path relative to the rootdir;
``none`` turns collection off). Each contract file is **one** test item, named after its node(s)::

    contracts/talker.interfaces.yaml::/talker
    contracts/pipeline.interfaces.yaml::/camera,/detector     # several nodes: one item, one capture

One item per contract (not per node) because one contract names one target, which is run
once; the drift report of the item covers all its nodes. A contract without nodes (only a
header with a ``target:`` block, to be filled by ``pytest --update-golden``) is named
``::no-nodes``; a contract that cannot be loaded is named ``::invalid`` and fails with the
loader's message.

The item runs the contract's ``target:`` (plus ``--rmw-introspect-timeout/-settle`` and the ini
defaults below it) and compares with the comparison options (contract ``options:`` > command
line > ini), exactly like an ``interfaces`` marker test without keyword arguments: drift is a
failure whose message is the drift report ending with the ``pytest --update-golden`` command
for this item, ``--update-golden`` rewrites the ``nodes:`` block and lists the file in the
terminal summary, and the drift is attached as the ``rmw_introspect_drift`` user property
(JUnit XML ``<property>``). When an ``interfaces`` marker test of the session names the file
as its golden with keywords of its own (or the file names no target), that test checks the
file and the item is skipped (``marker_goldens``).
"""

from __future__ import annotations

import fnmatch
import threading
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

from ..errors import RmwIntrospectError, SetupError
from ..model import contract as contract_module
from ..model import contract_kind
from ..model.contract import Contract
from . import verdict
from .session import state

if TYPE_CHECKING:  # imported by the first item that runs: a session without one never loads them
    from ..check import pipeline
    from ..model.capture import Capture

def patterns(config: pytest.Config) -> list[str] | None:
    """The glob patterns of contract files for this session: None when none are set (files are
    collected by their content, :func:`collects`), empty when collection is off."""
    cli = config.getoption("rmw_introspect_contracts", None)
    if cli is not None:
        raw = [p for p in cli.replace(",", " ").split() if p]
    else:
        raw = list(config.getini("rmw_introspect_contracts"))
    if not raw:
        return None
    if any(p.lower() in ("none", "off") for p in raw):
        return []
    return raw


#: the kinds of contract file collected by content: those that name (or may name) what to run; a
#: NoDL document never does (a marker test or ``rmw-introspect check --package`` names its target)
COLLECTED_KINDS = (contract_kind.Kind.NODE, contract_kind.Kind.GOLDEN, contract_kind.Kind.SYSTEM)


def collects(file_path: Path, config: pytest.Config) -> bool:
    """Whether pytest collects ``file_path`` as a contract file: by the glob patterns when the
    session sets some (:func:`patterns`), else by its content (a YAML file that
    ``contract_kind`` says is a node or system contract; its text is read, not parsed)."""
    globs = patterns(config)
    if globs is not None:
        return matches(file_path, config, globs)
    return file_path.suffix.lower() in (".yaml", ".yml") and contract_kind.kind_of_file(file_path) in COLLECTED_KINDS


def matches(file_path: Path, config: pytest.Config, globs: list[str]) -> bool:
    if not globs:
        return False
    name = file_path.name
    try:
        rel = file_path.relative_to(config.rootpath).as_posix()
    except ValueError:
        rel = file_path.as_posix()
    return any(fnmatch.fnmatchcase(rel if "/" in g else name, g) for g in globs)


class ContractFile(pytest.File):
    """A contract file: yields one :class:`ContractItem`."""

    def collect(self) -> Iterator[pytest.Item]:
        try:
            loaded = contract_module.load(self.path)
        except RmwIntrospectError as exc:
            yield ContractItem.from_parent(self, name="invalid", load_error=exc)
            return
        name = ",".join(sorted(loaded.nodes)) or "no-nodes"
        yield ContractItem.from_parent(self, name=name, node_names=sorted(loaded.nodes), loaded=loaded)


def _no_target(contract: Contract | None, shown: str) -> str:
    from ..check import golden_tests

    marker_test = golden_tests.how_to_check(contract.path, shown) if contract and contract.path else None
    if marker_test is not None:  # a marker test's golden, that test not run here: it writes the target
        return marker_test
    return (
        f"The contract {shown} has no `target:` block, so there is nothing to run. Contract files "
        "collected as tests name their target themselves, e.g.\n"
        "  target:\n    package: my_pkg\n    executable: my_node\n"
        "(or command:, script:, module:), or check the contract from a test with "
        "@pytest.mark.interfaces(..., package=..., executable=...). If it is the golden of such a test, "
        "run that test with it (the test checks the file and this item is skipped; `pytest --update-golden` "
        "on that test writes its target into the file), or keep pytest from collecting it as an item: "
        "set the ini option rmw_introspect_contracts to glob patterns that leave it out, or list its "
        "directory in norecursedirs."
    )


class _Ahead:
    """A capture started before its item runs, in a daemon thread of its own (a thread that
    ends with the process: nothing waits for it when pytest stops early; a cold target dies
    with its thread, a warm one with its server)."""

    def __init__(self, work: Callable[[], tuple[pipeline.Prepared, Capture]]) -> None:
        self._work = work
        self._done = threading.Event()
        self._result: tuple[pipeline.Prepared, Capture] | None = None
        self._error: BaseException | None = None
        threading.Thread(target=self._run, name="rmw-introspect capture ahead", daemon=True).start()

    def _run(self) -> None:
        try:
            self._result = self._work()
        except BaseException as exc:  # noqa: BLE001  # handed to the item, which raises it
            self._error = exc
        finally:
            self._done.set()

    def result(self) -> tuple[pipeline.Prepared, Capture]:
        self._done.wait()
        if self._error is not None:
            raise self._error
        assert self._result is not None
        return self._result


class ContractItem(pytest.Item):
    """Captures the contract's target and compares it with the contract."""

    def __init__(self, *, load_error: RmwIntrospectError | None = None, node_names: list[str] | None = None,
                 loaded: Contract | None = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.load_error = load_error
        self.node_names = node_names or []
        self.loaded = loaded  # read at collection: not parsed again when the item runs
        self._ahead: _Ahead | None = None

    def capture_ahead(self) -> None:
        """Start this item's capture now, while the item before it runs (the plugin calls this
        for the next item of a session or xdist worker): a capture is mostly waiting (settle
        periods, nodes that sleep), so two of them overlap. The capture is the same one
        :meth:`runtest` would take; only its start is earlier."""
        if self._ahead is not None or self.load_error is not None or self.get_closest_marker("skip") is not None:
            return  # a skipped item (its golden checked by a marker test: ``marker_goldens``) captures nothing
        session_state = state(self.config)
        try:  # found once per session, on this thread: the capture's thread only uses them
            session_state.library()
        except SetupError:
            return  # runtest reports it
        self._ahead = _Ahead(self._capture)

    def _capture(self) -> tuple[pipeline.Prepared, Capture]:
        from ..check import pipeline

        session_state = state(self.config)
        prepared = pipeline.prepare(self.path, layers=session_state.layers(), shown=session_state.display(self.path),
                                    no_target=_no_target, loaded=self.loaded)
        return prepared, pipeline.run_capture(prepared, library=session_state.library(), ros=session_state.ros())

    def runtest(self) -> None:
        from ..check import pipeline

        if self.load_error is not None:
            verdict.fail_with(self, self.load_error)
        session_state = state(self.config)
        ahead, self._ahead = self._ahead, None
        error: RmwIntrospectError | None = None
        try:
            prepared, capture = ahead.result() if ahead is not None else self._capture()
        except RmwIntrospectError as exc:
            error = exc
        if error is not None:  # failed outside the except block: no chained exception in the report
            verdict.fail_with(self, error)
        verdict.apply(self, pipeline.compare(prepared, capture), session_state)

    def reportinfo(self) -> tuple[Path, int, str]:
        # a line number (0: the file itself) is needed by Node.warn for warnings below the threshold
        return self.path, 0, f"interface contract {self.path.name}::{self.name}"
