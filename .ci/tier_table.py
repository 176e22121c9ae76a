"""The closing table of .ci/run: each tier, its minutes, its budget; the tiers over budget named.

    python3 .ci/tier_table.py TIMES BUDGETS

TIMES has one line per tier .ci/run ran, ``NAME SECONDS STATUS`` (STATUS: the command's exit
status, or ``skipped``); BUDGETS is .ci/budgets (``NAME MINUTES``, ``#`` comments), where ``total``
is the budget of the whole run. A tier over its budget is a warning, not a failure: the exit
status is 0 whatever the times (issue 48, item 6). Standard library only: it runs with any python3.
"""

from __future__ import annotations

import sys
from pathlib import Path


def read_budgets(text: str) -> dict[str, float]:
    """``NAME MINUTES`` per line, comments and blank lines ignored."""
    budgets = {}
    for line in text.splitlines():
        fields = line.split("#", 1)[0].split()
        if fields:
            name, minutes = fields
            budgets[name] = float(minutes)
    return budgets


def read_times(text: str) -> list[tuple[str, float, str]]:
    """``(name, seconds, status)`` per line of TIMES, in the order the tiers ran."""
    rows = []
    for line in text.splitlines():
        if line.strip():
            name, seconds, status = line.split()
            rows.append((name, float(seconds), status))
    return rows


def table(times: list[tuple[str, float, str]], budgets: dict[str, float]) -> tuple[list[str], list[str]]:
    """The table's lines and the names of the tiers over budget (``total`` among them when the
    whole run is over its own)."""
    lines = [f"ci: {'tier':<20} {'minutes':>8} {'budget':>7}  result"]
    over = []
    for name, seconds, status in times:
        minutes = seconds / 60
        budget = budgets.get(name)
        result = "skipped" if status == "skipped" else "ok" if status == "0" else f"FAILED (exit {status})"
        if budget is not None and minutes > budget and status != "skipped":
            over.append(name)
            result += f", OVER BUDGET by {minutes - budget:.1f} min"
        lines.append(f"ci: {name:<20} {minutes:>8.1f} {'-' if budget is None else f'{budget:g}':>7}  {result}")
    total = sum(seconds for _, seconds, _ in times) / 60
    limit = budgets.get("total")
    lines.append(f"ci: {'total':<20} {total:>8.1f} {'-' if limit is None else f'{limit:g}':>7}")
    if limit is not None and total > limit:
        over.append("total")
    return lines, over


def main(argv: list[str]) -> int:
    times_file, budgets_file = map(Path, argv)
    times = read_times(times_file.read_text(encoding="utf-8")) if times_file.is_file() else []
    lines, over = table(times, read_budgets(budgets_file.read_text(encoding="utf-8")))
    print("\n".join(lines))
    if over:
        print(f"ci: warning: over budget ({budgets_file}): {', '.join(over)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
