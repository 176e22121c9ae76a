"""While preloaded, no call reaches Fast DDS: no Fast DDS threads, no sockets, no new shared
memory segments. The same node on Fast DDS shows all three, so the checks can fail."""

import os
import signal
import time
from pathlib import Path

import rmwi_helpers as h

SHM = Path("/dev/shm")


def _segments(pid):
    """The Fast DDS shared-memory segments the process ``pid`` has mapped or open (Fast DDS 2,
    Jazzy, names them fastrtps_*, Fast DDS 3, Kilted, fastdds_*). Read from the process itself,
    not from /dev/shm, so that Fast DDS processes of other tests running at the same time do not
    count."""
    paths = [line.split(maxsplit=5)[5] for line in Path(f"/proc/{pid}/maps").read_text().splitlines()
             if len(line.split(maxsplit=5)) == 6]
    for fd in os.listdir(f"/proc/{pid}/fd"):
        try:
            paths.append(os.readlink(f"/proc/{pid}/fd/{fd}"))
        except OSError:
            pass  # closed meanwhile
    names = {Path(path.removesuffix(" (deleted)")).name for path in paths if path.startswith(str(SHM) + "/")}
    return {name for name in names if name.startswith(("fastrtps_", "fastdds_"))}


def _observe(proc):
    threads = sorted((Path(f"/proc/{proc.pid}/task") / t / "comm").read_text().strip()
                     for t in os.listdir(f"/proc/{proc.pid}/task"))
    sockets = [fd for fd in os.listdir(f"/proc/{proc.pid}/fd")
               if os.readlink(f"/proc/{proc.pid}/fd/{fd}").startswith("socket:")]
    return threads, sockets


def _run_and_observe(library, tmp_path, name):
    path = tmp_path / f"{name}.json"
    proc = h.spawn(library, h.python_node("talker.py"), path, {"RMW_INTROSPECT_EXIT": "0"})
    try:
        if library is not None:
            h.wait_for(lambda: h.read_capture_if(path, state="settled"))
        else:
            time.sleep(2.0)  # Fast DDS: let discovery start
        assert proc.poll() is None
        threads, sockets = _observe(proc)
        segments = _segments(proc.pid)
    finally:
        h.stop(proc, signal.SIGINT)
    return threads, sockets, segments


def test_no_fast_dds_activity_when_preloaded(middleware_library, tmp_path):
    threads, sockets, segments = _run_and_observe(middleware_library, tmp_path, "preloaded")
    print("preloaded:", threads, sockets, segments)
    assert not [t for t in threads if t.startswith("dds.")], threads
    assert sockets == []
    assert segments == set()
    assert "rmwi_monitor" in threads

    # Control: the same node on Fast DDS (no preload) trips every check.
    threads, sockets, segments = _run_and_observe(None, tmp_path, "fastdds")
    print("fast dds:", threads, sockets, segments)
    assert [t for t in threads if t.startswith("dds.")], threads
    assert sockets
    assert segments or not SHM.is_dir()
