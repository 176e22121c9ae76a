"""Contract files that a marker test of the session names as its golden.

A golden named by an ``interfaces`` (or ``system_contract``) marker test is often also a file
that pytest collects as a contract item of its own (``*.interfaces.yaml``, ``*.system.yaml``).
That item checks the file with the file's ``target:`` and ``options:`` only, without the
marker's keywords, so it can fail where the test passes: a golden that ``--update-golden``
created for a marker test has no ``target:`` at all (the marker names the target), and a
marker's keywords (a namespace, parameters, options) change what is captured or how it is
judged. So the marker test checks its golden and the item is skipped, naming that test; unless
the item checks exactly what the test does (the file names its target and the marker adds no
keywords): then both run, as before. Only marker tests that run in this session count
(collected and not deselected); without them the file is an item like any other."""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import pytest

from ..errors import OptionError
from . import items as contract_items
from . import marker, system_marker
from .session import state


@dataclass(frozen=True)
class MarkerTest:
    """A marker test naming a golden: its node id, and whether its marker has keywords of its
    own (target, options, launch arguments) over the file's."""

    nodeid: str
    keywords: bool


def goldens_of_marker_tests(items: Sequence[pytest.Item]) -> dict[str, list[MarkerTest]]:
    """The real path of every golden that marker tests among ``items`` name → those tests. A
    marker that cannot be read is left out (its test fails saying why)."""
    goldens: dict[str, list[MarkerTest]] = {}
    for item in items:
        for name, parse in ((marker.MARKER, marker.parse), (system_marker.MARKER, system_marker.parse)):
            if item.get_closest_marker(name) is None:
                continue
            try:
                path, *keywords = parse(item)
            except OptionError:
                continue
            goldens.setdefault(os.path.realpath(path), []).append(MarkerTest(item.nodeid, any(keywords)))
    return goldens


def checked_by(tests: list[MarkerTest], *, runs_alone: bool) -> MarkerTest | None:
    """The marker test that checks a contract file instead of its item, or None: the item
    checks the file as the test does (the file names its target, the marker adds nothing)."""
    with_keywords = [test for test in tests if test.keywords]
    if with_keywords:
        return with_keywords[0]
    return None if runs_alone or not tests else tests[0]


def skip_checked_contract_items(items: Sequence[pytest.Item]) -> None:
    """Mark the contract-file items whose file a marker test among ``items`` checks differently
    (:func:`checked_by`) to be skipped, naming that test (no capture is started ahead for them)."""
    goldens = goldens_of_marker_tests(items)
    if not goldens:
        return
    for item in items:
        if not isinstance(item, (contract_items.ContractItem, system_marker.SystemContractItem)):
            continue
        # what a loaded file runs by itself: a system contract's launch file, a node contract's `target:`
        runs_alone = item.load_error is None and (not isinstance(item, contract_items.ContractItem)
                                                  or bool(item.loaded and item.loaded.target))
        test = checked_by(goldens.get(os.path.realpath(item.path), []), runs_alone=runs_alone)
        if test is not None:
            shown = state(item.config).display(Path(item.path))
            item.add_marker(pytest.mark.skip(reason=skip_reason(shown, test.nodeid, runs_alone=runs_alone)))


def skip_reason(shown: str, test: str, *, runs_alone: bool) -> str:
    reason = f"{shown} is the golden of {test}, which checks it in this session"
    if runs_alone:
        reason += (" with the marker's keywords; to check the file with only its own target and options, "
                   f"run it alone: pytest {shown}")
    return reason
