"""The CI dimensions' selection (tests/support/dimensions.py, tests/dimensions.toml; issue 48 item
4): when a tier runs selected and when in full, and the checks that keep the selection honest as
the code moves."""

from __future__ import annotations

import argparse
import ast
import os
import time
from pathlib import Path

import dimensions
import pytest

ROOT = dimensions.ROOT
PACKAGE = ROOT / "pytest_rmw_introspect"
DEFINED = dimensions.load()
RUN = {"m": "", "k": "", "ignore": [], "deselect": []}


def _dimension(**overrides) -> dimensions.Dimension:
    fields = {"name": "python", "title": "Python 3.12", "select": ("tests/unit",),
              "full_when": ("pkg/run/*", "requirements/lock.txt"), "sensitive_imports": ()}
    return dimensions.Dimension(**{**fields, **overrides})


@pytest.fixture
def tree(tmp_path: Path) -> Path:
    for path, text in {"pkg/run/process.py": "import signal\n", "pkg/run/warm/server.py": "x = 1\n",
                       "pkg/model/contract.py": "y = 2\n", "requirements/lock.txt": "pyyaml==6.0.1\n"}.items():
        (tmp_path / path).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / path).write_text(text)
    return tmp_path


def test_full_when_patterns_cross_directories_and_name_files(tree: Path):
    assert dimensions.matching_files(tree, ("pkg/run/*",)) == ["pkg/run/process.py", "pkg/run/warm/server.py"]
    assert dimensions.matching_files(tree, ("requirements/lock.txt", "pkg/model")) == [
        "pkg/model/contract.py", "requirements/lock.txt"]
    assert dimensions.matching_files(tree, ("pkg/*.md", "absent/file")) == []


def test_a_tier_runs_in_full_until_a_full_run_passed_for_the_same_content(tree: Path, tmp_path_factory):
    records = tmp_path_factory.mktemp("records")
    dimension = _dimension()
    first = dimensions.decide(tree, dimension, RUN, records)
    assert first.full and "no full run recorded" in first.why
    dimensions.record(records, dimension, first)
    again = dimensions.decide(tree, dimension, RUN, records)
    assert not again.full and again.why.startswith("selected")
    # a file outside full_when changes: still selected
    (tree / "pkg/model/contract.py").write_text("y = 3\n")
    assert not dimensions.decide(tree, dimension, RUN, records).full
    # a file it depends on changes: in full, and the file is named
    (tree / "pkg/run/warm/server.py").write_text("x = 2\n")
    changed = dimensions.decide(tree, dimension, RUN, records)
    assert changed.full and "pkg/run/warm/server.py" in changed.why and "process.py" not in changed.why
    # a new file under a full_when directory counts too
    (tree / "pkg/run/warm/server.py").write_text("x = 1\n")
    (tree / "pkg/run/new.py").write_text("")
    assert "pkg/run/new.py" in dimensions.decide(tree, dimension, RUN, records).why


def test_other_run_options_or_a_forced_run_are_not_the_recorded_full_run(tree: Path, tmp_path_factory):
    records = tmp_path_factory.mktemp("records")
    dimension = _dimension()
    dimensions.record(records, dimension, dimensions.decide(tree, dimension, RUN, records))
    other = dimensions.decide(tree, dimension, {**RUN, "m": "not e2e"}, records)
    assert other.full and "options or the Python differ" in other.why
    forced = dimensions.decide(tree, dimension, RUN, records, force=True)
    assert forced.full and dimensions.FORCE_FULL in forced.why
    # another dimension's record is not this one's
    assert dimensions.decide(tree, _dimension(name="distro"), RUN, records).full


def test_records_are_pruned_to_the_newest(tree: Path, tmp_path_factory):
    records = tmp_path_factory.mktemp("records")
    dimension = _dimension()
    for n in range(4):
        (tree / "pkg/run/process.py").write_text(f"n = {n}\n")
        dimensions.record(records, dimension, dimensions.decide(tree, dimension, RUN, records), keep=2)
        time.sleep(0.01)
        os.utime(max(records.glob("*.json"), key=lambda p: p.stat().st_mtime))
    assert len(list(records.glob("python-*.json"))) == 2
    assert not dimensions.decide(tree, dimension, RUN, records).full  # n = 3, the newest


def test_selection_by_directory_file_and_node_id():
    select = ("tests/unit", "tests/cli/test_cli_capture.py", "tests/plugin/test_plugin_xdist.py::test_one")
    assert dimensions.selected("tests/unit/test_qos.py::test_x[a]", select)
    assert dimensions.selected("tests/cli/test_cli_capture.py::test_y", select)
    assert dimensions.selected("tests/plugin/test_plugin_xdist.py::test_one[p]", select)
    assert not dimensions.selected("tests/plugin/test_plugin_xdist.py::test_one_more", select)
    assert not dimensions.selected("tests/unitary/test_z.py::t", select)
    assert not dimensions.selected("tests/cli/test_cli_check.py::test_y", select)


# ---------------------------------------------------------------------------- honesty of the file
def test_the_dimensions_of_ci_are_defined_and_ci_runs_them():
    assert set(DEFINED) == {"python", "deps", "distro", "jazzy-py312"}
    ci = (ROOT / ".ci" / "run").read_text()
    for name in DEFINED:
        assert f"--dimension {name}" in ci, f".ci/run runs no tier with --dimension {name}"


@pytest.mark.parametrize("name", sorted(DEFINED))
def test_a_dimension_without_a_full_run_of_its_own_says_where_it_happens(name: str):
    dimension = DEFINED[name]
    assert bool(dimension.full_when) != bool(dimension.full_run), \
        f"tests/dimensions.toml [{name}]: give either full_when or full_run (where its full run happens)"


def test_a_dimension_without_full_when_always_runs_its_selection(tree: Path, tmp_path_factory):
    records = tmp_path_factory.mktemp("records")
    dimension = _dimension(full_when=(), full_run="in the kilted tier")
    for force in (False, True):
        decision = dimensions.decide(tree, dimension, RUN, records, force=force)
        assert not decision.full and "no full run of its own (in the kilted tier)" in decision.why


@pytest.mark.parametrize("name", sorted(DEFINED))
def test_every_selected_entry_names_tests_that_exist(name: str):
    for entry in DEFINED[name].select:
        path = entry.split("::", 1)[0]
        assert (ROOT / path).exists(), f"tests/dimensions.toml [{name}] selects {entry}: no such test"
        if "::" in entry:
            assert f"def {entry.split('::')[-1].split('[')[0]}" in (ROOT / path).read_text(), entry


@pytest.mark.parametrize("name", sorted(DEFINED))
def test_every_full_when_pattern_names_files(name: str):
    for pattern in DEFINED[name].full_when:
        assert dimensions.matching_files(ROOT, (pattern,)), \
            f"tests/dimensions.toml [{name}] full_when {pattern!r} names no file"


def _imports(path: Path) -> set[str]:
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names.update(alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module.split(".")[0])
    return names


@pytest.mark.parametrize("name", [n for n in sorted(DEFINED) if DEFINED[n].sensitive_imports])
def test_every_module_using_what_a_dimension_is_about_makes_it_run_in_full(name: str):
    """A new module that imports a library the dimension varies (yaml under the lowest versions,
    ctypes or signal under another Python, ...) must be under the dimension's ``full_when``: else
    a change to it would be tested along that dimension only by the selection."""
    dimension = DEFINED[name]
    covered = set(dimensions.matching_files(ROOT, dimension.full_when))
    missing = [path.relative_to(ROOT).as_posix() for path in sorted(PACKAGE.rglob("*.py"))
               if _imports(path) & set(dimension.sensitive_imports)
               and path.relative_to(ROOT).as_posix() not in covered]
    assert not missing, f"tests/dimensions.toml [{name}]: add to full_when (they import " \
                        f"{', '.join(dimension.sensitive_imports)}): {missing}"


def test_a_green_exit_that_ran_nothing_or_a_part_is_no_full_run():
    """A collection alone once recorded a full Kilted run, and the next CI ran the selection."""
    options = argparse.Namespace(collectonly=False, setuponly=False, setupplan=False, lf=False, stepwise=False,
                                 stepwise_skip=False)
    assert dimensions.not_a_full_run(options, ran=818) is None
    assert dimensions.not_a_full_run(options, ran=0) == "no test ran"
    for dest, flag in dimensions.PARTIAL_RUN_OPTIONS.items():
        why = dimensions.not_a_full_run(argparse.Namespace(**{**vars(options), dest: True}), ran=818)
        assert why and flag in why, dest
    assert "paths on the command line" in dimensions.not_a_full_run(options, ran=818, paths_given=True)


# ---------------------------------------------------------------------------- one tier, two dimensions
_TESTS = {"tests/middleware/test_python_nodes.py": "def test_node():\n    pass\n",  # jazzy-py312's
          "tests/cli/test_cli_capture.py": "def test_capture():\n    pass\n",  # python's
          "tests/cmake/test_ctest.py": "def test_ctest():\n    pass\n"}  # nobody's


@pytest.fixture
def suite(pytester: pytest.Pytester, tmp_path_factory, monkeypatch) -> pytest.Pytester:
    for path, text in _TESTS.items():
        (pytester.path / path).parent.mkdir(parents=True, exist_ok=True)
        (pytester.path / path).write_text(text)
    monkeypatch.setenv("RMW_INTROSPECT_CACHE", str(tmp_path_factory.mktemp("cache")))
    monkeypatch.delenv(dimensions.FORCE_FULL, raising=False)
    return pytester


#: in-process runs of files named like the suite's own: importlib mode keeps them apart in sys.modules
_IN_PROCESS = ("-p", "dimensions", "-p", "no:cacheprovider", "--import-mode=importlib")


def _run(suite: pytest.Pytester, *names: str) -> pytest.RunResult:
    return suite.runpytest_inprocess(*_IN_PROCESS, *(f"--dimension={name}" for name in names))


def test_a_tier_of_two_dimensions_runs_in_full_for_either_and_records_each(suite: pytest.Pytester):
    """The kilted tier is Kilted and Python 3.12 at once: in full while either must be, then the
    union of their selections; a dimension with no full run of its own records nothing."""
    alone = _run(suite, "jazzy-py312")
    alone.assert_outcomes(passed=1, deselected=2)
    alone.stdout.fnmatch_lines(["dimension jazzy-py312 (*): selected: it has no full run of its own (*)"])
    assert "recorded" not in alone.stdout.str()

    first = _run(suite, "jazzy-py312", "python")
    first.assert_outcomes(passed=3)
    first.stdout.fnmatch_lines(["dimension jazzy-py312 (*): selected: *; the tier runs in full for python",
                                "dimension python (*): in full: no full run recorded*"])
    # the record's line is a line of its own, after the tests' progress
    first.stdout.re_match_lines([r"^dimension python: a green full run recorded \(.*python-\w+\.json\)$"])
    assert "dimension jazzy-py312: a green full run" not in first.stdout.str()

    again = _run(suite, "jazzy-py312", "python")
    again.assert_outcomes(passed=2, deselected=1)
    again.stdout.fnmatch_lines(["dimension python (*): selected: a full run passed on this machine*"])


def test_a_tier_run_with_paths_of_its_own_records_no_full_run_and_says_why(suite: pytest.Pytester):
    result = suite.runpytest_inprocess(*_IN_PROCESS, "--dimension=python", "tests/cmake")
    result.assert_outcomes(passed=1)
    result.stdout.fnmatch_lines(["dimension python: no full run recorded: paths on the command line run a part*"])
