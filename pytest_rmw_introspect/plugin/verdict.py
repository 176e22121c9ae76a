"""The pytest side of an outcome: a passing test, a written golden, a failure with the drift
report, or a warning below the threshold. Shared by ``interfaces`` marker tests and
contract-file items; the decision itself is ``check.outcome.decide``."""

from __future__ import annotations

import json
import shlex
from pathlib import Path
from typing import NoReturn

import pytest

from ..check import golden_record
from ..check.outcome import Checked, Verdict, decide
from ..errors import BaselineError, ContractError, GoldenWriteError, RmwIntrospectError
from . import gate_items
from .session import NOTE_PROPERTY, STOOD_IN_PROPERTY, SessionState, state

#: user property with the drift items as JSON (report.to_json + contract), for JUnit XML
DRIFT_PROPERTY = "rmw_introspect_drift"


def fail_with(item: pytest.Item, error: RmwIntrospectError) -> NoReturn:
    """Fail ``item`` with ``error``'s message, no traceback; a contract's path shown relative to
    where pytest was started, as in every other message. A golden that --update-golden cannot
    rewrite because it is invalid is said so, and listed in the session's summary."""
    session_state = state(item.config)
    if not isinstance(error, ContractError) or error.path is None:
        pytest.fail(str(error), pytrace=False)
    message = error.shown_from(session_state.display)
    if session_state.update:
        item.user_properties.append((golden_record.USER_PROPERTY,
                                     golden_record.property_value(golden_record.INVALID, error.path)))
        message += ("\n--update-golden does not overwrite an invalid contract (it may hold entries written by "
                    "hand): fix it, or delete it and run --update-golden again to write a new one.")
    pytest.fail(message, pytrace=False)


def accept_command(item: pytest.Item, session_state: SessionState) -> str:
    """``pytest --update-golden FILE::TEST``: the command that accepts this item's drift."""
    file_part = session_state.display(Path(item.path))
    suffix = item.nodeid.split("::", 1)[1] if "::" in item.nodeid else ""
    node = file_part + (f"::{suffix}" if suffix else "")
    return f"pytest --update-golden {shlex.quote(node)}"


def apply(item: pytest.Item, result: Checked, session_state: SessionState) -> None:
    """Turn a compared result into the test's outcome (raises ``pytest.fail`` on failure)."""
    try:
        session_state.apply_baseline(result)
    except BaselineError as exc:
        pytest.fail(str(exc), pytrace=False)
    outcome = decide(result, update=session_state.update, accept_command=accept_command(item, session_state),
                     verbose=item.config.getoption("verbose", 0) > 0)
    for stood_in in result.stood_in:  # listed in the terminal summary (session.terminal_summary)
        item.user_properties.append((STOOD_IN_PROPERTY, f"{session_state.display(result.path)}\t{stood_in}"))
    for note in result.check_notes():  # said once, in the terminal summary, not in every report
        item.user_properties.append((NOTE_PROPERTY, f"{session_state.display(result.path)}\t{note}"))
    if outcome.verdict is Verdict.PASS:  # a pass with findings of the level NOTE: they are said in the summary
        for found in outcome.json:
            if found.get("severity") == "NOTE" and not found.get("accepted"):
                item.user_properties.append((NOTE_PROPERTY, f"{session_state.display(result.path)}\t"
                                             f"[{found.get('rule')}] {found.get('message')}"))
    if outcome.json:
        # the machine-readable drift on the report (JUnit writes it as a <property>)
        item.user_properties.append((DRIFT_PROPERTY, json.dumps(outcome.json, sort_keys=True, default=str)))
    if outcome.verdict is Verdict.WRITE:
        try:
            action = result.update()
        except GoldenWriteError as exc:
            pytest.fail(str(exc), pytrace=False)
        if action is not None:
            item.user_properties.append((golden_record.USER_PROPERTY, golden_record.property_value(action, result.path)))
        advice = gate_items.version_advice(item.config, result.path, outcome.version_advice)
        if advice:  # --update-golden never changes interface_version itself
            item.warn(pytest.PytestWarning(advice))
        if outcome.unfixed:  # the golden is written, the system is still broken: not a green update
            said = f"{action or 'unchanged'} {session_state.display(result.path)}"
            pytest.fail(f"{said}, but {outcome.unfixed}\n\n{outcome.report}".rstrip("\n"), pytrace=False)
    elif outcome.failed:
        pytest.fail(outcome.message, pytrace=False)
    elif outcome.verdict is Verdict.WARN:
        item.warn(pytest.PytestWarning(outcome.message))
