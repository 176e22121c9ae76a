"""Interface versions: ``interface_version: MAJOR.MINOR.PATCH`` of a contract, judged against the
drift between the contract at a base revision and the contract now (``rmw-introspect diff
--against REF``). Semantic versioning, with the drift rules' severities as its words:

- a BREAKING change needs a MAJOR bump (``1.4.2`` → ``2.0.0``);
- a RISKY change needs at least a MINOR bump (``1.4.2`` → ``1.5.0``);
- a SAFE change needs at least a PATCH bump (``1.4.2`` → ``1.4.3``); without one it is a note;
- while MAJOR is 0 (an interface still settling) everything moves one place down, as Cargo reads
  semantic versioning: ``0.3.1`` → ``0.4.0`` is the bump of a BREAKING change, ``0.3.1`` →
  ``0.3.2`` that of a RISKY one.

A change covered by the bump made is *accepted by the version* (reported as accepted, never
failing); a BREAKING or RISKY change without the bump it needs adds the finding
``INTERFACE_VERSION_BUMP_MISSING`` (BREAKING: it fails the gate) that says which version to
write; a version that went down is ``INTERFACE_VERSION_DECREASED``. A bump with no change and a
SAFE change without one are notes. Without a version on both sides (a version added or removed
since the base) nothing here applies: the gate judges the drift as ``diff`` does, and the one
note of ``model.interface_version.advice`` says so.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from ..model.acceptance import Acceptance
from ..model.interface_version import Bump, Version, advice, made, needed, needed_by
from ..model.vocabulary import Severity
from .acceptance import Accepted
from .drift import RULES, DriftItem

#: the pseudo node of findings about the version itself (``DriftItem.node``; kind ``node``)
VERSION_NODE = "interface_version"

@dataclass
class VersionJudgement:
    """The drift sorted by the version: ``kept`` still counts, ``accepted`` is covered by the bump,
    ``findings`` are about the version itself, ``notes`` are said and never fail."""

    kept: list[DriftItem] = field(default_factory=list)
    accepted: list[Accepted] = field(default_factory=list)
    findings: list[DriftItem] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    #: the smallest bump the drift needs (NONE: no drift)
    needs: Bump = Bump.NONE


def judge(items: Sequence[DriftItem], old_text: str | None, new_text: str | None, *, source: str,
          line: int | None = None, ref: str = "the base revision") -> VersionJudgement:
    """Sort ``items`` (the drift from the contract at the base revision ``ref`` to the contract
    now) by the two versions. ``source``/``line``: where the version is written now (for the
    accepted findings' reason)."""
    judged = VersionJudgement(needs=needed_by(items))
    if old_text is None or new_text is None:
        judged.kept = list(items)
        note = advice(items, new_text, base=old_text, base_known=True, ref=ref)
        if note is not None:
            judged.notes.append(note)
        return judged
    old, new = Version.parse(old_text), Version.parse(new_text)
    if new < old:
        judged.kept = list(items)
        judged.findings.append(_finding("INTERFACE_VERSION_DECREASED", old, new,
                                        f"interface_version went down from {old} to {new}; versions only go up"
                                        + (f": write {old.bumped(judged.needs)}" if judged.needs else "")))
        return judged
    bump = made(old, new)
    covered = Acceptance(rule="", reason=f"interface_version {old} → {new} ({bump.name} bump)", source=source,
                         line=line)
    for item in items:
        if needed(item.severity) <= bump:
            judged.accepted.append(Accepted(item, covered))
        else:
            judged.kept.append(item)
    if not items and bump is not Bump.NONE:
        judged.notes.append(f"interface_version {old} → {new} ({bump.name} bump) with no change of the interface")
    missing = [item for item in judged.kept if item.severity >= Severity.RISKY]
    if missing:
        need = needed_by(missing)
        worst = max(item.severity for item in missing)
        have = "not changed" if bump is Bump.NONE else f"{old} → {new} is a {bump.name} bump"
        judged.findings.append(_finding(
            "INTERFACE_VERSION_BUMP_MISSING", old, new,
            f"{len(missing)} {worst.name} change(s) need a {need.name} bump: write interface_version: "
            f"{old.bumped(need)} (it is {have})"))
    elif judged.kept:
        judged.notes.append(f"{len(judged.kept)} SAFE change(s) without a version bump: interface_version "
                            f"{old.bumped(Bump.PATCH)} would record them")
    return judged


def _finding(rule: str, old: Version, new: Version, message: str) -> DriftItem:
    return DriftItem(node=VERSION_NODE, kind="node", name=VERSION_NODE, change=VERSION_NODE, old=str(old),
                     new=str(new), rule=rule, severity=RULES[rule].severity, message=message)
