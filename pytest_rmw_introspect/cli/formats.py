"""What the commands print or write: ``capture``'s contract, JSON, NoDL or raw capture; any
command's output to ``-o FILE`` or stdout; JSON; the Markdown report appended to ``--summary FILE``."""

from __future__ import annotations

import argparse
import errno
import json
import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import UsageError
from ..model import nodl
from ..model import qos as qos_module
from ..model.contract_shapes import ContractNodes, InterfaceEntry, empty_node
from ..model.unstable_names import NameRules
from ..model.vocabulary import KIND_TO_LIST, LIFECYCLE, LIFECYCLE_UNKNOWN, PARAMETERS, TOPIC_KINDS
from ..run.target import TargetSpec

if TYPE_CHECKING:  # the capture model is imported by the runner while the target starts
    from ..model.capture import Capture


def nodl_documents(cap: Capture, *, raw: bool) -> str:
    """One NoDL v2 document per node (a YAML stream, ``model.nodl.render``); ``raw``: every live
    endpoint as created, ungrouped and unfiltered."""
    if not raw:  # a NoDL document names its node literally (no patterns of model.unstable_names)
        return nodl.render(cap.to_contract_nodes(names=NameRules.literal(cap.node_names)))
    nodes: ContractNodes = {}
    live = {n.id: n for n in cap.raw_nodes if n.alive}
    for n in sorted(live.values(), key=lambda n: n.seq):
        node = nodes.setdefault(n.fqn, empty_node())
        if n.parameters is not None and PARAMETERS not in node:
            node[PARAMETERS] = [p.to_contract() for p in n.parameters]
        if n.lifecycle is not None:
            node[LIFECYCLE] = n.lifecycle.state or LIFECYCLE_UNKNOWN
    for e in sorted(cap.raw_endpoints, key=lambda e: e.seq):
        owner = live.get(e.node_id)
        if owner is None or not e.alive:
            continue
        entry: InterfaceEntry = {"name": e.name, "type": e.type}
        if e.kind in TOPIC_KINDS:
            entry["qos"] = qos_module.from_capture(e.qos)
        nodes[owner.fqn][KIND_TO_LIST[e.kind]].append(entry)
    return nodl.render(nodes)


def capture_text(cap: Capture, args: argparse.Namespace, spec: TargetSpec, cwd: Path,
                 partial_reason: str | None = None) -> str:
    """The capture in the format asked for; a partial yaml contract says so in its header."""
    if args.format == "nodl":
        return nodl_documents(cap, raw=args.raw)
    if args.raw:
        raw = dict(cap.raw)
        if args.format == "json":
            return json.dumps(raw, indent=2)
        import yaml  # ~20 ms: imported once a capture is there to print (start-up without it)

        return yaml.safe_dump(raw, sort_keys=False, default_flow_style=False)
    if args.format == "json":
        return json.dumps(cap.to_contract_nodes(), indent=2)
    from ..check import golden  # the contract writer: once a capture is there to print

    base = Path(args.output).absolute().parent if args.output else cwd
    text = golden.new_contract_text(cap.to_contract_nodes(), spec=spec, base=base,
                                    include_infrastructure=bool(args.include_infrastructure),
                                    run_dir=spec.cwd or cwd, distribution=cap.ros_distribution)
    if partial_reason is not None:
        text = f"# PARTIAL capture (not a complete interface): {partial_reason}\n" + text
    return text


def emit(text: str, output: str | None) -> None:
    """Print ``text``, or write it to ``output`` through the one writer (atomic, locked)."""
    if not text.endswith("\n"):
        text += "\n"
    if output is None:
        sys.stdout.write(text)
        return
    from ..check import golden

    golden.write_text(output, text)  # raises GoldenWriteError: a message, exit status 2
    print(f"wrote {output}", file=sys.stderr)


def print_json(document: Any) -> None:
    """A report document (``--format json`` or ``sarif``) on stdout."""
    print(json.dumps(document, indent=2, default=str))


def append_summary(path: str, markdown: str) -> None:
    """Append the Markdown report to ``path`` (``$GITHUB_STEP_SUMMARY`` collects what each step
    appends; the run's own result is never replaced)."""
    try:
        # O_NONBLOCK: a FIFO nobody reads is refused at once (ENXIO) instead of blocking forever
        # (issue 50, N22); one somebody reads (``--summary /dev/stdout`` in a pipe) is written to
        fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT | os.O_NONBLOCK | os.O_CLOEXEC, 0o666)
    except OSError as exc:
        if exc.errno == errno.ENXIO:
            raise UsageError(f"--summary {path}: is a FIFO (named pipe) that nobody reads: the report cannot be "
                             "appended; give a regular file (in GitHub Actions \"$GITHUB_STEP_SUMMARY\")") from None
        raise UsageError(f"--summary {path}: cannot append the report ({exc.strerror or exc}); "
                         "give a file in a directory that exists and is writable") from None
    try:
        os.set_blocking(fd, True)
        with os.fdopen(fd, "a", encoding="utf-8") as summary:
            summary.write(markdown if markdown.endswith("\n") else markdown + "\n")
    except OSError as exc:
        raise UsageError(f"--summary {path}: cannot append the report ({exc.strerror or exc}); "
                         "give a file in a directory that exists and is writable") from None


def say_notes(noted: dict[str, list[str]]) -> None:
    """The notes of a run (note → the contracts that noted it) on stderr, each once, however many
    contracts note it: ``note: CONTRACT: NOTE`` (``CONTRACT (and N more)``)."""
    for note, contracts in noted.items():
        more = f" (and {len(contracts) - 1} more)" if len(contracts) > 1 else ""
        print(f"note: {contracts[0]}{more}: {note}", file=sys.stderr)
