"""The precision suite's machinery, shared by its tests (tests/precision/test_precision.py) and by
the command that regenerates the precision table (scripts/precision_table.py).

A **modelled system** is a directory of tests/precision/systems: ``system.yaml`` (what it is
modelled on, its launch file, the outside world it declares under ``external:``, and its seeded
mutations) and one directory per ROS package of the bring-up (launch files, parameters files,
calibration and map files, and ``standins.yaml``: the nodes of its executables, run by
``standin_node.py``). Packages several systems share (robot_state_publisher, joy, ...) live in
tests/precision/packages and are named by a system's ``shared:`` list.

A system is **installed** into a prefix of its own (``share/<package>/`` with the package's files,
the ament index entry, an executable per ``standins.yaml`` entry under ``lib/<package>/``), which is
put ahead of AMENT_PREFIX_PATH, so ``$(find-pkg-share)``, ``package``/``exec`` and ``--launch-package``
resolve to it like to a colcon install.

**The gate** is what a team gets on day one: ``rmw-introspect capture --launch-package P
--launch-file F`` writes the system contract, the system's ``external:`` block is added to it, and
``rmw-introspect check`` checks it (default options: system_fail_on breaking). A correct system must
pass it with no finding at all. A **mutation** is a seeded bug applied to a copy of the installed
system (a text edit of one installed file, or an installed file deleted); the correct system's
contract is then checked against it, and the system rules' findings (the compatibility rules of a
system check, not the drift from the contract's nodes) are the gate without a golden."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml
from cli_process import Result, console_script

HERE = Path(__file__).resolve().parent
SYSTEMS_DIR = HERE / "systems"
SHARED_DIR = HERE / "packages"
RESULTS = HERE / "results.json"
STANDIN = HERE / "standin_node.py"

#: the seeded bugs every system has, in the order of the table
MUTATION_KINDS = {
    "remap_to_wrong_name": "a remap to the wrong name",
    "wrong_namespace": "a topic in the wrong namespace",
    "renamed_node_section": "a parameters file section for a renamed node",
    "retyped_topic": "a retyped topic",
    "lost_comment_hash": "a lost `#` in a parameters file comment",
    "missing_calibration": "a missing installed calibration or data file",
}
#: seeded bugs a system may add to those (issue 49: the systems with dead remappings), in the order
#: of the table
OPTIONAL_MUTATION_KINDS = {
    "remap_near_miss": "a remap whose `from` is a near miss of the node's own name",
    "moved_off_zenoh": "a Zenoh robot moved to a DDS middleware",
}
ALL_MUTATION_KINDS = {**MUTATION_KINDS, **OPTIONAL_MUTATION_KINDS}


#: rules that report a note by design, not a problem: a device the capture machine lacks (the robot
#: has it). A correct system may have them and still counts as "no finding"; so may any finding of
#: the level NOTE (:data:`NOTE`: a dead remapping, a file of the robot), which never fails the gate
NOTE_RULES = frozenset({"PARAM_DEVICE_ABSENT"})
NOTE = "NOTE"


def is_note(rule: str, severity: str) -> bool:
    """Whether a finding is a note (listed, allowed on a correct system), not a problem."""
    return rule in NOTE_RULES or severity == NOTE


class SuiteError(Exception):
    """A modelled system that is itself wrong (a mutation whose text is not in the file, ...)."""


@dataclass
class Mutation:
    kind: str
    file: str                      # <package>/<path inside its share directory>
    old: str | None = None         # the text replaced (exactly once); None: the file is deleted
    new: str = ""
    expect: list[str] = field(default_factory=list)   # the rules that must name the bug


@dataclass
class System:
    name: str
    directory: Path
    title: str
    modelled_on: str
    launch: dict[str, Any]
    external: dict[str, dict[str, str]]
    shared: list[str]
    mutations: dict[str, Mutation]
    #: rule → why it fails this correct system (a defect of the rule, written down; the test then
    #: expects exactly those findings and fails once they are gone, so the entry is removed)
    known_false_findings: dict[str, str] = field(default_factory=dict)

    @property
    def packages(self) -> list[Path]:
        own = sorted(p for p in self.directory.iterdir() if p.is_dir() and not p.name.startswith(("_", ".")))
        return own + [SHARED_DIR / name for name in self.shared]


def load_system(directory: Path) -> System:
    spec = yaml.safe_load((directory / "system.yaml").read_text(encoding="utf-8"))
    mutations = {kind: Mutation(kind=kind, **entry) for kind, entry in (spec.get("mutations") or {}).items()}
    return System(name=directory.name, directory=directory, title=spec["title"], modelled_on=spec["modelled_on"],
                  launch=spec["launch"], external=spec.get("external") or {}, shared=spec.get("shared") or [],
                  mutations=mutations, known_false_findings=spec.get("known_false_findings") or {})


def systems() -> list[System]:
    return [load_system(d) for d in sorted(SYSTEMS_DIR.iterdir()) if (d / "system.yaml").is_file()]


# ---------------------------------------------------------------------------- installing


def executable_text(package: str, executable: str) -> str:
    """``lib/<package>/<executable>``: runs the stand-in with the table of the prefix it is in (so a
    copy of an installed system, mutated, runs its own)."""
    return (f"#!{sys.executable}\n"
            "# a stand-in node of the precision suite (tests/precision/standin_node.py)\n"
            "import os\n"
            "import sys\n"
            f"sys.path.insert(0, {str(HERE)!r})\n"
            "import standin_node\n"
            "prefix = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))\n"
            f"sys.exit(standin_node.main(os.path.join(prefix, 'share', {package!r}, 'standins.yaml'), {executable!r}))\n")


def install(system: System, prefix: Path) -> Path:
    """Install the system's packages into ``prefix`` like a colcon install; returns ``prefix``."""
    index = prefix / "share" / "ament_index" / "resource_index" / "packages"
    index.mkdir(parents=True, exist_ok=True)
    for package in system.packages:
        share = prefix / "share" / package.name
        shutil.copytree(package, share, dirs_exist_ok=True)
        (index / package.name).write_text("")
        table = share / "standins.yaml"
        if not table.is_file():
            continue
        lib = prefix / "lib" / package.name
        lib.mkdir(parents=True, exist_ok=True)
        for executable in yaml.safe_load(table.read_text(encoding="utf-8")) or {}:
            path = lib / executable
            path.write_text(executable_text(package.name, executable))
            path.chmod(0o755)
    return prefix


def mutate(system: System, prefix: Path, mutation: Mutation) -> None:
    """Apply a seeded bug to the system installed in ``prefix``."""
    target = prefix / "share" / mutation.file
    if not target.is_file():
        raise SuiteError(f"{system.name}: mutation {mutation.kind} names {mutation.file}, which is not installed")
    if mutation.old is None:
        target.unlink()
        return
    text = target.read_text(encoding="utf-8")
    if text.count(mutation.old) != 1:
        raise SuiteError(f"{system.name}: mutation {mutation.kind}: {mutation.old!r} occurs "
                         f"{text.count(mutation.old)} times in {mutation.file} (must be once)")
    target.write_text(text.replace(mutation.old, mutation.new), encoding="utf-8")


# ---------------------------------------------------------------------------- the gate


def environment(prefix: Path, base: Mapping[str, str]) -> dict[str, str]:
    env = {k: v for k, v in base.items() if k not in ("CI", "PYTEST_ADDOPTS")}
    env["AMENT_PREFIX_PATH"] = os.pathsep.join([str(prefix), *filter(None, base.get("AMENT_PREFIX_PATH", "").split(os.pathsep))])
    return env


def rmw_introspect(args: list[str], cwd: Path, env: Mapping[str, str], timeout: float = 300) -> Result:
    proc = subprocess.run([console_script(), *args], cwd=cwd, env=dict(env), capture_output=True, text=True,
                          timeout=timeout, check=False)
    return Result(proc.returncode, proc.stdout, proc.stderr)


def declare_external(contract_text: str, external: Mapping[str, Mapping[str, str]]) -> str:
    """The contract with the system's ``external:`` block added above ``processes:``."""
    if not external:
        return contract_text
    block = yaml.safe_dump({"external": {k: dict(v) for k, v in external.items()}}, sort_keys=False)
    head, sep, tail = contract_text.partition("\nprocesses:")
    if not sep:
        raise SuiteError("the contract capture --launch wrote has no `processes:`")
    return f"{head}\n{block.rstrip()}{sep}{tail}"


CONTRACT = "system.system.yaml"


def capture_contract(system: System, prefix: Path, workdir: Path, env: Mapping[str, str]) -> Path:
    """``capture --launch`` of the installed system, its ``external:`` declared: the contract."""
    launch = system.launch
    args = ["capture", "--launch-package", launch["package"], "--launch-file", launch["file"]]
    for name, value in (launch.get("arguments") or {}).items():
        args += ["--launch-arg", f"{name}:={value}"]
    created = rmw_introspect([*args, "-o", CONTRACT], workdir, environment(prefix, env))
    if created.returncode != 0:
        raise SuiteError(f"{system.name}: capture --launch failed\n{created}")
    contract = workdir / CONTRACT
    contract.write_text(declare_external(contract.read_text(encoding="utf-8"), system.external), encoding="utf-8")
    return contract


@dataclass
class Finding:
    rule: str
    severity: str
    name: str
    system: bool                   # a system rule's finding (not drift from the contract's nodes)

    def key(self) -> list[str]:
        return [self.rule, self.severity, self.name]


def check(contract: Path, prefix: Path, env: Mapping[str, str]) -> tuple[Result, list[Finding]]:
    run = rmw_introspect(["check", contract.name, "--format", "json"], contract.parent, environment(prefix, env))
    if run.returncode not in (0, 1):
        raise SuiteError(f"check of {contract} failed\n{run}")
    return run, findings(run)


def findings(run: Result) -> list[Finding]:
    """The items of a `check --format json` run."""
    items = json.loads(run.stdout) if run.stdout.strip() else []
    return [Finding(rule=str(i.get("rule")), severity=str(i.get("severity")), name=str(i.get("name")),
                    system="requester" in i) for i in items]


# ---------------------------------------------------------------------------- recorded results


def observed(findings: list[Finding], *, system_only: bool) -> list[list[str]]:
    return sorted(f.key() for f in findings if f.system or not system_only)


def load_results(path: Path = RESULTS) -> dict[str, Any]:
    return json.loads(path.read_text(encoding="utf-8")) if path.is_file() else {}


def write_results(results: Mapping[str, Any], path: Path = RESULTS) -> None:
    path.write_text(json.dumps(results, indent=1, sort_keys=True) + "\n", encoding="utf-8")


# ---------------------------------------------------------------------------- running it all


def gate_system(system: System, workdir: Path, env: Mapping[str, str]) -> dict[str, Any]:
    """The correct system and each of its seeded bugs through the gate: the record of
    results.json for this system."""
    prefix = install(system, workdir / "prefix")
    contract = capture_contract(system, prefix, workdir, env)
    _, correct = check(contract, prefix, env)
    record: dict[str, Any] = {"title": system.title, "correct": observed(correct, system_only=False), "mutations": {}}
    for kind, mutation in system.mutations.items():
        mutant = workdir / f"prefix-{kind}"
        shutil.copytree(prefix, mutant, symlinks=True)
        mutate(system, mutant, mutation)
        try:
            found = observed(check(contract, mutant, env)[1], system_only=True)
        except SuiteError as exc:  # the check itself failed (exit 2): recorded, and the suite's test fails on it
            found = [[CHECK_ERROR, CHECK_ERROR, str(exc).splitlines()[0]]]
        record["mutations"][kind] = {"expect": sorted(mutation.expect), "found": found}
    return record


# ---------------------------------------------------------------------------- the table

TABLE_START = "<!-- precision-table:start -->"
TABLE_END = "<!-- precision-table:end -->"
FAILING = "BREAKING"
#: what a seeded bug's record says when its check could not run to the end (exit status 2)
CHECK_ERROR = "ERROR"


def seeded_findings(correct: list[list[str]], found: list[list[str]]) -> list[list[str]]:
    """The findings of a seeded bug that the correct system does not have (those it has are the
    correct system's own, known false findings: not the bug's)."""
    own = {tuple(f) for f in correct}
    return [f for f in found if tuple(f) not in own]


def _ratio(hits: int, total: int) -> str:
    return f"{hits}/{total} ({100 * hits / total:.0f} %)" if total else "n/a"


def render_table(results: Mapping[str, Any]) -> str:
    """The Markdown between the precision-table markers of docs/drift-rules.md, from results.json."""
    recorded = results.get("systems") or {}
    rules: dict[str, dict[str, Any]] = {}

    def row(rule: str) -> dict[str, Any]:
        return rules.setdefault(rule, {"severities": set(), "false": 0, "true": 0, "expected": 0, "named": 0})

    clean = passing = 0
    kinds: dict[str, dict[str, Any]] = {kind: {"seeded": 0, "failing": 0, "named": 0} for kind in MUTATION_KINDS}
    kinds.update({kind: {"seeded": 0, "failing": 0, "named": 0} for kind in OPTIONAL_MUTATION_KINDS
                  if any(kind in record["mutations"] for record in recorded.values())})
    for record in recorded.values():
        problems = [f for f in record["correct"] if not is_note(f[0], f[1])]
        clean += not problems
        passing += not any(severity == FAILING for _, severity, _ in problems)
        for rule, severity, _name in record["correct"]:
            row(rule)["false"] += 1
            row(rule)["severities"].add(severity)
        for kind, outcome in record["mutations"].items():
            found = seeded_findings(record["correct"], outcome["found"])
            failing = {rule for rule, severity, _ in found if severity in (FAILING, CHECK_ERROR)}
            for rule, severity, _name in found:
                row(rule)["true"] += 1
                row(rule)["severities"].add(severity)
            for rule in outcome["expect"]:
                row(rule)["expected"] += 1
                row(rule)["named"] += rule in failing
            counts = kinds.setdefault(kind, {"seeded": 0, "failing": 0, "named": 0})
            counts["seeded"] += 1
            counts["failing"] += bool(failing)
            counts["named"] += set(outcome["expect"]) <= failing
    seeded = sum(k["seeded"] for k in kinds.values())
    failing_total = sum(k["failing"] for k in kinds.values())
    lines = [
        f"{clean} of {len(recorded)} correct systems pass the default gate with no finding (notes aside), "
        f"{passing} of {len(recorded)} pass it; {failing_total} of {seeded} seeded bugs fail it.",
        "",
        "| rule (severity) | findings on correct systems (false) | findings on seeded bugs | bugs it should name "
        "| named (failing) | precision | recall |",
        "|---|---|---|---|---|---|---|",
    ]
    for rule in sorted(rules):
        r = rules[rule]
        precision = "note" if rule in NOTE_RULES or r["severities"] == {NOTE} else _ratio(r["true"], r["true"] + r["false"])
        # the severity inside the first cell: the rule tables above own rows that begin "| `RULE` |"
        lines.append(f"| `{rule}` ({', '.join(sorted(r['severities'])) or '-'}) | {r['false']} | {r['true']} "
                     f"| {r['expected']} | {r['named']} | {precision} | {_ratio(r['named'], r['expected'])} |")
    lines += ["", "| seeded bug | systems | fail the default gate | named by the expected rule |", "|---|---|---|---|"]
    for kind, counts in kinds.items():
        label = ALL_MUTATION_KINDS.get(kind, kind)
        lines.append(f"| {label} | {counts['seeded']} | {counts['failing']} | {counts['named']} |")
    lines += ["", "| system | modelled on |", "|---|---|"]
    for name, record in sorted(recorded.items()):
        lines.append(f"| `{name}` | {record['title']} |")
    return "\n".join(lines) + "\n"


def with_table(document: str, table: str) -> str:
    """``document`` with the text between the precision-table markers replaced by ``table``."""
    start, end = document.find(TABLE_START), document.find(TABLE_END)
    if start < 0 or end < start:
        raise SuiteError(f"the document has no `{TABLE_START}` ... `{TABLE_END}` markers")
    return f"{document[:start + len(TABLE_START)]}\n{table}{document[end:]}"


def run_all(env: Mapping[str, str], workdir: Path, jobs: int = 1,
            only: list[str] | None = None) -> dict[str, Any]:
    """Every system (or those named in ``only``) through the gate: the content of results.json."""
    from concurrent.futures import ThreadPoolExecutor

    chosen = [s for s in systems() if not only or s.name in only]
    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        records = list(pool.map(lambda s: gate_system(s, workdir / s.name, env), chosen))
    return {"systems": {s.name: r for s, r in zip(chosen, records, strict=True)}}
