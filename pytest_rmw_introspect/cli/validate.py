"""``rmw-introspect validate``: contract files checked without running anything (a pre-commit
hook). Kept apart from the other commands so that it imports only the contract loader."""

from __future__ import annotations

import argparse
import sys

from ..compare.ci_report import annotation
from ..errors import ContractError
from ..model import contract as contract_module
from .parser import EXIT_ERROR, EXIT_OK


def cmd_validate(args: argparse.Namespace) -> int:
    """Load every contract (nothing runs): one line per file, exit 2 when any is invalid."""
    status = EXIT_OK
    for shown in args.contracts:
        try:
            loaded = contract_module.load(shown)
        except ContractError as exc:
            status = EXIT_ERROR
            if args.format == "github":
                print(annotation("error", exc.reason, file=shown, line=exc.line, title="invalid contract"))
            else:
                print(f"rmw-introspect: {exc}", file=sys.stderr)
            continue
        if args.format == "text":
            print(f"{shown}: valid ({', '.join(sorted(loaded.nodes)) or 'no nodes'})")
    return status
