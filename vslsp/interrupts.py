"""Signals and crashes: every way a run can end leaves no process and no temporary folder behind.

The rules (docs/bad-input.md, "Signals and crashes"):

- every signal a shell can send to end a command (SIGINT, SIGTERM, SIGHUP, SIGQUIT) is handled
  **once** (:func:`handled`): the first raises (``KeyboardInterrupt`` for SIGINT,
  :class:`~vslsp.errors.Interrupted` for the others), so that ``finally`` blocks end child
  processes and remove temporary folders; a second signal during that cleanup is noted and
  never cuts it short. The exit code is 128 + the first signal's number (130, 143, 129, 131).
  A signal the command was started with ignored (``nohup``, a background job) stays ignored.
- a child process dies with its parent, however the parent ends (SIGKILL included): a worker
  asks the kernel for a parent-death signal (:func:`die_with_parent`); a planner runs under a
  small guard process (:func:`guarded_command`) that takes its parent's death as the order to
  kill the whole planner tree (its translator and search too, which a death signal alone does
  not reach: the setting is not inherited by the children a process forks) and to remove the
  planner's temporary folder.
- a wait of the main thread never blocks for long (:data:`WAIT_SLICE_S`, :func:`communicate`):
  Python runs a signal's handler only between two bytecodes of the main thread, and a signal
  that lands after the last such point and before a blocking call (a lock, ``poll``, ``waitpid``)
  leaves its handler unrun until that call returns, so every wait is cut into slices.
- a memory limit never asks for more address space than the user's own ``ulimit -v``
  (:func:`memory_limit_mb`): a limit above it is lowered to it, with a one-line notice.
"""

from __future__ import annotations

import ctypes
import errno
import os
import resource
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from vslsp.errors import Interrupted

#: The signals a shell or a terminal sends to end a command.
SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGQUIT)
_PR_SET_PDEATHSIG = 1
#: The longest one blocking call of a waiting main thread lasts, in seconds: a signal that came
#: just before the call (its handler not yet run) is acted upon when the slice ends.
WAIT_SLICE_S = 0.25
_received: list[str] = []  # the names of the signals received since the last resume(), first first
_depth = 0  # how many handled() blocks are open (the outermost installs the handlers)


def exit_code(signal_name: str) -> int:
    """128 + the signal's number: 130 for SIGINT, 143 SIGTERM, 129 SIGHUP, 131 SIGQUIT."""
    return 128 + int(signal.Signals[signal_name])


def received() -> list[str]:
    """The signals received since the last :func:`resume` (first first); a live list."""
    return _received


def resume() -> None:
    """Forget the signals received: a program that handled one and goes on (an interactive shell
    after Ctrl-C stopped a command) takes the next one as a first again."""
    _received.clear()


def _once(number: int, frame: Any) -> None:
    if postponed(number):
        return
    _received.append(signal.Signals(number).name)
    if len(_received) > 1:  # the run is already stopping: let its cleanup finish
        return
    if number == signal.SIGHUP:
        _leave_a_closed_terminal()
    if number == signal.SIGINT:
        raise KeyboardInterrupt
    raise Interrupted(_received[0])


@contextmanager
def handled(final: bool = False) -> Iterator[list[str]]:
    """Handle each of :data:`SIGNALS` once inside the block (see the module's rules); yields the
    live list of the signals received. Nested blocks share the outermost one's handlers. On
    leaving, the previous handlers come back, unless the block is the program's ``final`` one
    (the CLI's ``main``) and a signal arrived: the process is then stopping, and later signals
    stay ignored until it has exited. Outside the main thread (an embedding program) signals
    are left alone."""
    global _depth
    if _depth:
        _depth += 1
        try:
            yield _received
        finally:
            _depth -= 1
        return
    try:
        previous = {number: signal.getsignal(number) for number in SIGNALS}
        for number, handler in previous.items():
            if handler is not signal.SIG_IGN:
                signal.signal(number, _once)
    except ValueError:  # not the main thread
        yield _received
        return
    _depth = 1
    resume()
    try:
        yield _received
    finally:
        _depth = 0
        stopping = final and bool(_received)
        for number, handler in previous.items():
            if handler is not signal.SIG_IGN:
                signal.signal(number, signal.SIG_IGN if stopping else handler)


def _leave_a_closed_terminal() -> None:
    """After a hang-up, standard output and error that were the terminal go to /dev/null: the
    terminal is gone, and a write to it (EIO) must not turn the cleanup into a traceback."""
    for fd in (1, 2):
        try:
            os.tcgetpgrp(fd)  # a hung-up terminal answers EIO (a file or a pipe: ENOTTY, left alone)
        except OSError as error:
            if error.errno != errno.EIO:
                continue
            try:
                null = os.open(os.devnull, os.O_WRONLY)
                os.dup2(null, fd)
                os.close(null)
            except OSError:
                pass


def die_with_parent(number: int = signal.SIGKILL, parent: int | None = None) -> None:
    """Ask the kernel to send this process ``number`` when its parent ends (Linux's
    ``PR_SET_PDEATHSIG``); when the parent (pid ``parent``) has already ended, act on it now.
    Elsewhere nothing is done (the parent's own cleanup ends its children there)."""
    if sys.platform.startswith("linux"):
        try:
            ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, int(number), 0, 0, 0)
        except (OSError, AttributeError):
            return
    if parent is not None and os.getppid() != parent:
        os.kill(os.getpid(), number)


def orphaned(parent: int) -> bool:
    """Whether this process's parent ``parent`` has ended (it was adopted by another)."""
    return os.getppid() != parent


_noticed: set[int] = set()


def memory_limit_mb(requested: int) -> int:
    """``requested`` MB of address space, or the user's own limit (``ulimit -v``, this process's
    ``RLIMIT_AS``) when that is lower: a child cannot be given more than its parent has. The
    first time a limit is lowered, one line on stderr says so."""
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    own = min(limit for limit in (soft, hard, requested * 1024 * 1024) if limit != resource.RLIM_INFINITY)
    if own >= requested * 1024 * 1024:
        return requested
    lowered = max(1, own // (1024 * 1024))
    if requested not in _noticed:
        _noticed.add(requested)
        print(
            f"note: the planner's memory limit is {lowered} MB, your own address-space limit "
            f"(ulimit -v), not the {requested} MB asked for",
            file=sys.stderr,
        )
    return lowered


def user_limited(memory_mb: int) -> bool:
    """Whether ``memory_mb`` is the user's own address-space limit (so --memory cannot raise it)."""
    soft = resource.getrlimit(resource.RLIMIT_AS)[0]
    return soft != resource.RLIM_INFINITY and memory_mb == max(1, soft // (1024 * 1024))


# The guard: a small program between vslsp and a planner. It is the planner tree's subreaper (the
# processes the planner starts and leaves are adopted by it, not by init), it has a parent-death
# signal, and on that signal (or SIGTERM, SIGHUP from anyone) it kills the whole tree and removes
# the planner's folder. A terminal's Ctrl-C is vslsp's to act on: the guard ignores it (the planner
# itself does not). When the planner ends, the guard kills what it left and ends the same way.
_GUARD = r"""
import ctypes, os, resource, shutil, signal, sys
parent, folder, limit, command = int(sys.argv[1]), sys.argv[2], int(sys.argv[3]), sys.argv[4:]
libc = ctypes.CDLL(None, use_errno=True)
def tree():
    children = {}
    for name in os.listdir("/proc"):
        if name.isdigit():
            try:
                with open("/proc/" + name + "/stat", "rb") as stat:
                    children.setdefault(int(stat.read().rsplit(b")", 1)[1].split()[1]), []).append(int(name))
            except (OSError, IndexError, ValueError):
                pass
    found, todo = [], [os.getpid()]
    while todo:
        for child in children.get(todo.pop(), []):
            found.append(child)
            todo.append(child)
    return found
def kill_all():
    for pid in tree():
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass
def end(number, frame):
    for other in (signal.SIGTERM, signal.SIGHUP):
        signal.signal(other, signal.SIG_IGN)
    kill_all()
    if folder:
        shutil.rmtree(folder, ignore_errors=True)
    os._exit(128 + number)
shell_signals = (signal.SIGTERM, signal.SIGHUP, signal.SIGINT, signal.SIGQUIT)
inherited = {number: signal.getsignal(number) for number in shell_signals}
for number in (signal.SIGTERM, signal.SIGHUP):
    signal.signal(number, end)
for number in (signal.SIGINT, signal.SIGQUIT):
    signal.signal(number, signal.SIG_IGN)
libc.prctl(36, 1, 0, 0, 0)
libc.prctl(1, signal.SIGTERM, 0, 0, 0)
if os.getppid() != parent:
    end(signal.SIGTERM, None)
child = os.fork()
if child == 0:
    for number in shell_signals:  # as the guard got them (a worker's planner keeps ignoring Ctrl-C)
        signal.signal(number, signal.SIG_IGN if inherited[number] is signal.SIG_IGN else signal.SIG_DFL)
    try:
        if limit:
            resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        os.execvp(command[0], command)
    except OSError as error:
        sys.stderr.write("vslsp's planner guard: cannot start " + command[0] + ": " + str(error) + "\n")
    os._exit(127)
while True:
    pid, status = os.waitpid(-1, 0)
    if pid == child:
        break
kill_all()
while True:
    try:
        os.waitpid(-1, 0)
    except ChildProcessError:
        break
code = os.waitstatus_to_exitcode(status)
if code < 0:
    signal.signal(-code, signal.SIG_DFL)
    os.kill(os.getpid(), -code)
sys.exit(code)
"""


def guarded_command(
    command: list[str], folder: str | os.PathLike[str] | None = None, memory_mb: int | None = None
) -> list[str]:
    """``command`` run under the guard (see above): killed, with every process it starts, when
    this process ends in any way, ``folder`` removed then; with an address-space limit of
    ``memory_mb`` per process (lowered to the user's own: :func:`memory_limit_mb`). Linux only
    (the guard reads ``/proc``); elsewhere ``command`` itself, limited the same way."""
    limit = memory_limit_mb(memory_mb) * 1024 * 1024 if memory_mb else 0
    if not sys.platform.startswith("linux"):
        if not limit:
            return list(command)
        bounded = "import os, resource, sys; n = int(sys.argv[1]); resource.setrlimit(resource.RLIMIT_AS, (n, n)); "
        return [sys.executable, "-c", bounded + "os.execvp(sys.argv[2], sys.argv[2:])", str(limit), *command]
    return [sys.executable, "-c", _GUARD, str(os.getpid()), str(folder or ""), str(limit), *command]


@contextmanager
def alarm(seconds: float, stop: type[BaseException], repeat: float) -> Iterator[None]:
    """Raise ``stop()`` in the block (main thread) after ``seconds``, again every ``repeat`` seconds
    while it runs, and once more on leaving it when the time ran out but the raise was caught.

    The rule that keeps the timer from outliving the block: it is armed inside the ``try`` and
    disarmed first in the ``finally`` (again if an alarm lands on the way out), and an alarm after
    the block only notes the expiry. A signal handler runs wherever the main thread is, a finalizer
    the garbage collector runs included, where a raise is only printed and lost: hence the repeat."""
    expired = False
    inside = True

    def ring(signum: int, frame: Any) -> None:
        nonlocal expired
        expired = True
        if inside:
            raise stop()

    previous = signal.signal(signal.SIGALRM, ring)
    try:
        signal.setitimer(signal.ITIMER_REAL, seconds, repeat)
        yield
    finally:
        while True:
            try:
                inside = False
                signal.setitimer(signal.ITIMER_REAL, 0)
                break
            except stop:
                continue
        signal.signal(signal.SIGALRM, previous)
    if expired:
        raise stop()


_deferring = 0  # how many deferred() blocks run now (in any thread)
_postponed: list[int] = []  # the signals that came during them


@contextmanager
def deferred() -> Iterator[None]:
    """A critical section no signal cuts short (e.g. between stopping a process and killing it):
    vslsp's handlers leave a signal that comes meanwhile (:func:`postponed`) for the end of the
    block, where it is sent again. Blocking the signal would not do: the kernel gives a signal
    sent to the process to any thread that does not block it, and its handler still runs here."""
    global _deferring
    _deferring += 1
    try:
        yield
    finally:
        _deferring -= 1
        if not _deferring and _postponed:
            number = _postponed[0]
            _postponed.clear()
            signal.raise_signal(number)


def postponed(number: int) -> bool:
    """Whether a handler must leave signal ``number`` for the end of a :func:`deferred` block."""
    if _deferring:
        _postponed.append(number)
        return True
    return False


def communicate(process: subprocess.Popen, timeout: float | None = None) -> tuple[Any, Any]:
    """``process.communicate(timeout=timeout)`` in slices of :data:`WAIT_SLICE_S` (a retried
    communicate loses no output): a signal is acted upon within a slice, never after the timeout."""
    deadline = time.monotonic() + (float("inf") if timeout is None else timeout)
    while True:
        try:
            return process.communicate(timeout=max(0.0, min(WAIT_SLICE_S, deadline - time.monotonic())))
        except subprocess.TimeoutExpired:
            if timeout is not None and time.monotonic() >= deadline:
                raise subprocess.TimeoutExpired(process.args, timeout) from None
