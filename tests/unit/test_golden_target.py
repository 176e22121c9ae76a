"""The ``target:`` block ``--update-golden`` writes into a marker test's golden (issue 47 item 2):
which block (``plugin.marker.golden_target``), how it goes into the file (``golden.with_target``),
that a golden lacking it is updated for it (``CheckResult.gains``), and the marker test a golden
without one names (``golden_tests``)."""

from __future__ import annotations

from pathlib import Path

from pytest_rmw_introspect.check import golden, golden_tests
from pytest_rmw_introspect.check.pipeline import CheckResult
from pytest_rmw_introspect.model import contract as contract_module
from pytest_rmw_introspect.plugin.marker import golden_target

HEADER = "# my comment\ncontract_version: 1\nros_distribution: jazzy\n# the nodes\nnodes:\n  /talker: {}\n"


def test_a_golden_without_target_gets_the_block_above_nodes_and_its_comments():
    text = golden.with_target(HEADER, {"package": "my_pkg", "executable": "talker"})
    assert text == ("# my comment\ncontract_version: 1\nros_distribution: jazzy\n"
                    "target:\n  package: my_pkg\n  executable: talker\n# the nodes\nnodes:\n  /talker: {}\n")
    assert golden.with_target(text, {"package": "my_pkg", "executable": "talker"}) == text  # no byte changes
    assert golden.with_target(HEADER, None) == HEADER


def test_a_target_spelled_otherwise_stays_and_another_is_replaced_keeping_the_rest():
    text = "contract_version: 1\ntarget: {executable: talker, package: my_pkg}  # mine\noptions:\n  fail_on: breaking\nnodes: {}\n"
    assert golden.with_target(text, {"package": "my_pkg", "executable": "talker"}) == text
    assert golden.with_target(text, {"script": "talker.py"}) == (
        "contract_version: 1\ntarget:\n  script: talker.py\noptions:\n  fail_on: breaking\nnodes: {}\n")


def test_the_block_is_the_markers_target_over_the_files_with_paths_relative_to_the_golden(tmp_path):
    golden_path, test_dir = tmp_path / "test" / "contracts" / "talker.yaml", tmp_path / "test"
    assert golden_target(None, golden_path, {"script": "nodes/talker.py", "parameters": {"rate": 5.0}}, test_dir,
                         "marker") == {"script": "../nodes/talker.py", "parameters": {"rate": 5.0}}
    # nothing to run, or no target keywords: nothing written
    assert golden_target(None, golden_path, {"namespace": "/robot"}, test_dir, "marker") is None
    assert golden_target(None, golden_path, {}, test_dir, "marker") is None

    own = contract_module.loads("contract_version: 1\ntarget:\n  script: ../nodes/talker.py\n  timeout: 20\nnodes: {}\n",
                                path=golden_path)
    # the marker decides what runs; the file's other keys stay; a file that says it already keeps its words
    assert golden_target(own, golden_path, {"package": "my_pkg", "executable": "talker"}, test_dir, "marker") == {
        "package": "my_pkg", "executable": "talker", "timeout": 20.0}
    assert golden_target(own, golden_path, {"script": "nodes/talker.py"}, test_dir, "marker") == own.target


def test_a_matching_golden_without_the_markers_target_is_updated_for_it(tmp_path):
    path = tmp_path / "talker.yaml"
    contract = contract_module.loads("contract_version: 1\nnodes: {}\n", path=path)
    result = CheckResult(path=path, shown="talker.yaml", contract=contract)
    assert result.gains == []  # (no capture: nothing to write)
    result.golden_target = {"package": "my_pkg", "executable": "talker"}
    assert result.gains == []
    contract_with = contract_module.loads("contract_version: 1\ntarget: {package: my_pkg, executable: talker}\n"
                                          "nodes: {}\n", path=path)
    assert CheckResult(path=path, shown="talker.yaml", contract=contract_with,
                       golden_target={"package": "my_pkg", "executable": "talker"}).gains == []


def test_the_marker_test_naming_a_golden_is_found_in_the_package(tmp_path):
    (tmp_path / "package.xml").write_text("<package/>")
    (tmp_path / "test" / "contracts").mkdir(parents=True)
    (tmp_path / "test" / "test_nodes.py").write_text(
        "import pytest\n\n"
        "@pytest.mark.interfaces('contracts/talker.yaml', package='p', executable='talker')\n"
        "def test_talker(interfaces):\n    pass\n\n"
        "class TestMore:\n    @pytest.mark.interfaces(contract='contracts/other.yaml')\n"
        "    def test_other(self, interfaces):\n        pass\n")
    (tmp_path / "build").mkdir()
    (tmp_path / "build" / "test_copy.py").write_text("# contracts/talker.yaml\n")
    golden_path = tmp_path / "test" / "contracts" / "talker.yaml"
    assert golden_tests.marker_tests(golden_path, cwd=tmp_path) == ["test/test_nodes.py::test_talker"]
    assert golden_tests.marker_tests(tmp_path / "test" / "contracts" / "other.yaml", cwd=tmp_path) == [
        "test/test_nodes.py::TestMore::test_other"]
    assert golden_tests.how_to_check(tmp_path / "test" / "contracts" / "none.yaml", "none.yaml") is None
    said = golden_tests.how_to_check(golden_path, "test/contracts/talker.yaml", cwd=tmp_path)
    assert said is not None and "\n  pytest --update-golden test/test_nodes.py::test_talker\n" in said
    assert Path(golden_tests.search_root(golden_path)) == tmp_path
