"""Baselines: today's findings recorded in a file (``--write-baseline``), so that a later run
(``--baseline``, ini ``rmw_introspect_baseline``) fails only on findings that are new. A finding
in the baseline is reported as accepted by it (like an ``accept:`` entry of the contract, with
the baseline as the reason); baseline entries that no longer occur are counted as fixed, so the
baseline can be tightened by writing it again.

A finding is identified by the contract it was found in (its path relative to the baseline
file, so that the command line and pytest, started anywhere, agree) and :func:`findings.key`
(rule and place), never by its message: rewording a message keeps the baseline valid. The
findings of ``compat`` have no contract of their own; their ends name the contracts as given.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import BaselineError, UnreadableFile
from ..model import versioned_json
from ..model.acceptance import Acceptance
from . import findings
from .acceptance import Accepted, Finding

FORMAT = "rmw_introspect_baseline"
VERSION = 1


def _contract(contract: Path | None, directory: Path) -> str:
    return Path(os.path.relpath(contract.absolute(), directory.absolute())).as_posix() if contract else ""


def render(found: Iterable[tuple[Path | None, Finding]], path: str | Path) -> str:
    """The baseline file at ``path`` of ``found`` (the contract file or None, finding): JSON,
    sorted, so that writing the same findings again changes no byte."""
    directory = Path(path).parent
    entries = {(_contract(contract, directory), *findings.key(item)):
               {"rule": item.rule, "contract": _contract(contract, directory) or None, "message": item.message}
               for contract, item in found}
    document = {"format": FORMAT, "version": VERSION,
                "findings": [{"key": list(key), **entries[key]} for key in sorted(entries)]}
    return json.dumps(document, indent=2, ensure_ascii=False) + "\n"


@dataclass
class Baseline:
    """A loaded baseline; :meth:`split` records which entries it used."""

    path: str  # as shown
    directory: Path  # where the file is: contract paths are relative to it
    entries: dict[tuple[str, ...], dict[str, Any]]
    used: set[tuple[str, ...]] = field(default_factory=set)

    def split(self, contract: Path | None, items: Sequence[Finding]) -> tuple[list[Finding], list[Accepted]]:
        """``items`` of the contract file ``contract`` (None: ``compat``) into the new ones and
        those the baseline holds."""
        new: list[Finding] = []
        known: list[Accepted] = []
        for item in items:
            key = (_contract(contract, self.directory), *findings.key(item))
            if key in self.entries:
                self.used.add(key)
                known.append(Accepted(item, Acceptance(item.rule, "in the baseline (a finding known when it was "
                                                                  "written)", source=self.path, baseline=True)))
            else:
                new.append(item)
        return new, known

    def fixed(self) -> list[dict[str, Any]]:
        """The entries no split has met: findings of the baseline that are gone."""
        return [self.entries[key] for key in sorted(self.entries) if key not in self.used]

    def fixed_note(self, contracts: Iterable[Path] | None = None) -> str | None:
        """A note for people when findings of the baseline are gone (of ``contracts`` when given:
        a run over some of the contracts does not meet the others' entries)."""
        mine = None if contracts is None else {_contract(c, self.directory) for c in contracts}
        gone = [e for e in self.fixed() if mine is None or (e.get("contract") or "") in mine]
        if not gone:
            return None
        return (f"{len(gone)} finding(s) of the baseline {self.path} are gone; write it again "
                f"(--write-baseline {self.path}) to tighten it")


def load(path: str | Path, shown: str | None = None) -> Baseline:
    """Read a baseline file (raises :class:`BaselineError` naming the file and what to do)."""
    shown = shown or str(path)
    try:
        document = versioned_json.read(path, file_format=FORMAT, version=VERSION, what="a baseline")
    except UnreadableFile as problem:
        raise BaselineError(shown, problem.reason) from None
    entries: dict[tuple[str, ...], dict[str, Any]] = {}
    found = document.get("findings") or []
    if not isinstance(found, list):  # (issue 50: a number here was a TypeError traceback)
        raise BaselineError(shown, f"\"findings\" is {type(found).__name__}, not a list; write the baseline again "
                                   "(--write-baseline FILE)")
    for i, entry in enumerate(found):
        key = entry.get("key") if isinstance(entry, dict) else None
        if not isinstance(key, list) or not all(isinstance(part, str) for part in key):
            raise BaselineError(shown, f"findings[{i}] has no \"key\" list of strings")
        entries[tuple(key)] = entry
    return Baseline(shown, Path(path).parent, entries)
