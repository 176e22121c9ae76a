"""Every report command in every format, for every kind of contract it reads (issue 51 item 3).

Each command hands its outcome to the one writer (``cli/emit.py``); this test runs each command ×
contract kind × ``--format`` and compares what it printed with what the report model writes for
that format (``compare.ci_report`` and ``compare.sarif`` over the command's own result), plus a
look at the format itself, so that a command that skipped a format (the system ``diff`` once
printed its text for ``--format markdown``) fails here. Nothing runs: the commands read contracts,
a git repository and a recording."""

from __future__ import annotations

import json
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from test_check_bag import LISTENER, SYSTEM, TALKER, bag, topic

from pytest_rmw_introspect import cli
from pytest_rmw_introspect.compare import ci_report, junit

FORMATS = ("text", "json", "markdown", "github", "sarif", "junit")


def _weakened(text: str) -> str:
    return text.replace("reliability: RELIABLE", "reliability: BEST_EFFORT", 1)


def _looks_like(fmt: str, out: str) -> None:
    """The format itself: what a reader of that format expects."""
    if fmt == "json":
        json.loads(out)
    elif fmt == "sarif":
        log = json.loads(out)
        assert log["version"] == "2.1.0" and log["runs"][0]["tool"]["driver"]["name"] == "rmw-introspect"
    elif fmt == "markdown":
        assert out.startswith("## "), out[:200]
    elif fmt == "github":
        assert all(line.startswith("::") for line in out.splitlines()), out[:300]
    elif fmt == "junit":
        suites = ET.fromstring(out)
        assert suites.tag == "testsuites" and suites.find("testsuite/testcase") is not None, out[:300]
    else:
        assert not out.startswith(("{", "## ", "::")), out[:200]


def _run(capsys, *argv: str) -> tuple[int, str]:
    status = cli.main(list(argv))
    return status, capsys.readouterr().out


# ---------------------------------------------------------------------------- the commands
@pytest.fixture
def contracts(tmp_path, monkeypatch):
    """Each kind before and after a weakened publisher QoS."""
    monkeypatch.chdir(tmp_path)
    for name, text in {"talker": TALKER, "listener": LISTENER, "robot": SYSTEM}.items():
        kind = "system" if name == "robot" else "interfaces"
        Path(f"old/{name}.{kind}.yaml").parent.mkdir(exist_ok=True)
        Path(f"old/{name}.{kind}.yaml").write_text(text)
        Path(f"{name}.{kind}.yaml").write_text(_weakened(text) if name != "listener" else text)
    return tmp_path


KINDS = {"node": "talker.interfaces.yaml", "system": "robot.system.yaml"}


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("kind", sorted(KINDS))
def test_diff(contracts, capsys, kind, fmt):
    from pytest_rmw_introspect.check import diff

    new = KINDS[kind]
    status, out = _run(capsys, "diff", f"old/{new}", new, "--format", fmt)
    assert status == 1
    result = diff.diff_contracts(
        f"old/{new}", new, [({}, "command line")])
    outcome = result.for_ci()
    expected = {"text": result.render_text(), "json": result.to_json(),
                "markdown": ci_report.drift_markdown([outcome], title=f"Interface drift of {new}"),
                "github": ci_report.drift_github([outcome]), "sarif": "QOS_RELIABILITY_WEAKENED",
                "junit": junit.drift_junit([outcome])}[fmt]
    _compare(fmt, out, expected)


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("kind", sorted(KINDS))
def test_diff_against_a_revision(contracts, capsys, kind, fmt):
    subprocess.run(["git", "init", "-q", "-b", "main"], check=True)
    for config in (["user.email", "t@example.com"], ["user.name", "t"]):
        subprocess.run(["git", "config", *config], check=True)
    Path(KINDS[kind]).write_text(Path(f"old/{KINDS[kind]}").read_text())
    subprocess.run(["git", "add", KINDS[kind]], check=True)
    subprocess.run(["git", "commit", "-q", "-m", "contract"], check=True)
    Path(KINDS[kind]).write_text(_weakened(Path(KINDS[kind]).read_text()))
    status, out = _run(capsys, "diff", "--against", "HEAD", KINDS[kind], "--format", fmt)
    assert status == 1
    from pytest_rmw_introspect.check import gate

    result = gate.run("HEAD", [KINDS[kind]])
    expected = {"text": result.render_text(), "json": result.to_json(),
                "markdown": ci_report.drift_markdown(result.for_ci(), title=result.title(), intro=result.intro()),
                "github": ci_report.drift_github(result.for_ci()), "sarif": "QOS_RELIABILITY_WEAKENED",
                "junit": junit.drift_junit(result.for_ci())}[fmt]
    if fmt == "github":  # the gate says first what it looked at
        out = out.split("\n", 1)[1]
    _compare(fmt, out, expected)


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("kind", sorted(KINDS))
def test_compat(contracts, capsys, kind, fmt):
    """A best-effort publisher and a reliable subscription: the system problem in each format."""
    from pytest_rmw_introspect.check import system_pipeline

    files = [KINDS[kind], "listener.interfaces.yaml"]
    status, out = _run(capsys, "compat", *files, "--format", fmt)
    assert status == 1
    result = system_pipeline.check_contracts(files)
    expected = {"text": result.render_text(), "json": result.to_json(),
                "markdown": ci_report.compat_markdown(result.items, threshold=result.threshold, labels=result.labels),
                "github": ci_report.compat_github(result.items, threshold=result.threshold, lines=result.lines,
                                                  file_of=result.file_of),
                "sarif": "QOS_INCOMPATIBLE",
                "junit": junit.compat_junit(result.items, threshold=result.threshold, labels=result.labels,
                                            file_of=result.file_of)}[fmt]
    _compare(fmt, out, expected)


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("kind", sorted(KINDS))
def test_check_of_a_recording(contracts, capsys, kind, fmt):
    bag(contracts, [topic(profiles=[{"reliability": "best_effort"}])])
    Path(KINDS[kind]).write_text(Path(f"old/{KINDS[kind]}").read_text())
    status, out = _run(capsys, "check", "--bag", "rec", KINDS[kind], "--format", fmt)
    assert status == 1
    _looks_like(fmt, out)
    assert "QOS_RELIABILITY_WEAKENED" in out or fmt == "text" and "reliability" in out


@pytest.mark.parametrize("fmt", ("text", "github", "sarif", "junit"))
@pytest.mark.parametrize("kind", sorted(KINDS))
def test_validate(contracts, capsys, kind, fmt):
    broken = Path(KINDS[kind]).read_text().replace("nodes:", "nodez:", 1)
    Path(f"broken.{KINDS[kind].split('.', 1)[1]}").write_text(broken)
    status, out = _run(capsys, "validate", KINDS[kind], f"broken.{KINDS[kind].split('.', 1)[1]}", "--format", fmt)
    assert status == 2
    _looks_like(fmt, out)
    if fmt == "text":
        assert out.startswith(f"{KINDS[kind]}: valid ")
    elif fmt == "github":
        assert out.count("::error ") == 1 and "broken." in out
    elif fmt == "junit":
        cases = {case.get("name"): case for case in ET.fromstring(out).iter("testcase")}
        assert cases[KINDS[kind]].find("failure") is None
        failure = cases[f"broken.{KINDS[kind].split('.', 1)[1]}"].find("failure")
        assert failure.get("message") == "invalid contract" and "'nodes' is required" in failure.text
    else:
        assert [r["ruleId"] for r in json.loads(out)["runs"][0]["results"]] == ["CONTRACT_INVALID"]


def _compare(fmt: str, out: str, expected) -> None:
    _looks_like(fmt, out)
    if fmt == "json":
        assert json.loads(out) == json.loads(json.dumps(expected, default=str))
    elif fmt == "sarif":
        assert expected in {r["ruleId"] for r in json.loads(out)["runs"][0]["results"]}
    else:
        assert out == expected
