"""``pytest --against REF``: the pull-request gate (``check.gate``, the same one as
``rmw-introspect diff --against REF``) as test items, one per contract::

    contracts/talker.interfaces.yaml::against:origin/main
    robot.system.yaml::against:origin/main

The gate reads files only, so it runs once when the session collects; each item then reports its
contract: it fails with the contract's report (the bump its changes need, the consumers they
break), or passes. The contracts are those git tracks under the directory pytest was started in,
found by their content whatever their names (marker goldens too), and those it tracked at REF
(a removed contract is an item too); the system contracts among them
judge consumers, or those ``--against-system`` names. Comparison options come from pytest's
command line (``--rmw-introspect-fail-on``, ``--rmw-introspect-ignore-qos``, ...) over each
contract's ``options:``; the session's baseline (ini ``rmw_introspect_baseline``) applies. A
REF that cannot be read (no git repository, no such revision, a shallow clone without it) is a
usage error: one message, nothing collected; so is a gate that finds no contract at all. The
terminal summary says what the gate looked at (a section "rmw-introspect: the gate against REF":
how many contracts of each kind it compared, the tracked YAML files it decided were not contracts,
those it could not read), as ``diff --against`` does on its first lines.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

from ..errors import RmwIntrospectError
from ..model.option_tables import COMPARISON, GATE
from . import option_flags
from .session import state

if TYPE_CHECKING:  # the gate (and the comparison pipeline) is imported when --against is given
    from ..check.diff import DiffResult
    from ..check.gate import GateResult

#: what the gate of this session looked at (``GateResult.intro``), for the terminal summary
_LOOKED_AT = pytest.StashKey[list[str]]()


def addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("rmw-introspect")
    option_flags.add_gate(group, GATE)


def version_advice(config: pytest.Config, path: Path, advice: str) -> str:
    """The ``interface_version`` advice of a golden ``--update-golden`` just wrote (``advice``:
    the update's own, which cannot know the base): with ``--against REF`` what the gate against
    REF decides of it (``check.gate.update_advice``), else ``advice``."""
    against = config.getoption(GATE["against"].pytest_dest, None)
    if not against:
        return advice
    from ..check import gate

    try:
        return gate.update_advice(against, path, cwd=config.invocation_params.dir) or ""
    except RmwIntrospectError:  # the gate cannot compare it (REF missing, invalid there): its items say why
        return advice


class GateItem(pytest.Item):
    """One contract against its version at REF."""

    def __init__(self, *, compared: DiffResult, against: str, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.compared = compared
        self.against = against

    def runtest(self) -> None:
        compared = self.compared
        if compared.error is not None:
            pytest.fail(compared.error, pytrace=False)
        if compared.items or compared.accepted:
            self.user_properties.append(("rmw_introspect_drift", json.dumps(compared.to_json(), default=str)))
        if compared.failed:
            pytest.fail(compared.render_text(), pytrace=False)

    def reportinfo(self) -> tuple[Path, int, str]:
        return self.compared.path or self.path, 0, f"interface gate {self.compared.shown} against {self.against}"


@pytest.hookimpl(tryfirst=True)  # before -k/-m deselect: they select gate items like any other
def pytest_collection_modifyitems(session: pytest.Session, config: pytest.Config, items: list[pytest.Item]) -> None:
    against = config.getoption(GATE["against"].pytest_dest, None)
    if not against:
        return
    from ..check import gate  # the gate and the comparison pipeline (~40 ms): only with --against
    from ..compare import baseline

    options = option_flags.flag_values(config, COMPARISON)
    fail_on = options.pop("fail_on", None)
    session_state = state(config)
    try:
        known = (baseline.load(session_state.baseline_path, session_state.display(session_state.baseline_path))
                 if session_state.baseline_path is not None else None)
        result = gate.run(against, systems=config.getoption(GATE["against_system"].pytest_dest, None),
                          options=[(options, "pytest command line")], fail_on=fail_on, baseline=known,
                          cwd=config.invocation_params.dir)
    except RmwIntrospectError as exc:
        # A usage error, as for a REF that cannot be read: `--against` asked for a gate, and a gate that
        # finds nothing to compare is a mistake of the set-up (the wrong directory, contracts not committed),
        # not a test result; an item that fails would sit among passing tests, a usage error stops the
        # session with pytest's exit status 4 and this one message (nothing "passed" with no gate item).
        raise pytest.UsageError(f"--against {against}: {exc}") from None
    config.stash[_LOOKED_AT] = _looked_at(result)
    for compared in result.contracts:
        items.append(GateItem.from_parent(session, name=f"{compared.shown}::against:{against}",
                                          nodeid=f"{compared.shown}::against:{against}", path=compared.path,
                                          compared=compared, against=against))


def _looked_at(result: GateResult) -> list[str]:
    return [f"{result.title()}: {result.intro()[0]}", *result.intro()[1:]]


def terminal_summary(terminalreporter: pytest.TerminalReporter, config: pytest.Config) -> None:
    """What the gate looked at, once at the end of the session (a gate must say what it read).
    Under xdist the controller collects nothing: it reads the gate itself (files only, no target
    is run); a gate that could not run said so as a usage error already."""
    against = config.getoption(GATE["against"].pytest_dest, None)
    if not against or hasattr(config, "workerinput"):
        return
    said = config.stash.get(_LOOKED_AT, None)
    if said is None:
        from ..check import gate

        try:
            said = _looked_at(gate.run(against, systems=config.getoption(GATE["against_system"].pytest_dest, None),
                                       cwd=config.invocation_params.dir))
        except RmwIntrospectError:
            return
    terminalreporter.section(f"rmw-introspect: the gate against {against}")
    for line in said:
        terminalreporter.write_line(line)
