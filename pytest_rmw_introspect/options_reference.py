"""The option tables (``model.option_tables``) for people and for the contract schema.

:func:`render_markdown` renders a family's reference page (the docs build calls it);
:func:`contract_schema_text` is ``schema/contract.schema.json`` with its ``options`` and
``target`` definitions generated from the tables (``python -m
pytest_rmw_introspect.options_reference --write-schema`` writes it; a unit test fails while the
file differs). ``python -m pytest_rmw_introspect.options_reference comparison`` prints a page.
"""

from __future__ import annotations

import argparse
import json
from collections.abc import Sequence
from importlib import resources
from pathlib import Path

from .model.option_tables import FAMILIES, PRECEDENCE, FrontEnd, Option, Source, family, schema_definition

#: the contract schema's definition that each family generates
SCHEMA_DEFINITIONS = {"comparison": "options", "target": "target"}

_SOURCES = {
    Source.DEFAULT: "the default (the table's)",
    Source.INI: "the ini file (`rmw_introspect_<name>`, pytest)",
    Source.PYTEST: "pytest's command line (`--rmw-introspect-<name>`)",
    Source.CONTRACT: "the contract's `{block}:` block",
    Source.OWN: "the test's or command's own: the marker's keyword arguments, `rmw_capture()` arguments, "
                "`rmw-introspect` flags",
}


def render_markdown(name: str) -> str:
    """The Markdown reference page of the option family ``name`` (``comparison`` or ``target``):
    what the table holds, every front end's spelling, and the precedence."""
    table = family(name)
    lines = [f"# {table.title}", "", f"{table.description} The contract's `{table.block}:` block holds them.", "",
             "| option | type | default | pytest option | ini key | `rmw-introspect` flag | marker | meaning |",
             "|---|---|---|---|---|---|---|---|"]
    for option in table.options:
        lines.append("| " + " | ".join([
            f"`{option.name}`", _escape(option.type_text), _default(option),
            _spelling(option, FrontEnd.PYTEST, option.pytest_flag), _spelling(option, FrontEnd.INI, option.ini_key),
            _cli(option, diff=bool(table.names(FrontEnd.DIFF))),
            "yes" if FrontEnd.MARKER in option.front_ends else "no", _escape(option.help),
        ]) + " |")
    system = table.names(FrontEnd.SYSTEM)
    lines += ["", f"A system contract's `{table.block}:` block takes " + ", ".join(f"`{n}`" for n in system) + ".",
              "", "## Precedence", "", "From weakest to strongest; a stronger source overrides a weaker one "
              "option by option:", ""]
    lines += [f"{i}. {_SOURCES[source].format(block=table.block)}" for i, source in enumerate(PRECEDENCE, 1)]
    if table.notes:
        lines += ["", "## Notes", ""] + [f"- {note}" for note in table.notes]
    return "\n".join(lines) + "\n"


def _default(option: Option) -> str:
    return _escape(option.shown_default) or ("false" if option.default is False else "none")


def _escape(text: str) -> str:
    return text.replace("|", "\\|")


def _spelling(option: Option, front_end: FrontEnd, words: str) -> str:
    return f"`{words}`" if front_end in option.front_ends else ""


def _cli(option: Option, *, diff: bool) -> str:
    """The flag (``diff``: the family's flags are also those of ``rmw-introspect diff``)."""
    if option.name == "command":
        return "`-- COMMAND ...`"
    if FrontEnd.CLI not in option.front_ends:
        return ""
    flag = option.flag if option.default is not True else f"{option.flag}, --no-{option.flag[2:]}"
    only = " (not `diff`)" if diff and FrontEnd.DIFF not in option.front_ends else ""
    return f"`{flag}`{only}"


def contract_schema_text(current: str | None = None) -> str:
    """The contract schema file's text with the tables' definitions (``current``: the file as it is)."""
    if current is None:
        current = resources.files(__package__).joinpath("schema", "contract.schema.json").read_text("utf-8")
    schema = json.loads(current)
    for name, definition in SCHEMA_DEFINITIONS.items():
        schema["definitions"][definition] = schema_definition(FAMILIES[name])
    return json.dumps(schema, indent=2, ensure_ascii=False) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m pytest_rmw_introspect.options_reference",
                                     description="Print an option family's reference page, or write the "
                                     "contract schema's generated definitions.")
    parser.add_argument("family", nargs="?", choices=sorted(FAMILIES))
    parser.add_argument("--write-schema", action="store_true", help="rewrite schema/contract.schema.json")
    args = parser.parse_args(argv)
    if args.write_schema:
        path = Path(__file__).parent / "schema" / "contract.schema.json"
        path.write_text(contract_schema_text(path.read_text("utf-8")), encoding="utf-8")
    if args.family:
        print(render_markdown(args.family), end="")
    elif not args.write_schema:
        parser.print_help()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
