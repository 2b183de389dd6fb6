"""Signals and crashes (docs/bad-input.md, "Signals and crashes"): every signal a shell sends
ends a command with 128 + its number (SIGINT 130, SIGTERM 143, SIGHUP 129, SIGQUIT 131), once
(a second signal during the cleanup does not cut it short); whatever ends the command, SIGKILL
included, no worker, resource tracker or planner process is left, nothing of the run stays in
TMPDIR, and a lock file left by a killed run is taken over by the next one with a notice.

The runs of whole programs are ``slow``; the rules of :mod:`vslsp.interrupts` run by default."""

from __future__ import annotations

import fcntl
import os
import resource
import signal
import subprocess
import sys
import termios
from pathlib import Path

import pytest
from helpers.cli import REPO
from helpers.events import became_true, process_gone, wait_until
from helpers.processes import command, planner_processes, start

from vslsp import interrupts
from vslsp.errors import Interrupted
from vslsp.files import cache_folder
from vslsp.outputs import LOCK_NAME, lock_folder
from vslsp.symbolic.engines.fast_downward import descendants

LIMITS = REPO / "tests" / "data" / "limits"
GROWING_PLAN = ["plan", REPO / "pddl" / "domain.pddl", LIMITS / "forall-or.pddl", "--memory", "700"]


# --- the rules, in this process ---


@pytest.mark.parametrize(("name", "code"), [("SIGINT", 130), ("SIGTERM", 143), ("SIGHUP", 129), ("SIGQUIT", 131)])
def test_the_exit_code_is_128_plus_the_signal(name, code):
    assert interrupts.exit_code(name) == code == Interrupted(name).exit_code


def test_the_first_signal_raises_and_the_later_ones_are_only_noted():
    cleaned = []
    with pytest.raises(Interrupted) as stopped, interrupts.handled(final=True) as received:
        try:
            os.kill(os.getpid(), signal.SIGTERM)
            signal.sigtimedwait([], 0)  # a point where the handler runs, in case it has not yet
        finally:  # the cleanup: further signals must not cut it short
            os.kill(os.getpid(), signal.SIGINT)
            os.kill(os.getpid(), signal.SIGHUP)
            cleaned.append(True)
    assert stopped.value.signal_name == "SIGTERM" and cleaned == [True]
    assert received == ["SIGTERM", "SIGINT", "SIGHUP"]
    # The program's final block, stopping: later signals stay ignored until the process has exited.
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_IGN
    for number in interrupts.SIGNALS:
        signal.signal(number, signal.default_int_handler if number == signal.SIGINT else signal.SIG_DFL)


def test_a_library_call_gives_the_handlers_back_even_after_a_signal():
    """run_trials outside the CLI: the caller goes on after the interrupt, with its own handlers."""
    previous = signal.getsignal(signal.SIGTERM)
    with pytest.raises(Interrupted), interrupts.handled():
        os.kill(os.getpid(), signal.SIGTERM)
        signal.sigtimedwait([], 0)
    assert signal.getsignal(signal.SIGTERM) is previous


def test_a_handled_ctrl_c_is_forgotten_so_the_next_one_raises_again():
    """The shell takes Ctrl-C and goes on: after resume() the next Ctrl-C is a first one."""
    with interrupts.handled():
        for _ in range(2):
            with pytest.raises(KeyboardInterrupt):
                os.kill(os.getpid(), signal.SIGINT)
                signal.sigtimedwait([], 0)
            interrupts.resume()
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # no signal pending: restored


def test_a_signal_ignored_at_start_stays_ignored():
    """``nohup vslsp ...``: SIGHUP was ignored before vslsp started, and stays so."""
    previous = signal.signal(signal.SIGHUP, signal.SIG_IGN)
    try:
        with interrupts.handled():
            assert signal.getsignal(signal.SIGHUP) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGHUP, previous)


def test_the_memory_limit_is_lowered_to_the_users_own(tmp_path):
    """Under ``ulimit -v 3G`` a planner limit of 4096 MB is 3072 MB, said once on stderr."""
    program = (
        "import resource; n = 3 * 1024 ** 3; resource.setrlimit(resource.RLIMIT_AS, (n, n))\n"
        "from vslsp.interrupts import memory_limit_mb\n"
        "print(memory_limit_mb(4096), memory_limit_mb(4096), memory_limit_mb(1024))"
    )
    done = subprocess.run(
        [sys.executable, "-c", program],
        capture_output=True,
        text=True,
        env={**os.environ, "PYTHONPATH": str(REPO)},
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["3072", "3072", "1024"]
    assert done.stderr.count("note: the planner's memory limit is 3072 MB") == 1, done.stderr
    if resource.getrlimit(resource.RLIMIT_AS)[0] == resource.RLIM_INFINITY:
        assert interrupts.memory_limit_mb(4096) == 4096


def test_plan_under_the_users_own_ulimit_v_plans_within_it(tmp_path):
    """``ulimit -v 3G`` and the default --memory 4096: a notice and a plan (it was exit 3,
    'Exception occurred in preexec_fn')."""
    limit = 3 * 1024**3
    done = subprocess.run(
        [sys.executable, "-m", "vslsp", "plan", REPO / "pddl" / "domain.pddl", REPO / "pddl" / "pull-in-order.pddl"],
        capture_output=True,
        text=True,
        env={**os.environ, "PYTHONPATH": str(REPO), "TMPDIR": str(tmp_path)},
        preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_AS, (limit, limit)),
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert "1. pull orange" in done.stdout and "Traceback" not in done.stderr
    notes = [line for line in done.stderr.splitlines() if line.startswith("note:")]
    assert len(notes) == 1 and notes[0].startswith("note: the planner's memory limit is 3072 MB, your own")
    assert list(tmp_path.iterdir()) == []


def test_the_cache_is_never_in_the_temporary_folder(tmp_path, monkeypatch):
    monkeypatch.setenv("TMPDIR", str(tmp_path / "tmp"))
    monkeypatch.delenv("VSLSP_CACHE", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    assert cache_folder() == tmp_path / "cache" / "vslsp"
    assert not (tmp_path / "tmp").exists()


def test_a_lock_file_left_by_a_killed_run_is_taken_over_with_a_notice(tmp_path, capsys):
    folder = tmp_path / "out"
    folder.mkdir()
    holder = subprocess.Popen(
        [
            sys.executable,
            "-c",
            "import sys; from vslsp.outputs import lock_folder; lock_folder(sys.argv[1]); "
            "print('locked', flush=True); sys.stdin.read()",
            str(folder),
        ],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONPATH": str(REPO)},
    )
    assert holder.stdout is not None and holder.stdout.readline() == "locked\n"
    record = (folder / LOCK_NAME).read_text()
    assert f'"pid": {holder.pid}' in record and '"host"' in record and '"started"' in record
    holder.kill()
    holder.wait()
    lock_folder(folder)
    notice = capsys.readouterr().err
    assert notice.count("\n") == 1 and "left by a vslsp run that ended without releasing it" in notice
    assert f"pid {holder.pid}:" in notice


# --- whole programs ---


def _tree_gone(pids: list[int]) -> bool:
    return all(process_gone(pid) for pid in pids)


def _leftovers(tmp_path: Path) -> list[str]:
    return sorted(p.name for p in (tmp_path / "tmp").iterdir())


@pytest.mark.slow
@pytest.mark.parametrize(("name", "code"), [("SIGHUP", 129), ("SIGQUIT", 131)])
def test_a_hangup_or_quit_during_an_experiment_ends_its_workers_and_releases_the_folder(tmp_path, name, code):
    out = tmp_path / "report"
    args = ["experiment", "test-waits-after-the-first", "--trials", "4", "--workers", "2", "--out", out]
    process = start(args, tmp_path)
    try:
        assert became_true(lambda: (tmp_path / "markers" / "waiting-1").exists(), process)
        children = descendants(process.pid)  # the two workers and multiprocessing's resource tracker
        assert len(children) >= 3
        process.send_signal(getattr(signal, name))
        _, stderr = process.communicate(timeout=120)
    finally:
        process.kill()
    assert process.returncode == code, stderr
    assert "Traceback" not in stderr
    wait_until(lambda: _tree_gone(children), f"the workers and the resource tracker {children} to end")
    assert not (out / LOCK_NAME).exists()
    assert '"interrupted": "' + name in (out / "report.json").read_text()
    assert _leftovers(tmp_path) == []


@pytest.mark.slow
def test_a_killed_experiment_takes_its_workers_along_and_its_lock_is_taken_over(tmp_path):
    out = tmp_path / "report"
    args = ["experiment", "test-waits-after-the-first", "--trials", "4", "--workers", "2", "--out", out]
    process = start(args, tmp_path)
    try:
        assert became_true(lambda: (tmp_path / "markers" / "waiting-1").exists(), process)
        children = descendants(process.pid)
        process.kill()
        process.communicate(timeout=120)
    finally:
        process.kill()
    wait_until(lambda: _tree_gone(children), f"the workers and the resource tracker {children} to end")
    assert (out / LOCK_NAME).exists()  # a SIGKILL leaves the file (the kernel released the lock)
    rerun = start(["experiment", "test-quick", "--trials", "2", "--workers", "2", "--out", out], tmp_path)
    _, stderr = rerun.communicate(timeout=600)
    assert rerun.returncode == 0, stderr
    assert [line for line in stderr.splitlines() if "taking over" in line], stderr
    assert "Traceback" not in stderr and not (out / LOCK_NAME).exists()
    assert _leftovers(tmp_path) == []


@pytest.mark.slow
@pytest.mark.parametrize("name", ["SIGKILL", "SIGHUP"])
def test_a_killed_or_hung_up_plan_leaves_no_planner_and_no_folder(tmp_path, name):
    process = start(GROWING_PLAN, tmp_path)
    try:
        assert became_true(lambda: len(planner_processes(process.pid)) >= 3, process)  # guard, driver, translator
        planners = planner_processes(process.pid)
        assert [p.name for p in (tmp_path / "tmp").glob("vslsp-fd-*")]
        process.send_signal(getattr(signal, name))
        _, stderr = process.communicate(timeout=120)
    finally:
        process.kill()
    assert process.returncode == (-9 if name == "SIGKILL" else 129), stderr
    wait_until(lambda: _tree_gone(planners), f"the planner's processes {planners} to end")
    wait_until(lambda: _leftovers(tmp_path) == [], "the planner's folder to be removed")


@pytest.mark.slow
def test_a_killed_experiment_ends_the_planners_of_its_workers(tmp_path):
    process = start(["experiment", "test-plans", "--trials", "2", "--workers", "2", "--out", tmp_path / "r"], tmp_path)
    try:
        assert became_true(lambda: len(planner_processes(process.pid)) >= 2, process)
        everything = descendants(process.pid)
        process.kill()
        process.communicate(timeout=120)
    finally:
        process.kill()
    wait_until(lambda: _tree_gone(everything), f"the workers and their planners {everything} to end")
    wait_until(lambda: _leftovers(tmp_path) == [], "the planners' folders to be removed")


@pytest.mark.slow
def test_ctrl_c_twice_then_sigterm_at_once_is_still_the_first_signals_exit(tmp_path):
    """SIGINT, SIGINT, SIGTERM back to back: the cleanup of the first runs to its end (130)."""
    out = tmp_path / "report"
    args = ["experiment", "test-waits-after-the-first", "--trials", "4", "--workers", "2", "--out", out]
    process = start(args, tmp_path)
    try:
        assert became_true(lambda: (tmp_path / "markers" / "waiting-1").exists(), process)
        children = descendants(process.pid)
        for number in (signal.SIGINT, signal.SIGINT, signal.SIGTERM):
            process.send_signal(number)
        _, stderr = process.communicate(timeout=120)
    finally:
        process.kill()
    assert process.returncode == 130, stderr
    assert "Traceback" not in stderr
    wait_until(lambda: _tree_gone(children), f"the workers {children} to end")
    assert not (out / LOCK_NAME).exists() and (out / "report.json").exists()


@pytest.mark.slow
def test_closing_the_terminal_ends_an_experiment_as_sighup_does(tmp_path):
    """The terminal itself goes (its master side closed): the kernel hangs up the session, writes
    to the terminal fail with EIO, and the run still ends with 129, its report written and no
    process left."""
    out = tmp_path / "report"
    line, env = command(
        ["experiment", "test-waits-after-the-first", "--trials", "4", "--workers", "2", "--out", out], tmp_path
    )
    master, terminal = os.openpty()

    def on_the_terminal() -> None:  # the terminal becomes the program's controlling terminal
        os.setsid()
        fcntl.ioctl(0, termios.TIOCSCTTY, 0)

    process = subprocess.Popen(
        line, env=env, stdin=terminal, stdout=terminal, stderr=terminal, preexec_fn=on_the_terminal, cwd=tmp_path
    )
    os.close(terminal)
    try:
        assert became_true(lambda: (tmp_path / "markers" / "waiting-1").exists(), process)
        children = descendants(process.pid)
        os.close(master)
        process.wait(timeout=120)
    finally:
        process.kill()
    assert process.returncode == 129
    wait_until(lambda: _tree_gone(children), f"the workers and the resource tracker {children} to end")
    assert '"interrupted": "SIGHUP"' in (out / "report.json").read_text()
    assert not (out / LOCK_NAME).exists() and _leftovers(tmp_path) == []


@pytest.mark.slow
def test_teach_leaves_nothing_in_the_temporary_folder(tmp_path):
    """The simulator's reusable files go to the cache folder ($XDG_CACHE_HOME/vslsp), not TMPDIR."""
    process = start(["teach", "push", "--demos", "1", "--out", tmp_path / "skills"], tmp_path)
    _, stderr = process.communicate(timeout=600)
    assert process.returncode == 0, stderr
    assert _leftovers(tmp_path) == []
