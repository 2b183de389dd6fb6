"""Fast Downward run directly on PDDL text (the copy that unified-planning's up-fast-downward ships).

Paper: "Implementation" (an off-the-shelf planner takes the learned domain and the task).
vslsp writes the domain and the problem itself (the model's ``to_pddl``, constraints compiled
by :mod:`vslsp.symbolic.engines.lifted`) and hands them to Fast Downward's driver: its translator
grounds the lifted schemas, so no grounding happens in Python. unified-planning's own writer
lists every ground atom of every predicate in the initial state, which on a 200-object order
takes longer than the search. Part of the planning adapter with :mod:`vslsp.symbolic.engines.planner`.
"""

from __future__ import annotations

import importlib.util
import math
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from vslsp.errors import InputError
from vslsp.interrupts import communicate, deferred, guarded_command
from vslsp.outputs import NO_SPACE, write_error
from vslsp.symbolic.engines.outcomes import PlanStatus

_CODES = {
    0: PlanStatus.SOLVED,
    1: PlanStatus.SOLVED,
    2: PlanStatus.SOLVED,
    3: PlanStatus.SOLVED,
    10: PlanStatus.UNSOLVABLE_PROVEN,  # the translator proved it
    11: PlanStatus.UNSOLVABLE_PROVEN,  # a complete search proved it
    12: PlanStatus.UNSOLVABLE_INCOMPLETELY,  # an incomplete search gave up
    20: PlanStatus.MEMOUT,
    21: PlanStatus.TIMEOUT,
    22: PlanStatus.MEMOUT,
    23: PlanStatus.TIMEOUT,
    24: PlanStatus.TIMEOUT,
}


@dataclass(frozen=True)
class Run:
    """A Fast Downward run: how it ended (from the driver's exit code), the plan's steps (lower
    case), the log's tail and the time taken."""

    outcome: PlanStatus
    steps: tuple[tuple[str, tuple[str, ...]], ...]
    log: str
    time_s: float
    translate_s: float | None  # the translator's wall-clock time, from its log
    returncode: int | None = None  # the driver's exit code (None: killed at the wall-clock limit)


def driver() -> Path:
    """The ``fast-downward.py`` driver installed with up-fast-downward, found without importing the
    package (its ``__init__`` imports unified-planning's engines: about a second)."""
    spec = importlib.util.find_spec("up_fast_downward")
    if spec is None or not spec.submodule_search_locations:
        raise InputError("Fast Downward is not installed: pip install up-fast-downward")
    path = Path(list(spec.submodule_search_locations)[0]) / "downward" / "fast-downward.py"
    if not path.exists():
        raise InputError(f"Fast Downward's driver is missing ({path}); reinstall up-fast-downward")
    return path


def run(
    domain_text: str,
    problem_text: str,
    options: list[str],
    timeout: float | None = None,
    translate_only: bool = False,
    memory_mb: int | None = None,
) -> Run:
    """Run the driver on the two texts in a fresh folder.

    ``options``: ``["--search", "..."]`` or ``["--alias", "..."]``.

    ``timeout``: wall-clock seconds for the whole run (also the driver's CPU limit).
    ``memory_mb``: the address-space limit of every process of the run (``RLIMIT_AS``, set in the
    child before it starts, so the translator or the search fails its allocation instead of
    growing the machine out of memory).

    ``translate_only``: stop after the translator (to time it).

    Fast Downward runs in this process's group (no session of its own), so a signal to the
    group (Ctrl-C, ``timeout``) reaches it too; when this process stops otherwise (its own
    limit, an interrupt, an exception) every process of the run is killed and the folder removed;
    when this process is killed (SIGKILL), the run's guard does both
    (:func:`vslsp.interrupts.guarded_command`).
    """
    limit = ["--overall-time-limit", f"{max(1, math.ceil(timeout))}s"] if timeout else []
    if memory_mb:
        limit += ["--overall-memory-limit", f"{memory_mb}M"]
    with tempfile.TemporaryDirectory(prefix="vslsp-fd-") as folder:
        domain_file, problem_file = Path(folder) / "domain.pddl", Path(folder) / "problem.pddl"
        for path, text in ((domain_file, domain_text), (problem_file, problem_text)):
            try:
                path.write_text(text)
            except OSError as error:  # a full temporary folder is a full disk, not a planner failure
                if error.errno in NO_SPACE:
                    raise write_error(path, error) from None
                raise
        phase = ["--translate"] if translate_only else []
        alias = options if options[:1] == ["--alias"] and not translate_only else []
        search = [] if translate_only or alias else options
        command = [
            sys.executable,
            str(driver()),
            *limit,
            *alias,
            *phase,
            "--plan-file",
            "plan",
            str(domain_file),
            str(problem_file),
            *search,
        ]
        start = time.perf_counter()
        process = subprocess.Popen(
            guarded_command(command, folder, memory_mb),
            cwd=folder,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            errors="replace",
        )
        try:
            log, _ = communicate(process, timeout)  # wall-clock (the driver limits CPU time)
        except subprocess.TimeoutExpired:
            kill_tree(process)
            log, _ = process.communicate()
            return Run(PlanStatus.TIMEOUT, (), log[-4000:], time.perf_counter() - start, None)
        except BaseException:  # Ctrl-C, SIGTERM, an error: the translator and the search go too
            kill_tree(process)
            raise
        elapsed = time.perf_counter() - start
        translate = re.search(r"Done! \[[\d.]+s CPU, ([\d.]+)s wall-clock\]", log)
        outcome = outcome_of(process.returncode, log, timed=bool(timeout), limited=bool(memory_mb))
        steps: tuple = ()
        if outcome is PlanStatus.SOLVED and not translate_only:
            if (Path(folder) / "plan").exists():
                steps = _read_plan(Path(folder) / "plan")
            else:
                # "A plan found and out of memory / time", but none written: the limit's outcome. Exit 1
                # is also the driver's own crash on the translator's MemoryError report (up-fast-downward's
                # driver compares its stderr bytes with a str), after the memory limit was reached.
                outcome = {1: PlanStatus.MEMOUT, 2: PlanStatus.TIMEOUT, 3: PlanStatus.MEMOUT}.get(
                    process.returncode, PlanStatus.INTERNAL_ERROR
                )
        translated = float(translate.group(1)) if translate else None
        return Run(outcome, steps, log[-4000:], elapsed, translated, process.returncode)


def outcome_of(code: int, log: str, timed: bool, limited: bool) -> PlanStatus:
    """The outcome of the driver's exit ``code``. A component killed by a signal passes the
    signal on as its code (-24, i.e. 232): SIGXCPU is the CPU limit; SIGKILL under a limit is
    the limit's hard end (the kernel's, or a ``MemoryError`` the translator could not report)."""
    signal_number = 256 - code if code > 128 else -code if code < 0 else None
    if signal_number == signal.SIGXCPU and timed:
        return PlanStatus.TIMEOUT
    if signal_number in (signal.SIGKILL, signal.SIGSEGV, signal.SIGABRT) and limited and "MemoryError" in log:
        return PlanStatus.MEMOUT
    if code == 30 and limited and ("MemoryError" in log or "std::bad_alloc" in log):
        return PlanStatus.MEMOUT
    return _CODES.get(code, PlanStatus.INTERNAL_ERROR)


def failure(run: Run) -> str:
    """What failed in a run whose outcome is INTERNAL_ERROR: the component and its last line of output."""
    component = "driver"
    for match in re.finditer(r"Running (translator|search)", run.log):
        component = match.group(1)
    noise = ("INFO", "Driver aborting", "translate exit code", "search exit code", "[t=", "Planner time")
    lines = [line.strip() for line in run.log.splitlines() if line.strip() and not line.startswith(noise)]
    codes = re.findall(r"(?:translate|search) exit code: (-?\d+)", run.log)
    code = f" with exit code {codes[-1]}" if codes else ""
    last = lines[-1] if lines else "no output"
    return f"Fast Downward's {component} stopped{code}: {last[:300]}"


def descendants(pid: int) -> list[int]:
    """The processes below ``pid`` (children, grandchildren, ...), read from ``/proc``."""
    children: dict[int, list[int]] = {}
    for entry in os.scandir("/proc"):
        if not entry.name.isdigit():
            continue
        try:
            with open(f"/proc/{entry.name}/stat", "rb") as stat:
                fields = stat.read().rsplit(b")", 1)[1].split()
        except OSError:  # it ended meanwhile
            continue
        children.setdefault(int(fields[1]), []).append(int(entry.name))
    found, todo = [], [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            found.append(child)
            todo.append(child)
    return found


def kill_tree(process: subprocess.Popen) -> None:
    """SIGKILL ``process`` and every process below it, and reap it.

    A signal that comes meanwhile waits for the end (:func:`vslsp.interrupts.deferred`): a process
    stopped and then left unkilled would stay stopped for good, deaf to its parent-death signal."""
    with deferred():
        if process.poll() is None:
            try:  # stopped first, so that it starts no new process while its tree is read
                os.kill(process.pid, signal.SIGSTOP)
            except ProcessLookupError:
                pass
            tree = descendants(process.pid) if os.path.isdir("/proc") else []
            for pid in [process.pid, *tree]:
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
        process.wait()


def _read_plan(path: Path) -> tuple[tuple[str, tuple[str, ...]], ...]:
    steps = []
    for line in path.read_text().splitlines():
        line = line.split(";", 1)[0].strip()
        if line:
            words = line.strip("()").lower().split()
            steps.append((words[0], tuple(words[1:])))
    return tuple(steps)
