#!/usr/bin/env python3
"""Build and run the official RMW API suite (test_rmw_implementation) on our middleware.

    RMW_CONFORMANCE_SRC=/path/with/both/checkouts .venv/bin/python scripts/conformance/run.py

The sources are the user's upstream checkouts (see docs/conformance.md, for the
`git clone` lines: the rmw_implementation branch of the distribution the venv holds, `jazzy` for
.venv, `rolling` for .venv-kilted until a `kilted` branch is at hand); nothing upstream is kept
in this repository. Steps:

1. build osrf_testing_tools_cpp (memory tools) and the 16 gtest binaries of
   test_rmw_implementation out of the repository, into
   ``${RMW_CONFORMANCE_BUILD:-${RMW_INTROSPECT_CACHE:-~/.cache/pytest-rmw-introspect}/conformance}``,
   against the ROS 2 prefix of this venv (the PyPI wheels) or a sourced /opt/ros/<distro>;
2. run every binary in each configuration, with a per-run timeout, in its own process group:
     introspect          LD_PRELOAD=<our library>, RMW_IMPLEMENTATION=rmw_introspect_cpp,
                         RMW_INTROSPECT_SERVER_AVAILABLE=0 (no simulated servers),
                         RMW_INTROSPECT_DELIVERY=1 (in-process delivery)
     introspect+memcheck the same plus osrf_testing_tools_cpp's libmemory_tools_interpose.so
     fastdds             no preload (the baseline: the suite is sound here)
     fastdds+memcheck    the baseline with the memory checks (only with --baseline-memcheck)
   A binary that dies of a signal or times out counts that case as a crash and is run again
   without the cases already decided, so every other case still gets a result;
3. print a table pass/fail/skip/crash per binary and configuration with totals, and optionally
   write it as Markdown (--markdown) and every case with its failure messages as JSON (--json).

Exit status: 0 when every case of the `introspect` configurations passed or skipped, 1 when any
failed or crashed, 2 on a set-up error (missing sources, failed build).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT / "tests" / "support"))
import build_identity  # noqa: E402  (shared with the middleware tests' builds: what a build is built from)

TESTS = [
    "test_init_shutdown", "test_init_options", "test_create_destroy_node", "test_publisher",
    "test_subscription", "test_serialize_deserialize", "test_publisher_allocator",
    "test_subscription_allocator", "test_wait_set", "test_graph_api", "test_unique_identifiers",
    "test_service", "test_client", "test_qos_profile_check_compatible", "test_duration_infinite",
    "test_event",
]
CONFIGS = ["introspect", "introspect+memcheck", "fastdds", "fastdds+memcheck"]
STATUSES = ["pass", "fail", "skip", "crash"]
# Wheels the build needs (all but osrf_testing_tools_cpp, which has no wheel and is built from
# source), as ros-<distro>-<name>; the lock files (requirements/<distro>.txt) have them, so a venv
# made by `make bootstrap` has them too. Nothing is installed here: every package comes from
# the lock.
BUILD_WHEELS = {
    "share/test_msgs": "test-msgs",
    "share/ament_cmake_gtest": "ament-cmake-gtest",
    "src/gtest_vendor": "gtest-vendor",
    "share/rmw_dds_common": "rmw-dds-common",
    "share/rosidl_typesupport_cpp": "rosidl-typesupport-cpp",
}


class SetupError(Exception):
    pass


def log(message: str) -> None:
    print(f"conformance: {message}", file=sys.stderr, flush=True)


# --------------------------------------------------------------------------- sources and build

def find_sources(src: Path) -> tuple[Path, Path]:
    """(test_rmw_implementation/test dir, osrf_testing_tools_cpp package dir) under ``src``."""
    if not src.is_dir():
        raise SetupError(f"RMW_CONFORMANCE_SRC={src} is not a directory")
    tests = [p for pattern in ("test_rmw_implementation/test", "*/test_rmw_implementation/test")
             for p in src.glob(pattern) if (p / "test_publisher.cpp").is_file()]
    tools = [p.parent for pattern in ("osrf_testing_tools_cpp/CMakeLists.txt",
                                      "*/osrf_testing_tools_cpp/CMakeLists.txt")
             for p in src.glob(pattern) if (p.parent / "src" / "memory_tools").is_dir()]
    missing = []
    if not tests:
        missing.append("ros2/rmw_implementation (the branch of your distribution): "
                       "*/test_rmw_implementation/test")
    if not tools:
        missing.append("osrf/osrf_testing_tools_cpp (tag 2.0.0): */osrf_testing_tools_cpp/src/memory_tools")
    if missing:
        raise SetupError(f"not found under {src}: " + "; ".join(missing)
                         + " (see docs/conformance.md for how to get them)")
    return tests[0].resolve(), tools[0].resolve()


def ros_prefix(venv: Path) -> tuple[Path, bool]:
    """The ROS 2 prefix to build against and whether it is the wheels' venv."""
    if (venv / "share" / "rmw" / "cmake").is_dir():
        return venv, True
    for prefix in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep):
        if prefix and (Path(prefix) / "share" / "rmw" / "cmake").is_dir():
            return Path(prefix), False
    raise SetupError(f"no ROS 2 prefix: {venv} has no share/rmw and AMENT_PREFIX_PATH names none "
                     "(run `make bootstrap`, or source /opt/ros/<distro>/setup.bash)")


def wheels_distribution(python: Path) -> str:
    """The distribution of the venv whose interpreter is ``python``, as the package detects it."""
    out = subprocess.run([str(python), "-c", "from pytest_rmw_introspect.run import ros_env; "
                          "print(ros_env.detect().distro)"], capture_output=True, text=True, cwd=ROOT)
    lines = out.stdout.split()
    return lines[-1] if out.returncode == 0 and lines else "jazzy"


def ensure_build_wheels(prefix: Path, python: Path) -> None:
    distro = wheels_distribution(python)
    missing = sorted({f"ros-{distro}-{name}" for rel, name in BUILD_WHEELS.items()
                      if not (prefix / rel).exists()})
    if missing:
        raise SetupError(f"{prefix} lacks {', '.join(missing)}, which the lock file installs: "
                         f"run `make bootstrap` (it brings the venv back to "
                         f"requirements/{distro}.txt)")


def run_logged(cmd: list[str], logfile: Path, env: dict[str, str]) -> None:
    with logfile.open("a") as out:
        out.write("\n$ " + " ".join(cmd) + "\n")
        out.flush()
        status = subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT, env=env).returncode
    if status != 0:
        tail = "".join(logfile.read_text(errors="replace").splitlines(keepends=True)[-40:])
        raise SetupError(f"command failed ({status}): {' '.join(cmd)}\n{tail}\nfull log: {logfile}")


def checkout_id(path: Path) -> str:
    """A source tree's identity: its git commit plus a hash of uncommitted changes; a tree
    outside git is named by its path and the newest modification time under it."""
    head = subprocess.run(["git", "-C", str(path), "rev-parse", "HEAD"], capture_output=True, text=True)
    if head.returncode != 0:
        newest = max((f.stat().st_mtime for f in path.rglob("*") if f.is_file()), default=0.0)
        return f"{path}@{newest}"
    diff = subprocess.run(["git", "-C", str(path), "diff", "HEAD"], capture_output=True).stdout
    return head.stdout.strip() + ("+" + hashlib.sha256(diff).hexdigest()[:12] if diff else "")


def _configured_source(tree: Path) -> str | None:
    """The source directory a CMake build tree was configured for (None: not configured)."""
    cache = tree / "CMakeCache.txt"
    if not cache.is_file():
        return None
    found = re.search(r"^CMAKE_HOME_DIRECTORY:INTERNAL=(.*)$", cache.read_text(errors="replace"), re.M)
    return found.group(1) if found else None


def build_key(test_dir: Path, tools_dir: Path, prefix: Path) -> str:
    """The cache key of a build: what it is built from (the two checkouts' commits and changes,
    the ROS 2 prefix's content, this directory's CMakeLists.txt, the compiler and CMake), not
    where those are: a fresh clone with a new venv of the same lock reuses the build (issue 48)."""
    h = hashlib.sha256()
    for part in (checkout_id(test_dir), checkout_id(tools_dir), build_identity.prefix_identity(prefix),
                 (HERE / "CMakeLists.txt").read_text(), build_identity.first_line(["c++", "--version"]),
                 build_identity.first_line(["cmake", "--version"])):
        h.update(part.encode() + b"\0")
    return h.hexdigest()[:16]


def build(test_dir: Path, tools_dir: Path, prefix: Path, is_venv: bool, python: Path, build_root: Path,
          jobs: int) -> Path:
    """Build (incrementally) and return the directory holding the 16 gtest binaries. A complete
    build of the same key (``built.json``, written last) is reused as it is: the binaries find the
    current prefix's libraries through LD_LIBRARY_PATH (library_env), which the run sets."""
    key = build_key(test_dir, tools_dir, prefix)
    root = build_root / key
    tests_build = root / "test_rmw_implementation"
    done = root / "built.json"
    if done.is_file() and all((tests_build / name).is_file() for name in TESTS):
        info = json.loads(done.read_text())
        log(f"reusing the build {root} (built {info.get('built', '?')} against {info.get('prefix', '?')}, "
            "the same sources, wheels and compiler)")
        return tests_build
    root.mkdir(parents=True, exist_ok=True)
    logfile = root / "build.log"
    logfile.write_text("")
    env = dict(os.environ)
    env["AMENT_PREFIX_PATH"] = os.pathsep.join(
        p for p in [str(prefix), env.get("AMENT_PREFIX_PATH", "")] if p)
    tools_prefix = root / "osrf_testing_tools_cpp-install"
    common = ["-DCMAKE_BUILD_TYPE=RelWithDebInfo", "-DBUILD_TESTING=OFF"]
    # an unfinished build of this key left by another clone: CMake refuses a build tree made for
    # another source directory, so start such a tree again
    for tree, source in ((root / "osrf_testing_tools_cpp", tools_dir), (tests_build, HERE)):
        if _configured_source(tree) not in (None, str(source)):
            shutil.rmtree(tree)
    log(f"building osrf_testing_tools_cpp from {tools_dir} (log: {logfile})")
    run_logged(["cmake", "-S", str(tools_dir), "-B", str(root / "osrf_testing_tools_cpp"),
                f"-DCMAKE_INSTALL_PREFIX={tools_prefix}", *common], logfile, env)
    run_logged(["cmake", "--build", str(root / "osrf_testing_tools_cpp"), "-j", str(jobs)],
               logfile, env)
    run_logged(["cmake", "--install", str(root / "osrf_testing_tools_cpp")], logfile, env)
    log(f"building test_rmw_implementation from {test_dir}")
    run_logged(["cmake", "-S", str(HERE), "-B", str(tests_build),
                f"-DCMAKE_PREFIX_PATH={tools_prefix};{prefix}",
                f"-DRMW_CONFORMANCE_TEST_DIR={test_dir}",
                f"-DPython3_EXECUTABLE={python}", "-DCMAKE_BUILD_TYPE=RelWithDebInfo"], logfile, env)
    run_logged(["cmake", "--build", str(tests_build), "-j", str(jobs)], logfile, env)
    done.write_text(json.dumps({"key": key, "built": time.strftime("%Y-%m-%d %H:%M:%S"), "prefix": str(prefix),
                                "sources": [str(test_dir), str(tools_dir)]}, indent=1) + "\n")
    return tests_build


# --------------------------------------------------------------------------- running

@dataclass
class Case:
    name: str
    status: str = "crash"          # pass / fail / skip / crash
    detail: str = ""               # failure messages (file:line: ...), or how it crashed
    seconds: float = 0.0


@dataclass
class BinaryResult:
    binary: str
    config: str
    cases: dict[str, Case] = field(default_factory=dict)
    runs: int = 0
    notes: list[str] = field(default_factory=list)

    def count(self, status: str) -> int:
        return sum(1 for c in self.cases.values() if c.status == status)


_RESULT = re.compile(r"^\[\s*(OK|FAILED|SKIPPED)\s*\] (\S+) \((\d+) ms\)")
_RUN = re.compile(r"^\[ RUN\s*\] (\S+)")


def list_cases(exe: Path, env: dict[str, str], timeout: float) -> tuple[list[str], str]:
    proc = subprocess.run([str(exe), "--gtest_list_tests"], env=env, capture_output=True,
                          text=True, timeout=timeout)
    out = proc.stdout
    cases, suite = [], ""
    for line in out.splitlines():
        if not line.strip() or line.startswith("Running main"):
            continue
        if not line.startswith(" "):
            suite = line.split()[0]
        else:
            cases.append(suite + line.split()[0])
    return cases, f"status {proc.returncode}: {proc.stderr}"


def parse_xml(path: Path) -> dict[str, Case]:
    cases: dict[str, Case] = {}
    try:
        tree = ET.parse(path)
    except (OSError, ET.ParseError):
        return cases
    for tc in tree.iter("testcase"):
        name = f"{tc.get('classname')}.{tc.get('name')}"
        case = Case(name, "pass", seconds=float(tc.get("time", "0") or 0))
        failures = [f.get("message") or f.text or "" for f in tc.findall("failure")]
        if failures:
            case.status, case.detail = "fail", "\n".join(failures)
        elif tc.find("skipped") is not None or tc.get("result") == "skipped":
            case.status = "skip"
            skipped = tc.find("skipped")
            case.detail = (skipped.get("message") or "") if skipped is not None else ""
        cases[name] = case
    return cases


def parse_stdout(text: str) -> tuple[dict[str, Case], str | None, dict[str, str]]:
    """Cases finished according to gtest's console output, the case left running, and the
    output printed inside each case (its failure messages)."""
    cases: dict[str, Case] = {}
    outputs: dict[str, str] = {}
    current, lines = None, []
    for line in text.splitlines():
        m = _RUN.match(line)
        if m:
            current, lines = m.group(1), []
            continue
        m = _RESULT.match(line)
        if m and m.group(2) == current:
            status = {"OK": "pass", "FAILED": "fail", "SKIPPED": "skip"}[m.group(1)]
            cases[current] = Case(current, status, seconds=int(m.group(3)) / 1000)
            outputs[current] = "\n".join(lines)
            current = None
            continue
        if current is not None:
            lines.append(line)
    if current is not None:
        outputs[current] = "\n".join(lines)
    return cases, current, outputs


def run_binary(exe: Path, config: str, env: dict[str, str], timeout: float, workdir: Path,
               max_runs: int = 20) -> BinaryResult:
    result = BinaryResult(exe.name, config)
    try:
        all_cases, listing = list_cases(exe, env, timeout)
    except subprocess.TimeoutExpired:
        all_cases, listing = [], "timed out"
    if not all_cases:
        result.notes.append("--gtest_list_tests gave no case: " + listing.strip()[-300:])
    remaining = list(all_cases)
    while remaining and result.runs < max_runs:
        result.runs += 1
        xml = workdir / f"{exe.name}.{config}.{result.runs}.xml"
        xml.unlink(missing_ok=True)
        decided = [c for c in all_cases if c not in remaining]
        args = [str(exe), f"--gtest_output=xml:{xml}"]
        if decided:
            args.append("--gtest_filter=*-" + ":".join(decided))
        started = time.monotonic()
        proc = subprocess.Popen(args, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                start_new_session=True, cwd=workdir)
        try:
            raw, _ = proc.communicate(timeout=timeout)
            how = None if proc.returncode >= 0 else f"killed by signal {-proc.returncode} " \
                f"({signal.Signals(-proc.returncode).name})"
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            raw, _ = proc.communicate()
            how = f"timed out after {timeout:.0f} s (whole binary run)"
        text = raw.decode(errors="replace")
        (workdir / f"{exe.name}.{config}.{result.runs}.log").write_text(text)
        from_stdout, running, outputs = parse_stdout(text)
        from_xml = parse_xml(xml) if how is None else {}
        for name in list(remaining):
            case = from_xml.get(name) or from_stdout.get(name)
            if case is None:
                continue
            if case.status == "fail" and not case.detail:
                case.detail = outputs.get(name, "")
            result.cases[name] = case
            remaining.remove(name)
        if how is None:
            if remaining and proc.returncode != 0:  # exited early without a signal
                how = f"exited with status {proc.returncode} before finishing"
            elif remaining:
                result.notes.append(f"{len(remaining)} listed case(s) never ran")
                break
        if how is not None:
            victim = running if running in remaining else (remaining[0] if remaining else None)
            if victim is None:
                result.notes.append(f"after the last case: {how}")
                break
            result.cases[victim] = Case(victim, "crash", f"{how}\n{outputs.get(victim, '')}".strip(),
                                        time.monotonic() - started)
            remaining.remove(victim)
    for name in remaining:  # only if max_runs was exhausted
        result.cases[name] = Case(name, "crash", "not run: too many crashes before it")
    return result


def make_env(config: str, base: dict[str, str], library: str | None, interpose: Path,
             domain: int, workdir: Path) -> dict[str, str]:
    env = dict(base)
    for key in ("LD_PRELOAD", "RMW_IMPLEMENTATION", "RMW_INTROSPECT_OUTPUT"):
        env.pop(key, None)
    preload = []
    if config.endswith("+memcheck"):
        preload.append(str(interpose))
        # binaries that use no memory_tools symbol do not link libmemory_tools.so (--as-needed):
        # the interposer must find it by itself
        env["LD_LIBRARY_PATH"] = os.pathsep.join(
            p for p in [str(interpose.parent), env.get("LD_LIBRARY_PATH", "")] if p)
    if config.startswith("introspect"):
        preload.append(str(library))
        env["RMW_IMPLEMENTATION"] = "rmw_introspect_cpp"
        # No simulated servers: the suite expects a client to see only the servers of its own
        # process (test_client.cpp service_server_is_available_good_args).
        env["RMW_INTROSPECT_SERVER_AVAILABLE"] = "0"
        # In-process delivery: the suite publishes, calls services and waits for matched
        # events inside one process.
        env["RMW_INTROSPECT_DELIVERY"] = "1"
        # Each binary's capture goes to the run's temporary directory, not /tmp.
        env["RMW_INTROSPECT_OUTPUT"] = str(workdir / "rmw_introspect_<pid>.json")
    else:
        env["RMW_IMPLEMENTATION"] = "rmw_fastrtps_cpp"
    if preload:
        env["LD_PRELOAD"] = ":".join(preload)
    # Keep the Fast DDS baseline on this machine and away from other runs.
    env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    env["ROS_DOMAIN_ID"] = str(domain)
    env["_ROS_WHEELS_BOOTSTRAP_COMPLETE"] = "1"
    return env


def library_env(prefix: Path, is_venv: bool) -> dict[str, str]:
    env = dict(os.environ)
    if is_venv:
        try:
            import ros_wheels_bootstrapper  # the wheels' own computation of LD_LIBRARY_PATH
            paths = ros_wheels_bootstrapper.get_ros_paths()
        except Exception:  # noqa: BLE001 - fall back to the obvious directories
            paths = os.pathsep.join([str(prefix / "lib"), *map(str, sorted(
                prefix.glob("lib/python3*/site-packages/ros_*.libs")))])
        env["LD_LIBRARY_PATH"] = os.pathsep.join(
            p for p in [paths, env.get("LD_LIBRARY_PATH", "")] if p)
    return env


def middleware_library(python: Path) -> str:
    out = subprocess.run([str(python), "-m", "pytest_rmw_introspect.run.middleware"],
                         capture_output=True, text=True, cwd=ROOT)
    path = out.stdout.strip().splitlines()[-1] if out.stdout.strip() else ""
    if out.returncode != 0 or not Path(path).is_file():
        raise SetupError(f"could not get the middleware library: {out.stderr.strip()[-2000:]}")
    return path


# --------------------------------------------------------------------------- report

def table(results: dict[tuple[str, str], BinaryResult], configs: list[str], binaries: list[str],
          markdown: bool) -> str:
    def cell(r: BinaryResult | None) -> str:
        if r is None:
            return "-"
        return "/".join(str(r.count(s)) for s in STATUSES)

    totals = {c: {s: 0 for s in STATUSES} for c in configs}
    rows = []
    for b in binaries:
        row = [b]
        for c in configs:
            r = results.get((b, c))
            row.append(cell(r))
            if r is not None:
                for s in STATUSES:
                    totals[c][s] += r.count(s)
        rows.append(row)
    rows.append(["TOTAL"] + ["/".join(str(totals[c][s]) for s in STATUSES) for c in configs])
    header = ["binary (pass/fail/skip/crash)"] + configs
    if markdown:
        lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
        for row in rows:
            if row[0] == "TOTAL":
                row = [f"**{x}**" for x in row]
            lines.append("| " + " | ".join(row) + " |")
        return "\n".join(lines) + "\n"
    widths = [max(len(r[i]) for r in rows + [header]) for i in range(len(header))]
    fmt = "  ".join(f"{{:<{w}}}" if i == 0 else f"{{:>{w}}}" for i, w in enumerate(widths))
    out = [fmt.format(*header), fmt.format(*("-" * w for w in widths))]
    out += [fmt.format(*r) for r in rows[:-1]]
    out += [fmt.format(*("-" * w for w in widths)), fmt.format(*rows[-1])]
    return "\n".join(out) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--src", default=os.environ.get("RMW_CONFORMANCE_SRC"),
                        help="directory holding the rmw_implementation and osrf_testing_tools_cpp "
                             "checkouts (default: $RMW_CONFORMANCE_SRC)")
    cache = Path(os.environ.get("RMW_INTROSPECT_CACHE",
                                Path.home() / ".cache" / "pytest-rmw-introspect"))
    parser.add_argument("--build-dir", type=Path,
                        default=Path(os.environ.get("RMW_CONFORMANCE_BUILD", cache / "conformance")))
    parser.add_argument("--venv", type=Path, default=Path(os.environ.get("VENV", ROOT / ".venv")))
    parser.add_argument("--jobs", type=int, default=int(os.environ.get("CONFORMANCE_JOBS", "2")))
    parser.add_argument("--timeout", type=float, default=300.0,
                        help="seconds for one run of one binary (default 300)")
    parser.add_argument("--configs", default="introspect,introspect+memcheck,fastdds",
                        help=f"comma-separated, of {','.join(CONFIGS)}")
    parser.add_argument("--baseline-memcheck", action="store_true",
                        help="also run fastdds+memcheck")
    parser.add_argument("--only", default="", help="comma-separated binaries (default: all 16)")
    parser.add_argument("--no-build", action="store_true", help="reuse the binaries as built")
    parser.add_argument("--markdown", type=Path, help="also write the table as Markdown here")
    parser.add_argument("--json", type=Path, help="write every case with its messages here")
    parser.add_argument("--details", action="store_true",
                        help="print each failing or crashing case with its messages")
    args = parser.parse_args(argv)

    configs = [c for c in args.configs.split(",") if c]
    if args.baseline_memcheck and "fastdds+memcheck" not in configs:
        configs.append("fastdds+memcheck")
    unknown = [c for c in configs if c not in CONFIGS]
    binaries = [b for b in args.only.split(",") if b] or TESTS
    if unknown or any(b not in TESTS for b in binaries):
        parser.error(f"unknown configuration or binary: {unknown or binaries}")
    try:
        if not args.src:
            raise SetupError("set RMW_CONFORMANCE_SRC (or --src) to the directory holding the "
                             "rmw_implementation and osrf_testing_tools_cpp checkouts; "
                             "see docs/conformance.md")
        test_dir, tools_dir = find_sources(Path(args.src).expanduser().resolve())
        prefix, is_venv = ros_prefix(args.venv)
        python = args.venv / "bin" / "python" if is_venv else Path(sys.executable)
        if is_venv:
            ensure_build_wheels(prefix, python)
        if args.no_build:
            tests_build = args.build_dir / build_key(test_dir, tools_dir, prefix) / "test_rmw_implementation"
        else:
            tests_build = build(test_dir, tools_dir, prefix, is_venv, python, args.build_dir, args.jobs)
        interpose = tests_build.parent / "osrf_testing_tools_cpp-install" / "lib" / \
            "libmemory_tools_interpose.so"
        library = middleware_library(python) if any(c.startswith("introspect") for c in configs) \
            else None
    except (SetupError, subprocess.CalledProcessError) as exc:
        log(f"error: {exc}")
        return 2

    base = library_env(prefix, is_venv)
    domain = 100 + os.getpid() % 100
    log(f"middleware: {library}")
    log(f"binaries: {tests_build}")
    results: dict[tuple[str, str], BinaryResult] = {}
    with tempfile.TemporaryDirectory(prefix="rmw-conformance-") as tmp:
        workdir = Path(tmp)
        for binary in binaries:
            exe = tests_build / binary
            for config in configs:
                started = time.monotonic()
                if not exe.is_file():
                    r = BinaryResult(binary, config, notes=["binary not built"])
                else:
                    r = run_binary(exe, config,
                                   make_env(config, base, library, interpose, domain, workdir),
                                   args.timeout, workdir)
                results[(binary, config)] = r
                log(f"{binary:<34} {config:<20} " + " ".join(
                    f"{s} {r.count(s)}" for s in STATUSES)
                    + f"  ({time.monotonic() - started:.1f} s, {r.runs} run(s))"
                    + (f"  [{'; '.join(r.notes)}]" if r.notes else ""))

    print(table(results, configs, binaries, markdown=False), end="")
    if args.markdown:
        args.markdown.write_text(table(results, configs, binaries, markdown=True))
    if args.json:
        args.json.write_text(json.dumps({
            f"{b}|{c}": {"notes": r.notes, "cases": {n: {"status": k.status, "detail": k.detail}
                                                     for n, k in sorted(r.cases.items())}}
            for (b, c), r in results.items()}, indent=1) + "\n")
    bad = [(b, c, k) for (b, c), r in results.items() for k in r.cases.values()
           if k.status in ("fail", "crash")]
    if args.details:
        for b, c, k in sorted(bad, key=lambda x: (x[0], x[2].name, x[1])):
            print(f"\n=== {b} [{c}] {k.name}: {k.status.upper()}")
            print(k.detail.strip()[:3000])
    ours = [x for x in bad if x[1].startswith("introspect")]
    counts = {s: sum(r.count(s) for (b, c), r in results.items() if c.startswith("introspect"))
              for s in STATUSES}
    print(f"conformance (introspect configurations): {counts['pass']} passed, "
          f"{counts['fail']} failed, {counts['skip']} skipped, {counts['crash']} crashed")
    return 1 if ours or any(r.notes for (b, c), r in results.items()
                            if c.startswith("introspect")) else 0


if __name__ == "__main__":
    sys.exit(main())
