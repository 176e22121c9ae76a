"""System contracts on the command line: ``capture --launch`` and ``check``/``diff`` of
``*.system.yaml`` files. ``capture``, ``check`` and ``diff`` hand over to these when a launch
file or a system contract is involved."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any, cast

from ..check import system_pipeline
from ..check.pipeline import Layers
from ..compare.compatibility import propose_external
from ..errors import TargetConfigError, UsageError
from ..model import contract_kind, system_contract
from ..model.contract_kind import Kind
from ..model.contract_shapes import TargetBlock
from ..run import system_capture
from ..run.ros_env import RosEnvironment
from ..run.target import TargetSpec
from . import formats
from .arguments import compare_from_args, target_from_args
from .exit_status import EXIT_OK
from .launch_options import launch_arguments, launch_block, wants_launch


def checks_as_system(path: Path, args: argparse.Namespace | None = None) -> bool:
    """A system contract: ``*.system.yaml``, a file that says ``system_version``, or (for a
    contract still to be created) any path when a launch file is given."""
    if path.exists():
        return contract_kind.is_system_file(path)
    return contract_kind.kind_of_name(path) is Kind.SYSTEM or (args is not None and wants_launch(args))


def _process_target(args: argparse.Namespace, command: list[str] | None) -> dict[str, Any]:
    target = target_from_args(args, command)
    extra = sorted(k for k in target if k not in system_contract.SYSTEM_TARGET_KEYS)
    if extra:
        spelled = {"command": "-- COMMAND", "stimuli": "--stimulus"}
        flags = ", ".join(spelled.get(k, f"--{k.replace('_', '-')}") for k in extra)
        raise UsageError(f"with a launch file the launch file says what runs: {flags} cannot be given "
                         f"(only --settle, --timeout, --horizon, --lifecycle, --[no-]read-parameters, --env, for every process)")
    return target


def cmd_capture(args: argparse.Namespace, command: list[str] | None, ros: Callable[[], RosEnvironment],
                library: Callable[[], Path]) -> int:
    """``capture --launch ...``: every process of the launch file; a system contract (yaml) or JSON."""
    if args.format == "nodl" or args.raw:
        raise UsageError("with a launch file, capture writes a system contract (--format yaml) or JSON "
                         "(--format json); --raw and nodl are for single targets")
    cwd = Path.cwd()
    block = launch_block(args)
    assert block is not None
    target = _process_target(args, command)
    env = ros()
    spec = system_capture.resolve_launch(block, base_dir=cwd, source="command line",
                                         prefixes=system_capture.ament_prefixes(env))
    process_target = TargetSpec.from_mapping(target, base_dir=cwd, source="command line")
    include = bool(args.include_infrastructure)
    cap = system_capture.capture_system(spec, target=process_target, library=library(), ros=env,
                                        include_infrastructure=include, jobs=args.jobs)
    for note in cap.notes():
        print(f"note: {note}", file=sys.stderr)
    proposal = cap.stand_in_proposal()
    if proposal:
        print(f"note: a process created no node for lack of a device. {system_capture.STAND_IN_ADVICE}\n{proposal}",
              file=sys.stderr)
    nodes = cap.to_contract_nodes()
    if args.format == "json":
        processes = [{**p.entry(), "launched_at": str(p.launched.where),
                      "command": p.capture.command if p.capture is not None else None} for p in cap.processes]
        text = json.dumps({"processes": processes, "nodes": nodes}, indent=2)
    else:
        base = Path(args.output).absolute().parent if args.output else cwd
        proposal = propose_external(system_pipeline.launched_processes(cap))
        # TargetSpec.from_mapping accepted these flags above: a target block
        header = system_contract.new_header(spec.to_block(base), target=cast(TargetBlock, target) or None,
                                            options={"include_infrastructure": True} if include else None,
                                            external_proposal=proposal)
        text = system_contract.render(cap.process_entries(), nodes, header=header)
    formats.emit(text, args.output)
    return EXIT_OK


def check_system_contract(args: argparse.Namespace, path: Path, shown: str, command: list[str] | None,
                          ros: Callable[[], RosEnvironment],
                          library: Callable[[], Path]) -> system_pipeline.SystemCheckResult:
    """``check`` of one system contract (errors end up in ``result.error``)."""
    cwd = Path.cwd()
    try:
        target = _process_target(args, command)
        # a launch file given here replaces the contract's; launch arguments alone go on top of its
        block = launch_block(args) if wants_launch(args) else None
        arguments = launch_arguments(args) if block is None else None
        if block is None and args.allow_unsupported:
            raise UsageError("--allow-unsupported needs a launch file given here; in a system contract, "
                             "write `allow_unsupported: true` in its `launch:` block")
    except UsageError as exc:
        return system_pipeline.SystemCheckResult(path=path, shown=shown,
                                                 error=TargetConfigError(str(exc)))
    layers = Layers(strong_target=[(target, cwd, "command line")] if target else [],
                    strong_options=[(compare_from_args(args), "command line")])
    return system_pipeline.check_system_contract(
        path, library=library, ros=ros, layers=layers, launch=block, launch_base=cwd, launch_arguments=arguments,
        shown=shown, allow_missing=args.update, jobs=args.jobs)
