"""``rmw-introspect validate``: contract files checked without running anything (a pre-commit
hook): it imports only the contract loaders, and only once its arguments are valid. A file
is a system contract exactly when every other command takes it for one
(``model.contract_kind``: ``*.system.yaml`` or ``system_version:``)."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from ..errors import ContractError
from .exit_status import EXIT_ERROR, EXIT_OK

VALIDATE_EPILOG = """\
Each file is read like `check` reads it (YAML syntax, the contract schema, QoS values, duplicate
interfaces, contract_version); nothing is run. A NoDL v2 document is checked against NoDL's own
schema when it is found (the nodl_schema package, or RMW_INTROSPECT_NODL_SCHEMA); the line
says when it was not. As a pre-commit hook (.pre-commit-hooks.yaml of
this repository):

  - repo: https://github.com/<owner>/pytest-rmw-introspect
    rev: <version>
    hooks:
      - id: rmw-introspect-validate

exit status: 0 all valid, 2 at least one invalid file (each named with its line and reason).
"""


def add_parser(sub: Any) -> None:
    """Declare ``validate`` (``sub``: the subparsers of ``rmw-introspect``)."""
    val = sub.add_parser("validate", help="check that contract files are valid (no target is run)",
                         description="Load and validate contract files (YAML, schema, QoS values, duplicates) "
                         "without running anything: fast enough for a pre-commit hook. *.system.yaml files (and "
                         "files saying system_version:) are read as system contracts.",
                         epilog=VALIDATE_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    val.add_argument("contracts", nargs="+", metavar="CONTRACT", help="contract files (YAML), node or system contracts")
    val.add_argument("--format", choices=("text", "github", "sarif", "junit"), default="text",
                     help="text: one line per file (default); github: an annotation per invalid file; "
                     "sarif: a SARIF 2.1.0 log with a result per invalid file; junit: JUnit XML, a test case "
                     "per file")
    val.set_defaults(handler=cmd_validate)


def cmd_validate(args: argparse.Namespace) -> int:
    """Load every contract (nothing runs): one line per file, exit 2 when any is invalid."""
    from .emit import Report, emit

    valid: list[str] = []
    invalid: list[tuple[str, int | None, str, str]] = []
    for shown in args.contracts:
        try:
            valid.append(f"{shown}: {_validated(shown)}\n")
        except ContractError as exc:
            invalid.append((shown, exc.line, str(exc), exc.reason))
            if args.format == "text":
                print(f"rmw-introspect: {exc}", file=sys.stderr)
    emit(Report(text="".join(valid), data=None, invalid=invalid, read=list(args.contracts)), args.format)
    return EXIT_ERROR if invalid else EXIT_OK


def _validated(shown: str) -> str:
    """What a valid file holds, in words (raises ContractError)."""
    from ..compare import acceptance
    from ..model import contract as contract_module
    from ..model import contract_kind, system_contract

    if contract_kind.is_system_file(shown):
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
