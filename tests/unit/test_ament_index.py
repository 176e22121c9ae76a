"""model/ament_index.py: the one reader of the ament index. Prefixes are searched in order, the
first that registers a name wins; a prefix without an index is no error. Real directories, as
colcon installs them (``<prefix>/share/ament_index/resource_index/<type>/<name>``)."""

from __future__ import annotations

import os

from pytest_rmw_introspect.model import ament_index


def _register(prefix, name, resource_type="packages"):
    marker = prefix / "share" / "ament_index" / "resource_index" / resource_type / name
    marker.parent.mkdir(parents=True, exist_ok=True)
    marker.write_text("")
    return marker


def test_the_prefixes_come_from_ament_prefix_path_in_order_without_empty_entries(tmp_path, monkeypatch):
    a, b = tmp_path / "a", tmp_path / "b"
    monkeypatch.setenv("AMENT_PREFIX_PATH", os.pathsep.join([str(a), "", str(b), ""]))
    assert ament_index.env_prefixes() == [a, b]
    assert ament_index.env_prefixes({"AMENT_PREFIX_PATH": str(b)}) == [b]
    assert ament_index.env_prefixes({}) == []
    monkeypatch.delenv("AMENT_PREFIX_PATH")
    assert ament_index.env_prefixes() == []


def test_the_providers_of_a_package_are_the_prefixes_that_register_it_in_the_order_given(tmp_path):
    overlay, underlay, empty = tmp_path / "overlay", tmp_path / "underlay", tmp_path / "empty"
    _register(overlay, "talker_pkg")
    _register(underlay, "talker_pkg")
    _register(underlay, "other_pkg")
    empty.mkdir()
    assert ament_index.providers("talker_pkg", [empty, underlay, overlay]) == [underlay, overlay]
    assert ament_index.providers("talker_pkg", [str(overlay)]) == [overlay]
    assert ament_index.providers("missing_pkg", [overlay, underlay]) == []
    assert ament_index.providers("talker_pkg", [tmp_path / "not-there"]) == []


def test_other_resource_types_are_their_own_index(tmp_path):
    marker = _register(tmp_path, "my_pkg__talker", "nodl_desc")
    assert ament_index.resource(tmp_path, "my_pkg__talker", "nodl_desc") == marker
    assert ament_index.providers("my_pkg__talker", [tmp_path], "nodl_desc") == [tmp_path]
    assert ament_index.providers("my_pkg__talker", [tmp_path]) == []  # not a package


def test_the_names_a_prefix_registers(tmp_path):
    for name in ("b_pkg", "a_pkg"):
        _register(tmp_path, name)
    assert sorted(ament_index.names(tmp_path)) == ["a_pkg", "b_pkg"]
    assert ament_index.names(tmp_path, "nodl_desc") == []
    assert ament_index.names(tmp_path / "not-there") == []
