"""The ``rmw-introspect`` command line: its parser, help texts and the options it reads."""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from typing import Any

from .._version import __version__
from ..errors import UsageError
from ..model.option_tables import COMPARISON, TARGET, FrontEnd, Shape
from ..model.vocabulary import FAIL_ON
from . import option_flags, system_options

EXIT_OK, EXIT_DRIFT, EXIT_ERROR = 0, 1, 2
#: the start note of a command's only capture: a warm start server pays off from the second one
ONE_CAPTURE_STARTS_COLD = "a run with one capture starts it cold (a warm start server pays off from the second)"

_DESCRIPTION = """\
Interface contracts of ROS 2 nodes: run a node on the recording middleware (rmw_introspect_cpp)
and write down, check or compare the publishers, subscriptions, services and actions it creates.

A launch file is a target too: `capture --launch robot.launch.xml -o robot.system.yaml` captures
every process it starts into a system contract, which check, diff, compat and graph read.

Run `rmw-introspect COMMAND --help` for the options of a command.

examples:
  rmw-introspect capture --package my_pkg --executable talker -o talker.interfaces.yaml
  rmw-introspect capture --format nodl --script my_node.py --param rate:=10.0
  rmw-introspect check contracts/*.interfaces.yaml --fail-on risky
  rmw-introspect check --update contracts/talker.interfaces.yaml
  rmw-introspect diff old/talker.interfaces.yaml talker.interfaces.yaml --format json
  rmw-introspect compat contracts/*.interfaces.yaml
  rmw-introspect capture --launch-package my_robot --launch-file robot.launch.xml -o robot.system.yaml
  rmw-introspect graph robot.system.yaml --format html -o robot.html

exit status: 0 everything matches (or only drift below the fail threshold), 1 drift /
incompatibility at or above the fail threshold, 2 an error (a missing or malformed contract,
no target, a target that fails, hangs or creates no node, ROS 2 or the middleware missing,
a bad option). Errors are one message on stderr, never a traceback. Interrupted (Ctrl-C) 130,
terminated (SIGTERM) 143; a running target is stopped first.
"""

_TARGET_HELP = """\
What to run, exactly one of: --package P with --executable E (found like `ros2 run`, or a console
script of the Python distribution P as `pip install -e .` installs an ament_python package),
--script, --module, --entry-point, or `-- COMMAND ARGS...` (any command: everything after `--`).
The other target options (--namespace, --remap, --param, ...) are added as `--ros-args`.
"""

_CHECK_EPILOG = """\
Each contract's target comes from its `target:` block (paths relative to the contract); target
options given here override it (paths relative to the current directory), and a target named
here (--package/--executable, --script, --module, -- COMMAND) replaces the contract's.

Comparison options given here override the contract's `options:` block, which overrides the
defaults (fail_on: any, nothing ignored). Drift rules and severities: docs/drift-rules.md.

--update rewrites the `nodes:` block of every drifted contract from the capture (keeping the
comments, target and options above it) and creates missing ones (with a `target:` block from
the target options given here); it is refused when the CI environment variable is set.

--baseline FILE fails only on findings that FILE (written by --write-baseline FILE) does not
hold; the known ones are reported as accepted by the baseline.

A NoDL v2 document (*.nodl.yaml, or a file with `nodl_version:`) is a contract too: name the
target here; what NoDL cannot express (type hashes, lifecycle states, parameter ranges, service
QoS) and what the document leaves out are not compared. NoDL's schema is used when found (the
nodl_schema package, or RMW_INTROSPECT_NODL_SCHEMA).

--format json prints one JSON array with an object per drift item: contract, node, kind
(publishers, subscriptions, service_servers, service_clients, action_servers, action_clients,
parameters or node), name, change, rule, severity (SAFE, RISKY, BREAKING), old, new, message.

Parameters and lifecycle: a capture reads every node's parameters and drives lifecycle nodes
to --lifecycle (default active). A contract node without `parameters:` does not compare them;
--update adds them to contracts that match but do not state them yet. A lifecycle transition
that fails is an error (exit 2) naming the node, the transition and what to set instead.

exit status: 0 all contracts match (or drift below --fail-on), 1 drift at or above --fail-on,
2 errors (missing/malformed contract, no target, target failure, ROS 2/middleware missing).
"""

_CAPTURE_EPILOG = """\
formats:
  yaml  (default) a complete contract: contract_version, a `target:` block saying how the
        target was run (paths relative to the -o file, or to the current directory), and the
        `nodes:` block. Save it with -o NAME.interfaces.yaml and check it with
        `rmw-introspect check` or by running pytest next to it.
  json  the contract's `nodes` mapping as JSON.
  nodl  one NoDL v2 document per node (nodl_version: 2; parameters keyed by name with
        type, default_value, description, read_only, additional_constraints; publishers,
        subscriptions, service_servers, service_clients, action_servers, action_clients
        with name, type and qos for topics), as a YAML stream; a `# node: /fqn` comment
        names the node of each document (NoDL documents do not name their node), a
        `# lifecycle: STATE` comment a lifecycle node's state. `check` reads the file
        back as a contract, `check --update` rewrites it as NoDL.

parameters and lifecycle:
  every node's parameters are read through its own parameter services (--no-read-parameters
  to skip), lifecycle nodes are driven to --lifecycle (default active) first; the contract's
  nodes list their `parameters:` and a lifecycle node its `lifecycle:` state.

endpoints:
  default               infrastructure endpoints (/rosout, /parameter_events, parameter,
                        type description, logger and lifecycle services) and parameters
                        (use_sim_time, start_type_description_service) are left out; the
                        services and topics of an action are grouped into one action entry.
  --include-ros-infra   keeps the infrastructure endpoints (the yaml contract then gets
                        `options: {include_infrastructure: true}`); actions stay grouped.
  --raw                 every endpoint exactly as the middleware recorded it, destroyed ones
                        included: with yaml/json the capture document itself (nodes and
                        endpoints with raw rmw QoS), with nodl the endpoints per node,
                        ungrouped and unfiltered.

--partial: when the target fails, hangs or creates no node, still write what was captured so
far (to -o or stdout; a yaml contract gets a `# PARTIAL capture` comment). The exit status stays 2.

Notes about how the capture came about (the program ended by itself, exited after settling,
uses sim time, virtual time stopped early) are printed to stderr as `note: ...` lines.

exit status: 0 captured, 2 error (no target, target failed/hung/created no node, setup).
"""

_DIFF_EPILOG = """\
OLD plays the contract and NEW the capture, so the drift rules and severities are exactly those
of `check`: NEW losing a publisher of OLD is BREAKING, NEW adding one is SAFE. OLD's `options:`
block applies, overridden by the comparison options given here.

--against REF (the pull-request gate, docs/ci.md): each contract is compared with its file at
REF the same way (a renamed file with its old name; a removed one loses everything it promised;
an added one adds its nodes). It fails on BREAKING changes unless --fail-on says otherwise. A
contract with `interface_version: MAJOR.MINOR.PATCH` at REF and now is judged by semantic
versioning: a BREAKING change needs a MAJOR bump, a RISKY one at least a MINOR bump (the
message says which version to write); changes the bump covers are accepted. With system
contracts (--system, or those git tracks here) a changed topic, service or action is checked
against the nodes that use it: one that no longer fits them is BREAKING and named. The git
history must hold REF: in CI fetch the base branch (actions/checkout `fetch-depth: 0`).

  rmw-introspect diff --against origin/main --format markdown
  rmw-introspect diff --against origin/main...HEAD contracts/talker.interfaces.yaml

exit status: 0 no drift (or below --fail-on), 1 drift at or above --fail-on, 2 errors (a missing
or invalid contract, also one invalid at REF; REF not found; not a git repository; a shallow
clone without REF).
"""

_COMPAT_EPILOG = """\
All nodes of all contracts form one system. Every subscription, service client and action
client is matched with the publishers/servers of the same name: type, type hash and QoS
compatibility (incompatible QoS is BREAKING, possibly incompatible RISKY); a requester without
any provider is RISKY. A policy left at SYSTEM_DEFAULT on both ends is not reported unless
--strict-system-default. Rules: docs/drift-rules.md ("Compatibility rules").

--fail-on defaults to `breaking` here (a partial system lacking some publisher is common).
exit status: 0 compatible (or problems below --fail-on), 1 problems at or above --fail-on,
2 errors (missing or malformed contract).
"""


_INIT_EPILOG = """\
Each executable is captured with default options (no parameters, remappings or namespace);
edit a contract's `target:` block and run `rmw-introspect check --update` on it for another
configuration. Executables that cannot be captured (they need arguments, hardware, a peer)
are listed with the reason and get no contract. Existing contracts are kept unless --force.

exit status: 0 every executable captured, 2 at least one could not be (or no executables).
"""

_VALIDATE_EPILOG = """\
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


_LOCK_EPILOG = """\
Each contract needs a types: section (`rmw-introspect check --update --include-types CONTRACT`
writes it). The lockfile is JSON, sorted: commit it. `check` (and pytest) then compare every
interface type of a capture, nested types included, with it: a type that changed upstream is
TYPE_LOCK_CHANGED with the path to it (sensor_msgs/msg/Image -> std_msgs/msg/Header changed), a
type it does not list TYPE_NOT_LOCKED. check finds the file in a contract's directory or above,
up to the package root (package.xml, setup.py, pyproject.toml or .git).

exit status: 0 written (or unchanged), 2 a contract is missing, invalid or has no types: section.
"""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> Any:  # argparse's own errors: message + usage hint, status 2
        self.exit(EXIT_ERROR, f"{self.prog}: error: {message}\n(see `{self.prog} --help`)\n")


# ---------------------------------------------------------------------------- parser


def _add_target(parser: argparse.ArgumentParser) -> None:
    option_flags.add_group(parser, TARGET, FrontEnd.CLI, "target options", _TARGET_HELP)


def _add_compare(parser: argparse.ArgumentParser, front_end: FrontEnd = FrontEnd.CLI) -> None:
    option_flags.add_group(parser, COMPARISON, front_end, "comparison options (override the contract's options: block)")


REPORT_FORMATS = ("text", "json", "markdown", "github", "sarif")


def _add_format(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--format", choices=REPORT_FORMATS, default="text",
                        help="text: the report for people (default); json: machine-readable items; "
                        "markdown: a summary table and the grouped drift (a pull-request comment, "
                        "$GITHUB_STEP_SUMMARY); github: GitHub Actions annotations on the contract lines; "
                        "sarif: a SARIF 2.1.0 log (GitHub code scanning), a result per finding on its contract line")


def _add_baseline(parser: argparse.ArgumentParser) -> None:
    g = parser.add_argument_group("baselines (turn the gate on with known findings, tighten it later)")
    g.add_argument("--baseline", metavar="FILE",
                   help="fail only on findings that are not in FILE (written by --write-baseline); the known "
                   "ones are reported as accepted by the baseline")
    g.add_argument("--write-baseline", metavar="FILE",
                   help="record today's findings (those no `accept:` entry accepts) in FILE and exit 0 unless "
                   "a contract could not be checked")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="rmw-introspect", description=_DESCRIPTION,
                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser, title="commands")
    sub.required = True

    cap = sub.add_parser("capture", help="run a target and print its interfaces (a contract, JSON, NoDL or the raw capture)",
                         description="Run a target on the recording middleware and print its interfaces.",
                         epilog=_CAPTURE_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
                         usage="%(prog)s [options] (--package P --executable E | --script F | --module M "
                               "| --entry-point MOD:FUNC | -- COMMAND ...)")
    _add_target(cap)
    out = cap.add_argument_group("output")
    out.add_argument("--format", choices=("yaml", "json", "nodl"), default="yaml",
                     help="yaml: a complete contract (default); json: the nodes as JSON; nodl: NoDL v2 per node")
    out.add_argument("--raw", action="store_true", help="every endpoint as created: no infrastructure filter, no action grouping")
    out.add_argument("--include-ros-infra", dest="include_infrastructure", action="store_true",
                     help="keep infrastructure endpoints (actions stay grouped)")
    out.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of stdout")
    out.add_argument("--partial", action="store_true",
                     help="when the target fails or hangs, still write what was captured (exit status stays 2)")
    system_options.add_launch(cap)

    chk = sub.add_parser("check", help="run the target of each contract and compare it with the contract (drift report)",
                         description="Capture the target of each contract and compare it with the contract.",
                         epilog=_CHECK_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
                         usage="%(prog)s [options] CONTRACT... [-- COMMAND ...]")
    chk.add_argument("contracts", nargs="+", metavar="CONTRACT", help="contract files (YAML)")
    _add_target(chk)
    _add_compare(chk)
    _add_format(chk)
    chk.add_argument("--update", action="store_true",
                     help="rewrite drifted contracts and create missing ones (refused when CI is set)")
    _add_baseline(chk)
    chk.add_argument("--summary", metavar="FILE",
                     help="also append the Markdown report (a table of the contracts, the drift by severity) to FILE, "
                     "whatever --format prints: --format github --summary \"$GITHUB_STEP_SUMMARY\" gives the "
                     "annotations and the job summary from one run")
    chk.add_argument("--shard", metavar="I/N",
                     help="check only this CI job's share of the contracts: job I of N (e.g. 2/4); the contracts are "
                     "sorted by path and dealt round-robin, so the N jobs together check each exactly once")
    system_options.add_launch(chk)
    chk.add_argument("-v", "--verbose", action="store_true",
                     help="a passing system contract names every node it matched (else it says how many nodes in "
                     "how many processes)")

    dif = sub.add_parser("diff", help="compare two contract files, or every contract with a git revision (no "
                         "target is run)",
                         description="Compare two contract files, or every contract with its version at a git "
                         "revision (--against REF: the pull-request gate), without running anything.",
                         epilog=_DIFF_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
                         usage="%(prog)s [options] OLD NEW\n       %(prog)s --against REF [options] [CONTRACT...]")
    dif.add_argument("files", nargs="*", metavar="FILE",
                     help="OLD NEW: the contract as it was and as it is now; with --against: the contracts to compare "
                     "(default: every *.interfaces.yaml and *.system.yaml git tracks under the current directory)")
    gate = dif.add_argument_group("the pull-request gate (docs/ci.md)")
    gate.add_argument("--against", metavar="REF",
                      help="compare every contract with its version at the git revision REF: a branch, tag or commit, "
                      "or BASE...HEAD (their merge base, as git diff reads it); renamed, added and removed contract "
                      "files included; interface_version bumps judged by semantic versioning; fails on BREAKING "
                      "unless --fail-on says otherwise")
    gate.add_argument("--system", action="append", dest="against_systems", metavar="FILE",
                      help="a system contract whose nodes judge who consumes a changed interface (repeatable; "
                      "default: every *.system.yaml git tracks under the current directory)")
    gate.add_argument("--baseline", metavar="FILE",
                      help="fail only on findings that FILE (written by `check --write-baseline`) does not hold")
    gate.add_argument("--summary", metavar="FILE",
                      help="also append the Markdown report to FILE (\"$GITHUB_STEP_SUMMARY\"), whatever --format prints")
    _add_compare(dif, FrontEnd.DIFF)
    _add_format(dif)

    ini = sub.add_parser("init", help="write a contract for every executable of a package",
                         description="Capture every executable an installed package provides and write one "
                         "contract per executable into DIR/contracts/.", epilog=_INIT_EPILOG,
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    ini.add_argument("--package", required=True, metavar="P", help="the installed package (ament index, or a "
                     "Python distribution with console scripts)")
    ini.add_argument("--output-dir", default=".", metavar="DIR",
                     help="the package's source directory: contracts go to DIR/contracts (default: .)")
    ini.add_argument("--force", action="store_true", help="overwrite existing contracts")
    option_flags.add(ini, (TARGET[name] for name in ("settle", "timeout", "horizon")))

    val = sub.add_parser("validate", help="check that contract files are valid (no target is run)",
                         description="Load and validate contract files (YAML, schema, QoS values, duplicates) "
                         "without running anything: fast enough for a pre-commit hook. *.system.yaml files (and "
                         "files saying system_version:) are read as system contracts.",
                         epilog=_VALIDATE_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    val.add_argument("contracts", nargs="+", metavar="CONTRACT", help="contract files (YAML), node or system contracts")
    val.add_argument("--format", choices=("text", "github", "sarif"), default="text",
                     help="text: one line per file (default); github: an annotation per invalid file; "
                     "sarif: a SARIF 2.1.0 log with a result per invalid file")

    lck = sub.add_parser("lock", help="write the type-hash lockfile of a package's contracts (no target is run)",
                         description="Write the RIHS01 hash of every interface type the contracts use, nested types "
                         "included (from their types: sections), into a lockfile that check compares with.",
                         epilog=_LOCK_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    lck.add_argument("contracts", nargs="+", metavar="CONTRACT", help="node contract files with a types: section")
    lck.add_argument("-o", "--output", metavar="FILE",
                     help="the lockfile (default: interfaces.lock.json at the package root above the contracts)")

    com = sub.add_parser("compat", help="check that the nodes of several contracts fit together",
                         description="Compatibility check: do the nodes of these contracts fit together?",
                         epilog=_COMPAT_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    com.add_argument("contracts", nargs="+", metavar="CONTRACT", help="contract files (YAML)")
    com.add_argument("--fail-on", choices=FAIL_ON, default="breaking",
                     help="least severe problem that fails (exit 1); default breaking")
    com.add_argument("--strict-system-default", action="store_true",
                     help="also report policies left at SYSTEM_DEFAULT on both ends (what rmw would warn about)")
    _add_format(com)
    _add_baseline(com)
    system_options.add_graph(sub, _Parser)
    return parser


# ---------------------------------------------------------------------------- helpers


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
