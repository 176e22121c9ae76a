"""Where the middleware library comes from: explicit path, installed package, or cached build."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import fake_library
import pytest

from pytest_rmw_introspect.errors import SetupError
from pytest_rmw_introspect.run import middleware, progress, ros_env


def fake_ros(prefix: Path) -> ros_env.RosEnvironment:
    return ros_env.RosEnvironment(ros_env.WHEELS, prefix, "jazzy", (prefix,), (prefix / "lib",))


def test_explicit_library_wins(tmp_path, monkeypatch):
    lib = tmp_path / "librmw_introspect_cpp.so"
    lib.write_bytes(fake_library.WHOLE)
    monkeypatch.setenv("RMW_INTROSPECT_LIBRARY", str(lib))
    found = middleware.resolve_library(ros=fake_ros(tmp_path))
    assert (found.path, found.origin) == (lib.resolve(), "environment")


def test_explicit_library_that_does_not_exist_is_an_error(tmp_path, monkeypatch):
    monkeypatch.setenv("RMW_INTROSPECT_LIBRARY", str(tmp_path / "nope.so"))
    with pytest.raises(SetupError, match="RMW_INTROSPECT_LIBRARY points at .*nope.so"):
        middleware.resolve_library(ros=fake_ros(tmp_path))


def test_installed_package_is_found_through_the_ament_index(tmp_path, monkeypatch):
    monkeypatch.delenv("RMW_INTROSPECT_LIBRARY", raising=False)
    prefix = tmp_path / "install"
    index = prefix / "share" / "ament_index" / "resource_index" / "packages"
    index.mkdir(parents=True)
    (index / "rmw_introspect_cpp").write_text("")
    (prefix / "lib").mkdir()
    (prefix / "lib" / "librmw_introspect_cpp.so").write_bytes(fake_library.WHOLE)
    found = middleware.resolve_library(ros=fake_ros(prefix))
    assert (found.path, found.origin) == (prefix / "lib" / "librmw_introspect_cpp.so", "installed")


def test_sources_hash_follows_build_inputs_and_ignores_tests(tmp_path):
    src = tmp_path / "src"
    shutil.copytree(middleware.source_dir(), src, ignore=shutil.ignore_patterns("build"))
    before = middleware.sources_hash(src)
    (src / "test").mkdir(exist_ok=True)
    (src / "test" / "extra_test.cpp").write_text("// a test changes nothing")
    assert middleware.sources_hash(src) == before
    (src / "CMakeLists.txt").write_text((src / "CMakeLists.txt").read_text() + "\n# changed\n")
    assert middleware.sources_hash(src) != before


def test_sources_hash_is_remembered_under_names_sizes_and_times(tmp_path):
    src = tmp_path / "src"
    shutil.copytree(middleware.source_dir(), src, ignore=shutil.ignore_patterns("build", "test"))
    memo_dir = tmp_path / "cache"
    plain = middleware.sources_hash(src)
    assert middleware.sources_hash(src, memo_dir=memo_dir) == plain
    memos = list(memo_dir.glob("sources-*"))
    assert len(memos) == 1 and memos[0].read_text().strip() == plain
    # the remembered value is what a second run returns (without reading the files)
    memos[0].write_text("f" * 64 + "\n")
    assert middleware.sources_hash(src, memo_dir=memo_dir) == "f" * 64
    # a damaged memo is hashed again and rewritten
    memos[0].write_text("not a hash")
    assert middleware.sources_hash(src, memo_dir=memo_dir) == plain
    assert memos[0].read_text().strip() == plain
    # an edited file has another size or time: another memo, the new contents' hash
    cmake = src / "CMakeLists.txt"
    cmake.write_text(cmake.read_text() + "\n# changed\n")
    changed = middleware.sources_hash(src, memo_dir=memo_dir)
    assert changed != plain and changed == middleware.sources_hash(src)
    assert len(list(memo_dir.glob("sources-*"))) == 2
    # a dangling link is nothing a build reads
    (src / "dangling").symlink_to(src / "no-such-file")
    assert middleware.sources_hash(src, memo_dir=memo_dir) == changed
    # an unwritable cache only costs the hashing
    blocked = tmp_path / "blocked"
    blocked.write_text("a file where the cache directory should be")
    assert middleware.sources_hash(src, memo_dir=blocked) == changed


def test_missing_build_tools_are_named_with_how_to_install_them(monkeypatch):
    monkeypatch.setattr(shutil, "which", lambda name: None)
    with pytest.raises(SetupError) as info:
        middleware._require_tools()
    message = str(info.value)
    assert "CMake (apt-get install cmake" in message
    assert "C++17 compiler" in message


def test_cached_build_is_reused_without_rebuilding(tmp_path, monkeypatch):
    monkeypatch.delenv("RMW_INTROSPECT_LIBRARY", raising=False)
    calls = []

    def fake_build(src, ros, dest, reason=""):
        calls.append(dest)
        lib = dest / "install" / "lib" / middleware.LIBRARY_FILE
        lib.parent.mkdir(parents=True)
        lib.write_bytes(fake_library.WHOLE)
        return lib

    monkeypatch.setattr(middleware, "build", fake_build)
    ros = fake_ros(tmp_path / "empty-prefix")
    first = middleware.resolve_library(ros=ros, cache_dir=tmp_path / "cache")
    second = middleware.resolve_library(ros=ros, cache_dir=tmp_path / "cache")
    assert first == second and first.origin == "built"
    assert len(calls) == 1
    assert first.path.parent.parent.parent.name.startswith("jazzy-")


def test_failed_build_reports_the_step_and_the_log_tail(tmp_path, monkeypatch):
    said: list[str] = []
    monkeypatch.setattr(progress, "_sink", said.append)
    src = tmp_path / "broken"
    src.mkdir()
    (src / "package.xml").write_text("<package/>")
    (src / "CMakeLists.txt").write_text("cmake_minimum_required(VERSION 3.16)\nproject(broken)\nmessage(FATAL_ERROR \"deliberately broken\")\n")
    with pytest.raises(SetupError) as info:
        middleware.build(src, fake_ros(tmp_path), tmp_path / "out")
    message = str(info.value)
    assert "CMake configure step" in message
    assert "deliberately broken" in message
    assert str(tmp_path / "out" / "build.log") in message
    assert said[0].startswith("building the recording middleware for ROS 2 jazzy") and said[-1].startswith(
        "building the recording middleware failed after ")


def test_the_library_is_looked_up_once_per_process_while_it_is_there(tmp_path, monkeypatch):
    """capture() without a library used to hash the middleware's source listing at every capture."""
    monkeypatch.delenv("RMW_INTROSPECT_LIBRARY", raising=False)
    monkeypatch.setattr(middleware, "_ensured", {})
    hashed = []
    real_hash = middleware.sources_hash

    def counting_hash(*args, **kwargs):
        hashed.append(args)
        return real_hash(*args, **kwargs)

    def fake_build(src, ros, dest, reason=""):
        lib = dest / "install" / "lib" / middleware.LIBRARY_FILE
        lib.parent.mkdir(parents=True, exist_ok=True)
        lib.write_bytes(fake_library.WHOLE)
        return lib

    monkeypatch.setattr(middleware, "sources_hash", counting_hash)
    monkeypatch.setattr(middleware, "build", fake_build)
    ros = fake_ros(tmp_path / "empty-prefix")
    first = middleware.ensure_library(ros, tmp_path / "cache")
    assert middleware.ensure_library(ros, tmp_path / "cache") == first
    assert len(hashed) == 1
    first.unlink()  # gone (a cache cleared): looked up, and built, again
    assert middleware.ensure_library(ros, tmp_path / "cache") == first and first.is_file()
    assert len(hashed) == 2
    chosen = tmp_path / "mine.so"
    chosen.write_bytes(fake_library.WHOLE)
    monkeypatch.setenv("RMW_INTROSPECT_LIBRARY", str(chosen))  # the environment's choice still wins
    assert middleware.ensure_library(ros, tmp_path / "cache") == chosen.resolve()


def _unwritable_caches(tmp_path: Path) -> list[tuple[Path, str]]:
    """Cache directories the middleware cannot be built in, and what the error says of each."""
    a_file = tmp_path / "cache-file"
    a_file.write_text("not a directory\n")
    cases = [(a_file, f"{a_file} is a file, not a directory"),
             (a_file / "below", f"{a_file} is a file, not a directory")]
    read_only = tmp_path / "read-only"
    read_only.mkdir()
    read_only.chmod(0o555)
    if not os.access(read_only, os.W_OK):  # root writes anyway: that case is then told by /sys
        cases.append((read_only, "Permission denied"))
    sys_fs = Path("/sys/fs/pytest-rmw-introspect-cache")
    if Path("/sys/fs").is_dir() and _cannot_create(sys_fs):  # sysfs takes no new directory, even from root
        cases.append((sys_fs, str(sys_fs)))
    return cases


def _cannot_create(path: Path) -> bool:
    try:
        path.mkdir()
    except OSError:
        return True
    path.rmdir()
    return False


def test_a_cache_that_cannot_be_written_is_an_error_that_says_what_to_do(tmp_path, monkeypatch):
    """Issue 50, N28: a read-only cache directory, or a cache path that is a file, was a traceback
    when the middleware had to be built."""
    monkeypatch.delenv("RMW_INTROSPECT_LIBRARY", raising=False)
    monkeypatch.setattr(middleware, "build", lambda *a, **k: pytest.fail("built in a cache it cannot write"))
    try:
        for cache, why in _unwritable_caches(tmp_path):
            with pytest.raises(SetupError) as refused:
                middleware.resolve_library(ros=fake_ros(tmp_path / "empty-prefix"), cache_dir=cache)
            message = str(refused.value)
            assert message.startswith("The recording middleware must be built, but its cache directory "), message
            assert why in message and "RMW_INTROSPECT_CACHE" in message and "RMW_INTROSPECT_LIBRARY" in message
    finally:
        (tmp_path / "read-only").chmod(0o755)


def test_a_damaged_cached_library_is_named_with_its_cache_directory_to_delete(tmp_path, monkeypatch):
    """Issue 50, N29: a corrupted or truncated cached library was reported as the target exiting
    with status 102 (rcl found another middleware), the library not named."""
    monkeypatch.delenv("RMW_INTROSPECT_LIBRARY", raising=False)
    ros, cache = fake_ros(tmp_path / "empty-prefix"), tmp_path / "cache"
    entry = middleware.cache_entry(ros, cache)
    library = entry / "install" / "lib" / middleware.LIBRARY_FILE
    library.parent.mkdir(parents=True)
    (entry / "complete").write_text(f"{library}\n")
    for content, damage in ((fake_library.elf_header(900_000), "it is truncated (64 bytes; its ELF headers describe at least "
                                                              "900192)"),
                            (bytes(4096), "it is not an ELF shared library (4096 bytes that do not start like one)"),
                            (b"", "it is not an ELF shared library (0 bytes")):
        library.write_bytes(content)
        with pytest.raises(SetupError) as damaged:
            middleware.resolve_library(ros=ros, cache_dir=cache)
        assert str(damaged.value) == (
            f"The recording middleware library {library} (built) is damaged: {damage}"
            + str(damaged.value).split(damage, 1)[1])
        assert str(damaged.value).endswith(f"Delete its cache directory {entry} (rm -r) and run again: the "
                                           "middleware is built anew.")
    library.write_bytes(fake_library.WHOLE)
    assert middleware.resolve_library(ros=ros, cache_dir=cache).path == library


def test_a_damaged_library_named_by_the_environment_says_to_fix_the_variable(tmp_path, monkeypatch):
    damaged = tmp_path / middleware.LIBRARY_FILE
    damaged.write_bytes(fake_library.elf_header(900_000))
    monkeypatch.setenv("RMW_INTROSPECT_LIBRARY", str(damaged))
    with pytest.raises(SetupError, match="Point RMW_INTROSPECT_LIBRARY at a whole build of it") as refused:
        middleware.resolve_library()
    assert f"library {damaged.resolve()} (environment) is damaged: it is truncated" in str(refused.value)
