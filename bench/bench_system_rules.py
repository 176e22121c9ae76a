"""What the system rules add to a system check (issue 37: at most 5 %), in one process.

A launch file starts the example robot (examples/rmw_introspect_examples/launch/robot.launch.xml,
7 processes) ``--robots`` times, each in its own namespace; its system contract is written from
a first capture. Then each repetition runs the system check as ``rmw-introspect check`` does
(``system_pipeline.prepare``, the capture of every process, ``compare``: drift and system rules)
and, on that repetition's capture, the rule pass alone: the processes as the rules read them
(``launched_processes``: what the launch file gives each), the files and devices their
parameters point at (``launch_settings.missing_path``) and every compatibility rule of a launched
system (``check_launched``). The check without the rule pass is the check less that time.

    python bench/bench_system_rules.py [--robots 3 | --launch FILE | --precision SYSTEM] [--reps 5] [--rule-reps 50]

``--launch``: another launch file instead of the example robots. ``--precision``: a system of the
precision suite (tests/precision/systems/SYSTEM), installed into a temporary prefix with its
declared ``external:``, as the suite checks it (``--precision largest``: the one with the most
processes).

Prints the medians in ms and the ratio (rule pass / check without it).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

from pytest_rmw_introspect.check import launch_settings, system_pipeline
from pytest_rmw_introspect.compare.compatibility import check_launched
from pytest_rmw_introspect.run import middleware, ros_env, system_capture

REPO = Path(__file__).resolve().parents[1]
EXAMPLE = REPO / "examples" / "rmw_introspect_examples" / "launch" / "robot.launch.xml"


def launch_file(robots: int) -> str:
    includes = "\n".join(f'  <include file="{EXAMPLE}"><arg name="robot" value="robot{i + 1}"/></include>'
                         for i in range(robots))
    return f"<launch>\n{includes}\n</launch>\n"


def rule_pass(prepared: system_pipeline.SystemPrepared, capture: system_capture.SystemCapture) -> float:
    launch_settings.forget_parsed_files()  # what one check pays: its parameters files read once
    start = time.perf_counter()
    external = prepared.contract.external if prepared.contract is not None else None
    missing = launch_settings.missing_path(system_capture.ament_prefixes(prepared.ros))
    check_launched(system_pipeline.launched_processes(capture), external=external, missing_path=missing)
    return time.perf_counter() - start


def precision_system(name: str, root: Path) -> tuple[Path, dict[str, dict[str, str]]]:
    """The launch file of a precision-suite system installed under ``root`` (its prefix put first on
    AMENT_PREFIX_PATH, as the suite does) and the outside world it declares."""
    sys.path[:0] = [str(REPO / "tests" / "precision"), str(REPO / "tests" / "support")]
    import precision_suite  # the suite's own installer (tests/precision/precision_suite.py)

    systems = {system.name: system for system in precision_suite.systems()}
    if name == "largest":  # the most <node> elements in its launch files
        def nodes(system: precision_suite.System) -> int:
            return sum(f.read_text().count("<node ") for p in system.packages for f in p.rglob("*.launch.xml"))
        name = max(systems.values(), key=nodes).name
    system = systems[name]
    prefix = precision_suite.install(system, root / "prefix")
    os.environ.update(precision_suite.environment(prefix, os.environ))
    package, file = system.launch["package"], system.launch["file"]
    launch = next((prefix / "share" / package).rglob(file))
    print(f"precision system {name}: {launch}")
    return launch, system.external


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--robots", type=int, default=3)
    parser.add_argument("--launch", type=Path, help="a launch file to check instead of the example robots")
    parser.add_argument("--precision", help="a system of the precision suite (or `largest`) instead of the robots")
    parser.add_argument("--reps", type=int, default=5)
    parser.add_argument("--rule-reps", type=int, default=50)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="bench_system_rules_") as d:
        root = Path(d)
        external: dict[str, dict[str, str]] = {}
        if args.precision:
            launch, external = precision_system(args.precision, root)
        else:
            launch = args.launch.absolute() if args.launch else root / "robots.launch.xml"
        if not args.launch and not args.precision:
            launch.write_text(launch_file(args.robots))
        ros = ros_env.detect()
        library = middleware.ensure_library(ros)
        contract = root / "robots.system.yaml"
        first = system_pipeline.check_system_contract(contract, library=library, ros=ros, allow_missing=True,
                                                      launch={"path": str(launch)}, launch_base=root)
        assert first.error is None, first.error
        first.update()
        if external:  # the outside world the suite declares, as in its gate
            import precision_suite

            contract.write_text(precision_suite.declare_external(contract.read_text(), external))
        checks, rules = [], []
        for _ in range(args.reps):
            start = time.perf_counter()
            prepared = system_pipeline.prepare(contract, ros=ros)
            capture = system_pipeline.run_capture(prepared, library=library, ros=ros)
            result = system_pipeline.compare(prepared, capture)
            checks.append(time.perf_counter() - start)
            assert not result.failed, result.render_text()
            rules.append(statistics.median(rule_pass(prepared, capture) for _ in range(args.rule_reps)))
        processes = len(capture.processes)
    check, rule = statistics.median(checks), statistics.median(rules)
    without = check - rule
    what = args.precision or args.launch or f"{args.robots} example robots"
    print(f"system check of {processes} processes ({what}), median of {args.reps}:")
    print(f"  check with the rule pass:    {check * 1000:9.1f} ms")
    print(f"  the rule pass alone:         {rule * 1000:9.2f} ms (median of {args.rule_reps} per repetition)")
    print(f"  check without the rule pass: {without * 1000:9.1f} ms")
    print(f"  ratio (rule pass / check without it): {rule / without * 100:.2f} %")


if __name__ == "__main__":
    main()
