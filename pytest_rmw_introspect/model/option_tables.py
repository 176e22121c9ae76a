"""The option families, one declarative table each: every comparison option and every target
option with its type, default, help, and the front ends that expose it.

Everything that spells an option is generated from these tables: the pytest command-line
options and ini keys (``plugin.option_flags``), the ``rmw-introspect`` argparse groups
(``cli.option_flags``), the ``options:`` and ``target:`` entries of the contract schema
(:func:`schema_definition`, written into ``schema/contract.schema.json``), the keyword
arguments the markers accept, and the reference pages (``options_reference.render_markdown``).
What a value *means* is decided where it is used (``compare.options`` parses comparison
options, ``run.target`` target options); a test checks that both parse exactly their table.

Precedence is the same for both families and is data too (:data:`PRECEDENCE`, weakest first);
:func:`stack` orders layers by it and is the only place that does (``check.pipeline.Layers``
calls it).
"""

from __future__ import annotations

import enum
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, TypeVar

from .middlewares import KNOWN as MIDDLEWARES
from .qos import FIELDS as QOS_FIELDS
from .vocabulary import DEFAULT_LIFECYCLE_TARGET, FAIL_ON, LIFECYCLE_TARGETS, RULE_LEVELS

#: the largest settle, timeout or horizon accepted (a day); beyond it a value is a mistake
MAX_SECONDS = 86_400.0


class FrontEnd(enum.Enum):
    """Where users can set an option."""

    PYTEST = "pytest option"  # --rmw-introspect-<name>
    INI = "ini key"  # rmw_introspect_<name>
    CLI = "rmw-introspect flag"  # capture / check (target), check (comparison)
    DIFF = "rmw-introspect diff flag"  # comparison options `diff` takes (it captures nothing)
    CONTRACT = "contract key"  # the `options:` or `target:` block of a node contract
    SYSTEM = "system contract key"  # a system contract's `options:` / `target:`, @pytest.mark.system_contract
    MARKER = "marker argument"  # keyword arguments of @pytest.mark.interfaces
    GATE = "rmw-introspect diff --against flag"  # the pull-request gate's own flags
    ACTION = "GitHub action input"  # an input of action.yml


class Source(enum.Enum):
    """Where a value of an option came from, for :data:`PRECEDENCE`."""

    DEFAULT = "default"
    INI = "ini file"
    PYTEST = "pytest command line"
    CONTRACT = "contract"
    #: what a test or a command states for itself: the marker's keyword arguments, the arguments
    #: of ``rmw_capture()``, the flags of ``rmw-introspect`` (never two of them in one check)
    OWN = "marker, rmw_capture() or rmw-introspect flags"


#: weakest first: a later source overrides an earlier one, key by key. (A target layer that names
#: what to run replaces the whole choice of the weaker ones: ``run.target.KIND_KEYS``.)
PRECEDENCE: tuple[Source, ...] = (Source.DEFAULT, Source.INI, Source.PYTEST, Source.CONTRACT, Source.OWN)

L = TypeVar("L")


def stack(layers: Mapping[Source, Sequence[L]]) -> list[L]:
    """The layers of every source, weakest first as :data:`PRECEDENCE` orders them (within one
    source, in the order given)."""
    unknown = set(layers) - set(PRECEDENCE)
    assert not unknown, unknown
    return [layer for source in PRECEDENCE for layer in layers.get(source, ())]


class Shape(enum.Enum):
    """How a value is written on a command line (the contract writes it as YAML)."""

    SWITCH = "true or false"
    CHOICE = "one of"
    SECONDS = "seconds"
    WORDS = "words"  # `all`, or words separated by commas (a list in YAML)
    TEXT = "text"
    REPEATED = "repeated"  # one flag per item (a list or mapping in YAML)


@dataclass(frozen=True)
class Option:
    """One row of a table."""

    name: str
    shape: Shape
    #: the value when no layer sets it (None: as the text in ``default_text`` says)
    default: Any
    help: str
    front_ends: frozenset[FrontEnd]
    #: the JSON Schema of the value in a contract
    schema: Mapping[str, Any]
    #: how the reference page writes the type
    type_text: str
    default_text: str = ""
    choices: tuple[str, ...] = ()
    metavar: str | None = None
    #: the rmw-introspect flag when it is not ``--<name with dashes>``; ``dest`` stays ``name``
    cli_flag: str | None = None
    #: the pytest option when it is not ``--rmw-introspect-<name with dashes>`` (the gate's:
    #: ``pytest --against REF``, as ``rmw-introspect diff --against REF``)
    pytest_name: str | None = None

    @property
    def pytest_flag(self) -> str:
        return self.pytest_name or "--rmw-introspect-" + self.name.replace("_", "-")

    @property
    def pytest_dest(self) -> str:
        """Where pytest keeps the option's value (``config.getoption``)."""
        return "rmw_introspect_" + self.name

    @property
    def action_input(self) -> str:
        """The input of the GitHub action (``action.yml``): the name with dashes."""
        return self.name.replace("_", "-")

    @property
    def ini_key(self) -> str:
        return "rmw_introspect_" + self.name

    @property
    def flag(self) -> str:
        """The ``rmw-introspect`` flag."""
        return self.cli_flag or "--" + self.name.replace("_", "-")

    def flag_help(self) -> str:
        """The help of the option's command-line flag (pytest's and ``rmw-introspect``'s)."""
        extra = {Shape.WORDS: ["comma-separated, or 'all'"], Shape.REPEATED: ["repeatable"]}.get(self.shape, [])
        if self.shown_default:
            extra.append(f"default: {self.shown_default}")
        return self.help + (f" ({'; '.join(extra)})" if extra else "")

    @property
    def shown_default(self) -> str:
        """The default as people read it; empty when it is "not set" (none, nothing, false)."""
        if self.default_text:
            return self.default_text
        if self.default is True:
            return "true"
        if isinstance(self.default, float):
            return f"{self.default:g}"
        return self.default if isinstance(self.default, str) else ""


@dataclass(frozen=True)
class Family:
    """A table: the options a contract block holds, with the words the front ends use."""

    name: str
    title: str
    #: the contract block (``options`` or ``target``)
    block: str
    description: str
    options: tuple[Option, ...]
    notes: tuple[str, ...] = field(default=())

    def names(self, front_end: FrontEnd | None = None) -> tuple[str, ...]:
        """The option names (those ``front_end`` exposes), in table order."""
        return tuple(o.name for o in self.exposed(front_end))

    def exposed(self, front_end: FrontEnd | None = None) -> tuple[Option, ...]:
        return tuple(o for o in self.options if front_end is None or front_end in o.front_ends)

    def __getitem__(self, name: str) -> Option:
        for option in self.options:
            if option.name == name:
                return option
        raise KeyError(name)


def schema_definition(family: Family, front_end: FrontEnd = FrontEnd.CONTRACT) -> dict[str, Any]:
    """The JSON Schema of the family's contract block (``definitions.options`` / ``.target``)."""
    properties = {}
    for option in family.exposed(front_end):
        properties[option.name] = {"description": option.help[0].upper() + option.help[1:] + ".",
                                   **option.schema}
        if isinstance(option.default, (bool, str, float)):  # (an annotation editors show)
            properties[option.name]["default"] = option.default
    return {"description": family.description, "type": "object", "additionalProperties": False,
            "properties": properties}


# ---------------------------------------------------------------------------- value schemas

_BOOLEAN = {"type": "boolean"}
_TEXT = {"type": "string", "minLength": 1}
_PATH = _TEXT


def _seconds(minimum: str = "minimum") -> dict[str, Any]:
    return {"type": "number", minimum: 0, "maximum": int(MAX_SECONDS)}


def _true_or_unique(items: Mapping[str, Any]) -> dict[str, Any]:
    """``true``/``false``, or a list of distinct ``items``."""
    return {"type": ["boolean", "array"], "if": {"type": "array"},
            "then": {"type": "array", "uniqueItems": True, "items": dict(items)}}


def _front_ends(*extra: FrontEnd) -> frozenset[FrontEnd]:
    return frozenset({FrontEnd.CONTRACT, FrontEnd.MARKER, *extra})


_COMPARISON_EVERYWHERE = _front_ends(FrontEnd.PYTEST, FrontEnd.INI, FrontEnd.CLI, FrontEnd.DIFF, FrontEnd.SYSTEM)
#: options about what a capture holds: `diff` compares two files and captures nothing
_COMPARISON_OF_CAPTURES = _COMPARISON_EVERYWHERE - {FrontEnd.DIFF}
#: options of a system check alone: its contract, its marker (``system_contract``) and ``check``
_SYSTEM_ONLY = frozenset({FrontEnd.SYSTEM, FrontEnd.CLI})

COMPARISON = Family(
    name="comparison",
    title="Comparison options",
    block="options",
    description="How this contract is compared.",
    options=(
        Option("ignore_type_hash", Shape.SWITCH, False, "do not compare type hashes", _COMPARISON_EVERYWHERE,
               _BOOLEAN, "true or false"),
        Option("ignore_qos", Shape.WORDS, frozenset(), "QoS fields not to compare: a list of field names "
               "(depth, history) or true for all", _COMPARISON_EVERYWHERE,
               _true_or_unique({"enum": list(QOS_FIELDS)}), "true, or a list of QoS fields", metavar="FIELDS"),
        # the middleware QoS is judged for (issue 49 item 3): a command line's and a session's, for the
        # contracts that do not say; a system contract says it with its own top-level `rmw:` key
        Option("rmw", Shape.CHOICE, None, "the middleware (rmw implementation) whose QoS rules judge the contracts "
               "that do not say which one they run on (a system contract's `rmw:`, or RMW_IMPLEMENTATION in its "
               "launch environment)", frozenset({FrontEnd.PYTEST, FrontEnd.INI, FrontEnd.CLI, FrontEnd.DIFF}),
               {"enum": list(MIDDLEWARES)}, " | ".join(MIDDLEWARES), default_text="not set: the DDS rules of "
               "rmw_dds_common", choices=tuple(MIDDLEWARES), metavar="NAME"),
        Option("allow_extra", Shape.SWITCH, False, "interfaces and nodes the contract does not list are not drift",
               _COMPARISON_EVERYWHERE, _BOOLEAN, "true or false"),
        Option("include_infrastructure", Shape.SWITCH, False, "also capture and compare /rosout, /parameter_events, "
               "parameter and lifecycle services", _COMPARISON_OF_CAPTURES, _BOOLEAN, "true or false",
               cli_flag="--include-ros-infra"),
        Option("fail_on", Shape.CHOICE, "any", "least severe drift that fails the check", _COMPARISON_EVERYWHERE,
               {"enum": list(FAIL_ON)}, " | ".join(FAIL_ON), choices=FAIL_ON),
        Option("include_types", Shape.SWITCH, False, "keep a `types:` section in the contract (written by an update) "
               "so that a changed type hash is reported field by field", _COMPARISON_OF_CAPTURES, _BOOLEAN,
               "true or false"),
        Option("ignore_parameters", Shape.WORDS, frozenset(), "parameters not to compare: true (none is compared), "
               "or a list of names or fnmatch patterns (`qos_overrides.*`, `*.frame_id`)", _COMPARISON_EVERYWHERE,
               _true_or_unique(_TEXT), "true, or a list of name patterns", metavar="PATTERNS"),
        Option("ignore_parameter_values", Shape.WORDS, frozenset(), "parameters whose default values are not "
               "compared: true (no value is compared), or a list of names or patterns", _COMPARISON_EVERYWHERE,
               _true_or_unique(_TEXT), "true, or a list of name patterns", metavar="PATTERNS"),
        # ---- issue 49: rule levels per project (compare.rule_levels) ----
        Option("rules", Shape.REPEATED, (), "the project's level of a rule: a mapping of rule ids, or fnmatch "
               "patterns of them (`QOS_*`), to off, note, safe, risky or breaking (on a command line RULE=LEVEL); "
               "an exact id wins over a pattern, a longer pattern over a shorter one", _COMPARISON_EVERYWHERE,
               {"type": "object", "propertyNames": {"pattern": "^[A-Z0-9_*?\\[\\]!]+$"},
                "additionalProperties": {"enum": list(RULE_LEVELS)}}, "mapping of rule ids or patterns to levels",
               default_text="every rule at its default level (docs/drift-rules.md)", metavar="RULE=LEVEL",
               cli_flag="--rule"),
        # ---- end of issue 49's rows ----
        Option("system_fail_on", Shape.CHOICE, "breaking", "least severe system problem that fails a system "
               "contract's check (as `compat --fail-on`)", _SYSTEM_ONLY, {"enum": list(FAIL_ON)}, " | ".join(FAIL_ON),
               choices=FAIL_ON),
    ),
    notes=(
        "On a command line a list is one word: names separated by commas (`depth,history`), or `all`.",
        "Parameters that are ignored are left as the contract has them when an update rewrites it.",
    ),
)

_PER_TARGET = _front_ends(FrontEnd.CLI)
#: options of every process a target starts (a system contract's `target:` block takes them)
_PROCESS = _front_ends(FrontEnd.CLI, FrontEnd.SYSTEM)
#: options a whole pytest session can set
_SESSION = _front_ends(FrontEnd.CLI, FrontEnd.PYTEST, FrontEnd.INI)
_SESSION_PROCESS = _SESSION | {FrontEnd.SYSTEM}

TARGET = Family(
    name="target",
    title="Target options",
    block="target",
    description="What to run (the same keys as the capture API and the interfaces marker).",
    options=(
        Option("package", Shape.TEXT, None, "ament package of the executable (with executable), found like "
               "`ros2 run`", _PER_TARGET, _TEXT, "text", metavar="P"),
        Option("executable", Shape.TEXT, None, "executable inside `<prefix>/lib/<package>/` (or a console script of "
               "the Python distribution named package)", _PER_TARGET, _TEXT, "text", metavar="E"),
        Option("command", Shape.REPEATED, None, "any command: a list of strings, or one string split like a "
               "shell (on the command line: everything after `--`)", _front_ends(),
               {"type": ["string", "array"], "if": {"type": "string"}, "then": {"minLength": 1},
                "else": {"minItems": 1, "items": {"type": ["string", "number"]}}}, "list of strings"),
        Option("script", Shape.TEXT, None, "a Python file, run with this interpreter", _PER_TARGET, _PATH, "path",
               metavar="FILE"),
        Option("module", Shape.TEXT, None, "a Python module, run as `python -m M`", _PER_TARGET, _TEXT, "text",
               metavar="M"),
        Option("entry_point", Shape.TEXT, None, "a Python function (`my_pkg.camera:main`), called like its console "
               "script", _PER_TARGET,
               {"type": "string", "pattern": "^[A-Za-z_][A-Za-z0-9_]*([.][A-Za-z_][A-Za-z0-9_]*)*"
                ":[A-Za-z_][A-Za-z0-9_]*([.][A-Za-z_][A-Za-z0-9_]*)*$"}, "module:function", metavar="MOD:FUNC"),
        Option("arguments", Shape.REPEATED, None, "extra command-line arguments, before `--ros-args`", _PER_TARGET,
               {"type": "array", "items": {"type": ["string", "number"]}}, "list of strings", metavar="ARG",
               cli_flag="--arg"),
        Option("namespace", Shape.TEXT, None, "node namespace (`-r __ns:=NS`)", _PER_TARGET, {"type": "string"},
               "text", metavar="NS"),
        Option("node_name", Shape.TEXT, None, "node name (`-r __node:=NAME`)", _PER_TARGET, _TEXT, "text",
               metavar="NAME"),
        Option("remappings", Shape.REPEATED, None, "name remappings: a mapping from → to, or a list of FROM:=TO",
               _PER_TARGET, {"type": ["object", "array"], "if": {"type": "object"},
                              "then": {"additionalProperties": {"type": "string"}},
                              "else": {"items": {"type": "string", "pattern": ":="}}},
               "mapping", metavar="FROM:=TO", cli_flag="--remap"),
        Option("parameters", Shape.REPEATED, None, "parameters given to the node (`-p NAME:=VALUE`; nested mappings "
               "are flattened with dots); each VALUE is YAML: 5, 2.0, true, [1, 2], 'text'", _PER_TARGET,
               {"type": "object"}, "mapping", metavar="NAME:=VALUE", cli_flag="--param"),
        Option("params_file", Shape.TEXT, None, "ROS parameters YAML file (`--params-file`)", _PER_TARGET, _PATH,
               "path", metavar="FILE"),
        Option("env", Shape.REPEATED, None, "extra environment variables of the target", _PROCESS,
               {"$ref": "#/definitions/string_map"}, "mapping", metavar="K=V"),
        Option("cwd", Shape.TEXT, None, "working directory of the target", _PER_TARGET, _PATH, "path",
               default_text="the directory of the file that named the target", metavar="DIR"),
        Option("settle", Shape.SECONDS, 0.1, "quiet time (while the node waits) after which the capture is final",
               _SESSION_PROCESS, _seconds(), "seconds"),
        Option("timeout", Shape.SECONDS, 20.0, "time the target gets to settle before it is stopped", _SESSION_PROCESS,
               _seconds("exclusiveMinimum"), "seconds"),
        Option("horizon", Shape.SECONDS, 10.0, "seconds of the node's virtual life the capture observes, timers "
               "firing at once; 0 turns virtual time off", _SESSION_PROCESS, _seconds(), "seconds"),
        Option("cold_start", Shape.SWITCH, False, "start the target as a new process, never forked from the warm "
               "start server", _SESSION, _BOOLEAN, "true or false",
               default_text="false: Python targets start warm"),
        Option("lifecycle", Shape.CHOICE, DEFAULT_LIFECYCLE_TARGET, "how far lifecycle (managed) nodes are driven "
               "before the capture: active (configure, activate), inactive (configure), unconfigured, none (leave "
               "them alone, not even their state is read)", _SESSION_PROCESS, {"enum": list(LIFECYCLE_TARGETS)},
               " | ".join(LIFECYCLE_TARGETS), choices=LIFECYCLE_TARGETS),
        Option("read_parameters", Shape.SWITCH, True, "read every node's parameters through its own parameter "
               "services", _SESSION_PROCESS, _BOOLEAN, "true or false"),
        Option("stimuli", Shape.REPEATED, None, "fully resolved topic or service names: after the node settled, "
               "each subscription of such a name gets one default-constructed message and each service one default "
               "request, then the node settles again", _PER_TARGET,
               {"type": ["array", "string"], "items": {"type": "string", "pattern": "^(/[A-Za-z_][A-Za-z0-9_]*)+$"}},
               "list of names", default_text="none: a default message is input the node acts on", metavar="NAME",
               cli_flag="--stimulus"),
    ),
    notes=(
        "Exactly one of package with executable, command, script, module or entry_point names what to run; "
        "a layer that names one replaces the choice of the weaker layers entirely.",
        "Relative paths (script, params_file, cwd, a command whose first word contains a /) are relative to "
        "the file that named them: the contract, the test file, or the current directory for rmw-introspect flags.",
        "cold_start set in the ini file or on the pytest command line only ever switches cold starts on.",
    ),
)

FAMILIES: dict[str, Family] = {family.name: family for family in (COMPARISON, TARGET)}


def family(name: str) -> Family:
    """The family called ``name`` (``comparison`` or ``target``)."""
    try:
        return FAMILIES[name]
    except KeyError:
        raise KeyError(f"no option family {name!r}; known: {', '.join(FAMILIES)}") from None


# ---------------------------------------------------------------------------- the gate
_GATE_EVERYWHERE = frozenset({FrontEnd.GATE, FrontEnd.PYTEST, FrontEnd.ACTION})

GATE = Family(
    name="gate",
    title="The pull-request gate",
    block="",
    description="The flags of the gate against a git revision (docs/ci.md): `rmw-introspect diff --against`, "
                "`pytest --against` and the GitHub action's inputs, one name each.",
    options=(
        Option("against", Shape.TEXT, None, "compare every contract with its version at the git revision REF (a "
               "branch, tag or commit, or BASE...HEAD: their merge base), without running anything; renamed, added "
               "and removed contract files included, interface_version bumps judged by semantic versioning",
               _GATE_EVERYWHERE, _TEXT, "git revision", metavar="REF", pytest_name="--against"),
        Option("against_system", Shape.REPEATED, None, "a system contract whose nodes judge who consumes a changed "
               "interface (default: every system contract git tracks here)", _GATE_EVERYWHERE,
               {"type": "array", "items": _PATH}, "paths", metavar="FILE", pytest_name="--against-system"),
    ),
)
