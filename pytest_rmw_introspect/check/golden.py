"""Writing contracts: the one writer every front end uses, CI refusal, and what was written.

* :func:`update` writes a contract's ``nodes`` (creating the file, or replacing only its
  ``nodes:`` block so comments, ``target:`` and ``options:`` above it stay as they are);
  :func:`write_text` writes any other file a front end produces (``rmw-introspect capture -o``).
  Both write atomically (a temporary file in the same directory, then a rename) under a file
  lock keyed by the absolute path, so tests sharing a golden under pytest-xdist write it once
  (the second writer finds the bytes it would write already there) and a killed run never
  leaves half a file. The locks live in a directory only the calling user can create files in
  (:func:`lock_directory`). A symlinked golden is written through the link (the shared file is
  updated, the link stays); an existing file keeps its permission bits, owner and group, and a
  file with several hard links stays one file (both rewritten in place where a rename cannot
  keep them); a read-only file is refused, not replaced; a file with CRLF line endings keeps
  them (its header byte for byte). Failures are :class:`GoldenWriteError`.
* :func:`new_contract_text` is a complete new contract with a header saying how it was written
  and a ``target:`` block (paths relative to the contract's directory).
* ``ci_refusal()`` and the record of what was written (``GoldenSession``) are in
  :mod:`.golden_record`, which a pytest session's controller needs without the writer.
"""

from __future__ import annotations

import hashlib
import os
import secrets
import stat
import tempfile
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import yaml

from ..errors import ContractError, GoldenWriteError, LockTimeout, UnsafeLockDirectory
from ..model import contract as contract_module
from ..model import types as type_model
from ..model import untrusted, yaml_blocks
from ..model.contract_shapes import ContractNode
from ..model.paths import relative_or_absolute
from ..run import locks
from ..run.target import TargetSpec
from .golden_record import CREATED, UPDATED

LOCK_TIMEOUT = 120.0


# ---------------------------------------------------------------------------- the writer


#: the calling user's lock directory in the temporary directory: ``<name>-<uid>``, mode 0700
LOCK_DIRECTORY = "pytest-rmw-introspect-locks"


def lock_directory() -> Path:
    """The directory of the golden-write locks: ``<tempdir>/pytest-rmw-introspect-locks-<uid>``,
    created with mode 0700. Lock names are predictable (a digest of the golden's path) and
    filelock opens them for writing, so a directory another user could create entries in would
    let that user plant a lock name as a symlink to any file the victim can write. The
    directory must therefore be a real directory (not a symlink), owned by the calling user,
    with no permission for anyone else; otherwise nothing is written (raises
    UnsafeLockDirectory with what is wrong and what to do)."""
    uid = os.geteuid()
    directory = Path(tempfile.gettempdir()) / f"{LOCK_DIRECTORY}-{uid}"
    try:
        os.mkdir(directory, 0o700)
    except FileExistsError:
        pass
    info = os.lstat(directory)
    if stat.S_ISLNK(info.st_mode) or not stat.S_ISDIR(info.st_mode):
        problem = "is not a directory (a symlink or a file)"
    elif info.st_uid != uid:
        problem = f"belongs to uid {info.st_uid}, not to you (uid {uid})"
    elif stat.S_IMODE(info.st_mode) & 0o077:
        problem = f"has mode {stat.S_IMODE(info.st_mode):04o}: other users may create files in it or read it"
    else:
        return directory
    raise UnsafeLockDirectory(
        f"its lock directory {directory} {problem}, so another user may have planted it: nothing was written",
        f"Remove that directory if you do not know where it comes from (rm -r {directory}), or set TMPDIR "
        "to a directory of your own.")


def lock_path(path: Path) -> Path:
    """The golden-write lock of ``path`` (in :func:`lock_directory`; its holder's pid beside it)."""
    key = hashlib.sha256(str(path.resolve()).encode()).hexdigest()[:24]
    return lock_directory() / f"{key}.lock"


def _read_only(target: Path, info: os.stat_result) -> str | None:
    """Why an existing file must not be replaced, or None. A rename would replace a read-only
    file (the directory is what a rename needs), so permission is asked of the file: no write
    bit at all (which root ignores) or no write access for the caller."""
    mode = stat.S_IMODE(info.st_mode)
    if not mode & 0o222 or not os.access(target, os.W_OK):
        return f"it is read-only (mode {mode:04o}, owner uid {info.st_uid}) and was left as it is"
    return None


def _replace(target: Path, data: bytes, old: os.stat_result | None) -> None:
    """Write ``data`` to ``target``: atomically (a temporary file renamed over it) when the
    rename keeps what the file was, else in place. An existing file keeps its permission bits,
    owner and group; a rename cannot keep the owner and group where the caller may not set
    them (someone else's file, writable through its group), nor the other names of a file with
    several hard links (it would split them): such a file is rewritten in place, which keeps
    all of that but is not atomic."""
    if old is not None and old.st_nlink > 1:
        _rewrite_in_place(target, data)
        return
    tmp, fd = _new_temporary(target)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            owner_kept = old is None or _carry_over(fd, old)
        if owner_kept:
            tmp.replace(target)
        else:
            _rewrite_in_place(target, data)
    finally:
        tmp.unlink(missing_ok=True)


def _carry_over(fd: int, old: os.stat_result) -> bool:
    """Give the open file ``fd`` the permission bits, owner and group of ``old``; False when
    the caller may not set that owner and group."""
    os.fchmod(fd, stat.S_IMODE(old.st_mode))
    if (old.st_uid, old.st_gid) == (os.geteuid(), os.getegid()):
        return True
    try:
        os.fchown(fd, old.st_uid, old.st_gid)
    except PermissionError:
        return False
    return True


def _new_temporary(target: Path) -> tuple[Path, int]:
    """A new file next to ``target`` for its next text, opened for writing. Its name is not
    predictable and it is created exclusively, never through a symlink: in a directory others
    may write to, a name planted as a symlink would make this write another file."""
    while True:
        tmp = target.with_name(f".{target.name}.{os.getpid()}.{secrets.token_hex(6)}.tmp")
        try:
            return tmp, os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC, 0o666)
        except FileExistsError:
            continue


def _rewrite_in_place(target: Path, data: bytes) -> None:
    fd = os.open(target, os.O_WRONLY | os.O_NOFOLLOW | os.O_CLOEXEC)
    with os.fdopen(fd, "wb") as f:
        f.write(data)
        f.truncate()
        f.flush()
        os.fsync(f.fileno())


def _write_locked(path: Path, new_text: Callable[[str | None], str], timeout: float) -> bool:
    """Under the path's lock: compute the new text from the current one (None: no file) and
    replace the file (:func:`_replace`) when it differs. True when the file's bytes changed.

    Text is handled with LF line endings; a file that used CRLF gets CRLF back. Raises
    GoldenWriteError."""
    target = path.resolve() if path.is_symlink() else path  # write through a link, keep the link
    try:
        with locks.held(lock_path(target), timeout):
            info = _existing(target)
            old_bytes = target.read_bytes() if info is not None else None
            old = old_bytes.decode("utf-8") if old_bytes is not None else None
            crlf = old is not None and "\r\n" in old
            text = new_text(old.replace("\r\n", "\n") if old is not None else None)
            if crlf:
                text = text.replace("\r\n", "\n").replace("\n", "\r\n")
            if old == text:
                return False
            refusal = _read_only(target, info) if info is not None else None
            if refusal is not None:
                raise GoldenWriteError(path, refusal, f"Make it writable (chmod u+w {path}) if it should be updated.")
            target.parent.mkdir(parents=True, exist_ok=True)
            _replace(target, text.encode("utf-8"), info)
            return True
    except UnsafeLockDirectory as exc:
        raise GoldenWriteError(path, *exc.args) from None
    except LockTimeout as exc:
        raise GoldenWriteError(path, f"another process held its lock for over {timeout:g} s ({exc.holder})",
                               "If that process is stopped or hung, end it (kill <pid>).") from None
    except UnicodeDecodeError as exc:
        raise GoldenWriteError(path, f"the existing file is not UTF-8 text ({exc.reason})") from None
    except OSError as exc:
        where = f" ({exc.filename})" if exc.filename and str(exc.filename) != str(path) else ""
        raise GoldenWriteError(path, f"{exc.strerror or exc}{where}") from None


def _existing(target: Path) -> os.stat_result | None:
    """The ``stat`` of the file to replace (None: there is none); raises GoldenWriteError for
    something that is not a regular file (a FIFO would block the read of its current text)."""
    try:
        info = os.stat(target)
    except FileNotFoundError:
        return None
    problem = untrusted.not_a_file(info.st_mode)
    if problem is not None:
        raise GoldenWriteError(target, f"it {problem}")
    return info


def write_text(path: str | Path, text: str, *, timeout: float = LOCK_TIMEOUT) -> bool:
    """Write ``text`` to ``path`` atomically under its lock; True when the bytes changed.
    Raises GoldenWriteError when the file or its directory cannot be written."""
    return _write_locked(Path(path), lambda _old: text, timeout)


def update(path: str | Path, nodes: Mapping[str, ContractNode], *, new_header: str | None = None,
           types: Mapping[str, type_model.TypeDescription] | None = None,
           distribution: str | None = None, target: Mapping[str, Any] | None = None,
           timeout: float = LOCK_TIMEOUT) -> str | None:
    """Write the golden at ``path`` with ``nodes``; return ``CREATED``, ``UPDATED`` or None
    (nothing to change). A new file starts with ``new_header`` (default: the plain contract
    header). Entries the golden spells differently but equivalently keep their spelling
    (``contract.preserve_spelling``); a broken golden is replaced, keeping its header when it
    can be found. ``types``: the ``types:`` section to write (``types.replace_section``);
    None leaves the file's section, if any, as it is. ``distribution``: the ROS 2 distribution
    the nodes were captured on, written as ``ros_distribution:`` into a new file and into an
    existing one that records one already (None leaves it as it is). ``target``: the
    ``target:`` block the golden states (a marker test's target, :func:`with_target`); None
    leaves the file's, if any, as it is."""
    path = Path(path)
    existed = path.exists()

    def new_text(old: str | None) -> str:
        # a new file records the distribution; an existing one keeps its header, but for the
        # distribution it already records
        text = contract_module.with_distribution(with_types(nodes_text(old), types), distribution,
                                                 add_missing=not old)
        return with_target(text, target)

    def nodes_text(old: str | None) -> str:
        wanted = nodes
        if old:
            try:
                current = contract_module.loads(old, path=path)
                wanted = contract_module.preserve_spelling(current.nodes, nodes)
            except ContractError:
                pass
            return contract_module.update_text(old, wanted)
        if new_header is not None:
            return contract_module.render(wanted, header=new_header)
        return contract_module.render(wanted)

    if not _write_locked(path, new_text, timeout):
        return None
    return UPDATED if existed else CREATED


def update_with(path: str | Path, new_text: Callable[[str | None], str], *,
                timeout: float = LOCK_TIMEOUT) -> str | None:
    """Write the file at ``path`` as ``new_text(current text or None)`` computes it, under its
    lock and atomically (system contracts); return ``CREATED``, ``UPDATED`` or None."""
    path = Path(path)
    existed = path.exists()
    if not _write_locked(path, new_text, timeout):
        return None
    return UPDATED if existed else CREATED


def with_types(text: str, types: Mapping[str, type_model.TypeDescription] | None) -> str:
    """``text`` with its ``types:`` section replaced by ``types`` (None: unchanged)."""
    return text if types is None else type_model.replace_section(text, types)


def with_target(text: str, target: Mapping[str, Any] | None) -> str:
    """``text`` whose top-level ``target:`` block states ``target`` (None: unchanged). A block
    that states it already (whatever its spelling) is kept byte for byte; one that states
    something else is replaced (its comments with it); a file without one gets it right above
    ``nodes:`` (above the comment lines directly over ``nodes:``). Every other line is kept."""
    if target is None:
        return text
    wanted = yaml.safe_dump({"target": dict(target)}, sort_keys=False, default_flow_style=False, allow_unicode=True)
    block = yaml_blocks.top_level_block(text, "target")
    if block is not None:
        lines, first, end = block
        try:
            current = yaml.safe_load("".join(lines[first:end]))
        except yaml.YAMLError:
            current = None
        if current == {"target": dict(target)}:
            return text
        return "".join(lines[:first]) + wanted + "".join(lines[end:])
    nodes = yaml_blocks.top_level_block(text, "nodes")
    if nodes is None:
        return text
    lines, at, _end = nodes
    while at > 0 and lines[at - 1].startswith("#"):
        at -= 1
    return "".join(lines[:at]) + wanted + "".join(lines[at:])


# ---------------------------------------------------------------------------- new contracts


def target_block(spec: TargetSpec, base: Path, run_dir: Path | None = None) -> dict[str, Any]:
    """A contract ``target:`` block for ``spec`` with paths relative to ``base`` (the contract's
    directory). ``run_dir``: the directory the target ran in; when its command line names
    relative paths that exist there and no ``cwd`` is set, ``cwd`` is recorded, so that the
    contract checks the same way from any directory."""
    block = spec.to_mapping()
    if run_dir is not None and "cwd" not in block and _names_relative_paths(spec, run_dir):
        block["cwd"] = str(run_dir.absolute())
    for key in ("script", "params_file", "cwd"):
        if key in block:
            block[key] = relative_or_absolute(Path(block[key]), base)
    if "command" in block and "/" in block["command"][0]:
        first = relative_or_absolute(Path(block["command"][0]).absolute(), base)
        block["command"][0] = first if "/" in first else "./" + first
    return block


def _names_relative_paths(spec: TargetSpec, run_dir: Path) -> bool:
    words = [*(spec.command or ())[1:], *spec.arguments]
    return any(w and not os.path.isabs(w) and not w.startswith("-") and (run_dir / w).exists() for w in words)


def new_contract_header(*, spec: TargetSpec, base: Path, include_infrastructure: bool = False,
                        how: str = "rmw-introspect capture", run_dir: Path | None = None) -> str:
    """The header of a new contract: how it was written, ``contract_version``, a ``target:``
    block (paths relative to ``base``, the contract's directory) and options."""
    header = (
        f"# Interface contract written by `{how}`.\n"
        "# Check it with `rmw-introspect check` or pytest (pytest-rmw-introspect); comments and keys\n"
        "# above `nodes:` are kept when it is updated.\n"
        f"contract_version: {contract_module.CONTRACT_VERSION}\n"
    )
    header += yaml.safe_dump({"target": target_block(spec, base, run_dir)}, sort_keys=False, default_flow_style=False,
                             allow_unicode=True)
    if include_infrastructure:
        header += "options:\n  include_infrastructure: true\n"
    return header


def new_contract_text(nodes: Mapping[str, ContractNode], *, spec: TargetSpec, base: Path,
                      include_infrastructure: bool = False, how: str = "rmw-introspect capture",
                      run_dir: Path | None = None, distribution: str | None = None) -> str:
    """A complete new contract: :func:`new_contract_header`, then ``nodes``; ``distribution``
    recorded as every new golden records it (``contract.with_distribution``)."""
    header = new_contract_header(spec=spec, base=base, include_infrastructure=include_infrastructure, how=how,
                                 run_dir=run_dir)
    return contract_module.with_distribution(contract_module.render(nodes, header=header), distribution)
