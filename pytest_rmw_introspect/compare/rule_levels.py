"""Rule levels per project: the comparison option ``rules`` (issue 49).

Every finding carries a rule id and the level its rule has by default (docs/drift-rules.md says
why). A project may set a rule's level for itself, like ruff's ``select``/``ignore``,
cargo-semver-checks' lint levels or oasdiff's severity levels file::

    options:
      rules:
        PARAM_DEFAULT_CHANGED: note     # shown, never failing
        SUB_ADDED: breaking             # this robot has no optional inputs
        QOS_*_UNCERTAIN: off            # a family, by fnmatch pattern

The levels are ``off`` (the finding is dropped; the report counts them: "N findings turned off by
the project's rules"), ``note``, ``safe``, ``risky`` and ``breaking`` (``model.vocabulary.Severity``).
A key is a rule id or an ``fnmatch`` pattern of rule ids. Which key decides for a rule: its exact
id first; else, of the patterns that match it, the most specific, i.e. the one with the most
characters that are not wildcards (``QOS_DEPTH_*`` before ``QOS_*`` before ``*``); patterns equally
specific are an error where they are set, since their order would decide. Layers (ini file, pytest
command line, contract ``options:``, marker or ``rmw-introspect`` flags) merge key by key, the
stronger layer winning a key both set (``option_tables.PRECEDENCE``).

:func:`known` is the one list of every rule id a finding can carry, with its default level (a
unit test fails when a rule id used in the code is missing from it). An unknown id, a pattern
that matches no rule, or a level that is not one of the words is an ``OptionError`` that names
where it was set and, for an id, the closest known one.
"""

from __future__ import annotations

import dataclasses
import difflib
import fnmatch
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, TypeVar

from ..errors import OptionError
from ..model.vocabulary import Severity

#: the level words of the option, weakest first; ``off`` drops the finding
OFF = "off"
LEVELS: dict[str, Severity | None] = {
    OFF: None,
    "note": Severity.NOTE,
    "safe": Severity.SAFE,
    "risky": Severity.RISKY,
    "breaking": Severity.BREAKING,
}
_WILDCARDS = frozenset("*?[]")


def known() -> dict[str, Severity]:
    """Every rule id a finding can carry (drift, type, parameter, lifecycle, destruction and gate
    rules, and the compatibility rules of system checks) with its default level."""
    from . import compatibility, drift

    table = {rule_id: rule.severity for rule_id, rule in drift.RULES.items()}
    table.update(compatibility.RULES)
    return table


@dataclass(frozen=True)
class RuleLevel:
    """One key of ``rules``: a rule id or pattern, its level word, and where it was set."""

    key: str
    level: str
    source: str = dataclasses.field(compare=False)  # (two layers that say the same say the same)

    @property
    def severity(self) -> Severity | None:
        return LEVELS[self.level]

    @property
    def is_pattern(self) -> bool:
        return any(c in _WILDCARDS for c in self.key)

    @property
    def specificity(self) -> int:
        """The characters of the key that are not wildcards (an exact id: more than any pattern)."""
        if not self.is_pattern:
            return 1_000_000
        return sum(1 for c in self.key if c not in _WILDCARDS)

    def describe(self) -> str:
        """``set by rules: in SOURCE`` (and the pattern, when one decided)."""
        pattern = f" `{self.key}`" if self.is_pattern else ""
        return f"set by rules{pattern}: in {self.source}"


def _closest(key: str, ids: Sequence[str]) -> str:
    """The known id (or, for a pattern, the family pattern ``WORD_*``) closest to ``key``."""
    if any(c in _WILDCARDS for c in key):
        families = sorted({rule_id.split("_")[0] + "_*" for rule_id in ids})
        close = difflib.get_close_matches(key, families, n=1, cutoff=0.5)
        return f"; the closest family of rule ids is {close[0]}" if close else ""
    close = difflib.get_close_matches(key, ids, n=1, cutoff=0.5)
    return f"; the closest known rule id is {close[0]}" if close else ""


def _pairs(value: Any, source: str) -> list[tuple[str, Any]]:
    """``{RULE: LEVEL}`` (YAML, marker), or ``RULE=LEVEL`` words (a list from repeated flags, or one
    string with them separated by commas or spaces: an ini key) → (rule, level) pairs."""
    if isinstance(value, Mapping):
        return [(str(k), v) for k, v in value.items()]
    if isinstance(value, str):
        value = [v for v in value.replace(" ", ",").split(",") if v.strip()]
    if isinstance(value, (list, tuple)):
        pairs = []
        for word in value:
            if isinstance(word, Mapping):
                pairs += [(str(k), v) for k, v in word.items()]
                continue
            text = str(word).strip()
            rule, sep, level = text.partition("=")
            if not sep or not rule.strip():
                raise OptionError(f"{source}: `rules`: {text!r} is not RULE=LEVEL (a rule id or an fnmatch pattern "
                                  f"of rule ids, and one of {', '.join(LEVELS)})")
            pairs.append((rule.strip(), level.strip()))
        return pairs
    raise OptionError(f"{source}: `rules` must be a mapping of rule ids (or fnmatch patterns) to one of "
                      f"{', '.join(LEVELS)}, got {value!r}")


def parse(value: Any, source: str) -> tuple[RuleLevel, ...]:
    """Validate one layer's ``rules`` (raises OptionError naming ``source``)."""
    rules = known()
    ids = sorted(rules)
    parsed: dict[str, RuleLevel] = {}
    for key, level in _pairs(value, source):
        word = level if isinstance(level, str) else ("off" if level is False else str(level))
        word = word.strip().lower()
        if word not in LEVELS:
            raise OptionError(f"{source}: `rules`: {key}: unknown level {level!r}; the levels are "
                              f"{', '.join(LEVELS)}")
        entry = RuleLevel(key, word, source)
        if entry.is_pattern:
            if not any(fnmatch.fnmatchcase(rule, key) for rule in ids):
                raise OptionError(f"{source}: `rules`: the pattern {key} matches no rule id{_closest(key, ids)} "
                                  "(the rule ids are in docs/drift-rules.md)")
        elif key not in rules:
            raise OptionError(f"{source}: `rules`: unknown rule id {key}{_closest(key, ids)} (the rule ids are in "
                              "docs/drift-rules.md)")
        parsed[key] = entry
    _check_ties(parsed.values(), ids)
    return tuple(parsed.values())


def _check_ties(entries: Iterable[RuleLevel], ids: Sequence[str]) -> None:
    """Two patterns equally specific that match one rule with different levels: their order would
    decide, so it is an error."""
    patterns = [e for e in entries if e.is_pattern]
    for rule in ids:
        matching = [e for e in patterns if fnmatch.fnmatchcase(rule, e.key)]
        best = max((e.specificity for e in matching), default=None)
        tied = sorted({(e.key, e.level) for e in matching if e.specificity == best})
        if len({level for _, level in tied}) > 1:
            said = " and ".join(f"{key}: {level}" for key, level in tied)
            raise OptionError(f"{matching[0].source}: `rules`: {said} are equally specific and both match {rule}: "
                              "write the rule id, or a longer pattern, to say which level it has")


def merge(weaker: Sequence[RuleLevel], stronger: Sequence[RuleLevel]) -> tuple[RuleLevel, ...]:
    """Two layers' ``rules``, key by key, the stronger layer winning a key both set."""
    merged = {entry.key: entry for entry in weaker}
    merged.update((entry.key, entry) for entry in stronger)
    entries = tuple(merged.values())
    _check_ties(entries, sorted(known()))
    return entries


def level_of(rule: str, entries: Sequence[RuleLevel]) -> RuleLevel | None:
    """The key of ``entries`` that decides ``rule`` (None: its default level stands)."""
    matching = [e for e in entries if e.key == rule or (e.is_pattern and fnmatch.fnmatchcase(rule, e.key))]
    return max(matching, key=lambda e: e.specificity, default=None)


F = TypeVar("F")


@dataclass
class Applied:
    """The findings at the project's levels, and how many the rules turned off."""

    items: list[Any]
    off: int = 0


def apply(items: Iterable[F], entries: Sequence[RuleLevel]) -> Applied:
    """``items`` (drift items, system problems: frozen dataclasses with ``rule``, ``severity`` and
    ``level_set_by``) at the levels ``entries`` give them; ``off`` drops an item."""
    if not entries:
        return Applied(list(items))
    return apply_each(items, lambda item: [entries])


def _severest(decided: list[RuleLevel]) -> RuleLevel:
    return max(decided, key=lambda e: -2 if e.severity is None else int(e.severity))


def apply_each(items: Iterable[F], entries_of: Callable[[F], Sequence[Sequence[RuleLevel]]]) -> Applied:
    """As :func:`apply`, with each item's levels from the layers ``entries_of(item)`` gives (the
    files of a system problem's two ends, say): the most severe level any of them sets (``off`` the
    least), so that no file can make light of what another calls serious."""
    out: list[Any] = []
    off = 0
    for item in items:
        decided = [e for entries in entries_of(item) if (e := level_of(item.rule, entries)) is not None]  # type: ignore[attr-defined]
        if not decided:
            out.append(item)
            continue
        entry = _severest(decided)
        if entry.severity is None:
            off += 1
        else:
            out.append(dataclasses.replace(item, severity=entry.severity,  # type: ignore[type-var]
                                           level_set_by=entry.describe()))
    return Applied(out, off)


def turned_off_text(count: int) -> str:
    """The sentence a report says for the findings the project's rules turned off."""
    return f"{count} finding{'' if count == 1 else 's'} turned off by the project's rules"
