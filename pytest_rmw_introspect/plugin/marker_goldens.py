"""Contract files that a marker test of the session names as its golden.

A golden named by an ``interfaces`` (or ``system_contract``) marker test is often also a file
that pytest collects as a contract item of its own (``*.interfaces.yaml``, ``*.system.yaml``).
Running that item too would check the same file twice, and differently: the item knows only
the file's ``target:`` and ``options:``, not the marker's keywords (and a golden that
``--update-golden`` created for a marker test has no ``target:`` at all: the marker names the
target). So the marker test checks its golden and the item is skipped, naming that test. Only
marker tests that run in this session count (collected and not deselected); without them the
file is an item like any other."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import pytest

from ..compare.options import OptionError
from . import items as contract_items
from . import marker, system_marker
from .session import state


def goldens_of_marker_tests(items: Sequence[pytest.Item]) -> dict[str, str]:
    """The real path of every golden a marker test among ``items`` names → the first such
    test's node id. A marker that cannot be read is left out (its test fails saying why)."""
    owners: dict[str, str] = {}
    for item in items:
        for name, parse in ((marker.MARKER, marker.parse), (system_marker.MARKER, system_marker.parse)):
            if item.get_closest_marker(name) is None:
                continue
            try:
                path = parse(item)[0]
            except OptionError:
                continue
            owners.setdefault(os.path.realpath(path), item.nodeid)
    return owners


def skip_checked_contract_items(items: Sequence[pytest.Item]) -> None:
    """Mark every contract-file item whose file a marker test among ``items`` names as its
    golden to be skipped, naming that test (its capture is not started ahead either)."""
    owners = goldens_of_marker_tests(items)
    if not owners:
        return
    for item in items:
        if not isinstance(item, (contract_items.ContractItem, system_marker.SystemContractItem)):
            continue
        test = owners.get(os.path.realpath(item.path))
        if test is None:
            continue
        # what the file runs by itself: a system contract's launch file, a node contract's `target:`
        runs_alone = not isinstance(item, contract_items.ContractItem) or bool(item.loaded and item.loaded.target)
        shown = state(item.config).display(Path(item.path))
        item.add_marker(pytest.mark.skip(reason=skip_reason(shown, test, runs_alone=runs_alone)))


def skip_reason(shown: str, test: str, *, runs_alone: bool) -> str:
    reason = f"{shown} is the golden of {test}, which checks it in this session"
    if runs_alone:
        reason += (" with the marker's keywords; to check the file with only its own target and options, "
                   f"run it alone: pytest {shown}")
    return reason
