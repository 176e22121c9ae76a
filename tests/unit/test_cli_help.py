"""What `rmw-introspect --help` and `capture --help` show a new user: each command and each target
option once, and examples that run in the venv a user has."""

import re

import pytest

from pytest_rmw_introspect.cli.parser import build_parser

COMMANDS = ("capture", "check", "diff", "init", "validate", "contracts", "lock", "compat", "graph")


def _help(*command: str) -> str:
    parser = build_parser()
    if not command:
        return parser.format_help()
    subparsers = next(a for a in parser._actions if a.dest == "command")
    return subparsers.choices[command[0]].format_help()


def test_the_top_level_help_lists_every_command_once():
    text = _help()
    for command in COMMANDS:
        listed = re.findall(rf"^\s{{2,}}{command}\s{{2,}}\S", text, flags=re.MULTILINE)
        assert len(listed) == 1, (command, text)
    assert "positional arguments" not in text  # the commands are under "commands:", nowhere else


def test_the_examples_name_no_package_a_wheel_venv_lacks():
    text = _help()
    assert "demo_nodes_py" not in text
    assert "rmw-introspect capture --package my_pkg --executable talker" in text


@pytest.mark.parametrize("flag", ["--package P", "--executable E", "--script FILE", "--module M",
                                  "--entry-point MOD:FUNC", "--namespace NS"])
def test_capture_help_lists_each_target_option_once(flag):
    text = _help("capture")
    assert len(re.findall(rf"^\s+{re.escape(flag)}(\s|$)", text, flags=re.MULTILINE)) == 1, text
    assert "-- COMMAND ARGS..." in text  # the one kind of target without an option of its own


def test_the_command_line_page_names_every_target_option():
    """docs/cli.md's TARGET paragraph names each target option the parser has (it once missed two)."""
    from pathlib import Path

    page = (Path(__file__).resolve().parents[2] / "docs" / "cli.md").read_text()
    paragraph = page[page.index("TARGET is "):page.index("Comparison\nflags")]
    capture = next(a for a in build_parser()._actions if a.dest == "command").choices["capture"]
    group = next(g for g in capture._action_groups if g.title == "target options")
    flags = [next(o for o in action.option_strings if o.startswith("--")) for action in group._group_actions]
    assert flags, group
    missing = [flag for flag in flags
               if flag not in paragraph and flag.replace("--no-", "--[no-]") not in paragraph
               and flag.replace("--", "--[no-]", 1) not in paragraph]
    assert not missing, missing
