"""The ``interfaces`` marker: which contract a test checks, with which target and options.

The marker's first argument is the golden contract, relative to the test file; its keyword
arguments are the target and comparison options whose table (``model.option_tables``) says the
marker takes them (above the contract's ``target:`` and ``options:`` blocks).
The target is captured when the test sets up (:func:`prepare`); after the test body, the
capture is compared inside the call phase (:func:`check`).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

from ..errors import OptionError, RmwIntrospectError
from ..model import contract_kind
from ..model.contract_kind import Kind
from ..model.option_tables import COMPARISON, TARGET, FrontEnd
from ..run.target import merge
from . import verdict
from .session import SessionState

if TYPE_CHECKING:  # imported by the first marker test that runs: a session without one never loads them
    from ..check.pipeline import Prepared
    from ..model.capture import Capture
    from ..model.contract import Contract

MARKER = "interfaces"
TARGET_KEYS = TARGET.names(FrontEnd.MARKER)
OPTION_KEYS = COMPARISON.names(FrontEnd.MARKER)
MARKER_DOC = (
    f"{MARKER}(contract, **options): capture the test's target on the recording middleware and "
    "compare it with the golden contract (path relative to the test file). Keyword arguments: "
    f"target options ({', '.join(TARGET_KEYS)}) and comparison options ({', '.join(OPTION_KEYS)})."
)


@dataclass
class ItemState:
    """A marker test's prepared contract and capture, or the error that stopped them."""

    prepared: Prepared | None = None
    capture: Capture | None = None
    error: RmwIntrospectError | None = None
    #: the ``target:`` block an update writes into the golden (:func:`golden_target`)
    golden_target: dict[str, Any] | None = None


ITEM = pytest.StashKey[ItemState]()


def source(item: pytest.Item) -> str:
    return f"@pytest.mark.{MARKER} of {item.nodeid}"


def parse(item: pytest.Item) -> tuple[Path, dict[str, Any], dict[str, Any]]:
    """The marker's contract path, target options and comparison options (raises OptionError)."""
    marker = item.get_closest_marker(MARKER)
    assert marker is not None
    kwargs = dict(marker.kwargs)
    contract = kwargs.pop("contract", None)
    args = list(marker.args)
    where = source(item)
    if args:
        if len(args) > 1 or contract is not None:
            given = args + ([contract] if contract else [])
            raise OptionError(f"{where}: give one contract path (positional or contract=...), got {given}")
        contract = args[0]
    if not contract or not isinstance(contract, (str, os.PathLike)):
        raise OptionError(
            f"{where}: the first argument must be the path of the golden contract, e.g. "
            f"@pytest.mark.{MARKER}(\"contracts/talker.yaml\", script=\"talker.py\")"
        )
    unknown = sorted(set(kwargs) - set(TARGET_KEYS) - set(OPTION_KEYS))
    if unknown:
        raise OptionError(
            f"{where}: unknown keyword argument(s) {', '.join(unknown)}; target options: "
            f"{', '.join(TARGET_KEYS)}; comparison options: {', '.join(OPTION_KEYS)}"
        )
    path = Path(os.path.expanduser(str(contract)))
    if not path.is_absolute():
        path = Path(item.path).parent / path
    target = {k: v for k, v in kwargs.items() if k in TARGET_KEYS}
    options = {k: v for k, v in kwargs.items() if k in OPTION_KEYS}
    return path, target, options


def prepare(item: pytest.Item, session_state: SessionState) -> ItemState:
    """Load the marker's contract, layer its target and options, and capture the target."""
    from ..check import pipeline

    st = ItemState()
    try:
        path, target_kw, option_kw = parse(item)

        def no_target(contract: Contract | None, shown: str) -> str:
            if contract is None:
                return (
                    f"The golden contract {shown} does not exist and the @pytest.mark.{MARKER} marker "
                    "names no target, so there is nothing to capture. Name the target in the marker, "
                    f"e.g. @pytest.mark.{MARKER}(\"{path.name}\", package=\"my_pkg\", executable=\"my_node\"), "
                    f"then create the contract with:\n  {verdict.accept_command(item, session_state)}"
                )
            return (
                f"No target to run: neither the {MARKER} marker of {item.nodeid} nor the `target:` block "
                f"of {shown} names one (package+executable, command, script or module)."
            )

        layers = session_state.layers(strong_target=[(target_kw, Path(item.path).parent, source(item))],
                                      strong_options=[(option_kw, source(item))])
        st.prepared = pipeline.prepare(path, layers=layers, shown=session_state.display(path),
                                       allow_missing=True, no_target=no_target)
        st.golden_target = golden_target(st.prepared.contract, path, target_kw, Path(item.path).parent, source(item))
        st.capture = pipeline.run_capture(st.prepared, library=session_state.library(), ros=session_state.ros())
    except RmwIntrospectError as exc:
        st.error = exc
    return st


def check_marker_item(item: pytest.Item, st: ItemState, session_state: SessionState) -> None:
    """Compare the test's capture with its contract and apply the outcome."""
    from ..check import pipeline

    assert st.prepared is not None and st.capture is not None
    result = pipeline.compare(st.prepared, st.capture)
    result.golden_target = st.golden_target
    verdict.apply(item, result, session_state)


def golden_target(contract: Contract | None, path: Path, target_kw: dict[str, Any], test_dir: Path,
                  where: str) -> dict[str, Any] | None:
    """The ``target:`` block that ``--update-golden`` writes into the golden at ``path`` for a
    marker naming its target, so that the golden is checkable by itself (``rmw-introspect check``,
    ``pytest contracts/``, the action): the file's own block with the marker's keywords over it
    (the marker decides, as when the test runs; paths relative to the golden's directory). The
    file's block as it is when the marker adds nothing to it; None when the marker names no
    target keywords, the result names nothing to run, or the golden is a NoDL document."""
    from ..check import golden

    if not target_kw or (contract is not None and contract.nodl is not None) or \
            contract_kind.kind_of_name(path) is Kind.NODL:
        return None
    own = dict(contract.target) if contract is not None and contract.target else None
    base = path.absolute().parent
    ours = merge((own, base, f"{path}: target"))
    spec = merge((own, base, f"{path}: target"), (target_kw, test_dir, where))
    if spec.kind is None:
        return None
    if own is not None and spec == ours:
        return own  # the file says it already, in its own words
    allowed = TARGET.names(FrontEnd.CONTRACT)
    return {key: value for key, value in golden.target_block(spec, base).items() if key in allowed}
