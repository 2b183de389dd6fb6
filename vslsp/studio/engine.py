"""The studio's language work (check, complete, plan, validate) in a pool of worker processes, never on
the web server's event loop or in its process: a check of a large domain is pure Python, and in a
thread of the server it would hold the interpreter from every other client; in a process of its own
it holds nothing. The pool starts with the studio (:func:`warm_up`: the engine imported before the
first keystroke) and has :data:`WORKERS` processes, so one long check does not hold up another
client's. A worker that dies (killed, out of memory) is replaced with the next call.

What crosses to a worker and back is the call's texts and its JSON-like answer; a user error of the
engine comes back as the same :class:`~vslsp.errors.VslspError` message and exit code (and, for an
unsolvable problem, its ``conflict``).
"""

from __future__ import annotations

import asyncio
import multiprocessing
import os
import threading
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from typing import Any

from vslsp.errors import InputError, TaskFailed, VslspError

#: Worker processes (two at most: this is work for the machine's cores, beside the runs).
WORKERS = max(1, min(2, os.cpu_count() or 1))
#: The engine's calls, by name (only these run in a worker).
CALLS = ("check", "complete", "plan", "validate", "navigate")

_pool: ProcessPoolExecutor | None = None
_lock = threading.Lock()


def _work(name: str, args: tuple) -> tuple[str, Any]:
    """In a worker: ``vslsp.studio.pddl.NAME(*args)``, an error as ``("error", ...)`` (plain data)."""
    from vslsp.studio import navigation, pddl

    try:
        return "ok", getattr(navigation if name == "navigate" else pddl, name)(*args)
    except VslspError as error:
        return "error", (error.exit_code, str(error), getattr(error, "conflict", None), getattr(error, "reasons", []))


def _warm() -> None:
    from vslsp.studio import pddl

    pddl.check("(define (domain warm))", None)


def pool() -> ProcessPoolExecutor:
    """The pool (started when first needed), spawned: its workers share nothing with the server's threads.

    A spawned worker starts with the server's ``sys.path`` as it is at that moment, and OpenCV's loader
    puts its own folder on it while ``cv2`` imports (in any thread of the server): a worker spawned then
    finds ``cv2/typing`` as the standard ``typing`` and dies before its first call. So OpenCV is imported
    whole before any worker is spawned (once imported, it never touches the path again)."""
    global _pool
    import cv2  # noqa: F401  (see above)

    with _lock:
        if _pool is None:
            _pool = ProcessPoolExecutor(WORKERS, mp_context=multiprocessing.get_context("spawn"))
        return _pool


def warm_up() -> None:
    """Start the workers and import the engine in each, in the background."""
    for _ in range(WORKERS):
        pool().submit(_warm)


def shut_down() -> None:
    global _pool
    with _lock:
        if _pool is not None:
            _pool.shutdown(wait=False, cancel_futures=True)
            _pool = None


async def call(name: str, *args: Any) -> Any:
    """``vslsp.studio.pddl.NAME(*args)`` in a worker; its VslspError raised here as the same message."""
    if name not in CALLS:
        raise ValueError(name)
    loop = asyncio.get_running_loop()
    try:
        kind, answer = await loop.run_in_executor(pool(), _work, name, args)
    except BrokenProcessPool:
        shut_down()  # a worker died (killed, out of memory): a new pool for the next call
        raise InputError("the studio's language worker ended unexpectedly; try again") from None
    if kind == "ok":
        return answer
    exit_code, message, conflict, reasons = answer
    error: VslspError = TaskFailed(message) if exit_code == 1 else InputError(message)
    error.exit_code = exit_code
    if conflict is not None:
        error.conflict = conflict  # type: ignore[attr-defined]
        error.reasons = reasons  # type: ignore[attr-defined]
    raise error


def caller(name: str) -> Callable[..., Any]:
    """``call`` bound to one of :data:`CALLS`."""

    async def bound(*args: Any) -> Any:
        return await call(name, *args)

    return bound
