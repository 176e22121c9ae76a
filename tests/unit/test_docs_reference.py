"""The documentation site's generated reference pages (scripts/docs/reference.py) name everything
their source defines (every command and option of the CLI parser, every pytest option and ini
key of the plugin, every key of the contract schema) and follow the source when it changes; the
site hook (scripts/docs/site_hooks.py) turns repository-relative links into links of the site and
reports links to files that are not in it; and the troubleshooting page covers every error class
a user can meet."""

from __future__ import annotations

import argparse
import importlib.util
import inspect
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import pytest

from pytest_rmw_introspect import errors
from pytest_rmw_introspect.cli.parser import build_parser

ROOT = Path(__file__).resolve().parents[2]
DOCS_SCRIPTS = ROOT / "scripts" / "docs"


def _load(name: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(name, DOCS_SCRIPTS / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


reference = _load("reference")


def _subparsers(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    return next(dict(a.choices) for a in parser._actions if isinstance(a, argparse._SubParsersAction))


def test_the_cli_reference_names_every_command_and_option():
    parser = build_parser()
    page = reference.cli_reference(parser)
    for name, sub in _subparsers(parser).items():
        assert f"## `rmw-introspect {name}` {{#{name}}}" in page
        for action in sub._actions:
            if action.help == argparse.SUPPRESS:  # an old spelling still read, not taught
                continue
            for option in action.option_strings:
                assert f"`{option}`" in page, f"rmw-introspect {name} {option} is missing from the CLI reference"
        if sub.epilog:
            assert sub.epilog.strip().splitlines()[0] in page


def test_the_cli_reference_follows_the_parser():
    """A command or option added to the parser shows up without anyone writing it down."""
    parser = argparse.ArgumentParser(prog="rmw-introspect", description="the tool")
    sub = parser.add_subparsers(dest="command")
    frob = sub.add_parser("frobnicate", help="h", description="Frobnicate contracts.", epilog="see also: nothing")
    frob.add_argument("--wibble", choices=("a", "b"), default="a", help="how | much to wibble")
    frob.add_argument("--count", metavar="N", type=int, default=3, help="how often")
    page = reference.cli_reference(parser)
    assert "## `rmw-introspect frobnicate` {#frobnicate}" in page
    assert "| `--wibble` | `a` \\| `b` | how \\| much to wibble (default: `a`) |" in page  # pipes escaped in a cell
    assert "| `--count` | `N` | how often (default: `3`) |" in page
    assert "see also: nothing" in page and "[`frobnicate`](#frobnicate)" in page


def test_the_pytest_reference_names_every_option_and_ini_key_of_the_plugin():
    parser = reference.pytest_parser()
    page = reference.pytest_reference(parser)
    options = reference.pytest_options(parser)
    ini = reference.pytest_ini_keys(parser)
    assert len(options) >= 15 and len(ini) >= 15  # the plugin's own pytest_addoption was called
    for _group, names, _attrs in options:
        for name in names:
            assert f"`{name}`" in page, f"{name} is missing from the pytest reference"
    for key in ini:
        assert f"| `{key}` |" in page, f"ini key {key} is missing from the pytest reference"
    assert "`--update-golden`" in page and "`rmw_introspect_contracts`" in page


def _schema_keys(spec: object, found: set[str]) -> set[str]:
    if isinstance(spec, dict):
        for key, value in spec.get("properties", {}).items():
            found.add(key)
            _schema_keys(value, found)
        for branch in ("else", "then", "items", "additionalProperties"):
            _schema_keys(spec.get(branch), found)
    return found


def test_the_contract_reference_names_every_key_of_the_schema():
    schema = reference.load_schema()
    page = reference.contract_reference(schema)
    keys = _schema_keys(schema, set())
    for definition in schema["definitions"].values():
        _schema_keys(definition, keys)
    assert {"contract_version", "target", "nodes", "qos", "publishers", "timeout", "accept"} <= keys | set(schema["definitions"])
    for key in keys:
        assert f"| `{key}` |" in page, f"contract key {key} is missing from the contract reference"
    for name in schema["definitions"]:
        assert f"## `{name}` {{#{name.replace('_', '-')}}}" in page


def test_the_contract_reference_follows_the_schema():
    schema = {"description": "top", "type": "object", "required": ["a"], "additionalProperties": False,
              "properties": {"a": {"type": "integer", "minimum": 1, "description": "the a"},
                             "b": {"$ref": "#/definitions/thing_two"}},
              "definitions": {"thing_two": {"type": "array", "items": {"enum": ["x", "y"]}, "maxItems": 2}}}
    page = reference.contract_reference(schema)
    assert "| `a` | integer | yes | ≥ 1 | the a |" in page
    assert "| `b` | [thing_two](#thing-two) |  |  |  |" in page
    assert "## `thing_two` {#thing-two}" in page
    assert "Value: list of one of `x`, `y`." in page and "items ≤ 2" in page
    assert "No other key is allowed." in page


def test_the_troubleshooting_page_covers_every_error_class():
    page = (ROOT / "docs" / "troubleshooting.md").read_text(encoding="utf-8")
    classes = {name for name, value in inspect.getmembers(errors, inspect.isclass)
               if issubclass(value, errors.RmwIntrospectError) and value.__module__ == errors.__name__
               and not name.startswith("_")}
    classes -= {"RmwIntrospectError", "TargetError"}  # the bases: every error is one of their subclasses
    assert {"SetupError", "ContractError", "TargetTimeout", "GoldenWriteError"} <= classes
    missing = sorted(name for name in classes if f"`{name}`" not in page)
    assert not missing, f"docs/troubleshooting.md does not say what to do about {missing}"


# ----------------------------------------------------------------------------- the site hook


@pytest.fixture(scope="module")
def hooks() -> ModuleType:
    pytest.importorskip("mkdocs", reason="MkDocs is a tool of the development venv (requirements/tools.in)")
    return _load("site_hooks")


@pytest.mark.parametrize(("page", "target", "expected"), [
    ("index.md", "docs/ci.md", "ci.md"),                                       # README.md -> docs/
    ("index.md", "docs/getting-started/ament-python.md#2-write", "getting-started/ament-python.md#2-write"),
    ("index.md", "CONTRIBUTING.md", "contributing.md"),
    ("ci.md", "drift-rules.md#qos-rules", "drift-rules.md#qos-rules"),            # docs/ -> docs/
    ("getting-started/ament-cmake.md", "../ci.md", "../ci.md"),
    ("getting-started/ament-cmake.md", "../../examples/rmw_introspect_examples/README.md", "../example-package.md"),
    ("target-options.md", "../rmw_introspect_cpp/README.md#stimuli-opt-in", "middleware.md#stimuli-opt-in"),
    ("middleware.md", "../docs/conformance.md", "conformance.md"),              # rmw_introspect_cpp/README.md -> docs/
    ("example-package.md", "../../README.md", "index.md"),
    ("ci.md", "https://github.com/rhysd/actionlint", "https://github.com/rhysd/actionlint"),
    ("ci.md", "#baselines", "#baselines"),
])
def test_links_are_rewritten_for_the_site(hooks, page, target, expected):
    assert hooks.site_target(page, target) == expected


@pytest.mark.parametrize(("page", "target"), [
    ("index.md", "LICENSE"), ("index.md", "docs/"), ("ci.md", "../action.yml"), ("middleware.md", "src/rmw_node.cpp"),
])
def test_links_to_repository_files_outside_the_site_are_refused(hooks, page, target):
    assert hooks.site_target(page, target) is None


def test_a_link_outside_the_site_is_reported_with_its_file_and_line(hooks, caplog):
    class Page:
        class file:
            src_uri = "index.md"

    text = "intro\n\n[the action](action.yml) and [ci](docs/ci.md)\n```\n[in code](action.yml)\n```\n"
    with caplog.at_level("WARNING"):
        out = hooks.on_page_markdown(text, Page, None, None)
    assert "[ci](ci.md)" in out and "[the action](action.yml)" in out and "[in code](action.yml)" in out
    warnings = [record.getMessage() for record in caplog.records]
    assert len(warnings) == 1 and warnings[0].startswith("README.md:3 links to action.yml"), warnings


@pytest.mark.parametrize("family", ["comparison", "target"])
def test_the_option_table_pages_are_rendered_from_the_tables(family):
    from pytest_rmw_introspect.model import option_tables

    page = reference.PAGES[f"reference/{family}-options.md"]()
    rows = {"comparison": option_tables.COMPARISON, "target": option_tables.TARGET}[family]
    assert "generated by scripts/docs/reference.py" in page.splitlines()[0]
    assert rows.options
    for row in rows.options:
        assert f"`{row.name}`" in page


#: what a ROS 2 install provides: none of it may be needed to generate the reference pages
ROS_MODULES = ("rclpy", "rcl_interfaces", "ament_index_python", "rosidl_runtime_py", "rosidl_parser", "launch",
               "launch_ros", "std_msgs", "ros_wheels_bootstrapper")


def test_the_reference_pages_are_generated_without_ros():
    """`make docs` builds the site in .venv-docs, which has no ROS 2 (requirements/docs.txt): every
    generated page comes from the package with each ROS 2 module refused on import."""
    script = (f"import sys\nfor name in {ROS_MODULES!r}:\n    sys.modules[name] = None\n"
              f"sys.path.insert(0, {str(DOCS_SCRIPTS)!r})\nimport reference\n"
              "pages = {uri: make() for uri, make in reference.PAGES.items()}\n"
              "assert all(len(text) > 200 for text in pages.values()), pages\n"
              "print(sorted(pages))\n")
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert run.returncode == 0, run.stderr[-3000:]
    assert "reference/cli.md" in run.stdout and "reference/pytest.md" in run.stdout, run.stdout
