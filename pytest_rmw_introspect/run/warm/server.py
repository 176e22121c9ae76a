"""The warm start server: a Python process that has imported rclpy, ``rclpy.node``, numpy and
common message packages once, and forks one child per capture that becomes the target.

It runs as ``python -c BOOTSTRAP FD`` (``client.server_command``) with the middleware preloaded
and the import-relevant part of the targets' environment (``client.server_key``), talking to its
runner over FD, a ``SOCK_SEQPACKET`` Unix socket (one JSON message per packet):

* server → runner, once: ``{"ready": true, "pid": ..., "preloaded": [...]}`` after the imports;
* runner → server: ``{"op": "spawn", ...}`` with four file descriptors (SCM_RIGHTS): a reply
  socket of this capture and the child's stdin, stdout and stderr. The server forks; on the
  reply socket it answers ``{"pid": N}``, later ``{"returncode": RC}`` when the child ended
  (``-SIG`` for a signal, like ``subprocess``). The child stays unreaped (a zombie, so its
  pid and process group id cannot be reused) until the runner closes the reply socket; a reply
  socket closed while the child still runs means the runner gave up: the child's group is killed;
* runner → server: ``{"op": "preload", "types": [...]}``: message packages (and their type
  supports) later targets will probably use, imported while the server is idle;
* end of file on FD (the runner closed it or died): every child's group is killed, the server exits.

A server may be **shared** (pytest-xdist workers of one run, see ``client.Pool.share_within``): it is
then also given a listening socket (``LISTEN_FD``) and serves every runner that connects to it
with this user's uid (``SO_PEERCRED``), each connection like FD: the ready message, then spawn
and preload requests. A runner closing its connection only ends its own children (their reply
sockets close with it). When FD (its owner) reaches end of file, a shared server stops accepting,
tells the owner how many runners are still connected (``{"clients": N}``, and again whenever one
leaves) and exits when the last one is gone; the owner waits for that (``client.WarmServer.close``).

The child (:meth:`Server.become_target`) does what a cold start would have done: a session and
process group of its own (``setsid``), the parent-death signal SIGKILL (tied to the server, which
is itself tied to the runner: when the runner dies, both die), the three standard streams, the
signal dispositions and mask the interpreter started with, the target's environment, working
directory and umask, ``sys.argv``/``sys.orig_argv``/``sys.path``/``sys.executable``, a fresh
``__main__`` module, then returns a :class:`Job` that the bootstrap runs at the top level (so
``SystemExit``, an uncaught exception, ``KeyboardInterrupt``, ``atexit`` handlers and the
interpreter's finalization behave as in a process of its own). The middleware reads its
settings (``RMW_INTROSPECT_OUTPUT``, ...) when the target first uses it, after the fork: the
server imports ROS but never calls ``rclpy.init()`` or anything else that reaches the middleware.

Only the standard library is imported at module level; the ROS modules are imported by
:func:`main` through ``importlib`` (they are what this process exists for).
"""

from __future__ import annotations

import builtins
import ctypes
import gc
import importlib
import importlib.machinery
import inspect
import json
import os
import runpy
import selectors
import signal
import socket
import struct
import sys
import time
import types
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any, NoReturn

#: imported before the server says it is ready: what every rclpy node needs
#: (``rclpy.node.Node()`` imports the parameter and type-description services, and numpy)
PRELOAD_MODULES = (
    "rclpy",
    "rclpy.node",
    "rclpy.executors",
    "rclpy.qos",
    "rclpy.action",
    "rclpy.lifecycle",
    "numpy",
    "std_msgs.msg",
)
#: type supports every node loads when it creates its parameter and type-description services
#: (and the most common message package's)
PRELOAD_TYPES = (
    "rcl_interfaces/msg/ParameterEvent",
    "rcl_interfaces/msg/Log",
    "rcl_interfaces/srv/DescribeParameters",
    "rcl_interfaces/srv/GetParameterTypes",
    "rcl_interfaces/srv/GetParameters",
    "rcl_interfaces/srv/ListParameters",
    "rcl_interfaces/srv/SetParameters",
    "rcl_interfaces/srv/SetParametersAtomically",
    "type_description_interfaces/srv/GetTypeDescription",
    "std_msgs/msg/String",  # loads std_msgs' C type support: the package most nodes use
)
#: seconds an ``os._exit()`` of the target waits at most for the capture the middleware has pending
PENDING_CAPTURE_WAIT = 2.0
#: the middleware writes a progress snapshot 20 ms after its last change (rmw_introspect_cpp's
#: session): a capture file left unchanged this long after a write is the last one to come. Not
#: 20 ms: a snapshot taken before the node was created can land just after os._exit() is called,
#: and on a loaded 2-core machine the writer thread may wait well over 60 ms to write the next
#: (a fresh-clone CI read "no node created" from such a warm os._exit target, 2026-12-08)
CAPTURE_QUIET = 0.25
MAX_MESSAGE = 1 << 20
SPAWN_FDS = 4  # reply socket, stdin, stdout, stderr
_PR_SET_PDEATHSIG = 1
#: frames of this module and of the bootstrap (``-c``) are not the target's: tracebacks skip them
_OWN_FILES = frozenset({__file__, "<string>"})


def _libc() -> ctypes.CDLL | None:
    try:
        return ctypes.CDLL("libc.so.6", use_errno=True)
    except OSError:
        return None


_LIBC = _libc()


# ------------------------------------------------------------------------------------ imports


def type_module(type_name: str) -> tuple[str, str] | None:
    """``pkg/msg/Name`` → (``pkg.msg``, ``Name``); action parts (``X_SendGoal``) → the action ``X``."""
    parts = type_name.split("/")
    if len(parts) != 3 or not all(p.isidentifier() for p in parts) or parts[1] not in ("msg", "srv", "action"):
        return None
    name = parts[2]
    if parts[1] == "action":
        for suffix in ("_SendGoal", "_GetResult", "_FeedbackMessage", "_Feedback", "_Goal", "_Result"):
            if name.endswith(suffix):
                name = name[: -len(suffix)]
                break
    return f"{parts[0]}.{parts[1]}", name


def preload(modules: Iterable[str] = (), type_names: Iterable[str] = ()) -> list[str]:
    """Import ``modules`` and the message packages of ``type_names`` with their C type supports
    (what rclpy loads when a node first creates an endpoint of that type). Failures are ignored:
    a module this server cannot import is imported (or not) by the target itself. Returns the
    modules imported."""
    done: list[str] = []
    for name in modules:
        try:
            importlib.import_module(name)
            done.append(name)
        except Exception:  # noqa: BLE001  # the target will meet the same error, in its own process
            pass
    for type_name in type_names:
        found = type_module(type_name)
        if found is None:
            continue
        module_name, class_name = found
        try:
            module = importlib.import_module(module_name)
            cls = getattr(module, class_name)
            for part in (cls, getattr(cls, "Request", None), getattr(cls, "Response", None)):
                if part is not None:
                    type(part).__import_type_support__()
            if module_name not in done:
                done.append(module_name)
        except Exception:  # noqa: BLE001
            pass
    for package in sorted({name.split(".")[0] for name in done if name.endswith((".msg", ".srv", ".action"))}):
        load_introspection(package)
    index_module_files()
    return done


_INTROSPECTION_LOADED: set[str] = set()


def load_introspection(package: str) -> None:
    """Load ``package``'s C introspection type support library, which the middleware opens (through
    the package's C type support) for every type it describes: opened here once, a forked target
    finds it mapped and relocated instead of loading it again. Found the way the type support
    finds it (the dynamic loader's search path); a package without one is left alone."""
    if package in _INTROSPECTION_LOADED:
        return
    _INTROSPECTION_LOADED.add(package)
    try:
        ctypes.CDLL(f"lib{package}__rosidl_typesupport_introspection_c.so", mode=os.RTLD_LAZY | os.RTLD_LOCAL)
    except OSError:
        pass


#: the BLAS thread-count variables numpy's OpenBLAS reads when it is loaded
BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS")


def single_threaded_blas() -> None:
    """Load numpy's OpenBLAS without its thread pool, unless the targets' environment sizes it.
    The pool's threads spin while they wait for work, and OpenBLAS stops and restarts them around
    every fork: a few percent of every warm capture's CPU, in the server and each child. The
    variable is only this process's: a child gets the target's environment (``_set_up``), and
    a target that sets one of these variables gets a server of its own that keeps it."""
    if not any(name in os.environ for name in BLAS_THREAD_VARIABLES):
        os.environ["OPENBLAS_NUM_THREADS"] = "1"


def index_module_files() -> None:
    """Fill :mod:`inspect`'s module-by-file cache for every module imported so far, as the
    first log call of a node does: rclpy's logger finds its caller with
    ``inspect.getframeinfo``, whose ``getmodule`` resolves the real path of every loaded
    module's file (hundreds of ``lstat`` calls, 20-60 ms) once per process. Done in the server,
    a forked target inherits the cache and resolves only the modules it imports itself; the
    cache maps files to module names, the same in the child as here."""
    try:
        inspect.getframeinfo(sys._getframe())  # findsource → getmodule: the cache
    except Exception:  # noqa: BLE001  # a cache: without it the target only pays the cost itself
        pass


# ------------------------------------------------------------------------------------ fork


class _LttngFork:
    """lttng-ust (loaded by librcl's tracepoints) runs two listener threads from the moment it is
    loaded. A fork must go through its fork hooks (what ``liblttng-ust-fork.so`` does for
    programs that preload it): they take lttng's locks before the fork and give the child its
    own listener threads, as a freshly started process has."""

    def __init__(self) -> None:
        self.before: Callable[[Any], Any] | None = None
        self.after_parent: Callable[[Any], Any] | None = None
        self.after_child: Callable[[Any], Any] | None = None
        try:
            with open("/proc/self/maps", encoding="utf-8", errors="replace") as maps:
                paths = {line.split()[-1] for line in maps if "liblttng-ust" in line and "/" in line}
        except OSError:
            return
        for path in sorted(paths):
            base = os.path.basename(path)
            if not base.startswith("liblttng-ust") or base.startswith(("liblttng-ust-tracepoint", "liblttng-ust-fork")):
                continue
            try:
                lib = ctypes.CDLL(path, mode=os.RTLD_NOLOAD | os.RTLD_LOCAL)
            except OSError:
                continue
            for prefix in ("lttng_ust_", "ust_"):  # lttng-ust 2.13 / 2.12
                try:
                    self.before = getattr(lib, prefix + "before_fork")
                    self.after_parent = getattr(lib, prefix + "after_fork_parent")
                    self.after_child = getattr(lib, prefix + "after_fork_child")
                    return
                except AttributeError:
                    continue

    def fork(self) -> int:
        sigset = ctypes.create_string_buffer(256)  # sigset_t (128 bytes on Linux), saved by lttng
        if self.before is not None:
            self.before(sigset)
        try:
            pid = os.fork()
        except BaseException:
            if self.after_parent is not None:
                self.after_parent(sigset)
            raise
        if pid == 0:
            if self.after_child is not None:
                self.after_child(sigset)
        elif self.after_parent is not None:
            self.after_parent(sigset)
        return pid


# ------------------------------------------------------------------------------------ the job


@dataclass
class Job:
    """What the child runs at the top level of the interpreter: a script file or a module."""

    kind: str  # "script" or "module"
    target: str  # the script's path as a cold start sees it in argv, or the module name


def _main_module(file: str | None) -> types.ModuleType:
    """A fresh ``__main__`` with the attributes the interpreter gives a script's (or ``-m``'s, which
    runpy fills in)."""
    main = types.ModuleType("__main__")
    main.__dict__.update(__builtins__=builtins, __annotations__={}, __spec__=None,
                         __package__=None, __cached__=None)
    if file is not None:
        main.__file__ = file
        main.__loader__ = importlib.machinery.SourceFileLoader("__main__", file)
    return main


def _trim(tb: types.TracebackType | None) -> types.TracebackType | None:
    while tb is not None and tb.tb_frame.f_code.co_filename in _OWN_FILES:
        tb = tb.tb_next
    return tb


def _excepthook(exc_type: type[BaseException], exc: BaseException, tb: types.TracebackType | None) -> None:
    """An uncaught exception of the target, printed as a cold start prints it (without the frames
    of the bootstrap and this module, which a cold start does not have)."""
    trimmed = _trim(tb)
    if isinstance(exc, BaseException):
        exc = exc.with_traceback(trimmed)  # the display reads the exception's own traceback
    sys.__excepthook__(exc_type, exc, trimmed)


def run(job: Job) -> None:
    """Run the target in this (forked) process, at the top level of the bootstrap."""
    if job.kind == "module":
        # runpy._run_module_as_main is what `python -m` itself calls
        runpy._run_module_as_main(job.target, alter_argv=True)  # type: ignore[attr-defined]
        return
    try:
        with open(job.target, "rb") as f:
            source = f.read()
    except OSError as exc:
        print(f"{sys.executable}: can't open file {job.target!r}: [Errno {exc.errno}] {exc.strerror}",
              file=sys.stderr)
        raise SystemExit(2) from None
    filename = job.target if os.path.isabs(job.target) else os.path.join(os.getcwd(), job.target)
    code = compile(source, filename, "exec", dont_inherit=True)
    exec(code, sys.modules["__main__"].__dict__)  # noqa: S102  # the target, as `python script` runs it


_REAL_EXIT = os._exit


def _ros_initialised() -> bool:
    rclpy = sys.modules.get("rclpy")
    try:
        return bool(rclpy is not None and rclpy.ok())
    except Exception:  # noqa: BLE001  # a target may have broken rclpy in any way: then nothing is pending
        return False


def wait_for_pending_capture(path: str, *, wait: float = PENDING_CAPTURE_WAIT, quiet: float = CAPTURE_QUIET) -> None:
    """Give the middleware the time to write the capture it has pending to ``path`` (its progress
    snapshot, due 20 ms after its last change): return once a write that came after this call
    was followed by ``quiet`` seconds without another, or after ``wait`` seconds. Nothing is
    pending when ROS was never initialised and no capture was written."""

    def inode() -> int | None:
        try:
            return os.stat(path).st_ino  # each write is a new file renamed over the last one
        except OSError:
            return None

    seen = inode()
    if seen is None and not _ros_initialised():
        return
    written_at: float | None = None
    deadline = time.monotonic() + wait
    while time.monotonic() < deadline:
        now = inode()
        if now is not None and now != seen:
            seen, written_at = now, time.monotonic()
        elif written_at is not None and time.monotonic() - written_at >= quiet:
            return
        time.sleep(0.005)


def _exit_after_pending_capture(target_pid: int, output: str) -> Callable[[int], NoReturn]:
    """``os._exit`` for the target: a target that creates its node and calls ``os._exit()`` at once
    ends before the middleware's progress snapshot is due. A cold start spends that time
    importing what the node needs (the snapshot is written meanwhile); a warm child has
    everything imported, so its ``os._exit`` first lets the pending capture be written."""
    path = output.replace("<pid>", str(target_pid))

    def _exit(status: int) -> NoReturn:
        if os.getpid() == target_pid:  # not in processes the target forks (multiprocessing ends them so)
            wait_for_pending_capture(path)
        _REAL_EXIT(status)

    return _exit


# ------------------------------------------------------------------------------------ server


@dataclass
class _Child:
    pid: int
    reply: socket.socket | None
    reported: bool = False


@dataclass
class _Client:
    """A runner connected to a shared server (not its owner)."""

    sock: socket.socket


@dataclass
class Server:
    """The serve loop (single-threaded: it forks from it)."""

    control: socket.socket
    base_path: list[str]
    #: a shared server's listening socket (None: only the owner's control socket is served)
    listener: socket.socket | None = None
    ready_message: dict[str, Any] = field(default_factory=dict)
    selector: selectors.BaseSelector = field(default_factory=selectors.DefaultSelector)
    children: dict[int, _Child] = field(default_factory=dict)
    clients: list[_Client] = field(default_factory=list)
    owner_gone: bool = False
    lttng: _LttngFork = field(default_factory=_LttngFork)
    learned: set[str] = field(default_factory=set)
    pid_at_start: int = field(default_factory=os.getpid)

    def __post_init__(self) -> None:
        valid = sorted(signal.valid_signals())
        self.initial_signals = {sig: signal.getsignal(sig) for sig in valid
                                if sig not in (signal.SIGKILL, signal.SIGSTOP)}
        # a target starts with SIGINT and SIGQUIT at their default, as a cold start of
        # `python script` does (process.DEFAULT_IN_TARGETS), even when the runner, and so this
        # server, ignores them (started with `cmd &` by a non-interactive shell: issue 50, N30)
        self.initial_signals[signal.SIGINT] = signal.default_int_handler
        self.initial_signals[signal.SIGQUIT] = signal.SIG_DFL
        self.initial_mask = signal.pthread_sigmask(signal.SIG_BLOCK, [])
        self.wake_r, self.wake_w = os.pipe()
        os.set_blocking(self.wake_r, False)
        os.set_blocking(self.wake_w, False)
        signal.set_wakeup_fd(self.wake_w)
        signal.signal(signal.SIGCHLD, lambda signum, frame: None)
        self.selector.register(self.control, selectors.EVENT_READ, None)
        self.selector.register(self.wake_r, selectors.EVENT_READ, None)
        if self.listener is not None:
            self.listener.setblocking(False)
            self.selector.register(self.listener, selectors.EVENT_READ, None)

    # ---------------------------------------------------------------- loop
    def serve(self) -> Job | None:
        """Serve until the runner goes away (returns None) or, in a forked child, return its job."""
        try:
            while True:
                for key, _events in self.selector.select():
                    if key.fileobj is self.control or isinstance(key.data, _Client):
                        client = key.data if isinstance(key.data, _Client) else None
                        outcome = self._on_control(client.sock if client is not None else self.control)
                        if isinstance(outcome, Job):
                            return outcome
                        if outcome is False:
                            if client is not None:
                                self._drop_client(client)
                            else:
                                self._owner_left()
                            if self.owner_gone and not self.clients:
                                return None
                    elif key.fileobj is self.listener:
                        self._accept()
                    elif key.fileobj == self.wake_r:
                        try:
                            while os.read(self.wake_r, 512):
                                pass
                        except BlockingIOError:
                            pass
                    else:
                        self._on_reply(key.data)
                self._collect()
        finally:
            if os.getpid() == self.pid_at_start:
                self._kill_all()

    # ---------------------------------------------------------------- runners of a shared server
    def _accept(self) -> None:
        assert self.listener is not None
        try:
            sock, _addr = self.listener.accept()
        except OSError:  # nobody waiting after all (non-blocking), or the connection went away
            return
        sock.setblocking(True)
        if peer_uid(sock) != os.getuid():  # another user: refused
            sock.close()
            return
        client = _Client(sock)
        self.clients.append(client)
        self.selector.register(sock, selectors.EVENT_READ, client)
        _send(sock, self.ready_message)

    def _drop_client(self, client: _Client) -> None:
        """A runner closed its connection (or died): its children's reply sockets closed with it."""
        self.selector.unregister(client.sock)
        client.sock.close()
        self.clients.remove(client)
        if self.owner_gone:
            _send(self.control, {"clients": len(self.clients)})

    def _owner_left(self) -> None:
        """The owner closed its side: no new runner is accepted; those connected are served on."""
        self.owner_gone = True
        self.selector.unregister(self.control)
        if self.listener is not None:
            self.selector.unregister(self.listener)
            self.listener.close()
            self.listener = None
        _send(self.control, {"clients": len(self.clients)})

    def _on_control(self, sock: socket.socket) -> Job | bool:
        try:
            data, fds, _flags, _addr = socket.recv_fds(sock, MAX_MESSAGE, SPAWN_FDS)
        except (ConnectionResetError, OSError):
            return False
        if not data:
            for fd in fds:
                os.close(fd)
            return False  # the runner closed its end or died
        try:
            request = json.loads(data)
            op = request.get("op")
        except (ValueError, AttributeError):
            op, request = None, {}
        if op == "spawn" and len(fds) == SPAWN_FDS:
            return self._spawn(request, fds)
        for fd in fds:
            os.close(fd)
        if op == "preload":
            types_ = [t for t in request.get("types", []) if isinstance(t, str) and t not in self.learned]
            self.learned.update(types_)
            preload((), types_)
        elif op == "shutdown":
            return False
        return True

    def _spawn(self, request: Mapping[str, Any], fds: list[int]) -> Job | bool:
        reply = socket.socket(fileno=fds[0])
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):
                pass
        gc.freeze()  # the child's collections leave the server's objects (and their pages) alone
        try:
            pid = self.lttng.fork()
        except OSError as exc:
            _send(reply, {"error": f"fork failed: {exc}"})
            reply.close()
            for fd in fds[1:]:
                os.close(fd)
            return True
        if pid == 0:
            return self.become_target(request, reply, fds[1:])
        for fd in fds[1:]:
            os.close(fd)
        child = _Child(pid, reply)
        self.children[pid] = child
        self.selector.register(reply, selectors.EVENT_READ, child)
        _send(reply, {"pid": pid})
        return True

    def _on_reply(self, child: _Child) -> None:
        """The runner closed the reply socket of ``child``: it is done with it (or gave up)."""
        assert child.reply is not None
        try:
            data = child.reply.recv(MAX_MESSAGE)
        except OSError:
            data = b""
        if data:
            return  # nothing is expected from the runner on this socket
        self.selector.unregister(child.reply)
        child.reply.close()
        child.reply = None
        if not child.reported:
            _kill_group(child.pid)

    def _collect(self) -> None:
        """Report children that ended (without reaping them while the runner may still signal
        them) and reap those the runner is done with."""
        for pid, child in list(self.children.items()):
            if child.reply is None:
                try:
                    done, _status = os.waitpid(pid, os.WNOHANG)
                except ChildProcessError:
                    done = pid
                if done:
                    del self.children[pid]
                continue
            if child.reported:
                continue
            try:
                info = os.waitid(os.P_PID, pid, os.WEXITED | os.WNOHANG | os.WNOWAIT)
            except ChildProcessError:
                info = None
            if info is None:
                continue
            returncode = info.si_status if info.si_code == os.CLD_EXITED else -info.si_status
            child.reported = True
            _send(child.reply, {"returncode": returncode})

    def _kill_all(self) -> None:
        for pid in list(self.children):
            _kill_group(pid)
        for pid in list(self.children):
            try:
                os.waitpid(pid, 0)
            except ChildProcessError:
                pass
        self.children.clear()

    # ---------------------------------------------------------------- in the child
    def become_target(self, request: Mapping[str, Any], reply: socket.socket, stdio: list[int]) -> Job | bool:
        """In the forked child: become the process a cold start of the target would be."""
        server = os.getppid()
        try:
            os.setsid()
            if _LIBC is not None:
                _LIBC.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
            if os.getppid() != server:  # the server died before the signal was armed
                os._exit(1)
            signal.set_wakeup_fd(-1)
            self.selector.close()
            for sock in (self.control, reply, *(c.reply for c in self.children.values() if c.reply),
                         *(c.sock for c in self.clients), *([self.listener] if self.listener else [])):
                sock.close()
            self.clients.clear()
            self.listener = None
            self.children.clear()
            os.close(self.wake_r)
            os.close(self.wake_w)
            for target_fd, fd in enumerate(stdio):
                os.dup2(fd, target_fd)
                os.close(fd)
            for sig, handler in self.initial_signals.items():
                if signal.getsignal(sig) is not handler and handler is not None:
                    signal.signal(sig, handler)
            signal.pthread_sigmask(signal.SIG_SETMASK, self.initial_mask)
            self._set_up(request)
        except BaseException as exc:  # noqa: BLE001  # never return into the server's loop
            try:
                os.write(2, f"rmw-introspect warm start: cannot set up the target: {exc!r}\n".encode())
            finally:
                os._exit(127)
        return Job(kind=str(request["kind"]), target=str(request["target"]))

    def _set_up(self, request: Mapping[str, Any]) -> None:
        env = request["env"]
        os.environ.clear()
        os.environ.update(env)
        os.chdir(request["cwd"])
        os.umask(int(request["umask"]))
        sys.argv = list(request["argv"])
        sys.orig_argv = list(request["orig_argv"])
        if request.get("executable"):
            sys.executable = str(request["executable"])
        kind, target = request["kind"], request["target"]
        if kind == "script":
            file = target if os.path.isabs(target) else os.path.join(os.getcwd(), target)
            path0 = os.path.dirname(os.path.realpath(target))
            main = _main_module(file)
        else:
            path0 = os.getcwd()
            main = _main_module(None)
        sys.path[:] = ([] if sys.flags.safe_path else [path0]) + self.base_path
        sys.modules["__main__"] = main
        sys.excepthook = _excepthook
        if env.get("RMW_INTROSPECT_OUTPUT"):
            os._exit = _exit_after_pending_capture(os.getpid(), env["RMW_INTROSPECT_OUTPUT"])  # type: ignore[assignment]
        numpy_random = sys.modules.get("numpy.random")
        if numpy_random is not None:  # a fresh process seeds numpy's global generator afresh
            numpy_random.seed()


def _send(sock: socket.socket | None, message: Mapping[str, Any]) -> None:
    """Send without ever blocking: the server serves every runner, so one that does not read must
    not stop it. Nothing fills a socket today (a child's pid and end are the only messages on its
    socket; the owner gets a report per runner leaving, after its own end): a message that would
    block is dropped rather than waited for, should that change."""
    if sock is None:
        return
    try:
        sock.send(json.dumps(message).encode(), socket.MSG_DONTWAIT)
    except OSError:
        pass


def _kill_group(pid: int) -> None:
    for kill in (os.killpg, os.kill):
        try:
            kill(pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass


def exit_server() -> None:
    """End the server at once: its children are gone, and finalizing an interpreter that holds
    rclpy, numpy and the message packages takes ~150 ms the runner would wait for."""
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
    os._exit(0)


def peer_uid(sock: socket.socket) -> int | None:
    """The uid of the process at the other end of a Unix socket (``SO_PEERCRED``)."""
    try:
        creds = sock.getsockopt(socket.SOL_SOCKET, socket.SO_PEERCRED, struct.calcsize("3i"))
    except OSError:
        return None
    return int(struct.unpack("3i", creds)[1])


def main(fd: int, listen_fd: int = -1) -> Job | None:
    """The server: import what targets need, say ready on ``fd`` (and to each runner that
    connects to ``listen_fd``, a shared server's listening socket), serve. Returns None when it
    should exit, or in a forked child the job to run."""
    started = time.monotonic()
    control = socket.socket(fileno=fd)
    listener = socket.socket(fileno=listen_fd) if listen_fd >= 0 else None
    base_path = sys.path[:] if sys.flags.safe_path else sys.path[1:]
    single_threaded_blas()
    done = preload(PRELOAD_MODULES, PRELOAD_TYPES)
    server = Server(control, base_path, listener)
    server.ready_message = {
        "ready": True, "pid": os.getpid(), "preloaded": done, "lttng_fork_hooks": server.lttng.before is not None,
        "shared": listener is not None, "seconds": round(time.monotonic() - started, 3),
    }
    _send(control, server.ready_message)
    return server.serve()
