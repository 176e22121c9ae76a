"""What the user is told while something slow runs (run.progress): a step's start and end lines,
lines said once by the workers of one run, and the middleware build's own lines (its progress,
a wait for another process's build, why it builds at all)."""

from __future__ import annotations

import re
import subprocess
import sys
import textwrap
import time
import types
from pathlib import Path

import fake_library
import pytest

from pytest_rmw_introspect.run import middleware, progress, ros_env


@pytest.fixture
def said(monkeypatch):
    """The lines said during the test, outside any run (the sink and the scope another test of
    the same worker may have set are put back afterwards)."""
    lines: list[str] = []
    previous, previous_scope = progress.set_sink(lines.append), progress.scope()
    progress.set_scope(None)
    yield lines
    progress.set_sink(previous)
    progress.set_scope(previous_scope)


def fake_ros(prefix: Path, kind: str = ros_env.WHEELS, distro: str = "jazzy") -> ros_env.RosEnvironment:
    return ros_env.RosEnvironment(kind, prefix, distro, (prefix,), (prefix / "lib",))


def test_a_step_says_when_it_starts_and_ends_with_the_time_it_took(said):
    with progress.step("building X (why; log: /tmp/x.log)", "built X in {time}", "building X failed") as elapsed:
        assert elapsed() >= 0
    assert said[0] == "building X (why; log: /tmp/x.log)"
    assert said[1].startswith("built X in ") and said[1].endswith(" s")
    with pytest.raises(RuntimeError):
        with progress.step("building Y", "built Y in {time}", "building Y failed"):
            raise RuntimeError("broken")
    assert said[3].startswith("building Y failed after ")


def test_the_default_sink_is_stderr_with_the_tools_name(capsys):
    previous = progress.set_sink(None)
    try:
        progress.say("hello")
    finally:
        progress.set_sink(previous)
    assert capsys.readouterr().err == "rmw-introspect: hello\n"


def test_a_line_said_once_is_said_by_one_worker_of_a_run(said, tmp_path, monkeypatch):
    monkeypatch.setattr(progress.tempfile, "gettempdir", lambda: str(tmp_path))
    progress.say_once("k", "outside a run: always")
    progress.say_once("k", "outside a run: always")
    progress.set_scope("run-1")
    progress.say_once("k", "first worker")
    progress.say_once("k", "second worker")  # (the mark is in the shared temp directory)
    progress.say_once("other", "another line")
    progress.set_scope("run-2")
    progress.say_once("k", "a worker of another run")
    assert said == ["outside a run: always", "outside a run: always", "first worker", "another line",
                    "a worker of another run"]


def test_seconds_read_like_people_write_them():
    assert progress.seconds(0.43) == "0.4 s"
    assert progress.seconds(12.4) == "12 s"


def test_a_build_says_how_far_it_got_every_few_seconds(said, monkeypatch):
    monkeypatch.setattr(middleware, "PROGRESS_EVERY", 0.0)
    shown = middleware._Progress(lambda: 12.0)
    shown.tick("CMake configure")
    shown.output("[ 12%] Building CXX object CMakeFiles/core.dir/src/a.cpp.o")
    shown.output("[ 42%] Building CXX object CMakeFiles/core.dir/src/b.cpp.o")
    shown.output("a warning without a percentage")
    shown.tick("compile")
    assert said == ["building the middleware: CMake configure, 12 s so far", "building the middleware: compile 42%, 12 s so far"]


def test_a_real_build_step_streams_its_output_to_the_log_and_says_its_progress(said, tmp_path, monkeypatch):
    monkeypatch.setattr(middleware, "PROGRESS_EVERY", 0.5)
    log = tmp_path / "build.log"
    script = "import time\nfor p in (10, 55, 100):\n    print(f'[{p:3d}%] step', flush=True); time.sleep(0.6)\n"
    middleware._run_logged([sys.executable, "-c", script], log, {}, "compile", middleware._Progress(lambda: 1.0))
    assert "[ 55%] step" in log.read_text()
    assert said and all(line.startswith("building the middleware: compile") for line in said)
    assert any("55%" in line or "100%" in line for line in said)


def test_why_the_middleware_is_built_from_source(monkeypatch, tmp_path):
    monkeypatch.setattr(middleware, "PREBUILT_DIR", tmp_path / "prebuilt")
    wheels = fake_ros(tmp_path / "venv")
    assert "no prebuilt middleware in this installation" in middleware.source_build_reason(wheels)
    (tmp_path / "prebuilt" / "kilted").mkdir(parents=True)
    (tmp_path / "prebuilt" / "kilted" / middleware.LIBRARY_FILE).write_bytes(fake_library.WHOLE)
    assert middleware.source_build_reason(wheels) == "the prebuilt middleware of this installation is for kilted, not jazzy"
    system = fake_ros(Path("/opt/ros/jazzy"), kind=ros_env.SYSTEM)
    assert middleware.source_build_reason(system).startswith("a standard ROS 2 install at /opt/ros/jazzy")


def test_the_prebuilt_library_of_the_wheels_distribution_is_chosen(monkeypatch, tmp_path):
    monkeypatch.delenv("RMW_INTROSPECT_LIBRARY", raising=False)
    monkeypatch.setattr(middleware, "PREBUILT_DIR", tmp_path / "prebuilt")
    for distro in ("jazzy", "kilted"):
        (tmp_path / "prebuilt" / distro).mkdir(parents=True)
        (tmp_path / "prebuilt" / distro / middleware.LIBRARY_FILE).write_bytes(fake_library.WHOLE)
    found = middleware.resolve_library(ros=fake_ros(tmp_path / "venv", distro="kilted"), cache_dir=tmp_path / "cache")
    assert (found.origin, found.path) == ("prebuilt", tmp_path / "prebuilt" / "kilted" / middleware.LIBRARY_FILE)
    # a standard install builds against its own rmw: never the prebuilt one
    assert middleware.find_prebuilt(fake_ros(tmp_path / "opt", kind=ros_env.SYSTEM)) is None


HOLD_THE_LOCK = textwrap.dedent("""
    import sys, time
    from pathlib import Path
    from filelock import FileLock
    entry, scope = Path(sys.argv[1]), sys.argv[2]
    with FileLock(f"{entry}.lock"):
        Path(f"{entry}.lock.pid").write_text(f"4242 {scope}\\n")
        print("holding", flush=True)
        time.sleep(2.5)
        library = entry / "install" / "lib" / "librmw_introspect_cpp.so"
        library.parent.mkdir(parents=True)
        library.write_bytes(bytes.fromhex(sys.argv[3]))  # a whole library (fake_library.WHOLE)
        (entry / "complete").write_text(str(library))
        Path(f"{entry}.lock.pid").unlink()
""")


def _held_by_another_process(entry: Path, scope: str) -> subprocess.Popen[str]:
    entry.parent.mkdir(parents=True, exist_ok=True)
    holder = subprocess.Popen([sys.executable, "-c", HOLD_THE_LOCK, str(entry), scope, fake_library.WHOLE.hex()], stdout=subprocess.PIPE, text=True)
    assert holder.stdout is not None and holder.stdout.readline() == "holding\n"
    return holder


def test_waiting_for_another_process_that_builds_says_so_with_its_log(said, tmp_path, monkeypatch):
    monkeypatch.setattr(middleware, "build", lambda *a, **k: pytest.fail("built although another process did"))
    ros = fake_ros(tmp_path / "venv")
    entry = middleware.cache_entry(ros, tmp_path / "cache")
    holder = _held_by_another_process(entry, "-")
    began = time.monotonic()
    library = middleware.source_build(ros, tmp_path / "cache")
    holder.wait(timeout=30)
    assert library == entry / "install" / "lib" / middleware.LIBRARY_FILE
    assert said[0] == (f"waiting for another process (pid 4242) that builds the recording middleware for ROS 2 jazzy; "
                       f"its log: {entry / 'build.log'}")
    assert said[1].startswith("the other process's middleware build ended after ") and said[1].endswith(" of waiting")
    assert len(said) == 2 and time.monotonic() - began >= 1.0


def test_a_worker_waiting_for_a_worker_of_its_own_run_says_nothing(said, tmp_path, monkeypatch):
    """The worker that builds tells the user; its siblings of the same pytest-xdist run wait quietly."""
    monkeypatch.setattr(middleware, "build", lambda *a, **k: pytest.fail("built although another process did"))
    progress.set_scope("run-7")
    ros = fake_ros(tmp_path / "venv")
    entry = middleware.cache_entry(ros, tmp_path / "cache")
    holder = _held_by_another_process(entry, "run-7")
    middleware.source_build(ros, tmp_path / "cache")
    holder.wait(timeout=30)
    assert said == []


class _FakePool:
    """The warm start pool's answers, in order, and the waits it was asked for."""

    def __init__(self, answers):
        self.answers, self.waits = list(answers), []

    def server(self, env, cwd, python, *, wait):
        self.waits.append(wait)
        return self.answers.pop(0)


def _fake_warm(answers):
    from pytest_rmw_introspect.run.warm import client

    class Ready:
        pass

    return types.SimpleNamespace(POOL=_FakePool(answers), STILL_STARTING=client.STILL_STARTING, WarmServer=Ready), Ready


def test_a_capture_waiting_for_the_warm_start_server_says_so_and_when_it_is_ready(said):
    from pytest_rmw_introspect.run import runner
    from pytest_rmw_introspect.run.warm import client

    warm, ready = _fake_warm([client.STILL_STARTING, None])
    warm.POOL.answers[1] = ready()
    assert isinstance(runner._warm_server(warm, {}, "/", None, 3.0), ready)
    assert warm.POOL.waits == [1.0, 2.0]
    assert said[0].startswith("the warm start server (one Python process that imports rclpy once") and "up to 3 s" in said[0]
    assert said[1].startswith("the warm start server is ready after ")


def test_a_warm_start_server_that_never_gets_ready_is_said_with_the_cold_start(said):
    from pytest_rmw_introspect.run import runner
    from pytest_rmw_introspect.run.warm import client

    warm, _ready = _fake_warm([client.STILL_STARTING, client.STILL_STARTING])
    assert runner._warm_server(warm, {}, "/", None, 3.0) == client.STILL_STARTING
    assert said[1].startswith("no warm start server after ") and said[1].endswith(
        f"({client.STILL_STARTING}): the target starts cold")


def test_a_ready_warm_start_server_and_a_short_wait_say_nothing(said):
    from pytest_rmw_introspect.run import runner
    from pytest_rmw_introspect.run.warm import client

    warm, ready = _fake_warm([])
    warm.POOL.answers = [ready()]
    runner._warm_server(warm, {}, "/", None, 3.0)
    warm.POOL.answers = [client.STILL_STARTING]
    assert runner._warm_server(warm, {}, "/", None, 0.5) == client.STILL_STARTING  # a short wait is quiet
    assert said == []


def test_a_system_capture_that_lasts_says_so_then_how_many_are_captured(said):
    from concurrent.futures import ThreadPoolExecutor

    from pytest_rmw_introspect.run import system_capture

    step = progress.LateStep("capturing 4", "captured 4 in {time}", "capturing ended", after=0.1, every=0.05)
    with ThreadPoolExecutor(max_workers=1) as pool:
        errors = system_capture._results(pool, lambda index: time.sleep(0.15), 4, step)
    step.end(ok=True)
    assert errors == [None] * 4
    assert said[0] == "capturing 4"
    # every process captured after the start line is counted, the last one by the end line
    counted = [line for line in said[1:-1] if line.startswith("captured ") and " of 4 processes, " in line]
    assert counted and counted == said[1:-1] and "captured 4 of 4" not in " ".join(counted)
    assert re.fullmatch(r"captured 4 in \d\.\d s", said[-1])


def test_a_system_capture_that_ends_quickly_says_nothing(said):
    from concurrent.futures import ThreadPoolExecutor

    from pytest_rmw_introspect.run import system_capture

    step = progress.LateStep("capturing 3", "captured 3 in {time}", "capturing ended", after=5.0, every=0.0)
    with ThreadPoolExecutor(max_workers=2) as pool:
        errors = system_capture._results(pool, lambda index: None, 3, step)
    step.end(ok=True)
    assert errors == [None] * 3
    assert said == []


def test_a_late_step_that_fails_says_after_how_long_only_if_it_was_said(said):
    quiet = progress.LateStep("a", "a done", "a failed", after=60.0, every=1.0)
    quiet.tick("never")
    quiet.end(ok=False)
    assert said == []
    loud = progress.LateStep("b", "b done", "b failed", after=0.0, every=60.0)
    loud.tick("not yet due")
    loud.tick("not yet due")
    loud.end(ok=False)
    assert said[0] == "b" and len(said) == 2 and re.fullmatch(r"b failed after \d\.\d s", said[1])
