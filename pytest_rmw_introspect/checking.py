"""Checking a contract: the one place that loads a contract, builds its target, captures it and
compares. The ``interfaces`` marker, contract files collected as pytest items and the
``rmw-introspect`` command line all go through here.

Layers (docs/design.md section 2). Every layer is a ``(mapping, source)`` pair for comparison
options and a ``(mapping, base_dir, source)`` triple for target options; within a list the
later layer wins. ``weak`` layers sit below the contract (ini file, command line of pytest),
``strong`` layers above it (marker keyword arguments, the target flags of ``rmw-introspect``)::

    prepared = prepare("contracts/talker.yaml", strong_target=[({"script": "t.py"}, here, "cli")])
    result = run(prepared, library=lib, ros=ros)      # captures; raises a TargetError
    result.failed, result.items, result.render_text(accept_command="...")

:func:`check` does both and never raises an :class:`~.errors.RmwIntrospectError`: it is put on
``result.error``. :func:`diff_contracts` compares two contract files without running anything;
:func:`check_system` runs the system check (``compat.check_system``) over contract files, and
:func:`check_compatible` is its pytest helper.
"""

from __future__ import annotations

import inspect
import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .errors import RmwIntrospectError, TargetConfigError
from .options import ComparisonOptions, resolve
from .target import TargetSpec

OptionLayer = tuple[Mapping[str, Any] | None, str]
TargetLayer = tuple[Mapping[str, Any] | None, "str | Path | None", str]


def display(path: str | Path, base: str | Path | None = None) -> str:
    """``path`` relative to ``base`` (default: the current directory) unless that climbs far."""
    try:
        rel = os.path.relpath(path, base if base is not None else os.getcwd())
    except ValueError:
        return str(path)
    return str(path) if rel.startswith("../../..") else rel


def _default_no_target(contract: Any, shown: str) -> str:
    if contract is None:
        return f"The contract {shown} does not exist and no target is given, so there is nothing to capture."
    return (
        f"No target to run: the contract {shown} has no `target:` block naming one (package+executable, "
        "command, script or module), and none was given."
    )


# ---------------------------------------------------------------------------- prepare


@dataclass
class Prepared:
    """A contract with its target and options resolved, ready to capture."""

    path: Path
    shown: str
    contract: Any  # contract.Contract | None when the file does not exist (allow_missing)
    spec: TargetSpec
    options: ComparisonOptions


def prepare(
    contract_path: str | Path,
    *,
    weak_target: Sequence[TargetLayer] = (),
    strong_target: Sequence[TargetLayer] = (),
    weak_options: Sequence[OptionLayer] = (),
    strong_options: Sequence[OptionLayer] = (),
    shown: str | None = None,
    allow_missing: bool = False,
    no_target: Callable[[Any, str], str] = _default_no_target,
) -> Prepared:
    """Load the contract and resolve its options and target (raises an RmwIntrospectError).

    ``allow_missing``: a contract file that does not exist is ``contract=None`` instead of a
    :class:`ContractError`. ``no_target(contract, shown)`` words the error raised when no layer
    names a target.
    """
    from . import contract as contract_module

    path = Path(contract_path)
    shown = shown or display(path)
    contract = None
    if path.exists() or not allow_missing:
        contract = contract_module.load(path)
    options = resolve(
        *weak_options,
        (contract.options if contract else None, f"{shown}: options"),
        *strong_options,
    )
    spec = TargetSpec()
    for values, base, source in weak_target:
        spec = spec.merged(values, base_dir=base, source=source)
    if contract is not None and contract.target:
        spec = spec.merged(contract.target, base_dir=path.absolute().parent, source=f"{shown}: target")
    for values, base, source in strong_target:
        spec = spec.merged(values, base_dir=base, source=source)
    if spec.kind is None:
        raise TargetConfigError(no_target(contract, shown))
    return Prepared(path=path, shown=shown, contract=contract, spec=spec, options=options)


# ---------------------------------------------------------------------------- result


@dataclass
class CheckResult:
    """The outcome of checking one contract.

    ``items``: the drift (empty when it matches, or when there is no contract or no capture);
    ``error``: the RmwIntrospectError that stopped the check (``check`` only).
    """

    path: Path
    shown: str
    contract: Any = None
    spec: TargetSpec | None = None
    options: ComparisonOptions = field(default_factory=ComparisonOptions)
    capture: Any = None
    items: list[Any] = field(default_factory=list)
    error: RmwIntrospectError | None = None
    compared: bool = False

    @property
    def missing(self) -> bool:
        """The contract file does not exist (and there was a capture to create it from)."""
        return self.contract is None and self.error is None

    @property
    def threshold(self) -> Any:
        return self.options.threshold()

    @property
    def drifted(self) -> bool:
        return bool(self.items)

    @property
    def failed(self) -> bool:
        """An error, a missing contract, or drift at or above the fail threshold."""
        from . import report

        return self.error is not None or self.missing or report.fails(self.items, self.threshold)

    def golden_nodes(self) -> dict[str, Any]:
        """The ``nodes`` to write when accepting the capture as the new contract."""
        opts = self.options
        return self.capture.to_contract_nodes(with_type_hash=not opts.ignore_type_hash,
                                              with_qos=not opts.ignores_all_qos)

    def update(self) -> str | None:
        """Write the golden (``golden.update``): ``created``, ``updated`` or None."""
        from . import golden

        return golden.update(self.path, self.golden_nodes())

    def title(self) -> str:
        return f"Interface drift of {self.spec.describe()}" if self.spec is not None else "Interface drift"

    def render_text(self, accept_command: str | None = None) -> str:
        """The report for people (the same text as a failing test)."""
        from . import report

        if self.error is not None:
            return str(self.error)
        text = report.render_text(self.items, contract_path=self.shown, threshold=self.threshold,
                                  accept_command=accept_command, title=self.title())
        notes = self.capture.notes() if self.capture is not None else []
        if notes:
            text = text.rstrip("\n") + "\n\nNotes on the capture:\n" + "\n".join(f"  - {note}" for note in notes)
        return text

    def to_json(self) -> list[dict[str, Any]]:
        """``report.to_json`` of the drift, each item with the ``contract`` it belongs to."""
        from . import report

        return [{"contract": self.shown, **item} for item in report.to_json(self.items)]


def compare(prepared: Prepared, capture: Any) -> CheckResult:
    """Compare a capture with the prepared contract (no drift items when it does not exist)."""
    from . import drift

    result = CheckResult(path=prepared.path, shown=prepared.shown, contract=prepared.contract,
                         spec=prepared.spec, options=prepared.options, capture=capture)
    if prepared.contract is not None:
        result.items = drift.compare(prepared.contract.nodes, capture.to_contract_nodes(),
                                     prepared.options.compare_options())
        result.compared = True
    return result


def run_capture(prepared: Prepared, *, library: str | Path | None = None, ros: Any = None) -> Any:
    """Capture the prepared target (raises a TargetError)."""
    from . import runner

    return runner.run(prepared.spec, library=library, ros=ros,
                      include_infrastructure=prepared.options.include_infrastructure)


def run(prepared: Prepared, *, library: str | Path | None = None, ros: Any = None) -> CheckResult:
    """Capture and compare (raises a TargetError when the target cannot be captured)."""
    return compare(prepared, run_capture(prepared, library=library, ros=ros))


def check(
    contract_path: str | Path,
    *,
    library: str | Path | None = None,
    ros: Any = None,
    **prepare_kwargs: Any,
) -> CheckResult:
    """:func:`prepare` + :func:`run`; an RmwIntrospectError ends up in ``result.error``.

    ``library``/``ros`` may be callables (called only once a target is known), so that a
    missing middleware is reported only for contracts that get as far as capturing.
    """
    path = Path(contract_path)
    shown = prepare_kwargs.get("shown") or display(path)
    prepared = None
    try:
        prepared = prepare(path, **prepare_kwargs)
        lib = library() if callable(library) else library
        env = ros() if callable(ros) else ros
        return run(prepared, library=lib, ros=env)
    except RmwIntrospectError as exc:
        result = CheckResult(path=path, shown=shown, error=exc)
        if prepared is not None:
            result.contract, result.spec, result.options = prepared.contract, prepared.spec, prepared.options
        return result


# ---------------------------------------------------------------------------- diff


@dataclass
class DiffResult:
    old: Any  # contract.Contract
    new: Any
    old_shown: str
    new_shown: str
    options: ComparisonOptions
    items: list[Any]

    @property
    def threshold(self) -> Any:
        return self.options.threshold()

    @property
    def failed(self) -> bool:
        from . import report

        return report.fails(self.items, self.threshold)

    def render_text(self) -> str:
        from . import report

        return report.render_text(self.items, contract_path=self.old_shown, threshold=self.threshold,
                                  title=f"Interface drift of {self.new_shown}")

    def to_json(self) -> list[dict[str, Any]]:
        from . import report

        return [{"contract": self.old_shown, **item} for item in report.to_json(self.items)]


def diff_contracts(
    old_path: str | Path,
    new_path: str | Path,
    options: Sequence[OptionLayer] | Mapping[str, Any] | ComparisonOptions | None = None,
) -> DiffResult:
    """Compare two contract files without running anything: ``old`` plays the contract,
    ``new`` the capture, so the rules and severities are those of a check.

    ``options``: a :class:`ComparisonOptions`, a mapping of option values, or layers stacked on
    top of the old contract's ``options:`` block. ``include_infrastructure`` has no effect
    (both files already list what they list). Raises :class:`ContractError`.
    """
    from . import contract as contract_module
    from . import drift

    old_shown, new_shown = display(old_path), display(new_path)
    old = contract_module.load(old_path)
    new = contract_module.load(new_path)
    if isinstance(options, ComparisonOptions):
        opts = options
    else:
        if isinstance(options, Mapping):
            layers: Sequence[OptionLayer] = [(options, "diff_contracts()")]
        else:
            layers = options or ()
        opts = resolve((old.options, f"{old_shown}: options"), *layers)
    items = drift.compare(old.nodes, new.nodes, opts.compare_options())  # compare expands QoS
    return DiffResult(old, new, old_shown, new_shown, opts, items)


# ---------------------------------------------------------------------------- system checks


@dataclass
class SystemResult:
    labels: list[str]
    items: list[Any]
    threshold: Any

    @property
    def failed(self) -> bool:
        from . import report

        return report.fails(self.items, self.threshold)

    def render_text(self) -> str:
        from . import report

        return report.render_compat_text(self.items, threshold=self.threshold,
                                         title=f"System check of {len(self.labels)} contract(s)")

    def to_json(self) -> list[dict[str, Any]]:
        from . import report

        return report.compat_to_json(self.items)


def check_system(
    contract_paths: Iterable[str | Path],
    *,
    fail_on: str = "breaking",
    strict_system_default: bool = False,
    base_dir: str | Path | None = None,
) -> SystemResult:
    """Load the contracts and check that their nodes fit together (``compat.check_system``).

    Labels are the paths as shown (relative to the current directory). Relative paths are
    relative to ``base_dir`` (default: the current directory). Raises ContractError, or
    ValueError for a bad ``fail_on``.
    """
    from . import compat
    from . import contract as contract_module
    from .report import parse_threshold

    threshold = parse_threshold(fail_on)
    systems: dict[str, Any] = {}
    for p in contract_paths:
        path = Path(os.path.expanduser(str(p)))
        if not path.is_absolute() and base_dir is not None:
            path = Path(base_dir) / path
        label = display(path)
        if label in systems:
            continue
        systems[label] = contract_module.load(path).nodes
    if not systems:
        raise ValueError("no contracts given to the system check")
    items = compat.check_system(systems, strict_system_default=strict_system_default)
    return SystemResult(labels=list(systems), items=items, threshold=threshold)


def check_compatible(
    *contract_paths: str | Path,
    fail_on: str = "breaking",
    strict_system_default: bool = False,
    base_dir: str | Path | None = None,
) -> SystemResult:
    """Fail the calling test unless the nodes of the given contracts fit together.

    ::

        def test_robot_system():
            pytest_rmw_introspect.check_compatible(
                "contracts/driver.interfaces.yaml", "contracts/planner.interfaces.yaml",
                fail_on="risky")

    Every subscription, service client and action client is matched with the publishers /
    servers of the same name in all contracts (type, type hash, QoS compatibility; requesters
    without a provider are RISKY). ``fail_on`` (``any``, ``risky``, ``breaking``; default
    ``breaking``) is the least severe problem that fails; the failure message is the system
    check report (``report.render_compat_text``). Relative paths are relative to ``base_dir``,
    by default the directory of the calling test file (like the ``interfaces`` marker).
    Returns the :class:`SystemResult` when the test does not fail, so it can assert more.
    A contract that cannot be loaded fails the test with the loader's message.
    """
    import pytest

    if base_dir is None:
        caller = inspect.stack()[1].filename
        base_dir = Path(caller).parent if caller and os.path.exists(caller) else None
    try:
        result = check_system(contract_paths, fail_on=fail_on,
                              strict_system_default=strict_system_default, base_dir=base_dir)
    except (RmwIntrospectError, ValueError) as exc:
        pytest.fail(str(exc), pytrace=False)
    if result.failed:
        pytest.fail(result.render_text(), pytrace=False)
    return result
