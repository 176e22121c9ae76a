"""model.contract_kind: a file is a contract, and of which kind, by its content (issue 47)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from pytest_rmw_introspect.model import contract_kind
from pytest_rmw_introspect.model.contract_kind import Kind

NODE_WITH_TARGET = "# a comment\ncontract_version: 1\ntarget:\n  package: p\n  executable: e\nnodes: {}\n"
GOLDEN = "contract_version: 1\nnodes:\n  /talker: {}\n"
SYSTEM = "# robot\nsystem_version: 1\nprocesses: []\nnodes: {}\n"
NODL = "nodl_version: 2\nnodes: []\n"
PARAMETERS = "/talker:\n  ros__parameters:\n    rate: 10.0\n"


@pytest.mark.parametrize(("text", "name", "kind"), [
    (NODE_WITH_TARGET, "contracts/talker.yaml", Kind.NODE),
    (GOLDEN, "test/contracts/talker.yaml", Kind.GOLDEN),      # the README's quick start names it so
    (SYSTEM, "robot.yaml", Kind.SYSTEM),
    (NODL, "talker.yml", Kind.NODL),
    (PARAMETERS, "config/params.yaml", None),
    ("", "empty.yaml", None),
    # a contract suffix makes a broken file a contract, so that its loader reports it
    ("{not: yaml", "x.interfaces.yaml", Kind.GOLDEN),
    ("", "x.system.yaml", Kind.SYSTEM),
    ("", "x.nodl.json", Kind.NODL),
    # a key that only looks like it, nested or indented, is not one
    ("params:\n  contract_version: 1\n", "a.yaml", None),
    ("description: |\n  system_version: 1\n", "a.yaml", None),
])
def test_kind_of_text(text: str, name: str, kind: Kind | None) -> None:
    assert contract_kind.kind_of_text(text, name) is kind


def test_kind_of_file_reads_the_content(tmp_path: Path) -> None:
    (tmp_path / "golden.yaml").write_text(GOLDEN)
    (tmp_path / "params.yaml").write_text(PARAMETERS)
    assert contract_kind.kind_of_file(tmp_path / "golden.yaml") is Kind.GOLDEN
    assert contract_kind.kind_of_file(tmp_path / "params.yaml") is None
    assert contract_kind.is_system_file(tmp_path / "params.yaml") is False


def test_a_file_that_cannot_be_read_is_judged_by_its_name(tmp_path: Path) -> None:
    fifo = tmp_path / "robot.system.yaml"
    os.mkfifo(fifo)  # reading it would block: never opened
    assert contract_kind.kind_of_file(fifo) is Kind.SYSTEM
    assert contract_kind.kind_of_file(tmp_path / "missing.yaml") is None
    (tmp_path / "latin1.yaml").write_bytes(b"contract_version: 1\n# \xe9\n")
    assert contract_kind.kind_of_file(tmp_path / "latin1.yaml") is None


@pytest.mark.parametrize(("name", "candidate"), [
    ("a.yaml", True), ("a.YML", True), ("a.nodl.json", True), ("a.json", False), ("a.py", False)])
def test_candidates(name: str, candidate: bool) -> None:
    assert contract_kind.is_candidate(name) is candidate


SYSTEM_WITH_NODES = """system_version: 1
interface_version: 1.2.0
launch: {package: demo, file: robot.launch.xml}
target: {timeout: 30}
options: {ignore_qos: true}
processes:
  - {package: demo_nodes_py, executable: talker, name: talker, nodes: [/talker]}
nodes:
  /talker:
    publishers:
      - {name: /chatter, type: std_msgs/msg/String}
"""


def test_either_kind_loads_as_the_node_contract_a_comparison_reads(tmp_path: Path) -> None:
    """One loader for both kinds (issue 51 item 2): a system contract gives its nodes, options and
    version the way a node contract does, and says which kind it was."""
    system_path = tmp_path / "robot.yaml"
    system_path.write_text(SYSTEM_WITH_NODES)
    loaded, kind = contract_kind.load(system_path)
    assert kind is Kind.SYSTEM and list(loaded.nodes) == ["/talker"]
    assert loaded.options == {"ignore_qos": True} and loaded.interface_version == "1.2.0"
    assert loaded.target == {"timeout": 30}
    assert loaded.text == SYSTEM_WITH_NODES
    from_text, kind_of_text = contract_kind.loads(SYSTEM_WITH_NODES, "REF:robot.yaml")
    assert kind_of_text is Kind.SYSTEM and from_text.nodes == loaded.nodes
    (tmp_path / "golden.yaml").write_text(GOLDEN)
    golden, kind = contract_kind.load(tmp_path / "golden.yaml")
    assert kind is Kind.GOLDEN and list(golden.nodes) == ["/talker"]


# ---------------------------------------------------------------------------- one place decides
PACKAGE = Path(contract_kind.__file__).resolve().parents[1]
#: the modules that may look at the kind keys and suffixes: this one, and the loaders of each format
#: (which check their own version key when they load)
_OWNERS = {"model/contract_kind.py", "model/contract.py", "model/system_contract.py", "model/nodl.py"}
_KIND_WORDS = ("system_version", "contract_version", "nodl_version", ".system.yaml", ".interfaces.yaml", ".nodl.")


def _leaves_outside_f_strings(node):
    import ast

    if isinstance(node, ast.JoinedStr):
        return
    yield node
    for child in ast.iter_child_nodes(node):
        yield from _leaves_outside_f_strings(child)


def _ad_hoc_kind_checks(source: str) -> list[str]:
    """The places in ``source`` that decide a kind themselves: a kind key or suffix in a
    comparison, an ``endswith``/``startswith``/``search``/``match`` call or a regular expression,
    or a function named like a kind check."""
    import ast

    found = []
    tree = ast.parse(source)
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef) and (node.name.startswith(("is_system", "any_system"))
                                                   or "contract_kind" in node.name
                                                   or (node.name.startswith("is_") and node.name.endswith("_contract"))):
            found.append(f"line {node.lineno}: def {node.name}")
        checked: list[ast.AST] = []
        if isinstance(node, ast.Compare):
            checked = [node.left, *node.comparators]
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in (
                "endswith", "startswith", "search", "match", "fullmatch", "compile", "get"):
            checked = list(node.args)
        for part in checked:
            for leaf in _leaves_outside_f_strings(part):  # an f-string names a file, it decides nothing
                if isinstance(leaf, ast.Constant) and isinstance(leaf.value, str) \
                        and any(word in leaf.value for word in _KIND_WORDS):
                    found.append(f"line {leaf.lineno}: {leaf.value!r}")
    return found


def test_the_guard_sees_an_ad_hoc_kind_check() -> None:
    assert _ad_hoc_kind_checks('def f(p):\n    return p.name.endswith(".system.yaml")\n')
    assert _ad_hoc_kind_checks('import re\nR = re.compile(r"^system_version:")\n')
    assert _ad_hoc_kind_checks('def is_system(p):\n    return True\n')
    assert _ad_hoc_kind_checks('def f(data):\n    return "nodl_version" in data\n')
    assert _ad_hoc_kind_checks('def f(p):\n    return p.name.endswith((".nodl.yaml", ".nodl.json"))\n')
    assert not _ad_hoc_kind_checks('MESSAGE = "a file saying system_version: is a system contract"\n')
    assert not _ad_hoc_kind_checks('def f(d, e):\n    return d / f"{e}.interfaces.yaml" in KEPT\n')


def test_no_module_decides_a_contract_kind_but_contract_kind() -> None:
    """Every other place asks ``model.contract_kind`` (issue 51 item 2): a new ad-hoc check of a
    kind key or a suffix anywhere else in the package fails here."""
    offenders = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        relative = path.relative_to(PACKAGE).as_posix()
        if relative in _OWNERS:
            continue
        found = _ad_hoc_kind_checks(path.read_text(encoding="utf-8"))
        if found:
            offenders[relative] = found
    assert not offenders, f"ask model.contract_kind instead: {offenders}"
