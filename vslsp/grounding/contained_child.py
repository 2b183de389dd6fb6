"""The child process that runs a user's predicates file for :mod:`vslsp.grounding.contained`.

It is started as ``python -I -c BOOTSTRAP`` (the bootstrap puts vslsp's own folder first on the
path and calls :func:`serve`) with three pipe descriptors: requests from vslsp, replies to it,
and a lifeline whose end of file means vslsp is gone. The protocol is one JSON object per line,
never pickle:

- ``{"load": PATH, "limits": {...}}`` -> ``{"predicates": [{"name": ..., "arity": ...}, ...]}``;
- ``{"scene": SCENE, "names": [...]}`` -> ``{"values": [[name, [object, ...], bool], ...]}``;
- any failure of the user's code -> ``{"error": MESSAGE}`` (the message vslsp shows, exit 2).

The process limits (address space, CPU time, processes) are set here, after vslsp's own
imports and before the user's file loads. The per-call time limits of the in-process guards
(:mod:`vslsp.grounding.user_code`) still give the precise message for a predicate that loops;
vslsp's wall-clock deadline is the backstop for code that blocks signals.
"""

from __future__ import annotations

import ctypes
import json
import os
import resource
import signal
import sys
import threading
from typing import IO, Any

_PR_SET_PDEATHSIG = 1


def serve(requests_fd: int, replies_fd: int, lifeline_fd: int, parent: int) -> None:
    """Answer vslsp's requests until it closes them (or goes away: then the whole group ends).

    When the user's code breaks the process itself (closes the pipes, replaces what vslsp
    needs), it ends with one line saying why on its output, which vslsp shows; no traceback."""
    try:
        _serve(requests_fd, replies_fd, lifeline_fd, parent)
    except BaseException as error:  # noqa: BLE001 - whatever the user's code broke; vslsp reports the end
        from vslsp.grounding.user_code import describe

        try:
            os.write(2, f"\nthe predicates' process broke: {describe(error)}\n".encode(errors="replace"))
        except OSError:
            pass
        os._exit(70)


def _serve(requests_fd: int, replies_fd: int, lifeline_fd: int, parent: int) -> None:
    _die_with(parent, lifeline_fd)
    sys.stdout = sys.stderr  # what the user's code prints is captured output, never a reply
    from vslsp.errors import VslspError
    from vslsp.grounding.loader import load_predicates
    from vslsp.grounding.predicates import Scene, ground_atoms

    requests = os.fdopen(requests_fd, "rb")
    replies = os.fdopen(replies_fd, "wb")
    predicates: dict[str, Any] = {}
    for line in requests:
        try:
            message = json.loads(line)
            if "load" in message:
                _limit(message.get("limits", {}))
                _time_limits(message.get("limits", {}))
                predicates = {p.name: p for p in load_predicates(message["load"])}
                reply: dict = {"predicates": [{"name": p.name, "arity": p.arity} for p in predicates.values()]}
            else:
                scene = Scene.from_dict(message["scene"])
                values = ground_atoms(scene, [predicates[name] for name in message["names"]])
                reply = {"values": [[name, list(args), value] for (name, args), value in values.items()]}
        except VslspError as error:
            reply = {"error": str(error)}
        except MemoryError:
            reply = {"error": "MemoryError"}
        _send(replies, reply)
    _end_group()


def _send(replies: IO[bytes], reply: dict) -> None:
    replies.write(json.dumps(reply).encode() + b"\n")
    replies.flush()


def _limit(limits: dict) -> None:
    """The process limits, each clamped to the hard limit this process has."""
    for which, value in (
        (resource.RLIMIT_AS, limits.get("memory_bytes")),
        (resource.RLIMIT_CPU, limits.get("cpu_s")),
        (resource.RLIMIT_NPROC, limits.get("processes")),
    ):
        if value is None:
            continue
        _, hard = resource.getrlimit(which)
        value = int(value) if hard == resource.RLIM_INFINITY else min(int(value), hard)
        resource.setrlimit(which, (value, hard))


def _time_limits(limits: dict) -> None:
    from vslsp.grounding import loader, predicates

    if "predicate_s" in limits:
        predicates.PREDICATE_TIME_LIMIT_S = float(limits["predicate_s"])
    if "load_s" in limits:
        loader.LOAD_TIME_LIMIT_S = float(limits["load_s"])


def _die_with(parent: int, lifeline_fd: int) -> None:
    """End this process group when vslsp ends: at once by the kernel (the parent-death signal),
    and from a thread that sees the lifeline close (which also ends processes the user's code
    started in the group)."""
    try:
        ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    except (OSError, AttributeError):  # not Linux: the lifeline alone
        pass
    if not parent:  # under a guard (the parent): it ends this group and removes the folder when vslsp ends
        _guard.append(os.getppid())
        return
    if os.getppid() != parent:  # vslsp ended before the signal was set
        _end_group()

    def watch() -> None:
        while os.read(lifeline_fd, 1):
            pass
        _end_group()

    threading.Thread(target=watch, name="vslsp-lifeline", daemon=True).start()


_guard: list[int] = []  # the guard's pid, when this process runs under one (vslsp.interrupts)


def _end_group() -> None:
    """Kill this process group; under a guard, the guard does it (it is in the group, and it must
    live on to remove this process's folder)."""
    if _guard and os.getppid() == _guard[0]:
        os.kill(_guard[0], signal.SIGTERM)
        threading.Event().wait(10)  # the guard kills this process meanwhile
    os.killpg(os.getpgid(0), signal.SIGKILL)
