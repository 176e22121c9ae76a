"""Names that change every run in a system contract (issue 43 item 3): the node a launch file
names (`$(anon NAME)` too: stable by the reader) keeps its name; the node a program names anew
every run is written as a pattern; the system then checks again and again without drift."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import yaml

MIDDLEWARE_NODES = Path(__file__).resolve().parents[1] / "middleware" / "nodes"

LAUNCH = """\
<launch>
  <node pkg="anon_demo" exec="anonymous_talker"/>
  <node pkg="rmw_introspect_examples" exec="talker" name="$(anon worker)"/>
</launch>
"""


def test_a_system_keeps_launch_given_names_and_writes_self_made_ones_as_patterns(cli, tmp_path):
    prefix = tmp_path / "prefix"
    (prefix / "share" / "ament_index" / "resource_index" / "packages").mkdir(parents=True)
    (prefix / "share" / "ament_index" / "resource_index" / "packages" / "anon_demo").write_text("")
    (prefix / "lib" / "anon_demo").mkdir(parents=True)
    exe = prefix / "lib" / "anon_demo" / "anonymous_talker"
    exe.write_text(f"#!{sys.executable}\n" + (MIDDLEWARE_NODES / "anonymous_talker.py").read_text())
    exe.chmod(0o755)
    env = {"AMENT_PREFIX_PATH": f"{prefix}{os.pathsep}{os.environ.get('AMENT_PREFIX_PATH', '')}"}
    cli.write("anon.launch.xml", LAUNCH)

    captured = cli("capture", "--launch", "anon.launch.xml", "-o", "anon.system.yaml", env=env, timeout=120)
    assert captured.returncode == 0, captured
    data = yaml.safe_load((tmp_path / "anon.system.yaml").read_text())
    [worker] = [n for n in data["nodes"] if n.startswith("/worker_anon_")]
    assert sorted(data["nodes"]) == ["/anonymous_talker_*", worker]
    assert "unstable_name" not in data["nodes"][worker]  # the launch file named it
    processes = {p["executable"]: p for p in data["processes"]}
    assert processes["anonymous_talker"]["nodes"] == ["/anonymous_talker_*"]
    assert processes["talker"]["name"] == worker and processes["talker"]["nodes"] == [worker]

    for attempt in range(3):
        checked = cli("check", "anon.system.yaml", env=env, timeout=120)
        assert checked.returncode == 0, f"check {attempt + 1} drifted:\n{checked}"
