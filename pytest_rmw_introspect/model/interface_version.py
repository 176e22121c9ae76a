"""Interface versions as values: ``interface_version: MAJOR.MINOR.PATCH`` parsed, the bump
between two versions, the bump a change of each severity needs (semantic versioning in the drift
rules' words: BREAKING a MAJOR bump, RISKY a MINOR one, SAFE a PATCH one; one place down while
MAJOR is 0), and what an update must do to the version. ``compare.versioning`` judges drift with
them; ``check.outcome`` says what an update needs (updates never change the version)."""

from __future__ import annotations

import enum
import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

from .vocabulary import Severity


class _Graded(Protocol):
    @property
    def severity(self) -> Severity: ...


#: each part at most 18 digits (the schema says so too): a version of 5,000 digits is refused, not
#: converted (int() of more than 4,300 digits raises, and nobody numbers an interface that far)
MAX_DIGITS = 18
_VERSION = re.compile(r"^(0|[1-9][0-9]{0,17})\.(0|[1-9][0-9]{0,17})\.(0|[1-9][0-9]{0,17})$")


class Bump(enum.IntEnum):
    """How far a version moved, in semantic versioning's places."""

    NONE = 0
    PATCH = 1
    MINOR = 2
    MAJOR = 3


@dataclass(frozen=True, order=True)
class Version:
    major: int
    minor: int
    patch: int

    @classmethod
    def parse(cls, text: str) -> Version:
        """``1.2.3`` (the schema checked the form; raises ValueError otherwise)."""
        found = _VERSION.match(str(text).strip())
        if found is None:
            shown = str(text) if len(str(text)) <= 60 else f"{str(text)[:30]}... ({len(str(text)):,} characters)"
            raise ValueError(f"interface_version {shown!r} is not MAJOR.MINOR.PATCH with parts of at most "
                             f"{MAX_DIGITS} digits (e.g. 1.0.0)")
        return cls(*(int(part) for part in found.groups()))

    def __str__(self) -> str:
        return f"{self.major}.{self.minor}.{self.patch}"

    def bumped(self, bump: Bump) -> Version:
        """The smallest version after this one with ``bump`` (read as :func:`needed` reads it)."""
        place = _place(self, bump)
        if place is Bump.MAJOR:
            return Version(self.major + 1, 0, 0)
        if place is Bump.MINOR:
            return Version(self.major, self.minor + 1, 0)
        return Version(self.major, self.minor, self.patch + 1)


def _place(version: Version, bump: Bump) -> Bump:
    """Where ``bump`` is written in ``version``: one place down while MAJOR is 0."""
    if version.major == 0 and bump > Bump.PATCH:
        return Bump(bump - 1)
    return bump


def made(old: Version, new: Version) -> Bump:
    """The bump from ``old`` to ``new`` (NONE when equal; the caller checks for a decrease)."""
    if new.major != old.major:
        bump = Bump.MAJOR
    elif new.minor != old.minor:
        bump = Bump.MINOR
    elif new.patch != old.patch:
        bump = Bump.PATCH
    else:
        return Bump.NONE
    if old.major == 0 and new.major == 0:  # 0.x: the minor place says MAJOR, the patch place MINOR
        return Bump(bump + 1)
    return bump


def needed(severity: Severity) -> Bump:
    return {Severity.BREAKING: Bump.MAJOR, Severity.RISKY: Bump.MINOR, Severity.SAFE: Bump.PATCH,
            Severity.NOTE: Bump.NONE}[severity]


def needed_by(items: Sequence[_Graded]) -> Bump:
    """The bump the drift needs: that of its most severe change."""
    return max((needed(item.severity) for item in items), default=Bump.NONE)


def advice(items: Sequence[_Graded], version: str | None, *, base: str | None = None, base_known: bool = False,
           ref: str = "the base revision") -> str | None:
    """The one piece of ``interface_version`` advice the gate and the updates give beside what the
    gate decides (``compare.versioning.judge`` turns a bump that is missing between two versions
    into a finding; this says everything else), or None: nothing to say.

    ``items``: the changes; ``version``: the contract's version now. ``base_known`` (the gate):
    ``base`` is the version at ``ref``, and the advice is what the gate decides against it: a
    version on one side only is no version for this change (judged as ``diff`` judges it), the
    next change is judged against it. Not ``base_known`` (``check --update``, ``pytest
    --update-golden``: they never change the version): the bump is owed to the version at the base
    revision the pull request goes to, which an update cannot know; the gate against it decides."""
    items = [item for item in items if item.severity > Severity.NOTE]  # a note needs no bump
    need = needed_by(items)
    worst = max((item.severity for item in items), default=None)
    changes = f"these {worst.name} change(s)" if worst is not None else "no change"
    try:
        now = Version.parse(version) if version is not None else None
        old = Version.parse(base) if base is not None else None
    except ValueError:
        return None
    if not base_known:
        if now is None or worst is None:
            return None
        return (f"interface_version {now} was not changed: this update holds {worst.name} change(s), which need a {need.name} "
                f"bump over the version at the base revision (an update cannot know it): write interface_version: "
                f"{now.bumped(need)}, unless {now} already is such a bump over the base; `rmw-introspect diff "
                "--against BASE` (pytest --against BASE) decides (docs/ci.md)")
    if old is not None and now is not None:
        return None  # both versions: compare.versioning.judge decides, and its findings say what to write
    if now is not None:
        return (f"interface_version {now} is new here (none at {ref}): {changes} judged without a version, as "
                f"`diff` judges them; the next change is judged against {now}")
    if old is not None:
        keep = f" (kept, they would need interface_version: {old.bumped(need)})" if need is not Bump.NONE else ""
        return f"interface_version {old} was removed: {changes} judged without it{keep}"
    if need is Bump.NONE:
        return None
    return (f"under semantic versioning {changes} need a {need.name} bump; with `interface_version: "
            f"MAJOR.MINOR.PATCH` at {ref} and now the gate judges changes by their bump (docs/ci.md)")
