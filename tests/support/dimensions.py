"""What the Python 3.12, lowest-versions and Kilted tiers of .ci/run run (issue 48, item 4).

The suite runs in full on Jazzy and Python 3.11. Each other *dimension* CI covers (another Python,
the lowest dependency versions, another ROS 2 distribution) runs the tests that can differ along
it, chosen in ``tests/dimensions.toml`` (``select``), unless a file it depends on (``full_when``)
has changed since the last time that tier ran in full **and passed on this machine**: then it
runs in full, and a green full run is recorded in the cache (``ci-dimensions/`` under
``RMW_INTROSPECT_CACHE``, else ``~/.cache/pytest-rmw-introspect``), keyed by the content of those
files, the dimension's own definition, the Python that runs it and the run's ``-m``/``-k``/
``--ignore``/``--deselect`` options. The record says nothing about other content: a change of
any such file, on any branch, runs the tier in full once more.

    pytest --dimension python ...       # the tier of .ci/run: selected or full, as above
    pytest --dimension python --dimension distro ...   # one tier for two dimensions (below)
    RMWI_DIMENSION_FULL=1 pytest --dimension python ...   # in full, whatever the record

One tier may run several dimensions (Kilted on Python 3.12 is both another distribution and
another Python): it runs the union of their selections, or in full when any of them must, and
a green full run is recorded for each. A dimension with no ``full_when`` (``full_run`` says
where its full run happens instead) always runs its selection. Without ``--dimension`` nothing
changes. The selection stays honest as the code moves because
``tests/unit/test_dimensions.py`` fails when a package module imports a library a dimension
is about (``sensitive_imports``) without being under that dimension's ``full_when``, or when a
``select`` entry names no test.
"""

from __future__ import annotations

import datetime
import fnmatch
import hashlib
import json
import os
import subprocess
import sys
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]
DEFINITIONS = ROOT / "tests" / "dimensions.toml"
#: "1": run the dimension's tier in full whatever the record says
FORCE_FULL = "RMWI_DIMENSION_FULL"
#: the files every dimension's key holds besides its own ``full_when``: the selection itself
ALWAYS = ("tests/dimensions.toml", "tests/support/dimensions.py", "tests/conftest.py")
#: directories never walked for ``full_when`` files (venvs, builds, caches)
_SKIP_DIRS = {".git", "__pycache__", "build", "site", ".mypy_cache", ".ruff_cache", ".pytest_cache"}


@dataclass(frozen=True)
class Dimension:
    name: str
    title: str
    select: tuple[str, ...]
    full_when: tuple[str, ...]
    sensitive_imports: tuple[str, ...]
    #: where the dimension's full run happens when it has none of its own (no ``full_when``)
    full_run: str = ""


def load(path: Path = DEFINITIONS) -> dict[str, Dimension]:
    """The dimensions of ``tests/dimensions.toml``, by name."""
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    return {name: Dimension(name, table["title"], tuple(table["select"]), tuple(table["full_when"]),
                            tuple(table.get("sensitive_imports", ())), table.get("full_run", ""))
            for name, table in data.items()}


def _walk(root: Path, top: str) -> list[str]:
    """Every file under ``root/top`` (or ``top`` itself), as paths relative to ``root``."""
    start = root / top
    if start.is_file():
        return [top]
    found = []
    for directory, dirs, files in os.walk(start):
        dirs[:] = sorted(d for d in dirs if d not in _SKIP_DIRS and not d.startswith(".venv"))
        found += [Path(directory, f).relative_to(root).as_posix() for f in files if not f.endswith(".pyc")]
    return found


def matching_files(root: Path, patterns: tuple[str, ...]) -> list[str]:
    """The files (relative to ``root``) that the fnmatch ``patterns`` name; ``*`` crosses
    directories (``pytest_rmw_introspect/run/*`` is everything under run/), and a pattern without
    a wildcard names a file or everything under a directory."""
    found: set[str] = set()
    for pattern in patterns:
        literal = pattern.split("*", 1)[0].split("?", 1)[0].split("[", 1)[0]
        if literal == pattern:  # a file, or a directory
            found.update(_walk(root, pattern.rstrip("/")) if (root / pattern).exists() else [])
            continue
        top = literal.rsplit("/", 1)[0] if "/" in literal else "."
        found.update(path.removeprefix("./") for path in _walk(root, top)
                     if fnmatch.fnmatchcase(path.removeprefix("./"), pattern))
    return sorted(found)


def content(root: Path, dimension: Dimension) -> dict[str, str]:
    """Each file the dimension's full run depends on → the sha256 of its bytes."""
    files = sorted(set(matching_files(root, dimension.full_when)) | {p for p in ALWAYS if (root / p).is_file()})
    return {path: hashlib.sha256((root / path).read_bytes()).hexdigest() for path in files}


def key(dimension: Dimension, files: dict[str, str], run: dict[str, Any]) -> str:
    """The identity of a full run: the dimension, its files' content, the Python and the run's
    selection options."""
    h = hashlib.sha256()
    h.update(json.dumps([dimension.name, files, sys.version, run], sort_keys=True).encode())
    return h.hexdigest()[:20]


def record_dir() -> Path:
    explicit = os.environ.get("RMW_INTROSPECT_CACHE")
    base = Path(explicit) if explicit else Path.home() / ".cache" / "pytest-rmw-introspect"
    return base / "ci-dimensions"


@dataclass(frozen=True)
class Decision:
    """Whether the tier runs in full, and why (one line for the terminal)."""

    full: bool
    why: str
    key: str
    files: dict[str, str]
    #: the commit checked out when the files were read (what a green full run vouches for)
    commit: str = ""


def decide(root: Path, dimension: Dimension, run: dict[str, Any], records: Path,
           force: bool = False) -> Decision:
    """Full when forced, or when no green full run is recorded for this content; else selected.
    The reason names the files that differ from the newest full run recorded."""
    files = content(root, dimension)
    run_key = key(dimension, files, run)
    head = subprocess.run(["git", "-C", str(root), "rev-parse", "HEAD"], capture_output=True, text=True)
    commit = head.stdout.strip() if head.returncode == 0 else ""
    if not dimension.full_when:
        return Decision(False, f"selected: it has no full run of its own ({dimension.full_run})", run_key, files,
                        commit)
    if force:
        return Decision(True, f"in full ({FORCE_FULL}=1)", run_key, files, commit)
    if (records / f"{dimension.name}-{run_key}.json").is_file():
        return Decision(False, "selected: a full run passed on this machine for the same content of its "
                        f"{len(files)} files (tests/dimensions.toml)", run_key, files, commit)
    newest = _newest(records, dimension.name)
    if newest is None:
        return Decision(True, "in full: no full run recorded on this machine yet", run_key, files, commit)
    before = newest.get("files", {})
    changed = sorted(p for p in set(files) | set(before) if files.get(p) != before.get(p))
    shown = ", ".join(changed[:5]) + (f" and {len(changed) - 5} more" if len(changed) > 5 else "")
    why = f"changed since the last full run ({newest.get('when', '?')}): {shown}" if changed \
        else "the run's options or the Python differ from the last full run's"
    return Decision(True, f"in full: {why}", run_key, files, commit)


def _newest(records: Path, name: str) -> dict[str, Any] | None:
    paths = sorted(records.glob(f"{name}-*.json"), key=lambda p: p.stat().st_mtime)
    for path in reversed(paths):
        try:
            return json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
    return None


def record(records: Path, dimension: Dimension, decision: Decision, keep: int = 20) -> Path:
    """Write the record of a green full run (and drop all but the ``keep`` newest)."""
    records.mkdir(parents=True, exist_ok=True)
    path = records / f"{dimension.name}-{decision.key}.json"
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps({"dimension": dimension.name, "when": datetime.datetime.now(datetime.UTC)
                               .strftime("%Y-%m-%d %H:%M UTC"), "commit": decision.commit,
                               "python": sys.version.split()[0], "files": decision.files}, indent=1),
                   encoding="utf-8")
    tmp.replace(path)
    for old in sorted(records.glob(f"{dimension.name}-*.json"), key=lambda p: p.stat().st_mtime)[:-keep]:
        old.unlink(missing_ok=True)
    return path


def selected(nodeid: str, select: tuple[str, ...]) -> bool:
    """Whether a test (by node id, relative to the rootdir) is one of ``select``: a directory, a
    file or a node id prefix."""
    path = nodeid.split("::", 1)[0]
    for entry in select:
        if "::" in entry:
            if nodeid == entry or nodeid.startswith(entry + "::") or nodeid.startswith(entry + "["):
                return True
        elif path == entry or path.startswith(entry.rstrip("/") + "/"):
            return True
    return False


#: pytest options under which a green exit is no full run: nothing runs, or only a part does
PARTIAL_RUN_OPTIONS = {"collectonly": "--collect-only", "setuponly": "--setup-only", "setupplan": "--setup-plan",
                       "lf": "--last-failed", "stepwise": "--stepwise", "stepwise_skip": "--stepwise-skip"}


def not_a_full_run(options: Any, ran: int, paths_given: bool = False) -> str | None:
    """Why a green exit of a tier that was to run in full must not be recorded as a full run (a
    collection alone once recorded one, and the next CI then ran the selection), or None."""
    if paths_given:
        return "paths on the command line run a part of the tier"
    for dest, flag in PARTIAL_RUN_OPTIONS.items():
        if getattr(options, dest, False):
            return f"{flag} runs no test or a part of them"
    return None if ran else "no test ran"


class _Ran:
    """Counts the tests that ran (their call reports: in the xdist controller, its workers'). The
    terminal reporter's stats hold the same counts, but not under ``-p no:terminal``."""

    def __init__(self) -> None:
        self.count = 0

    def pytest_runtest_logreport(self, report: pytest.TestReport) -> None:
        if report.when == "call":
            self.count += 1


# ---------------------------------------------------------------------------- the pytest plugin
_DECISIONS = pytest.StashKey[list[tuple[Dimension, Decision]]]()
_RAN = pytest.StashKey[_Ran]()
#: what the end of the run says of its records (written in the terminal summary, on a line of its own)
_RECORDED = pytest.StashKey[list[str]]()


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption("--dimension", action="append", default=[], choices=sorted(load()),
                     help="run a CI dimension's tier: its selection of tests/dimensions.toml, or in full "
                          "when a file it depends on changed since its last green full run here "
                          "(repeat it for a tier that covers several dimensions)")


def _run_options(config: pytest.Config) -> dict[str, Any]:
    option = config.option
    return {"m": option.markexpr or "", "k": option.keyword or "",
            "ignore": sorted(option.ignore or []), "deselect": sorted(option.deselect or [])}


def pytest_configure(config: pytest.Config) -> None:
    names = list(dict.fromkeys(config.getoption("--dimension", None) or []))
    if not names:
        return
    defined = load()
    force = os.environ.get(FORCE_FULL) == "1"
    config.stash[_DECISIONS] = [(defined[name], decide(ROOT, defined[name], _run_options(config), record_dir(),
                                                       force=force and bool(defined[name].full_when)))
                                for name in names]
    config.stash[_RAN] = _Ran()
    config.stash[_RECORDED] = []
    config.pluginmanager.register(config.stash[_RAN], "rmwi-dimension-ran")


def _in_full(config: pytest.Config) -> list[str]:
    """The dimensions of this run that must run in full (the tier then runs in full)."""
    return [dimension.name for dimension, decision in config.stash[_DECISIONS] if decision.full]


def pytest_report_header(config: pytest.Config) -> list[str] | None:
    if _DECISIONS not in config.stash:
        return None
    full = _in_full(config)
    lines = []
    for dimension, decision in config.stash[_DECISIONS]:
        also = f"; the tier runs in full for {', '.join(full)}" if full and not decision.full else ""
        lines.append(f"dimension {dimension.name} ({dimension.title}): {decision.why}{also}")
    return lines


@pytest.hookimpl(trylast=True)
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    if _DECISIONS not in config.stash or _in_full(config):
        return
    select = tuple(entry for dimension, _ in config.stash[_DECISIONS] for entry in dimension.select)
    kept = [item for item in items if selected(item.nodeid, select)]
    dropped = [item for item in items if not selected(item.nodeid, select)]
    if dropped:
        config.hook.pytest_deselected(items=dropped)
        items[:] = kept


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    config = session.config
    if _DECISIONS not in config.stash or hasattr(config, "workerinput"):
        return
    if not (_in_full(config) and exitstatus == 0):
        return
    said = config.stash[_RECORDED]
    why_not = not_a_full_run(config.option, config.stash[_RAN].count,
                             paths_given=config.args_source == pytest.Config.ArgsSource.ARGS)
    for dimension, decision in config.stash[_DECISIONS]:
        if not dimension.full_when:
            continue
        if why_not:
            said.append(f"dimension {dimension.name}: no full run recorded: {why_not}")
        else:
            said.append(f"dimension {dimension.name}: a green full run recorded "
                        f"({record(record_dir(), dimension, decision)})")


def pytest_terminal_summary(terminalreporter: Any, exitstatus: int, config: pytest.Config) -> None:
    for line in config.stash.get(_RECORDED, []):
        terminalreporter.write_line(line)
