"""How close two names are: one typo apart, or not.

Shared by the rules that suspect a typo: mis-wired topic names (``compare.wiring``), a given
parameter the node does not declare (``compare.launch_given``) and a new parameter next to an
existing one (``compare.parameter_drift``).
"""

from __future__ import annotations


def edit_distance(a: str, b: str) -> int:
    """Edit distance counting an insertion, a deletion, a substitution or two neighbouring
    characters swapped (``scna`` for ``scan``, the commonest typo) as one edit each."""
    rows = [list(range(len(b) + 1))]
    for i in range(1, len(a) + 1):
        row = [i] + [0] * len(b)
        for j in range(1, len(b) + 1):
            row[j] = min(rows[i - 1][j] + 1, row[j - 1] + 1, rows[i - 1][j - 1] + (a[i - 1] != b[j - 1]))
            if i > 1 and j > 1 and a[i - 1] == b[j - 2] and a[i - 2] == b[j - 1]:
                row[j] = min(row[j], rows[i - 2][j - 2] + 1)
        rows.append(row)
    return rows[-1][-1]


def typo_distance(a: str, b: str, *, shortest: int | None = None) -> int | None:
    """The edit distance of ``a`` and ``b`` when it is small enough to be a typo, else None.
    Short names are a letter apart by chance (``/a``, ``/b``): below 4 characters nothing is a
    typo, then one edit, and two from 10 characters. ``shortest``: the length that decides
    (default: the shorter name's)."""
    length = min(len(a), len(b)) if shortest is None else shortest
    allowed = 0 if length < 4 else 1 if length < 10 else 2
    distance = edit_distance(a, b)
    return distance if 0 < distance <= allowed else None
