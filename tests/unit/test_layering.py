"""The package's layers, read from its imports (docs/design.md, "Layers").

Each module may import only from its own layer and the layers below it; no module imports
another's private names; imports are at module level except the few that measurably cut
start-up time; and the module-level imports, type-only ones (``if TYPE_CHECKING:``) included,
form no cycle.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

import pytest_rmw_introspect
from pytest_rmw_introspect.cli import parser as cli_parser

PACKAGE = Path(pytest_rmw_introspect.__file__).parent
NAME = "pytest_rmw_introspect"

#: layer → the layers (besides itself) it may import
ALLOWED: dict[str, set[str]] = {
    "errors": set(),
    "_version": set(),
    "model": {"errors"},
    "compare": {"errors", "model"},
    "launch": {"errors", "model"},
    "run": {"errors", "model", "launch"},
    "check": {"errors", "model", "compare", "launch", "run"},
    "live": {"errors", "model", "compare", "launch", "run", "check"},
    "plugin": {"errors", "_version", "model", "compare", "launch", "run", "check", "live"},
    "cli": {"errors", "_version", "model", "compare", "launch", "run", "check", "live"},
    "__main__": {"cli"},
    "__init__": {"errors", "_version", "model", "compare", "launch", "run", "check", "plugin"},
    "options_reference": {"model"},
}

#: the one module of ``run`` that reads launch files: it runs the processes a launch file starts
#: (docs/design.md, "Layers"); the rest of ``run`` starts one target and knows no launch file
LAUNCH_JOINER = "run.system_capture"

#: function-local imports that are there on purpose, each cutting start-up time:
#: (module, imported module) → why
LOCAL_IMPORTS = {
    ("plugin.session", "pytest_rmw_introspect.check"): "the baseline's judge with the pipeline (~40 ms): only a "
                                                       "session with ini rmw_introspect_baseline, at its first check",
    ("plugin.session", "pytest_rmw_introspect.compare"): "the baseline reader (with the drift rules): as above",
    ("model.contract", "jsonschema"): "jsonschema costs ~80 ms; only validating a contract needs it",
    ("model.system_contract", "jsonschema"): "jsonschema costs ~80 ms; only validating a system contract needs it",
    ("compare.drift", "deepdiff"): "deepdiff costs 0.1-0.2 s; only comparing needs it",
    ("compare.rule_levels", "pytest_rmw_introspect.compare"): "the tables of every rule (with the drift rules' "
                                                              "deepdiff, 0.1-0.2 s) only when a project sets `rules`",
    ("cli", "pytest_rmw_introspect.cli.system_contracts"): "`--help`, usage errors and `capture` of one target "
                                                           "answer without the system pipeline",
    ("cli", "pytest_rmw_introspect.run.warm"): "`capture` (one target, started cold), `--help` and usage errors answer "
                                          "without the warm start client (~15 ms)",
    ("run.runner", "pytest_rmw_introspect.run.warm"): "the warm start client (~15 ms) only when a target may start warm: "
                                                 "`rmw-introspect capture` starts its one target cold without it",
    ("run.target", "pytest_rmw_introspect.run.executables"): "the spec's modules form no cycle: the executables "
                                                             "lookup (which reads the spec) only to list a "
                                                             "package's executables in an error message",
    ("run.prewarm", "pytest_rmw_introspect.run.warm"): "the warm start client (~15 ms) only when a session starts a "
                                                  "warm start server ahead of its captures",
    ("run.runner", "pytest_rmw_introspect.model.capture"): "the capture model (~30 ms of dataclass creation) is "
                                                           "imported while the first target starts, not before it",
    ("run.runner", "pytest_rmw_introspect.model.capture_diagnoses"): "the errors' diagnoses read the capture model: "
                                                                     "imported with it, once a target has ended",
    ("run.warm.plan", "socket"): "socket (+ selectors) only to plan a warm start: `rmw-introspect capture` plans "
                                 "its one target cold without it",
    ("run.ros_env", "importlib"): "importlib.metadata (+ email) costs ~10 ms; only a venv without the "
                                   "ros-<distro>-rclpy dist-info needs the scan of installed distributions",
    ("run.executables", "importlib"): "importlib.metadata (+ email) costs ~15 ms; only console scripts and packages "
                                 "without an ament index need the scan of installed distributions",
    ("model.untrusted", "yaml"): "PyYAML costs ~20 ms; `rmw-introspect capture` reads JSON captures only",
    ("model.yaml_blocks", "yaml"): "PyYAML costs ~20 ms; only writing a contract needs it",
    ("model.types", "yaml"): "PyYAML costs ~20 ms; only writing a `types:` section needs it",
    ("model.nodl", "yaml"): "PyYAML costs ~20 ms; `capture --format nodl` starts without it",
    ("model.nodl", "jsonschema"): "jsonschema costs ~80 ms; only validating a NoDL document needs it",
    ("model.nodl", "pytest_rmw_introspect.model.locate"): "the YAML locator (with PyYAML, ~20 ms): only a NoDL "
                                                          "document with a problem is located",
    ("model.nodl", "referencing"): "jsonschema's reference registry: only validating a NoDL document needs it",
    ("model.nodl", "referencing.jsonschema"): "as referencing: only validating a NoDL document needs it",
    ("run.target", "yaml"): "PyYAML costs ~20 ms; only a string parameter value on the command line needs it",
    ("cli.arguments", "yaml"): "PyYAML costs ~20 ms; only --param values need it",
    ("cli.formats", "yaml"): "PyYAML costs ~20 ms; `capture` starts without it, it prints with it",
    ("cli.formats", "pytest_rmw_introspect.check"): "the contract writer (~25 ms with PyYAML): `capture` "
                                                    "starts without it, it prints with it",
    ("run.locks", "filelock"): "filelock (+ logging) costs ~15 ms; only building the middleware or writing a golden "
                               "file needs it",
    ("plugin", "pytest_rmw_introspect.plugin"): "the hooks that run tests (~50 ms of imports): a pytest-xdist "
                                                "controller runs no test and starts its workers sooner",
    ("plugin.session", "pytest_rmw_introspect.check.pipeline"): "the pipeline (~80 ms): an xdist controller "
                                                                "reads the options but runs no test",
    ("run.warm.client", "pytest_rmw_introspect.run.warm.server"): "the server's own module (ctypes, runpy, selectors, "
                                                          "~5 ms); only runners sharing servers (xdist workers) "
                                                          "check a peer's uid with it",
    ("plugin.items", "pytest_rmw_introspect.check"): "the pipeline (~35 ms with the capture model): every pytest "
                                                     "process loads the plugin's hooks, most have no contract test",
    ("plugin.marker", "pytest_rmw_introspect.check"): "the pipeline (~35 ms with the capture model): only "
                                                      "`interfaces` tests need it",
    ("plugin.gate_items", "pytest_rmw_introspect.check"): "the gate and the comparison pipeline (~40 ms): only "
                                                          "a session with --against",
    ("plugin.gate_items", "pytest_rmw_introspect.compare"): "the baseline reader (with the drift rules): as above",
    ("plugin.live_fixtures", "pytest_rmw_introspect.live"): "the live check, the bring-up and the launch readers: "
                                                            "only tests that bring a system up",
    ("plugin.system_marker", "pytest_rmw_introspect.check"): "the system pipeline and launch readers (~15 ms): "
                                                             "only system contracts need them",
}


#: the command modules of the command line (``cli.parser.COMMANDS``): building the parser imports
#: every one of them (each declares its subparser beside its ``cmd_*``), so what a command runs is
#: imported inside its functions, and only when it runs: `--help`, a usage error and `capture`
#: answer without the pipelines (``test_building_the_parser_loads_no_pipeline``)
COMMAND_MODULES = frozenset(module.__name__.removeprefix(NAME + ".") for module in cli_parser.COMMANDS)


def _modules() -> dict[str, ast.Module]:
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        if "rmw_introspect_cpp" in path.parts:
            continue
        rel = path.relative_to(PACKAGE).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__" and len(parts) > 1:
            parts = parts[:-1]
        out[".".join(parts)] = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    return out


MODULES = _modules()


def _is_package(module: str) -> bool:
    return module == "__init__" or (PACKAGE / module.replace(".", "/") / "__init__.py").is_file()


def _resolve(module: str, node: ast.ImportFrom) -> str:
    """The absolute name a relative ``from`` import refers to."""
    if node.level == 0:
        return node.module or ""
    here = [] if module == "__init__" else module.split(".")
    base = here if _is_package(module) else here[:-1]
    if node.level > 1:
        base = base[: len(base) - (node.level - 1)]
    return ".".join([NAME, *base, *([node.module] if node.module else [])])


def _imports(module: str, tree: ast.Module) -> list[tuple[ast.AST, str, list[str], bool]]:
    """(node, imported module, names, at module level) for every import of ``module``."""
    top_level = set(map(id, tree.body))
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                found.append((node, alias.name, [], id(node) in top_level))
        elif isinstance(node, ast.ImportFrom):
            found.append((node, _resolve(module, node), [a.name for a in node.names], id(node) in top_level))
    return found


def _layer(absolute: str) -> str | None:
    if absolute == NAME:
        return "__init__"
    if absolute.startswith(NAME + "."):
        return absolute.split(".")[1]
    return None


def _under_type_checking(tree: ast.Module, target: ast.AST) -> bool:
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING":
            if any(target is child for stmt in node.body for child in ast.walk(stmt)):
                return True
    return False


def test_every_module_belongs_to_a_layer():
    assert {m.split(".")[0] for m in MODULES} <= set(ALLOWED), sorted(MODULES)


@pytest.mark.parametrize("module", sorted(MODULES))
def test_imports_follow_the_layers(module):
    own = module.split(".")[0]
    wrong = []
    for node, imported, names, _top in _imports(module, MODULES[module]):
        targets = [imported]
        if imported == NAME:  # `from .. import x` names submodules or package attributes
            targets = [f"{NAME}.{n}" for n in names]
        for target in targets:
            layer = _layer(target)
            if layer is not None and layer != own and layer not in ALLOWED[own]:
                wrong.append(f"line {node.lineno}: {target}")
    assert not wrong, f"{module} ({own}) may import only {sorted(ALLOWED[own] | {own})}: " + "; ".join(wrong)


@pytest.mark.parametrize("module", sorted(MODULES))
def test_no_private_names_of_other_modules(module):
    tree = MODULES[module]
    module_aliases = set()
    wrong = []
    for node, imported, names, _top in _imports(module, tree):
        if _layer(imported) is None and not imported.startswith(NAME):
            continue
        for name in names:
            if name.startswith("_") and not name.startswith("__"):
                wrong.append(f"line {node.lineno}: from {imported} import {name}")
            module_aliases.update(a.asname or a.name for a in node.names)  # type: ignore[attr-defined]
    for node in ast.walk(tree):
        if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                and node.value.id in module_aliases and node.attr.startswith("_") and not node.attr.startswith("__")):
            wrong.append(f"line {node.lineno}: {node.value.id}.{node.attr}")
    assert not wrong, f"{module} uses private names of other modules: " + "; ".join(wrong)


@pytest.mark.parametrize("module", sorted(MODULES))
def test_imports_are_at_module_level_unless_they_cut_start_up_time(module):
    tree = MODULES[module]
    local = [
        (node.lineno, imported)
        for node, imported, _names, top in _imports(module, tree)
        if not top and not _under_type_checking(tree, node) and (module, imported) not in LOCAL_IMPORTS
        and module not in COMMAND_MODULES
    ]
    assert not local, f"{module}: function-local imports {local}; import at module level, or list the " \
                      "import in LOCAL_IMPORTS with the start-up time it saves"


def test_only_the_launch_joiner_of_run_reads_launch_files():
    readers = sorted(module for module, tree in MODULES.items() if module.startswith("run.")
                     for _node, imported, _names, _top in _imports(module, tree) if _layer(imported) == "launch")
    assert set(readers) == {LAUNCH_JOINER}, readers


def test_the_listed_local_imports_exist():
    for (module, imported), _why in LOCAL_IMPORTS.items():
        assert any(i == imported and not top for _n, i, _names, top in _imports(module, MODULES[module])), (module, imported)


def test_module_level_imports_form_no_cycle():
    """Type-only imports (``if TYPE_CHECKING:``) count: a cycle of types is a cycle of concepts
    to untangle the same, even when it costs nothing at run time."""
    graph: dict[str, set[str]] = {m: set() for m in MODULES}
    for module, tree in MODULES.items():
        for _node, imported, names, top in _imports(module, tree):
            if not top and not _under_type_checking(tree, _node):
                continue
            candidates = [imported] + [f"{imported}.{n}" for n in names]
            for candidate in candidates:
                if candidate == NAME:
                    target = "__init__"
                elif candidate.startswith(NAME + "."):
                    target = candidate[len(NAME) + 1:]
                else:
                    continue
                if target in graph and target != module:
                    graph[module].add(target)
    # a package's modules import the package itself implicitly: ignore edges to an ancestor package
    for module in graph:
        graph[module] = {t for t in graph[module] if not module.startswith(t + ".") and t != "__init__"}
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(m: str) -> None:
        state[m] = 1
        stack.append(m)
        for t in sorted(graph[m]):
            if state.get(t) == 1:
                raise AssertionError("import cycle: " + " -> ".join(stack[stack.index(t):] + [t]))
            if t not in state:
                visit(t)
        stack.pop()
        state[m] = 2

    for m in sorted(graph):
        if m not in state:
            visit(m)


def test_the_public_api_exports_every_type_its_functions_return():
    import typing

    api = pytest_rmw_introspect
    exported = set(api.__all__)
    for name in ("capture", "diff_contracts", "load_contract", "check_compatible"):
        hints = typing.get_type_hints(getattr(api, name))
        returned = hints["return"]
        assert returned.__name__ in exported and getattr(api, returned.__name__) is returned, (name, returned)
    for name in exported:
        assert hasattr(api, name), name
    assert set(api._LAZY) | {"__version__"} == exported  # the table of lazy names is the export list
    assert (PACKAGE / "py.typed").is_file()


#: what `rmw-introspect capture` (without a launch file) must start without: the comparison and
#: system pipelines and their libraries, PyYAML (imported once a capture is printed), the capture
#: model (imported while the target starts), the warm start client (its one target starts cold),
#: and the slow parts of the standard library the CLI used to load (docs/performance.md)
NOT_FOR_CAPTURE = ("yaml", "deepdiff", "jsonschema", "numpy", "ctypes.util", "importlib.metadata",
                   "pytest_rmw_introspect.model.capture", "pytest_rmw_introspect.model.capture_file",
                   "pytest_rmw_introspect.model.capture_view", "pytest_rmw_introspect.model.capture_notes",
                   "pytest_rmw_introspect.run.warm.client", "socket",
                   "pytest_rmw_introspect.check.pipeline", "pytest_rmw_introspect.check.golden",
                   "pytest_rmw_introspect.compare.drift", "pytest_rmw_introspect.cli.system_contracts",
                   "pytest_rmw_introspect.launch.reader")


def _modules_loaded_by(code: str) -> set[str]:
    """The modules a fresh interpreter has loaded after running ``code``."""
    probe = f"import sys\n{code}\nprint('\\n'.join(sorted(sys.modules)))\n"
    result = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    return set(result.stdout.split())


def _is_module(absolute: str) -> bool:
    path = PACKAGE.joinpath(*absolute.split(".")[1:])
    return path.with_suffix(".py").is_file() or (path / "__init__.py").is_file()


def _imported_when_run(module: str, function: str) -> list[str]:
    """The modules ``function`` of ``module`` imports in its own body (not in a branch of it)."""
    tree = MODULES[module]
    body = next(n for n in ast.walk(tree) if isinstance(n, ast.FunctionDef) and n.name == function).body
    found = []
    for statement in body:
        if isinstance(statement, ast.ImportFrom):
            base = _resolve(module, statement)
            found += [f"{base}.{a.name}" if _is_module(f"{base}.{a.name}") else base for a in statement.names]
        elif isinstance(statement, ast.Import):
            found += [a.name for a in statement.names]
    return found


def test_the_capture_command_starts_without_the_pipeline_and_yaml():
    """What ``rmw-introspect capture`` of one target loads: the parser and what ``cmd_capture``
    imports when it runs (its launch-file branch left out)."""
    when_run = _imported_when_run("cli.capture", "cmd_capture")
    assert "pytest_rmw_introspect.run.runner" in when_run
    loaded = _modules_loaded_by("from pytest_rmw_introspect.cli import parser\n"
                                + "".join(f"import {m}\n" for m in when_run)
                                + "parser.build_parser().parse_args(['capture', '--script', 'node.py'])")
    assert "pytest_rmw_introspect.run.runner" in loaded  # the probe did import the command
    assert sorted(loaded & set(NOT_FOR_CAPTURE)) == []


#: what building the parser must load, of this package: the parser's own modules, the command
#: modules (``cli.parser.COMMANDS``) and the option tables their flags come from; everything a
#: command runs is imported when it runs
FOR_THE_PARSER = {"pytest_rmw_introspect", "pytest_rmw_introspect._version", "pytest_rmw_introspect.errors",
                  "pytest_rmw_introspect.cli", "pytest_rmw_introspect.cli.parser",
                  "pytest_rmw_introspect.cli.arguments", "pytest_rmw_introspect.cli.option_flags",
                  "pytest_rmw_introspect.cli.exit_status", "pytest_rmw_introspect.cli.launch_options",
                  "pytest_rmw_introspect.cli.live_options", "pytest_rmw_introspect.live",
                  "pytest_rmw_introspect.model", "pytest_rmw_introspect.model.option_tables",
                  "pytest_rmw_introspect.model.vocabulary", "pytest_rmw_introspect.model.qos",
                  "pytest_rmw_introspect.model.contract_shapes",
                  "pytest_rmw_introspect.model.middlewares",  # the `--rmw` choices: a table, errors alone
                  "pytest_rmw_introspect.model.tally",  # the test suite's accounting: os alone (issue 48)
                  *(f"{NAME}.{module}" for module in COMMAND_MODULES)}

#: the slow parts of the standard library no command needs to parse its arguments (each 5-15 ms)
NOT_FOR_THE_PARSER = ("logging", "concurrent.futures", "xml.etree.ElementTree")


def test_building_the_parser_loads_no_pipeline():
    """Every run of ``rmw-introspect`` (``--help``, a usage error, ``validate`` as a pre-commit
    hook) builds the whole parser, so the command modules it imports hold only their declarations."""
    loaded = _modules_loaded_by("from pytest_rmw_introspect.cli import parser\n"
                                "commands = parser.build_parser()._subparsers._group_actions[0].choices\n"
                                "assert len(commands) == len(parser.COMMANDS)\n"
                                "helps = [command.format_help() for command in commands.values()]")
    assert "pytest_rmw_introspect.cli.graph" in loaded  # the probe did import the command modules
    assert sorted({m for m in loaded if m.startswith(NAME)} - FOR_THE_PARSER) == []
    assert sorted(loaded & {*NOT_FOR_CAPTURE, *NOT_FOR_THE_PARSER}) == []


#: what the pytest entry point (all a pytest-xdist controller imports of the plugin) must load
#: without: the pipelines that run tests (docs/performance.md)
NOT_FOR_THE_CONTROLLER = ("yaml", "deepdiff", "jsonschema", "numpy", "pytest_rmw_introspect.check.pipeline",
                          "pytest_rmw_introspect.check.system_pipeline", "pytest_rmw_introspect.check.golden",
                          "pytest_rmw_introspect.run.runner", "pytest_rmw_introspect.model.capture",
                          "pytest_rmw_introspect.model.capture_file", "pytest_rmw_introspect.model.capture_view",
                          "pytest_rmw_introspect.plugin.hooks")


#: what the hooks that run tests (every pytest process but an xdist controller) must load without:
#: a session with no contract test never needs the pipelines (docs/performance.md)
NOT_FOR_THE_HOOKS = ("deepdiff", "jsonschema", "numpy", "pytest_rmw_introspect.check.pipeline",
                     "pytest_rmw_introspect.check.system_pipeline", "pytest_rmw_introspect.check.golden",
                     "pytest_rmw_introspect.model.capture", "pytest_rmw_introspect.model.capture_file",
                     "pytest_rmw_introspect.model.capture_view", "pytest_rmw_introspect.run.system_capture",
                     "pytest_rmw_introspect.compare.drift")


def test_the_hooks_load_no_pipeline():
    loaded = _modules_loaded_by("import pytest\nimport pytest_rmw_introspect.plugin.hooks")
    assert "pytest_rmw_introspect.plugin.items" in loaded  # the probe did import the hooks
    assert sorted(loaded & set(NOT_FOR_THE_HOOKS)) == []


def test_the_pytest_entry_point_loads_no_pipeline():
    loaded = _modules_loaded_by("import pytest_rmw_introspect.plugin\nimport pytest_rmw_introspect.plugin.session")
    assert "pytest_rmw_introspect.check.golden_record" in loaded  # the probe did import the session
    assert sorted(loaded & set(NOT_FOR_THE_CONTROLLER)) == []
