"""What each test costs and what the suite exercises (issue 48; docs/development.md, "What a test
costs"): `make test-cost`, `make coverage`.

Off unless ``RMWI_TEST_COST`` names a directory. Then each test process (each xdist worker, or
the one process of ``-n 0``) sets ``RMW_INTROSPECT_TALLY`` to a file of its own in it, which the
package appends one line to per target started, command run, format printed, rule met and
contract kind read (``pytest_rmw_introspect/model/tally.py``); the variable is inherited by the
pytest and ``rmw-introspect`` subprocesses a test starts, so what they start counts for the test
that started them. Around each test (setup, call and teardown) this plugin notes the wall time
and the lines the test appended, and writes one JSON line per test (``<worker>.jsonl``). At the
end of the session the controller (or the one process) reads them all, prints per tier the totals
and the 30 slowest tests with their target starts, and writes ``report.json``:

    {"tiers": {tier: {"tests", "seconds", "starts"}}, "top": {tier: [{"nodeid", "seconds", "starts",
     "cold", "warm", "direct"}, ...]}, "exercised": {"e2e": {what: [names]}, "unit": ...},
     "tests": [every test's record]}

``python tests/support/cost_report.py DIR`` prints the report of a directory again.

What is not counted: processes a test starts with an environment of its own that drops the
variable, processes the overlay tier starts itself, and lines a process writes after its test
ended (they count for the next test of that worker).
"""

from __future__ import annotations

import json
import os
import sys
import time
from collections import defaultdict
from pathlib import Path
from typing import Any

import pytest

#: the directory of the tally files, the per-test records and the report (unset: the plugin is off)
ENV = "RMWI_TEST_COST"
TALLY = "RMW_INTROSPECT_TALLY"  # pytest_rmw_introspect.model.tally.ENV
TOP = 30
#: the tiers, most specific first (tests/conftest.py marks them)
TIERS = ("slow", "overlay", "e2e", "plugin")
#: the tiers whose exercised set counts as end to end (a real process, or pytest in a subprocess)
END_TO_END = ("e2e", "overlay", "plugin", "slow")


def tier_of(markers: set[str]) -> str:
    """The tier a test's markers put it in: slow, overlay, e2e, plugin, else unit."""
    return next((tier for tier in TIERS if tier in markers), "unit")


def read_tally(text: str) -> dict[str, Any]:
    """The tally lines a test appended: its target starts by how they started, and what it
    exercised (``{"command": [...], "format": [...], "rule": [...], "kind": [...]}``)."""
    starts: dict[str, int] = defaultdict(int)
    exercised: dict[str, set[str]] = defaultdict(set)
    for line in text.splitlines():
        what, _, name = line.partition("\t")
        if what == "start":
            starts[name] += 1
        elif what and name:
            exercised[what].add(name)
    return {"starts": sum(starts.values()), "cold": starts["cold"], "warm": starts["warm"],
            "direct": starts["direct"], "exercised": {k: sorted(v) for k, v in sorted(exercised.items())}}


def summarize(records: list[dict[str, Any]], top: int = TOP) -> dict[str, Any]:
    """The report of every test's record (see the module's docstring)."""
    tiers: dict[str, dict[str, Any]] = {}
    by_tier: dict[str, list[dict[str, Any]]] = defaultdict(list)
    exercised: dict[str, dict[str, set[str]]] = {"e2e": defaultdict(set), "unit": defaultdict(set)}
    for rec in records:
        by_tier[rec["tier"]].append(rec)
        side = "e2e" if rec["tier"] in END_TO_END else "unit"
        for what, names in rec.get("exercised", {}).items():
            exercised[side][what].update(names)
    for tier, recs in sorted(by_tier.items()):
        tiers[tier] = {"tests": len(recs), "seconds": round(sum(r["seconds"] for r in recs), 2),
                       "starts": sum(r["starts"] for r in recs)}
    slowest = {tier: [{k: r[k] for k in ("nodeid", "seconds", "starts", "cold", "warm", "direct")}
                      for r in sorted(recs, key=lambda r: (-r["seconds"], r["nodeid"]))[:top]]
               for tier, recs in sorted(by_tier.items())}
    return {"tiers": tiers, "top": slowest,
            "exercised": {side: {what: sorted(names) for what, names in sorted(sets.items())}
                          for side, sets in exercised.items()},
            "tests": sorted(records, key=lambda r: r["nodeid"])}


def format_report(report: dict[str, Any]) -> str:
    """The report as the terminal shows it."""
    lines = ["test cost (docs/development.md, \"What a test costs\"): wall time and target processes started",
             f"{'tier':<8} {'tests':>6} {'seconds':>9} {'starts':>7}  {'s/test':>7}"]
    for tier, t in report["tiers"].items():
        lines.append(f"{tier:<8} {t['tests']:>6} {t['seconds']:>9.1f} {t['starts']:>7}  "
                     f"{t['seconds'] / max(t['tests'], 1):>7.2f}")
    for tier, recs in report["top"].items():
        lines.append(f"-- {tier}: the {len(recs)} slowest (seconds, starts cold+warm+direct, test)")
        for r in recs:
            lines.append(f"{r['seconds']:>8.2f} {r['starts']:>4} ({r['cold']}+{r['warm']}+{r['direct']})  {r['nodeid']}")
    e2e = report["exercised"]["e2e"]
    if e2e:
        lines.append("-- exercised end to end: " + "; ".join(f"{len(v)} {k}(s)" for k, v in e2e.items()))
    return "\n".join(lines)


def load_records(directory: Path) -> list[dict[str, Any]]:
    records = []
    for path in sorted(directory.glob("*.jsonl")):
        records += [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines() if line]
    return records


# ---------------------------------------------------------------------------- the plugin
def _directory() -> Path | None:
    value = os.environ.get(ENV)
    return Path(value).resolve() if value else None


def _controller(config: pytest.Config) -> bool:
    """This process hands the tests to xdist workers (and runs none itself)."""
    return not hasattr(config, "workerinput") and getattr(config.option, "dist", "no") != "no" \
        and bool(getattr(config.option, "numprocesses", 0))


#: the pid of the run's first pytest process (the xdist controller, or the one process of -n 0),
#: set by it: a pytest that a test starts inherits it and keeps out of the report
RUN = "RMWI_TEST_COST_RUN"


def _nested(config: pytest.Config) -> bool:
    """A pytest that a test of the measured run started (not the run, nor one of its xdist
    workers): its targets count for that test through the tally file it inherited, if any; it must
    not start a report of its own (a subprocess whose environment dropped ``RMW_INTROSPECT_*`` but
    kept ``RMWI_TEST_COST``, like the overlay tier's, once deleted the run's records)."""
    owner = os.environ.get(RUN)
    if not owner or owner == str(os.getpid()):
        return False
    return not (hasattr(config, "workerinput") and str(os.getppid()) == owner)


def pytest_configure(config: pytest.Config) -> None:
    directory = _directory()
    if directory is None or _nested(config):
        return  # off, or a pytest a test started (its tally goes to that test's file)
    os.environ.setdefault(RUN, str(os.getpid()))
    directory.mkdir(parents=True, exist_ok=True)
    if not hasattr(config, "workerinput"):  # a new report: the files of the last one go
        for old in (*directory.glob("*.jsonl"), *directory.glob("*.tally")):
            old.unlink()
    if _controller(config):
        return
    worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
    tally = directory / f"{worker}.tally"
    tally.write_bytes(b"")
    os.environ[TALLY] = str(tally)
    config.stash[_KEY] = (tally, directory / f"{worker}.jsonl")


_KEY = pytest.StashKey[tuple[Path, Path]]()


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item: pytest.Item, nextitem: pytest.Item | None):
    files = item.config.stash.get(_KEY, None)
    if files is None:
        yield
        return
    tally, records = files
    offset = tally.stat().st_size
    began = time.perf_counter()
    yield
    seconds = time.perf_counter() - began
    with tally.open("rb") as f:
        f.seek(offset)
        appended = f.read().decode("utf-8", "replace")
    rec = {"nodeid": item.nodeid, "tier": tier_of({m.name for m in item.iter_markers()}),
           "seconds": round(seconds, 3), **read_tally(appended)}
    with records.open("a", encoding="utf-8") as f:
        f.write(json.dumps(rec) + "\n")


def pytest_terminal_summary(terminalreporter: Any, config: pytest.Config) -> None:
    directory = _directory()
    if directory is None or hasattr(config, "workerinput") or _nested(config) or os.environ.get(RUN) != str(os.getpid()):
        return
    report = summarize(load_records(directory))
    (directory / "report.json").write_text(json.dumps(report, indent=1) + "\n", encoding="utf-8")
    terminalreporter.write_line(format_report(report))
    terminalreporter.write_line(f"test cost: {directory / 'report.json'}")


if __name__ == "__main__":
    print(format_report(summarize(load_records(Path(sys.argv[1])))))
