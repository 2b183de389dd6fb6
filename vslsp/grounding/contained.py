"""A user's predicates file run in a child process with limits, never in vslsp's own process.

``vslsp ground``, ``vslsp experiment`` (each of its workers) and the studio ground a user's
predicates (``--predicates FILE.py``, docs/grounding.md) through :class:`UserPredicates`: one
child per file for the whole command, asked once per observed scene for every atom of the
file's predicates. The child (:mod:`vslsp.grounding.contained_child`) is

- started with ``python -I`` (no ``PYTHON*`` variables, no user site, no script folder on the
  path; vslsp's own folder is put first on the path), in a fresh temporary folder as its working
  directory and ``HOME``, with an environment of ``PATH``, ``LANG``, ``HOME`` and ``TMPDIR`` only;
- its own process group (``start_new_session``): a terminal's Ctrl-C does not reach it, and at
  the end the whole group is killed (``SIGKILL``), with any process the user's code started;
  when vslsp itself is killed (SIGKILL), the guard it runs under
  (:func:`vslsp.interrupts.guarded_command`) kills them and removes the child's folder;
- limited: address space (``RLIMIT_AS``), CPU time (``RLIMIT_CPU``), processes
  (``RLIMIT_NPROC``, counted over the user's processes; no effect for root), each clamped to the
  hard limit vslsp has; a wall-clock deadline per call and for the whole session;
- fed standard input from ``/dev/null``; its standard output and error are one captured stream
  that vslsp copies to its own stderr (at most :attr:`Limits.output_bytes`), so what it prints
  or closes never touches vslsp's stdout.

Scenes go to the child and atoms come back as JSON lines over pipes (no pickle). Everything the
user's code does wrong is an :class:`~vslsp.errors.InputError` (exit 2) naming the file. This is
a boundary for resources and robustness, not a security sandbox: the code runs with the user's
rights and can read and write their files.
"""

from __future__ import annotations

import io
import json
import os
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import vslsp
from vslsp.errors import InputError
from vslsp.files import shown
from vslsp.grounding.predicates import Atom, Predicate, Scene, atoms_of
from vslsp.grounding.user_code import LOAD_TIME_LIMIT_S, PREDICATE_TIME_LIMIT_S
from vslsp.interrupts import WAIT_SLICE_S, guarded_command

if TYPE_CHECKING:
    import numpy as np

    from vslsp.grounding.operation import Grounding

_BOOTSTRAP = (
    "import sys; sys.path.insert(0, sys.argv[1]); "
    "from vslsp.grounding.contained_child import serve; "
    "serve(*map(int, sys.argv[2:6]))"
)
_MAX_REPLY_BYTES = 64_000_000
_GUARDED = sys.platform.startswith("linux")  # where guarded_command puts a guard between vslsp and the child


@dataclass(frozen=True)
class Limits:
    """What the child of a predicates file may use; every bound ends it with an error naming the file."""

    #: Seconds (wall clock) one call may take: loading the file, or every atom of one scene.
    call_s: float = 30.0
    #: Seconds (wall clock) of all calls of one session together (a command's whole grounding).
    session_s: float = 600.0
    #: Seconds one predicate call may take inside the child (stopped with a message naming the atom).
    predicate_s: float = PREDICATE_TIME_LIMIT_S
    #: Seconds loading the file may take inside the child (its imports included).
    load_s: float = LOAD_TIME_LIMIT_S
    #: Address space of the child (``RLIMIT_AS``), in MB.
    memory_mb: int = 2048
    #: CPU time of the child (``RLIMIT_CPU``), in seconds.
    cpu_s: int = 600
    #: Processes and threads the user's code may add (``RLIMIT_NPROC`` above the user's count now).
    processes: int = 32
    #: Bytes of the child's output copied to vslsp's stderr (the rest is counted, not shown).
    output_bytes: int = 64_000


DEFAULT_LIMITS = Limits()


class UserPredicates:
    """The running child of one predicates file; ``predicates`` are what ``load_predicates`` gives,
    each decided in the child (:func:`~vslsp.grounding.predicates.ground_atoms` asks once per scene).

    Use it as a context manager: ``with UserPredicates.start(path) as user: ground(..., predicates=
    with_builtins(user.predicates))``; leaving it kills the child's whole process group.
    """

    def __init__(self, path: Path, limits: Limits) -> None:
        self.path = path
        self.limits = limits
        self.name = shown(path)
        self._absolute = str(path.absolute())  # the child works in its own folder; messages name the file as given
        self.predicates: tuple[Predicate, ...] = ()
        self._owner = os.getpid()
        self._spent = 0.0
        self._lock = threading.Lock()
        #: Why the child was stopped (a deadline, its end, a bad reply); None while it runs.
        self.failure: str | None = None
        self._folder = tempfile.mkdtemp(prefix="vslsp-predicates-")
        self._output = _Relay(limits.output_bytes)
        self._buffer = b""
        requests_r, self._requests = os.pipe()
        os.set_blocking(self._requests, False)  # written with a deadline (_write)
        self._replies, replies_w = os.pipe()
        lifeline_r, self._lifeline = os.pipe()
        location = str(Path(vslsp.__file__).resolve().parent.parent)
        ours = (requests_r, replies_w, lifeline_r)
        watched = "0" if _GUARDED else str(os.getpid())
        try:
            self._process = subprocess.Popen(
                # Under a guard (vslsp.interrupts, Linux): when vslsp is killed, the guard kills this
                # process with every process the file started and removes the folder; the child then
                # has no pid of vslsp to watch ("0"): its parent is the guard.
                guarded_command(
                    [sys.executable, "-I", "-c", _BOOTSTRAP, location, *map(str, ours), watched],
                    self._folder if _GUARDED else None,
                ),
                stdin=subprocess.DEVNULL,
                stdout=subprocess.PIPE,
                stderr=subprocess.STDOUT,
                cwd=self._folder,
                env=_environment(self._folder),
                start_new_session=True,
                pass_fds=ours,
            )
        except OSError as error:
            self._close_fds()
            shutil.rmtree(self._folder, ignore_errors=True)
            raise InputError(f"predicates file {self.name}: cannot start its process: {error}") from None
        finally:
            for fd in ours:
                os.close(fd)
        assert self._process.stdout is not None
        self._output.start(self._process.stdout)  # type: ignore[arg-type]  # a BufferedReader (bufsize -1)

    @classmethod
    def start(cls, path: str | Path, limits: Limits | None = None) -> UserPredicates:
        """Start the child and load ``path`` in it (errors of the file: InputError, the child ended)."""
        from vslsp.grounding.loader import check_predicates_file

        check_predicates_file(Path(path))  # before a process starts, in the words load_predicates has
        chosen = limits or DEFAULT_LIMITS
        user = cls(Path(path), chosen)
        try:
            absolute = user._absolute
            reply = user._call({"load": absolute, "limits": _child_limits(chosen)}, chosen.call_s + chosen.load_s)
            try:
                user.predicates = tuple(
                    Predicate(str(p["name"]), int(p["arity"]), _Remote(user, str(p["name"])), source=user)
                    for p in reply["predicates"]
                )
            except (KeyError, TypeError, ValueError):
                raise user._broken("answered something that is not its predicates") from None
        except BaseException:
            user.close()
            raise
        return user

    def __reduce__(self) -> tuple:
        # Sent to another process (an experiment's result from a worker), it is that process's
        # own child of the same file: the predicates stay what they are, the process is not shared.
        return (_shared, (str(self.path.resolve()), self.limits))

    def __enter__(self) -> UserPredicates:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def evaluate(self, scene: Scene, predicates: Sequence[Predicate]) -> dict[Atom, bool]:
        """Every ground atom of ``predicates`` (this file's) over the scene, with its value, in the
        order :func:`~vslsp.grounding.predicates.ground_atoms` decides them."""
        reply = self._call({"scene": scene.to_dict(), "names": [p.name for p in predicates]}, self.limits.call_s)
        values: dict[Atom, bool] = {}
        try:
            for name, args, value in reply["values"]:
                if not isinstance(value, bool):
                    raise TypeError(value)
                values[(str(name), tuple(str(a) for a in args))] = value
        except (KeyError, TypeError, ValueError):
            raise self._broken("answered something that is not the atoms' values") from None
        objects = list(scene.objects.values())
        if values.keys() != {atom for made in predicates for atom in atoms_of(made, objects)}:
            raise self._broken("answered other atoms than it was asked for")
        return values

    def close(self) -> None:
        """Kill the child's process group (whatever the user's code started in it too) and clean up."""
        process = getattr(self, "_process", None)
        if process is not None and self._owner == os.getpid():
            _kill_group(process)
            self._output.join()
        self._close_fds()
        shutil.rmtree(self._folder, ignore_errors=True)

    def _call(self, message: dict, seconds: float) -> Any:
        with self._lock:  # one request at a time on the pipes (threads of a server may share a child)
            if self.failure is not None:
                raise InputError(self.failure)
            try:
                return self._exchange(message, seconds)
            except InputError as error:
                if self._process.poll() is not None:  # stopped: every later call gets the same answer
                    self.failure = str(error)
                raise

    def _exchange(self, message: dict, seconds: float) -> Any:
        if self._owner != os.getpid():
            raise InputError(f"predicates file {self.name}: its process belongs to another process of vslsp")
        if self._process.poll() is not None:
            raise self._ended()
        left = self.limits.session_s - self._spent
        deadline_s = min(seconds, left)
        began = time.monotonic()
        request = json.dumps(message, default=_plain).encode() + b"\n"
        line = self._read_line(began + deadline_s) if self._write(request, began + deadline_s) else None
        self._spent += time.monotonic() - began
        if line is None:
            _kill_group(self._process)
            if deadline_s < seconds:
                raise InputError(
                    f"predicates file {self.name}: its calls took more than {self.limits.session_s:g} s in all "
                    "and it was stopped; make each predicate decide its atom quickly"
                )
            raise InputError(
                f"predicates file {self.name}: did not answer within {deadline_s:g} s (it may block or loop); "
                "it was stopped. A predicate decides one atom, in microseconds: remove the loop, sleep or wait"
            )
        if not line:
            raise self._ended()
        try:
            reply = json.loads(line)
        except ValueError:
            raise self._broken("answered something that is not JSON") from None
        if not isinstance(reply, dict):
            raise self._broken("answered something that is not a reply")
        if "error" in reply:
            raise InputError(self._explain(str(reply["error"])))
        return reply

    def _write(self, data: bytes, deadline: float) -> bool:
        """Send ``data``; False past ``deadline`` (a child that loops reads no large scene)."""
        view = memoryview(data)
        while view:
            left = deadline - time.monotonic()
            if left <= 0:
                return False
            if not select.select([], [self._requests], [], min(left, WAIT_SLICE_S))[1]:
                continue
            try:
                view = view[os.write(self._requests, view) :]
            except BlockingIOError:
                continue
            except OSError:  # the child closed its end: it ended
                raise self._ended() from None
        return True

    def _read_line(self, deadline: float) -> bytes | None:
        """The next reply line; b"" at the end of the pipe, None past ``deadline``."""
        while b"\n" not in self._buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            if not select.select([self._replies], [], [], min(left, WAIT_SLICE_S))[0]:
                continue
            chunk = os.read(self._replies, 1 << 20)
            if not chunk:
                return b""
            self._buffer += chunk
            if len(self._buffer) > _MAX_REPLY_BYTES:
                raise self._broken("answered more than a reply holds")
        line, _, self._buffer = self._buffer.partition(b"\n")
        return line

    def _explain(self, message: str) -> str:
        message = message.replace(self._absolute, self.name)
        if "MemoryError" in message:
            message += f" (its memory limit is {self.limits.memory_mb} MB)"
        return message if self.name in message else f"predicates file {self.name}: {message}"

    def _ended(self) -> InputError:
        try:
            code = self._process.wait(timeout=5)
        except subprocess.TimeoutExpired:
            code = None
        _kill_group(self._process)
        if code is not None and code < 0:
            try:
                why = f"killed by {signal.Signals(-code).name}"
            except ValueError:  # a real-time signal Python has no name for
                why = f"killed by signal {-code}"
            if -code in (signal.SIGXCPU, signal.SIGKILL):
                why += f" (at its CPU-time limit of {self.limits.cpu_s} s, or killed from outside)"
        else:
            why = f"exit code {code}"
        last = self._output.last_line()
        return InputError(
            f"predicates file {self.name}: its process ended ({why})"
            + (f"; its last output: {last}" if last else "")
            + "; a predicate returns True or False and leaves the process alone"
        )

    def _broken(self, what: str) -> InputError:
        _kill_group(self._process)
        return InputError(f"predicates file {self.name}: its process {what} and was stopped")

    def _close_fds(self) -> None:
        for name in ("_requests", "_replies", "_lifeline"):
            fd = getattr(self, name, None)
            if fd is not None:
                try:
                    os.close(fd)
                except OSError:
                    pass
                setattr(self, name, None)


def ground_with_user_predicates(
    pre_image: np.ndarray,
    post_image: np.ndarray,
    robot_side: str,
    predicates_path: str | Path | None,
    limits: Limits | None = None,
) -> Grounding:
    """:func:`~vslsp.grounding.ground` of RGB images ``pre_image``, ``post_image`` (H, W, 3) uint8 with
    ``far`` and the predicates of the file ``predicates_path``, decided in a child process that ends
    with the call (errors of the file: InputError, exit 2). Without a file: ``ground`` as it is."""
    from vslsp.grounding.loader import with_builtins
    from vslsp.grounding.operation import ground

    if predicates_path is None:
        return ground(pre_image, post_image, robot_side=robot_side)
    with UserPredicates.start(predicates_path, limits) as user:
        return ground(pre_image, post_image, robot_side=robot_side, predicates=with_builtins(user.predicates))


_SHARED: dict[tuple[int, str, Limits], UserPredicates] = {}


def shared_predicates(path: str | Path, limits: Limits | None = None) -> tuple[Predicate, ...]:
    """The predicates of ``path`` from one child per file and process, started on first use and
    killed when the process exits (an experiment's trials ground many times: one start-up). Once
    its child was stopped, every later call raises the InputError that stopped it."""
    return _shared(str(Path(path).resolve()), limits or DEFAULT_LIMITS).predicates


def _shared(path: str, limits: Limits) -> UserPredicates:
    key = (os.getpid(), path, limits)
    user = _SHARED.get(key)
    if user is not None and user.failure is not None:  # not restarted: the next trial would wait as long
        raise InputError(user.failure)
    if user is None or user._process.poll() is not None:
        if not _SHARED:
            import atexit

            atexit.register(_close_shared)
        user = _SHARED[key] = UserPredicates.start(path, limits)
    return user


def _close_shared() -> None:
    for key in [k for k in _SHARED if k[0] == os.getpid()]:
        _SHARED.pop(key).close()


class _Remote:
    """A predicate's function when it is called directly (``p(obj, scene)``): one atom, one call."""

    def __init__(self, user: UserPredicates, name: str) -> None:
        self.user, self.name = user, name
        self.__qualname__ = self.__name__ = name

    def __call__(self, *args: Any) -> bool:
        *objects, scene = args
        made = next(p for p in self.user.predicates if p.name == self.name)
        return self.user.evaluate(scene, [made])[(self.name, tuple(o.name for o in objects))]


def _child_limits(limits: Limits) -> dict:
    return {
        "memory_bytes": limits.memory_mb * 1024 * 1024,
        "cpu_s": limits.cpu_s,
        "processes": None if os.getuid() == 0 else _user_tasks() + limits.processes,  # root is not counted
        "predicate_s": limits.predicate_s,
        "load_s": limits.load_s,
    }


def _user_tasks() -> int:
    """Processes and threads of this user now (what ``RLIMIT_NPROC`` counts)."""
    uid, count = os.getuid(), 0
    for entry in os.scandir("/proc") if os.path.isdir("/proc") else ():
        if entry.name.isdigit():
            try:
                status = Path(entry.path, "status").read_text()
            except OSError:
                continue
            fields = dict(line.split(":", 1) for line in status.splitlines() if ":" in line)
            if int(fields.get("Uid", "-1 0").split()[0]) == uid:
                count += int(fields.get("Threads", "1"))
    return count


def _environment(folder: str) -> dict[str, str]:
    return {
        "PATH": os.environ.get("PATH", os.defpath),
        "LANG": os.environ.get("LANG", "C.UTF-8"),
        "HOME": folder,
        "TMPDIR": folder,
        # one thread for the numerical libraries vslsp imports (the process limit counts threads)
        "OPENBLAS_NUM_THREADS": "1",
        "OMP_NUM_THREADS": "1",
        "MKL_NUM_THREADS": "1",
    }


def _kill_group(process: subprocess.Popen) -> None:
    """SIGKILL the child's process group (the leader not yet reaped, so its id is not reused), then reap it."""
    try:
        os.killpg(process.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass
    try:
        process.wait(timeout=10)
    except subprocess.TimeoutExpired:
        pass


def _plain(value: Any) -> Any:
    """numpy scalars in a scene as the Python numbers they are."""
    if hasattr(value, "item"):
        return value.item()
    raise TypeError(f"{type(value).__name__} is not JSON")


class _Relay:
    """Copies the child's output to vslsp's stderr, at most ``limit`` bytes; always drains it
    (a child blocked on a full pipe would look like one that loops)."""

    def __init__(self, limit: int) -> None:
        self.limit = limit
        self.shown = 0
        self.dropped = 0
        self._last = b""
        self._thread: threading.Thread | None = None

    def start(self, stream: io.BufferedReader) -> None:
        self._thread = threading.Thread(target=self._copy, args=(stream,), name="vslsp-predicates-output", daemon=True)
        self._thread.start()

    def _copy(self, stream: io.BufferedReader) -> None:
        with stream:
            for chunk in iter(lambda: stream.read1(65536), b""):
                self._last = (self._last + chunk)[-400:]
                room = max(0, self.limit - self.shown)
                if room:
                    _write_stderr(chunk[:room])
                    self.shown += min(room, len(chunk))
                self.dropped += max(0, len(chunk) - room)

    def join(self) -> None:
        if self._thread is not None:
            self._thread.join(timeout=5)
            self._thread = None
        if self.dropped:
            _write_stderr(f"\n[{self.dropped} more bytes of the predicates' output not shown]\n".encode())
            self.dropped = 0

    def last_line(self) -> str:
        lines = [line for line in self._last.decode(errors="replace").splitlines() if line.strip()]
        return lines[-1].strip()[:200] if lines else ""


def _write_stderr(data: bytes) -> None:
    try:
        sys.stderr.write(data.decode(errors="replace"))
        sys.stderr.flush()
    except (OSError, ValueError):  # vslsp's own stderr closed: the output is dropped
        pass


__all__ = ["DEFAULT_LIMITS", "Limits", "UserPredicates", "ground_with_user_predicates", "shared_predicates"]
