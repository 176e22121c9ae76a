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


_VERSION = re.compile(r"^(0|[1-9][0-9]*)\.(0|[1-9][0-9]*)\.(0|[1-9][0-9]*)$")


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
            raise ValueError(f"interface_version {text!r} is not MAJOR.MINOR.PATCH (e.g. 1.0.0)")
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
    return {Severity.BREAKING: Bump.MAJOR, Severity.RISKY: Bump.MINOR, Severity.SAFE: Bump.PATCH}[severity]


def needed_by(items: Sequence[_Graded]) -> Bump:
    """The bump the drift needs: that of its most severe change."""
    return max((needed(item.severity) for item in items), default=Bump.NONE)


def advice(items: Sequence[_Graded], version: str | None) -> str | None:
    """What an update that writes ``items`` into a contract at ``version`` must do to the version
    (``check --update``, ``--update-golden``: they never change it themselves); None without a
    version or drift."""
    need = needed_by(items)
    if version is None or need is Bump.NONE:
        return None
    try:
        current = Version.parse(version)
    except ValueError:
        return None
    worst = max(item.severity for item in items)
    return (f"interface_version {current} was not changed: this update holds {worst.name} change(s), which need "
            f"a {need.name} bump: write interface_version: {current.bumped(need)} (docs/ci.md)")


