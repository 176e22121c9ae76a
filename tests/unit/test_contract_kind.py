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
