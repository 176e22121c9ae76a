"""Issue 47, findings 3 and 7, end to end with `rmw-introspect check`: a system whose `cmd_vel` is
remapped on one side only (its subscription dangles) and whose driver runs fine without its
device. `check --update` writes the contract and exits 1, saying that it wrote it and what is
still broken (it printed "Result: FAIL", "updated ..." and exited 0); the device note is said once
per run, short, without the stand-in advice (the driver ran), and under `--format github` as a
`::notice` on the contract's line, not on stderr (it was ~300 characters on every check)."""

from __future__ import annotations

from sample_systems import half_remapped_robot

HEADER = "system_version: 1\nlaunch: {path: launch/robot.launch.xml}\n"


def test_an_update_that_leaves_the_system_broken_fails_and_the_device_note_is_said_once(cli):
    cli.write("launch/robot.launch.xml", half_remapped_robot())
    cli.write("robot.system.yaml", HEADER)
    updated = cli("check", "--update", "robot.system.yaml", timeout=120)
    assert updated.returncode == 1, updated  # finding 3: it was 0
    assert "updated robot.system.yaml\n" in updated.stderr
    assert ("rmw-introspect: updated robot.system.yaml, but the system still fails its check: 1 system problem(s) "
            "at or above system_fail_on (breaking): DANGLING_SUBSCRIPTION /robot/chatter.") in updated.stderr
    assert "[DANGLING_SUBSCRIPTION]" in updated.stdout
    text = cli.read("robot.system.yaml")
    assert text.startswith(HEADER) and "  /robot/base:\n" in text  # written all the same
    # finding 7: the note, once, short, no advice to stand in for a process that ran
    notes = [line for line in (updated.stdout + updated.stderr).splitlines() if "/dev/ttyFAKE" in line]
    assert notes == ["note: robot.system.yaml: /robot/driver: parameter `port` is '/dev/ttyFAKE:115200': the device "
                     "/dev/ttyFAKE, which this machine does not have (not judged: the robot has it)"], notes

    # two contracts launching the same driver: one note for the run; under github a notice, not stderr
    cli.write("copy.system.yaml", text)
    github = cli("check", "--format", "github", "robot.system.yaml", "copy.system.yaml", timeout=120)
    assert github.returncode == 1, github
    assert "ttyFAKE" not in github.stderr, github.stderr
    notices = [line for line in github.stdout.splitlines() if line.startswith("::notice")]
    line = text.splitlines().index("  /robot/driver:") + 1
    port = next(i for i, entry in enumerate(text.splitlines()) if i >= line and "- name: port" in entry) + 1
    assert notices == [f"::notice file=robot.system.yaml,line={port},title=note::/robot/driver: parameter `port` is "
                       "'/dev/ttyFAKE:115200': the device /dev/ttyFAKE, which this machine does not have (not judged: "
                       "the robot has it)"], github.stdout
