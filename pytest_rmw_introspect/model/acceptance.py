"""Findings a contract accepts on purpose (its ``accept:`` list): each entry names a rule and,
optionally, the interface name and node it is about, with the reason. ``compare.acceptance``
decides which findings an entry accepts; this module only reads the entries."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

#: the contract key (node and system contracts)
SECTION_KEY = "accept"


@dataclass(frozen=True)
class Acceptance:
    """One ``accept:`` entry. ``source``: the contract as shown; ``line``: where the entry is."""

    rule: str
    reason: str
    name: str | None = None
    node: str | None = None
    source: str = ""
    line: int | None = None
    #: an entry of a baseline file (``compare.baseline``), not of the contract
    baseline: bool = False

    def describe(self) -> str:
        """``RULE name /x node /n`` as a person reads it in a report."""
        words = [self.rule]
        if self.name is not None:
            words.append(f"name {self.name}")
        if self.node is not None:
            words.append(f"node {self.node}")
        return " ".join(words)

    def where(self) -> str:
        """``contract.yaml:12``: the entry's place, for messages."""
        return f"{self.source}:{self.line}" if self.line else self.source

    def to_json(self) -> dict[str, Any]:
        if self.baseline:
            return {"baseline": self.source, "reason": self.reason}
        return {"rule": self.rule, "name": self.name, "node": self.node, "reason": self.reason,
                "contract": self.source, "line": self.line}


def from_entries(entries: Sequence[Any] | None, *, source: str,
                 line_of: Callable[[int], int | None]) -> tuple[Acceptance, ...]:
    """The entries of a schema-valid ``accept:`` list; ``line_of(i)``: the line of entry ``i``."""
    return tuple(
        Acceptance(rule=str(entry["rule"]), reason=str(entry["reason"]).strip(),
                   name=str(entry["name"]) if entry.get("name") is not None else None,
                   node=str(entry["node"]) if entry.get("node") is not None else None,
                   source=source, line=line_of(i))
        for i, entry in enumerate(entries or ())
    )
