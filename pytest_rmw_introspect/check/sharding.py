"""Which contracts one CI job of several checks (``check --shard I/N``, pytest
``--rmw-introspect-shard I/N``): the contracts sorted by a stable key (their path, or a pytest
node id) and dealt round-robin, so that each job gets the same share whatever order the shell or
the collection gives them in, the shares differ by at most one contract, and together the N
jobs check every contract exactly once."""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TypeVar

from ..errors import UsageError

T = TypeVar("T")

_SPEC = re.compile(r"^\s*(\d+)\s*/\s*(\d+)\s*$")


@dataclass(frozen=True)
class Shard:
    """Shard ``index`` (1-based) of ``count``."""

    index: int
    count: int

    def __str__(self) -> str:
        return f"{self.index}/{self.count}"

    def select(self, things: Sequence[T], key: Callable[[T], str]) -> list[T]:
        """This shard's share of ``things`` (in their given order), by the sorted ``key``s;
        things with the same key stay together."""
        keys = sorted({key(thing) for thing in things})
        mine = {k for i, k in enumerate(keys) if i % self.count == self.index - 1}
        return [thing for thing in things if key(thing) in mine]


def parse(text: str, option: str = "--shard") -> Shard:
    """``I/N`` → Shard (raises UsageError saying what to write)."""
    found = _SPEC.match(str(text))
    if found is None:
        raise UsageError(f"{option} {text!r} is not of the form I/N (this job's number I of N jobs, e.g. 2/4)")
    index, count = int(found.group(1)), int(found.group(2))
    if count < 1 or not 1 <= index <= count:
        raise UsageError(f"{option} {text}: I must be between 1 and N (N >= 1), e.g. 1/{max(count, 2)} to "
                         f"{max(count, 2)}/{max(count, 2)}")
    return Shard(index, count)
