"""``check --live`` and ``capture --live``: contracts against the running ROS 2 graph (issue 52).

``check`` and ``capture`` hand over to these when ``--live`` is given: the graph is read once
per run (``live.graph``) and each contract is compared with it (``live.check``); the reports,
baselines, formats and exit statuses are ``check``'s own.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path
from typing import Any, cast

from ..check.outcome import Verdict, decide
from ..check.pipeline import Layers
from ..compare import drift, report
from ..errors import UsageError
from ..live import DEFAULT_PARAMETER_TIMEOUT, DEFAULT_SETTLE, DEFAULT_TIMEOUT
from ..live import check as live_check
from ..live.graph import LiveGraph, LiveSettings, read_graph, watch_graph
from ..model import system_contract
from ..model.contract_shapes import LaunchBlock
from . import formats
from .arguments import compare_from_args
from .exit_status import EXIT_DRIFT, EXIT_ERROR, EXIT_OK
from .launch_options import launch_block, wants_launch
from .ros_setup import Setup


def settings(args: argparse.Namespace, expect: tuple[str, ...] = ()) -> LiveSettings:
    settle = args.settle if args.settle is not None else DEFAULT_SETTLE
    timeout = args.timeout if args.timeout is not None else DEFAULT_TIMEOUT
    parameters = args.parameter_timeout if args.parameter_timeout is not None else DEFAULT_PARAMETER_TIMEOUT
    if settle < 0 or timeout <= 0 or parameters <= 0:
        raise UsageError("--settle must not be negative, --timeout and --parameter-timeout must be positive")
    if settle > timeout:
        raise UsageError(f"--settle {settle:g} is longer than --timeout {timeout:g}: the graph could never settle")
    return LiveSettings(settle=settle, timeout=timeout, parameter_timeout=parameters, expect=expect)


def refuse_with_live(args: argparse.Namespace, command: list[str] | None, *, launch: bool = False) -> None:
    """What ``--live`` cannot be given with (usage errors, before the graph is read)."""
    if command or any(getattr(args, name, None) for name in ("package", "executable", "script", "module",
                                                               "entry_point")):
        raise UsageError("--live checks what is running: a target to run (--package/--executable, --script, "
                         "--module, --entry-point, -- COMMAND) cannot be given with it")
    if getattr(args, "update", False):
        raise UsageError("--live does not update contracts; write one from the running system with "
                         "`rmw-introspect capture --live -o FILE`")
    if wants_launch(args) and not launch:
        raise UsageError("--live reads the running graph; a launch file (--launch, --launch-package) is not run")


def read(args: argparse.Namespace, include_infrastructure: bool = True) -> LiveGraph:
    """The running graph, read once for the whole run; every contract of ``check`` is loaded
    first, so that a contract that cannot be used is an error before the graph is joined."""
    expect = live_check.expected_nodes([live_check.load(Path(shown)) for shown in getattr(args, "contracts", None) or ()])
    return read_graph(settings(args, expect), ros=Setup().ros(), include_infrastructure=include_infrastructure)


def check_one(path: Path, shown: str, graph: LiveGraph, layers: Layers) -> live_check.LiveCheckResult:
    return live_check.check_contract(path, graph, layers=layers, shown=shown)


def cmd_capture(args: argparse.Namespace, command: list[str] | None) -> int:
    """``capture --live [-o FILE]``: a system contract (or JSON) of the running graph."""
    refuse_with_live(args, command, launch=True)
    if args.format == "nodl" or args.raw:
        raise UsageError("with --live, capture writes a system contract (--format yaml) or JSON (--format json)")
    if args.format == "yaml" and not wants_launch(args):
        raise UsageError("capture --live writes a system contract, which names what starts the system: give its launch "
                         "file (--launch FILE, or --launch-package P --launch-file F); it is not run. --format json "
                         "writes the nodes alone")
    graph = read(args, include_infrastructure=bool(args.include_infrastructure))
    nodes = graph.capture.to_contract_nodes()
    for note in graph.notes():
        print(f"note: {note}", file=sys.stderr)
    if not nodes:
        raise UsageError("the running graph has no node to write")
    if args.format == "json":
        formats.emit(json.dumps({"domain_id": graph.domain_id, "rmw_implementation": graph.rmw_implementation,
                                 "other_readers": graph.other_readers, "nodes": nodes}, indent=2), args.output)
        return EXIT_OK
    block = dict(launch_block(args) or {})
    if block.get("path") and args.output:  # relative to the contract file, as a system contract reads it
        block["path"] = os.path.relpath(Path(block["path"]).absolute(), Path(args.output).absolute().parent)
    header = system_contract.new_header(
        cast(LaunchBlock, block), options={"include_infrastructure": True} if args.include_infrastructure else None,
        how=f"rmw-introspect capture --live` (ROS_DOMAIN_ID {graph.domain_id}, {graph.rmw_implementation}")
    header += ("# processes: which process started each node cannot be seen in a live graph; `rmw-introspect check\n"
               "# --update` (without --live) fills it in from the launch file.\n")
    formats.emit(system_contract.render([], nodes, header=header), args.output)
    return EXIT_OK


def _change_line(at: float, item: dict[str, Any]) -> str:
    return f"{time.strftime('%H:%M:%S', time.localtime(at))} [{item['rule']}] {item['node']}: {item['message']}"


def cmd_watch(args: argparse.Namespace) -> int:
    """``check --live --watch``: the check of every contract, then every change of the graph as it
    happens, then (Ctrl-C, ``--duration``) the check again on the graph as it is then, and a summary;
    the exit status is that last check's."""
    if args.format not in ("text", "json"):
        raise UsageError("--watch reports each change as a text line or a JSON line: --format text or json")
    if args.duration is not None and args.duration <= 0:
        raise UsageError("--duration must be positive")
    if args.baseline or args.write_baseline or args.summary:
        raise UsageError("--watch takes no --baseline, --write-baseline or --summary; run check --live for them")
    expect = live_check.expected_nodes([live_check.load(Path(shown)) for shown in args.contracts])
    layers = Layers(strong_options=[(compare_from_args(args), "command line")])
    started = time.monotonic()
    changes = snapshots = 0
    graph: LiveGraph | None = None
    previous: Any = None
    stream = watch_graph(settings(args, expect), args.duration or 0.0, ros=Setup().ros())
    try:
        for graph in stream:
            snapshots += 1
            current = graph.capture.with_infrastructure(bool(args.include_infrastructure)).to_contract_nodes(
                with_parameters=False)
            if previous is None:
                _check_all(args, graph, layers)
                print(f"rmw-introspect: watching ROS_DOMAIN_ID {graph.domain_id}"
                      f"{f' for {args.duration:g} s' if args.duration else ''}; Ctrl-C ends it", file=sys.stderr)
            else:
                for item in report.to_json(drift.sort_items(drift.compare(previous, current))):
                    changes += 1
                    if args.format == "json":
                        print(json.dumps({"at": graph.at, **item}, default=str), flush=True)
                    else:
                        print(_change_line(graph.at, item), flush=True)
            previous = current
    except KeyboardInterrupt:
        pass
    finally:
        stream.close()
    if graph is None:
        return EXIT_ERROR
    print(f"rmw-introspect: watched ROS_DOMAIN_ID {graph.domain_id} for {time.monotonic() - started:.0f} s: "
          f"{changes} change(s) in {snapshots - 1} update(s) of the graph; the contracts against the graph as it "
          "is now:", file=sys.stderr)
    return _check_all(args, graph, layers)


def _check_all(args: argparse.Namespace, graph: LiveGraph, layers: Layers) -> int:
    """Every contract against ``graph``, as ``check`` reports it (text, or a JSON array); the exit status."""
    status = EXIT_OK
    found: list[dict[str, Any]] = []
    for shown in args.contracts:
        result = live_check.check_contract(Path(shown), graph, layers=layers, shown=shown)
        outcome = decide(result, update=False, verbose=args.verbose)
        found += outcome.json
        if args.format == "text":
            sys.stdout.write(outcome.report + "\n" if outcome.report else outcome.message + "\n")
        if outcome.failed:
            status = EXIT_ERROR if outcome.verdict is Verdict.ERROR else max(status, EXIT_DRIFT)
    if args.format == "json":
        print(json.dumps(found, indent=2, default=str), flush=True)
    return status
