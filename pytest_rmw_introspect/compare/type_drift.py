"""Why did a type hash change? Field-level differences between two descriptions of a type.

``compare_tables(old, new, roots)`` compares every type an interface uses (``roots`` and
everything they nest, as far as both tables describe them) and returns :class:`TypeChange`
records; ``compare.drift`` turns them into drift items under the interface, with the rule
severities of :data:`RULES` (reasons in docs/drift-rules.md).

Fields are matched by name. What is left over is paired by place: a removed and an added field
with the same type in the same place (after the same surviving field) look like a rename.
Fields still there but in another order are one reordering. Constants are compared by name,
and only when both sides know them.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from ..model.types import UNBOUNDED, Constant, Field, MessageType, TypeDescription, closure
from ..model.vocabulary import Severity

_B, _R, _S = Severity.BREAKING, Severity.RISKY, Severity.SAFE

#: rule id → (severity, summary); ``compare.drift.RULES`` holds them with the other rules
RULES: dict[str, tuple[Severity, str]] = {
    "TYPE_FIELD_REMOVED": (_B, "a field of a type was removed"),
    "TYPE_FIELD_INSERTED": (_B, "a field was added before existing fields"),
    "TYPE_FIELD_ADDED": (_R, "a field was added after the last existing field"),
    "TYPE_FIELD_RENAMED": (_B, "a field looks renamed (same type and place, another name)"),
    "TYPE_FIELD_RETYPED": (_B, "a field's element type or array layout changed"),
    "TYPE_FIELD_BOUND_NARROWED": (_R, "a sequence or string bound was lowered or added"),
    "TYPE_FIELD_BOUND_WIDENED": (_R, "a sequence or string bound was raised or removed"),
    "TYPE_FIELDS_REORDERED": (_B, "the same fields in another order"),
    "TYPE_CONSTANT_ADDED": (_S, "a constant was added"),
    "TYPE_CONSTANT_REMOVED": (_R, "a constant was removed"),
    "TYPE_CONSTANT_CHANGED": (_R, "a constant's value or type changed"),
}


@dataclass(frozen=True)
class TypeChange:
    """One difference in one type: ``old`` / ``new`` are ``.msg`` lines (``float64 x``,
    ``int32 LIMIT=3``), or the field names in order for a reordering; None on the side
    that lacks it."""

    type_name: str
    rule: str
    old: Any
    new: Any
    message: str


def compare_tables(
    old: Mapping[str, TypeDescription], new: Mapping[str, TypeDescription], roots: Iterable[str]
) -> list[TypeChange]:
    """Differences of the types ``roots`` use that both sides describe, type by type in order of
    first reference (a type only one side reaches is the consequence of a retyped field)."""
    roots = list(roots)
    reached_new = set(closure(new, roots))
    changes: list[TypeChange] = []
    for name in closure(old, roots):
        if name not in reached_new:
            continue
        before, after = old[name], new[name]
        if isinstance(before, MessageType) and isinstance(after, MessageType):
            changes += compare_messages(before, after)
    return changes


def compare_messages(old: MessageType, new: MessageType) -> list[TypeChange]:
    """Field and constant differences of two descriptions of one message type."""
    return _field_changes(old, new) + _constant_changes(old, new)


# ---------------------------------------------------------------------------- fields


def _slots(fields: tuple[Field, ...], common: set[str]) -> dict[str, tuple[str | None, int]]:
    """Each field not in ``common``: (the surviving field before it, its number after that one)."""
    slots: dict[str, tuple[str | None, int]] = {}
    anchor: str | None = None
    count = 0
    for f in fields:
        if f.name in common:
            anchor, count = f.name, 0
        else:
            slots[f.name] = (anchor, count)
            count += 1
    return slots


def _longest_common_subsequence(a: list[str], b: list[str]) -> list[str]:
    lengths = [[0] * (len(b) + 1) for _ in range(len(a) + 1)]
    for i in range(len(a) - 1, -1, -1):
        for j in range(len(b) - 1, -1, -1):
            lengths[i][j] = lengths[i + 1][j + 1] + 1 if a[i] == b[j] else max(lengths[i + 1][j], lengths[i][j + 1])
    out, i, j = [], 0, 0
    while i < len(a) and j < len(b):
        if a[i] == b[j]:
            out.append(a[i])
            i, j = i + 1, j + 1
        elif lengths[i + 1][j] >= lengths[i][j + 1]:
            i += 1
        else:
            j += 1
    return out


def _field_changes(old: MessageType, new: MessageType) -> list[TypeChange]:
    t = old.name
    new_by_name = {f.name: f for f in new.fields}
    old_names = {f.name for f in old.fields}
    common = {f.name for f in old.fields if f.name in new_by_name}
    old_slots, new_slots = _slots(old.fields, common), _slots(new.fields, common)
    added = [f for f in new.fields if f.name not in old_names]
    renamed: dict[str, Field] = {}  # old name → the new field it looks renamed to
    for removed in (f for f in old.fields if f.name not in new_by_name):
        for candidate in added:
            if (candidate not in renamed.values() and candidate.spec() == removed.spec()
                    and new_slots[candidate.name] == old_slots[removed.name]):
                renamed[removed.name] = candidate
                break

    changes: list[TypeChange] = []

    def change(rule: str, old_value: Any, new_value: Any, message: str) -> None:
        changes.append(TypeChange(t, rule, old_value, new_value, f"{t}: {message}"))

    for f in old.fields:
        if f.name in common:
            changes.extend(_same_field_changes(t, f, new_by_name[f.name]))
        elif f.name in renamed:
            g = renamed[f.name]
            change("TYPE_FIELD_RENAMED", f.line(), g.line(),
                   f"field `{f.name}` looks renamed to `{g.name}` (same type {f.spec()}, same place): the bytes "
                   "are the same, but everything that reads the field by name breaks")
        else:
            after = [g.name for g in old.fields[old.fields.index(f) + 1:] if g.name in common or g.name in renamed]
            consequence = ("the fields after it move on the wire" if after else
                           "peers built from the old definition find messages too short")
            change("TYPE_FIELD_REMOVED", f.line(), None, f"field `{f.line()}` removed: readers of it break and "
                   + consequence)

    renamed_to = {g.name for g in renamed.values()}
    kept_positions = [i for i, g in enumerate(new.fields) if g.name in common or g.name in renamed_to]
    last_kept = kept_positions[-1] if kept_positions else -1
    for i, g in enumerate(new.fields):
        if g.name in old_names or g.name in renamed_to:
            continue
        if i > last_kept:
            change("TYPE_FIELD_ADDED", None, g.line(),
                   f"field `{g.line()}` added at the end: peers built from the old definition ignore or reject "
                   "the longer messages (depending on the middleware), and their messages lack it")
        else:
            following = new.fields[i + 1].name
            change("TYPE_FIELD_INSERTED", None, g.line(),
                   f"field `{g.line()}` inserted before `{following}`: every field after it moves on the wire")

    old_order = [f.name for f in old.fields if f.name in common]
    new_order = [g.name for g in new.fields if g.name in common]
    if old_order != new_order:
        moved = [n for n in new_order if n not in set(_longest_common_subsequence(old_order, new_order))]
        change("TYPE_FIELDS_REORDERED", old_order, new_order,
               f"fields reordered ({', '.join(f'`{n}`' for n in moved)} moved): the wire layout changes although "
               "every field is still there")
    return changes


def _shape(f: Field) -> tuple[Any, ...]:
    """What decides the wire layout of a field besides its element type."""
    if f.array is None:
        return ("one",)
    if f.array == "fixed":
        return ("fixed", f.array_size)
    return ("sequence",)


def _bound_change(t: str, old: Field, new: Field, old_bound: int | None, new_bound: int | None,
                  what: str) -> TypeChange | None:
    if old_bound == new_bound:
        return None
    transition = f"field `{old.name}` {old.spec()} -> {new.spec()}"
    if new_bound is not None and (old_bound is None or new_bound < old_bound):
        return TypeChange(t, "TYPE_FIELD_BOUND_NARROWED", old.line(), new.line(),
                          f"{t}: {transition}: {what} longer than {new_bound}, valid before, are now rejected")
    limit = f"longer than {old_bound}"
    return TypeChange(t, "TYPE_FIELD_BOUND_WIDENED", old.line(), new.line(),
                      f"{t}: {transition}: peers built from the old definition reject {what} {limit}")


def _same_field_changes(t: str, old: Field, new: Field) -> list[TypeChange]:
    """A field present on both sides: its element type, array layout and bounds."""
    transition = f"field `{old.name}` {old.spec()} -> {new.spec()}"
    if old.type != new.type:
        return [TypeChange(t, "TYPE_FIELD_RETYPED", old.line(), new.line(),
                           f"{t}: {transition}: the field's wire representation changes")]
    if _shape(old) != _shape(new):
        return [TypeChange(t, "TYPE_FIELD_RETYPED", old.line(), new.line(),
                           f"{t}: {transition}: the array layout changes on the wire")]
    changes = []
    if old.array is not None and old.array != "fixed":
        old_bound = None if old.array == UNBOUNDED else old.array_size
        new_bound = None if new.array == UNBOUNDED else new.array_size
        found = _bound_change(t, old, new, old_bound, new_bound, "sequences")
        if found:
            changes.append(found)
    found = _bound_change(t, old, new, old.string_bound, new.string_bound, "strings")
    if found:
        changes.append(found)
    return changes


# ---------------------------------------------------------------------------- constants


def _constant_changes(old: MessageType, new: MessageType) -> list[TypeChange]:
    if old.constants is None or new.constants is None:
        return []  # one side does not know them: not compared
    t = old.name
    new_by_name: dict[str, Constant] = {c.name: c for c in new.constants}
    old_names = {c.name for c in old.constants}
    changes = []
    for c in old.constants:
        other = new_by_name.get(c.name)
        if other is None:
            changes.append(TypeChange(t, "TYPE_CONSTANT_REMOVED", c.line(), None,
                                      f"{t}: constant `{c.line()}` removed: code using it no longer builds"))
        elif (c.type, c.value) != (other.type, other.value):
            changes.append(TypeChange(
                t, "TYPE_CONSTANT_CHANGED", c.line(), other.line(),
                f"{t}: constant `{c.line()}` -> `{other.line()}`: not on the wire and not in the type hash, but "
                "peers built from the old definition give the values another meaning"))
    for c in new.constants:
        if c.name not in old_names:
            changes.append(TypeChange(t, "TYPE_CONSTANT_ADDED", None, c.line(),
                                      f"{t}: constant `{c.line()}` added"))
    return changes
