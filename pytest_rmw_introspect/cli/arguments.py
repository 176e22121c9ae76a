"""What several ``rmw-introspect`` commands share in their parsers: the parser class (argparse's
own errors as one line and a hint, exit status 2), the target, comparison, report-format and
baseline option groups, and the readers of the target and comparison options given. Each
command declares its own subparser beside what it runs (``cli/<command>.py``)."""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from typing import Any

from ..errors import UsageError
from ..model.option_tables import COMPARISON, TARGET, FrontEnd, Shape
from . import option_flags
from .exit_status import EXIT_ERROR

_TARGET_HELP = """\
What to run, exactly one of: --package P with --executable E (found like `ros2 run`, or a console
script of the Python distribution P as `pip install -e .` installs an ament_python package),
--script, --module, --entry-point, or `-- COMMAND ARGS...` (any command: everything after `--`).
The other target options (--namespace, --remap, --param, ...) are added as `--ros-args`.
"""


class CliParser(argparse.ArgumentParser):
    """The parser of ``rmw-introspect`` and of each command."""

    def error(self, message: str) -> Any:  # argparse's own errors: message + usage hint, status 2
        self.exit(EXIT_ERROR, f"{self.prog}: error: {message}\n(see `{self.prog} --help`)\n")


def add_target(parser: argparse.ArgumentParser) -> None:
    """The target options (``model.option_tables.TARGET``): what to run and how."""
    option_flags.add_group(parser, TARGET, FrontEnd.CLI, "target options", _TARGET_HELP)


def add_compare(parser: argparse.ArgumentParser, front_end: FrontEnd = FrontEnd.CLI) -> None:
    """The comparison options (``model.option_tables.COMPARISON``) a front end exposes."""
    option_flags.add_group(parser, COMPARISON, front_end, "comparison options (override the contract's options: block)")


REPORT_FORMATS = ("text", "json", "markdown", "github", "sarif", "junit")


def add_format(parser: argparse.ArgumentParser) -> None:
    """``--format`` of the commands that report drift or incompatibility."""
    parser.add_argument("--format", choices=REPORT_FORMATS, default="text",
                        help="text: the report for people (default); json: machine-readable items; "
                        "markdown: a summary table and the grouped drift (a pull-request comment, "
                        "$GITHUB_STEP_SUMMARY); github: GitHub Actions annotations on the contract lines; "
                        "sarif: a SARIF 2.1.0 log (GitHub code scanning), a result per finding on its contract line; "
                        "junit: JUnit XML, a test case per contract (GitLab, Jenkins, test-report actions)")


def add_baseline(parser: argparse.ArgumentParser) -> None:
    """``--baseline`` and ``--write-baseline`` (``cli.baselines`` reads them)."""
    g = parser.add_argument_group("baselines (turn the gate on with known findings, tighten it later)")
    g.add_argument("--baseline", metavar="FILE",
                   help="fail only on findings that are not in FILE (written by --write-baseline); the known "
                   "ones are reported as accepted by the baseline")
    g.add_argument("--write-baseline", metavar="FILE",
                   help="record today's findings (those no `accept:` entry accepts) in FILE and exit 0 unless "
                   "a contract could not be checked")


# ---------------------------------------------------------------------------- what was given


def _pairs(values: Sequence[str] | None, sep: str, what: str, example: str) -> list[tuple[str, str]]:
    out = []
    for value in values or ():
        key, found, rest = value.partition(sep)
        if not found or not key:
            raise UsageError(f"{what} {value!r} is not of the form {example}")
        out.append((key, rest))
    return out


def target_from_args(args: argparse.Namespace, command: list[str] | None) -> dict[str, Any]:
    """The target options given on the command line (a TargetSpec mapping)."""
    given = {k: v for k, v in option_flags.values(args, TARGET.exposed(FrontEnd.CLI)).items() if v is not None}
    target = {k: v for k, v in given.items() if TARGET[k].shape is not Shape.REPEATED}
    for key in ("arguments", "stimuli"):
        if given.get(key):
            target[key] = list(given[key])
    if command:
        target["command"] = list(command)
    remaps = _pairs(given.get("remappings"), ":=", "--remap", "FROM:=TO")
    if remaps:
        target["remappings"] = dict(remaps)
    params = {}
    pairs = _pairs(given.get("parameters"), ":=", "--param", "NAME:=VALUE")
    if pairs:
        import yaml  # ~20 ms: only --param values need it
    for name, text in pairs:
        try:
            params[name] = yaml.safe_load(text) if text.strip() else ""
        except yaml.YAMLError as exc:
            raise UsageError(f"--param {name}:={text}: the value is not valid YAML ({exc})") from None
    if params:
        target["parameters"] = params
    env = _pairs(given.get("env"), "=", "--env", "K=V")
    if env:
        target["env"] = dict(env)
    kinds = [k for k in ("package", "executable", "script", "module", "entry_point", "command") if k in target]
    if "package" in kinds and "executable" in kinds:
        kinds.remove("executable")
    if len([k for k in kinds if k != "executable"]) > 1 or ("executable" in kinds and len(kinds) > 1):
        shown = ["-- COMMAND" if k == "command" else f"--{k.replace('_', '-')}" for k in kinds]
        raise UsageError(f"give one target, not {' and '.join(shown)}")
    return target


def compare_from_args(args: argparse.Namespace) -> dict[str, Any]:
    """The comparison options given on the command line (None: not given)."""
    return option_flags.values(args, COMPARISON.options)
