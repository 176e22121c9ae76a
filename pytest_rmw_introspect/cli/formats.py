"""What ``rmw-introspect capture`` prints or writes: a contract, JSON, NoDL or the raw capture."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..model import qos as qos_module
from ..model.vocabulary import KIND_TO_LIST, LISTS
from ..run.target import TargetSpec

if TYPE_CHECKING:  # the capture model is imported by the runner while the target starts
    from ..model.capture import Capture
    from ..model.parameters import Parameter

_NODL_QOS_FIELDS = ("history", "depth", "reliability", "durability", "deadline_ns", "lifespan_ns", "liveliness",
                    "liveliness_lease_duration_ns")
#: parameter types in NoDL v2 spelling (generate_parameter_library's: ``int``); NoDL has no byte array
_NODL_PARAMETER_TYPES = {"integer": "int", "integer_array": "int_array"}


def _nodl_qos(q: Mapping[str, Any]) -> dict[str, Any]:
    return {k: q[k] for k in _NODL_QOS_FIELDS if k in q}


def nodl_parameters(parameters: Sequence[Parameter]) -> tuple[dict[str, Any], list[str]]:
    """NoDL v2 ``parameters`` (keyed by name: type, default_value, description, read_only,
    additional_constraints) and a comment line for each parameter NoDL cannot describe
    (byte arrays, no type). Ranges and dynamic typing have no NoDL field and are left out."""
    out: dict[str, Any] = {}
    left_out: list[str] = []
    for p in sorted(parameters, key=lambda p: p.name):
        if p.type is None or p.type == "byte_array":
            left_out.append(f"# parameter {p.name} ({p.type or 'no type'}) left out: NoDL v2 has no such type")
            continue
        entry: dict[str, Any] = {"type": _NODL_PARAMETER_TYPES.get(p.type, p.type)}
        if p.value is not None:
            entry["default_value"] = p.value
        if p.description:
            entry["description"] = p.description
        if p.read_only:
            entry["read_only"] = True
        if p.additional_constraints:
            entry["additional_constraints"] = p.additional_constraints
        out[p.name] = entry
    return out, left_out


def nodl_documents(cap: Capture, *, raw: bool) -> str:
    """One NoDL v2 document per node (a YAML stream): ``base: lifecycle_node`` for a lifecycle
    node, its parameters, its interfaces."""
    docs = []
    items: list[tuple[str, dict[str, list[dict[str, Any]]]]]
    parameters: dict[str, Sequence[Parameter]] = {}
    lifecycle: set[str] = set()
    if raw:
        per_node: dict[str, dict[str, list[dict[str, Any]]]] = {}
        live = {n.id: n for n in cap.raw_nodes if n.alive}
        for n in sorted(live.values(), key=lambda n: n.seq):
            per_node.setdefault(n.fqn, {name: [] for name in LISTS})
            if n.parameters is not None:
                parameters.setdefault(n.fqn, n.parameters)
            if n.lifecycle is not None:
                lifecycle.add(n.fqn)
        for e in sorted(cap.raw_endpoints, key=lambda e: e.seq):
            owner = live.get(e.node_id)
            if owner is None or not e.alive:
                continue
            entry: dict[str, Any] = {"name": e.name, "type": e.type}
            if e.kind in ("publisher", "subscription"):
                entry["qos"] = _nodl_qos(qos_module.from_capture(e.qos))
            per_node[owner.fqn][KIND_TO_LIST[e.kind]].append(entry)
        items = sorted(per_node.items())
    else:
        items = []
        for node in cap:
            lists: dict[str, list[dict[str, Any]]] = {}
            for list_name in LISTS:
                lists[list_name] = []
                for i in getattr(node, list_name):
                    entry = {"name": i.name, "type": i.type}
                    if i.qos is not None:
                        entry["qos"] = _nodl_qos(i.qos)
                    lists[list_name].append(entry)
            items.append((node.fqn, lists))
            if node.parameters is not None:
                parameters[node.fqn] = node.parameters
            if node.lifecycle is not None:
                lifecycle.add(node.fqn)
    import yaml  # ~20 ms: imported once a capture is there to print (start-up without it)

    for fqn, node_lists in items:
        doc: dict[str, Any] = {"nodl_version": 2}
        if fqn in lifecycle:
            doc["base"] = "lifecycle_node"
        params, left_out = nodl_parameters(parameters.get(fqn, ()))
        if params:
            doc["parameters"] = params
        doc.update({k: v for k, v in node_lists.items() if v})
        comments = "".join(f"{line}\n" for line in left_out)
        docs.append(f"# node: {fqn}\n{comments}"
                    + yaml.safe_dump(doc, sort_keys=False, default_flow_style=False, allow_unicode=True))
    return "---\n" + "---\n".join(docs)


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
