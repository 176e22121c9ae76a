"""``rmw-introspect validate``: contract files checked without running anything (a pre-commit
hook). Kept apart from the other commands so that it imports only the contract loaders. A file
is a system contract exactly when every other command takes it for one
(``system_contract.is_system_contract``: ``*.system.yaml`` or ``system_version:``)."""

from __future__ import annotations

import argparse
import sys

from ..compare.ci_report import annotation
from ..errors import ContractError
from ..model import contract as contract_module
from ..model import system_contract
from .parser import EXIT_ERROR, EXIT_OK


def cmd_validate(args: argparse.Namespace) -> int:
    """Load every contract (nothing runs): one line per file, exit 2 when any is invalid."""
    status = EXIT_OK
    for shown in args.contracts:
        try:
            summary = _validated(shown)
        except ContractError as exc:
            status = EXIT_ERROR
            if args.format == "github":
                print(annotation("error", exc.reason, file=shown, line=exc.line, title="invalid contract"))
            else:
                print(f"rmw-introspect: {exc}", file=sys.stderr)
            continue
        if args.format == "text":
            print(f"{shown}: {summary}")
    return status


def _validated(shown: str) -> str:
    """What a valid file holds, in words (raises ContractError)."""
    if system_contract.is_system_contract(shown):
        system = system_contract.load(shown)
        count = len(system.processes)
        nodes = ", ".join(sorted(system.nodes)) or "no nodes"
        return f"valid system contract ({count} process{'es' if count != 1 else ''}: {nodes})"
    loaded = contract_module.load(shown)
    return f"valid ({', '.join(sorted(loaded.nodes)) or 'no nodes'})"
