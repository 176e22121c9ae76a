"""``rmw-introspect validate``: contract files checked without running anything (a pre-commit
hook). Kept apart from the other commands so that it imports only the contract loaders. A file
is a system contract exactly when every other command takes it for one
(``system_contract.is_system_contract``: ``*.system.yaml`` or ``system_version:``)."""

from __future__ import annotations

import argparse
import json
import sys

from .._version import __version__
from ..compare import acceptance, sarif
from ..compare.ci_report import annotation
from ..errors import ContractError
from ..model import contract as contract_module
from ..model import system_contract
from .parser import EXIT_ERROR, EXIT_OK


def cmd_validate(args: argparse.Namespace) -> int:
    """Load every contract (nothing runs): one line per file, exit 2 when any is invalid."""
    status = EXIT_OK
    invalid: list[tuple[str, int | None, str]] = []
    for shown in args.contracts:
        try:
            summary = _validated(shown)
        except ContractError as exc:
            status = EXIT_ERROR
            invalid.append((shown, exc.line, str(exc)))
            if args.format == "sarif":
                continue
            if args.format == "github":
                print(annotation("error", exc.reason, file=shown, line=exc.line, title="invalid contract"))
            else:
                print(f"rmw-introspect: {exc}", file=sys.stderr)
            continue
        if args.format == "text":
            print(f"{shown}: {summary}")
    if args.format == "sarif":
        print(json.dumps(sarif.invalid_log(invalid, tool_version=__version__), indent=2))
    return status


def _validated(shown: str) -> str:
    """What a valid file holds, in words (raises ContractError)."""
    if system_contract.is_system_contract(shown):
        system = system_contract.load(shown)
        acceptance.check_rules(system.accept)  # a rule id no check has would never match
        count = len(system.processes)
        nodes = ", ".join(sorted(system.nodes)) or "no nodes"
        return f"valid system contract ({count} process{'es' if count != 1 else ''}: {nodes})"
    loaded = contract_module.load(shown)
    acceptance.check_rules(loaded.accept)
    nodes = ", ".join(sorted(loaded.nodes)) or "no nodes"
    if loaded.nodl is not None:  # say when NoDL's own schema was not there to check it
        unchecked = [note for note in loaded.nodl.notes if note.startswith("not validated")]
        return f"valid NoDL ({nodes})" + "".join(f"; {note}" for note in unchecked)
    return f"valid ({nodes})"
