"""Waiting on events instead of clocks: a file written, a process gone, a trial's result in the
driver. A bound guards against a hang only (it is far beyond any slow machine); no test asserts
how long something took (speed targets live in benchmarks/)."""

from __future__ import annotations

import subprocess
import time
from collections.abc import Callable
from pathlib import Path

HANG_S = 300.0


def became_true(condition: Callable[[], bool], process: subprocess.Popen | None = None, hang_s: float = HANG_S) -> bool:
    """Wait for ``condition()`` to hold and say whether it did: False when ``process`` ended
    first (and the condition still does not hold) or after ``hang_s`` (a hang, not a slow
    machine). For a test that asserts with its own message, and for code that must not fail
    (a trial in a worker process)."""
    deadline = time.monotonic() + hang_s
    while not condition():
        if process is not None and process.poll() is not None:
            return condition()
        if time.monotonic() >= deadline:
            return False
        time.sleep(0.05)
    return True


def wait_until(condition: Callable[[], bool], what: str | Callable[[], str], hang_s: float = HANG_S) -> None:
    """Wait for ``condition()`` to hold; fail the test after ``hang_s`` (a hang, not a slow
    machine), saying what it waited for (``what``, or what ``what()`` says then: e.g. a screen)."""
    if not became_true(condition, hang_s=hang_s):
        raise AssertionError(f"still waiting after {hang_s:.0f} s for {what if isinstance(what, str) else what()}")


def process_gone(pid: int) -> bool:
    """Whether the process ``pid`` has ended (gone, or a zombie not yet reaped by its parent)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[-1].split()[0]
    except (FileNotFoundError, ProcessLookupError):
        return True
    return state in ("Z", "X")


def experiment_program(setup: str = "") -> str:
    """The source of a program that runs ``vslsp`` (its arguments: ``sys.argv[1:]``) after
    ``setup`` (e.g. importing test tasks), with Python's Ctrl-C handler (a shell that starts
    jobs in the background has SIGINT ignored), and that writes ``<seed>.reported`` in the
    folder $VSLSP_TEST_MARKERS as the driver receives each trial's result (through the
    progress callback): the event a test waits for before it interrupts the run."""
    return "\n".join(
        [
            "import os, pathlib, signal, sys",
            "signal.signal(signal.SIGINT, signal.default_int_handler)",
            setup,
            "import vslsp.tasks",
            "run_trials = vslsp.tasks.run_trials",
            "def noting(*args, on_done=None, **options):",
            "    def done(result):",
            "        if on_done is not None:",
            "            on_done(result)",
            "        (pathlib.Path(os.environ['VSLSP_TEST_MARKERS']) / f'{result.seed}.reported').write_text('')",
            "    return run_trials(*args, on_done=done, **options)",
            "vslsp.tasks.run_trials = noting",
            "from vslsp.cli import main",
            "main(sys.argv[1:])",
        ]
    )
