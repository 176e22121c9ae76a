"""A baseline (``compare.baseline``) applied to check results, and the findings of results
written into one: the command line (``--baseline``, ``--write-baseline``) and the pytest plugin
(ini ``rmw_introspect_baseline``) go through here, so both judge a baseline the same way."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from ..compare.acceptance import Finding
from ..compare.baseline import Baseline
from ..compare.compatibility import CompatItem
from .outcome import Checked
from .pipeline import CompatibilityResult

#: a check of one contract, or the compatibility check of several
Result = Checked | CompatibilityResult


def apply(result: Result, baseline: Baseline) -> None:
    """Move the findings of ``result`` that ``baseline`` holds to ``result.accepted``: they are
    reported as accepted by the baseline and no longer fail."""
    if isinstance(result, CompatibilityResult):
        new, known = baseline.split(None, result.items)
        result.items = [item for item in new if isinstance(item, CompatItem)]
        result.accepted = [*result.accepted, *known]
    else:
        new, known = baseline.split(result.path, result.items)
        result.keep(new, known)


def findings(results: Iterable[Result]) -> list[tuple[Path | None, Finding]]:
    """What a baseline written from ``results`` records: every finding not accepted otherwise."""
    found: list[tuple[Path | None, Finding]] = []
    for result in results:
        path = None if isinstance(result, CompatibilityResult) else result.path
        found += [(path, item) for item in result.items]
    return found
