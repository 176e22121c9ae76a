"""Editable installs found on the Python path (model.editable_installs) and the symlink prefixes
made of them (run.editable), without pip: the files pip and `setup.py develop` write, by hand.
tests/cli/test_issue47_editable.py does it with a real `pip install -e` and a capture."""

from __future__ import annotations

import json
from pathlib import Path

from pytest_rmw_introspect.model import ament_index, editable_installs
from pytest_rmw_introspect.run import editable


def package_source(root: Path, name: str, package_xml: bool = True) -> Path:
    (root / "launch").mkdir(parents=True)
    (root / "launch" / "robot.launch.xml").write_text("<launch/>\n")
    if package_xml:
        (root / "package.xml").write_text(f"<package format='3'>\n  <name>{name}</name>\n</package>\n")
    return root


def test_a_pep660_install_and_an_egg_link_are_found(tmp_path: Path) -> None:
    site = tmp_path / "site"
    (site / "mybot-0.1.0.dist-info").mkdir(parents=True)
    new = package_source(tmp_path / "src" / "mybot", "mybot")
    (site / "__editable__.mybot-0.1.0.pth").write_text("import __editable___mybot_0_1_0_finder\n")
    (site / "mybot-0.1.0.dist-info" / "direct_url.json").write_text(
        json.dumps({"url": new.as_uri(), "dir_info": {"editable": True}}))
    old = package_source(tmp_path / "src" / "old bot", "old_bot", package_xml=False)
    (site / "old_bot.egg-link").write_text(f"{old}\n.\n")
    found = editable_installs.installs([str(site)])
    assert [(e.distribution, e.source, e.package) for e in found] == [("mybot", new, "mybot"), ("old_bot", old, None)]
    assert editable_installs.not_found_hint("mybot", [str(site)]) == ""
    hint = editable_installs.not_found_hint("old_bot", [str(site)])
    assert f"installed with `pip install -e` from {old}, which has no package.xml" in hint
    assert "pip install -e <its source directory>" in editable_installs.not_found_hint("nobody", [str(site)])
    assert editable_installs.not_found_hint("nobody", [str(site)], if_absent=False) == ""


def test_without_data_files_the_source_tree_is_the_share_directory(tmp_path: Path, monkeypatch) -> None:
    site = tmp_path / "site"
    site.mkdir()
    source = package_source(tmp_path / "src" / "mybot", "mybot")
    (site / "mybot.egg-link").write_text(f"{source}\n")
    monkeypatch.setattr(editable, "_data_files", lambda _source: None)  # setup files that cannot be read
    [prefix] = editable.prefixes([], [str(site)], cache=tmp_path / "cache")
    assert ament_index.providers("mybot", [prefix]) == [prefix]
    assert (prefix / "share" / "mybot" / "launch" / "robot.launch.xml").read_text() == "<launch/>\n"
    assert json.loads((prefix / editable.MANIFEST).read_text())["how"] == "source tree"
    # a prefix that already provides the package: nothing is made
    assert editable.prefixes([prefix], [str(site)], cache=tmp_path / "cache") == []
