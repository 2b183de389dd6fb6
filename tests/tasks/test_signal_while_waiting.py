"""A signal reaches a waiting run whichever thread the kernel gives it to (vslsp.interrupts,
``WAIT_SLICE_S``): Python runs a handler only between bytecodes of the main thread, so a signal
that another thread took, or that landed just before the main thread blocked, would wait for the
blocking call to return. Here the signal is sent to another thread while the main thread waits
(``pthread_kill``: the main thread is not woken), as the kernel does when it picks that thread."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
from pathlib import Path

import helpers.interrupt_tasks  # noqa: F401  (registers test-waits-after-the-first)
import pytest
from helpers.events import became_true

from vslsp import interrupts
from vslsp.errors import Interrupted
from vslsp.symbolic.engines import fast_downward
from vslsp.tasks import get_task, run_trials, runner

MAIN = threading.main_thread().native_id


def _main_thread_blocked() -> bool:
    """Whether the main thread sleeps in a blocking call (a lock, poll or select, a wait)."""
    try:
        state = Path(f"/proc/self/task/{MAIN}/stat").read_text().rsplit(")", 1)[1].split()[0]
        where = Path(f"/proc/self/task/{MAIN}/wchan").read_text()
    except OSError:
        return False
    return state == "S" and where.startswith(("futex", "do_sys_poll", "do_select", "poll_schedule"))


def _signal_another_thread_once(ready=lambda: True) -> threading.Thread:
    """A thread that, once ``ready()`` and the main thread blocks, takes SIGTERM itself."""

    def send() -> None:
        if became_true(lambda: ready() and _main_thread_blocked()):
            signal.pthread_kill(threading.get_ident(), signal.SIGTERM)

    thread = threading.Thread(target=send, daemon=True)
    thread.start()
    return thread


def test_a_signal_another_thread_took_stops_a_wait_on_a_child_process():
    # Its output read as the planner's is (a pipe): communicate then blocks in poll, not in a sleep.
    child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(600)"], stdout=subprocess.PIPE)
    try:
        with pytest.raises(Interrupted) as stopped, interrupts.handled():
            _signal_another_thread_once()
            interrupts.communicate(child, timeout=120)  # without slices: TimeoutExpired after 120 s
    finally:
        child.kill()
        child.wait()
    assert stopped.value.signal_name == "SIGTERM"


def test_a_signal_another_thread_took_stops_a_driver_waiting_on_its_workers(tmp_path, monkeypatch):
    monkeypatch.setenv("VSLSP_TEST_MARKERS", str(tmp_path))
    (tmp_path / "0.reported").write_text("")  # seed 1 and 2 start waiting at once
    before = signal.getsignal(signal.SIGTERM)
    timeouts = []  # every wait of the driver is a slice (without: one wait until a trial ends, 600 s)
    real_wait = runner.wait
    monkeypatch.setattr(runner, "wait", lambda *a, **k: timeouts.append(k.get("timeout")) or real_wait(*a, **k))
    _signal_another_thread_once(ready=lambda: (tmp_path / "waiting-1").exists())
    run = run_trials(get_task("test-waits-after-the-first"), [1, 2], workers=2)
    assert run.interrupted == "SIGTERM" and run.results == []
    assert signal.getsignal(signal.SIGTERM) is before
    assert timeouts and all(t is not None and t <= interrupts.WAIT_SLICE_S for t in timeouts)


def test_a_worker_raises_on_its_first_signal_only(monkeypatch):
    """A worker ended by its driver gets SIGTERM, then its parent-death SIGTERM when the driver
    exits: the second must not cut the first one's cleanup (the planner's kill) short."""
    monkeypatch.setattr(runner, "_in_trial", True)
    monkeypatch.setattr(runner, "_stopping", False)
    with pytest.raises(Interrupted):
        runner._raise_interrupted(signal.SIGTERM, None)
    assert runner._raise_interrupted(signal.SIGTERM, None) is None  # noted: the cleanup goes on


def test_a_signal_during_a_planner_kill_waits_until_the_whole_tree_is_dead(monkeypatch):
    """Stopped, then killed: a signal between the two would leave the process stopped for good
    (deaf to everything but SIGKILL). Here SIGTERM comes while the tree is read."""
    child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(600)"])
    real_descendants = fast_downward.descendants

    def signalled_meanwhile(pid):
        os.kill(os.getpid(), signal.SIGTERM)
        signal.sigtimedwait([], 0)  # a point where a handler would run
        return real_descendants(pid)

    monkeypatch.setattr(fast_downward, "descendants", signalled_meanwhile)
    with pytest.raises(Interrupted), interrupts.handled():
        try:
            fast_downward.kill_tree(child)
        finally:
            assert child.returncode == -signal.SIGKILL  # dead and reaped before the signal raised
