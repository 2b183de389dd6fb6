"""Running the user's code (a predicates file and its functions) so that nothing it does ends vslsp.

A predicate is the user's Python (docs/grounding.md). Whatever it raises, including
``SystemExit`` (``sys.exit(0)``) and other ``BaseException`` subclasses, an exception whose
``__str__`` raises, or a result whose ``__repr__`` raises, becomes an
:class:`~vslsp.errors.InputError` (exit 2) naming the predicate; a call that runs longer than
its time limit is stopped and reported the same way; what it prints goes to stderr, so that
``--json`` keeps stdout one JSON object. Two things pass through untouched: Ctrl-C
(``KeyboardInterrupt``) and vslsp's own exceptions (a user error vslsp raised inside, an
interrupt of the run).

The time limit is a ``SIGALRM`` timer, so it holds in the main thread of a process (the CLI,
every experiment worker); elsewhere, or while another timer runs, the code runs without one.
The timer repeats every second after it first fires, so code that catches the first stop is
stopped again.
"""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
from collections.abc import Iterator

from vslsp.interrupts import alarm

#: Seconds one call of a predicate may take (a predicate decides one atom: microseconds).
PREDICATE_TIME_LIMIT_S = 10.0
#: Seconds loading a predicates file may take (its imports included).
LOAD_TIME_LIMIT_S = 60.0


class TimeLimitExceeded(BaseException):
    """The user's code ran past its time limit (a BaseException: ``except Exception`` in it cannot keep it)."""


@contextlib.contextmanager
def time_limit(seconds: float) -> Iterator[None]:
    """Raise :class:`TimeLimitExceeded` in the block after ``seconds`` (main thread, no other timer running)."""
    armed = (
        hasattr(signal, "setitimer")
        and threading.current_thread() is threading.main_thread()
        and signal.getitimer(signal.ITIMER_REAL)[0] == 0
    )
    if not armed:
        yield
        return
    with alarm(seconds, TimeLimitExceeded, 1.0):  # raised again on leaving when the code caught it
        yield


@contextlib.contextmanager
def quiet_stdout() -> Iterator[None]:
    """What the block prints goes to stderr (stdout is kept for the command's own answer)."""
    with contextlib.redirect_stdout(sys.stderr):
        yield


def passes_through(error: BaseException) -> bool:
    """Whether ``error`` is not the user's to answer for: Ctrl-C, or one of vslsp's own exceptions."""
    return isinstance(error, KeyboardInterrupt) or str(getattr(type(error), "__module__", "")).startswith("vslsp.")


def safe_repr(value: object, limit: int = 200) -> str:
    """``repr(value)``, or a description when its ``__repr__`` raises; at most ``limit`` characters."""
    try:
        text = repr(value)
    except BaseException:  # noqa: BLE001 - the user's __repr__; whatever it raises is reported, not raised
        return f"<a {type(value).__name__} whose __repr__ raised>"
    return text if len(text) <= limit else text[: limit - 3] + "..."


def describe(error: BaseException) -> str:
    """``TypeName: message`` of an exception the user's code raised, even when its ``__str__`` raises."""
    name = type(error).__name__
    if isinstance(error, SystemExit):
        return f"SystemExit (it called sys.exit({safe_repr(error.code)}); a predicate returns True or False)"
    try:
        text = str(error)
    except BaseException:  # noqa: BLE001 - the user's __str__
        text = "<its message cannot be shown: its __str__ raised>"
    return f"{name}: {text}" if text else name
