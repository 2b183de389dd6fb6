"""Fast Downward run directly on PDDL text (the copy that unified-planning's up-fast-downward ships).

Paper: "Implementation" (an off-the-shelf planner takes the learned domain and the task).
vslsp writes the domain and the problem itself (the model's ``to_pddl``, constraints compiled
by :mod:`vslsp.symbolic.lifted`) and hands them to Fast Downward's driver: its translator
grounds the lifted schemas, so no grounding happens in Python. unified-planning's own writer
lists every ground atom of every predicate in the initial state, which on a 200-object order
takes longer than the search. Part of the planning adapter with :mod:`vslsp.symbolic.planner`.
"""

from __future__ import annotations

import importlib.resources
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from enum import Enum
from pathlib import Path

from vslsp.errors import InputError


class Outcome(Enum):
    """What a Fast Downward run ended with (from the driver's exit code)."""

    SOLVED = "solved"
    UNSOLVABLE = "unsolvable"  # proved: the translator or a complete search found no plan
    UNSOLVED = "unsolved"  # an incomplete search gave up
    TIMEOUT = "timeout"
    MEMOUT = "memout"
    ERROR = "error"  # the translator or the search failed


_CODES = {
    0: Outcome.SOLVED,
    1: Outcome.SOLVED,
    2: Outcome.SOLVED,
    3: Outcome.SOLVED,
    10: Outcome.UNSOLVABLE,
    11: Outcome.UNSOLVABLE,
    12: Outcome.UNSOLVED,
    20: Outcome.MEMOUT,
    21: Outcome.TIMEOUT,
    22: Outcome.MEMOUT,
    23: Outcome.TIMEOUT,
    24: Outcome.TIMEOUT,
}


@dataclass(frozen=True)
class Run:
    """A Fast Downward run: its outcome, the plan's steps (lower case), the log's tail and the time taken."""

    outcome: Outcome
    steps: tuple[tuple[str, tuple[str, ...]], ...]
    log: str
    time_s: float
    translate_s: float | None  # the translator's wall-clock time, from its log


def driver() -> Path:
    """The ``fast-downward.py`` driver installed with up-fast-downward."""
    try:
        path = Path(str(importlib.resources.files("up_fast_downward").joinpath("downward/fast-downward.py")))
    except ModuleNotFoundError:
        raise InputError("Fast Downward is not installed: pip install up-fast-downward") from None
    if not path.exists():
        raise InputError(f"Fast Downward's driver is missing ({path}); reinstall up-fast-downward")
    return path


def run(
    domain_text: str, problem_text: str, options: list[str], timeout: float | None = None, translate_only: bool = False
) -> Run:
    """Run the driver on the two texts in a fresh folder.

    ``options``: ``["--search", "..."]`` or ``["--alias", "..."]``.

    ``translate_only``: stop after the translator (to time it).
    """
    limit = ["--overall-time-limit", f"{max(1, int(timeout))}s"] if timeout else []
    with tempfile.TemporaryDirectory(prefix="vslsp-fd-") as folder:
        domain_file, problem_file = Path(folder) / "domain.pddl", Path(folder) / "problem.pddl"
        domain_file.write_text(domain_text)
        problem_file.write_text(problem_text)
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
            command, cwd=folder, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True
        )
        try:
            log, _ = process.communicate(timeout=timeout)  # wall-clock (the driver limits CPU time)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            log, _ = process.communicate()
            return Run(Outcome.TIMEOUT, (), log[-4000:], time.perf_counter() - start, None)
        except BaseException:  # Ctrl-C: the translator and the search go too
            os.killpg(process.pid, signal.SIGKILL)
            raise
        elapsed = time.perf_counter() - start
        translate = re.search(r"Done! \[[\d.]+s CPU, ([\d.]+)s wall-clock\]", log)
        outcome = _CODES.get(process.returncode, Outcome.ERROR)
        steps: tuple = ()
        if outcome is Outcome.SOLVED and not translate_only:
            steps = _read_plan(Path(folder) / "plan")
        return Run(outcome, steps, log[-4000:], elapsed, float(translate.group(1)) if translate else None)


def _read_plan(path: Path) -> tuple[tuple[str, tuple[str, ...]], ...]:
    steps = []
    for line in path.read_text().splitlines():
        line = line.split(";", 1)[0].strip()
        if line:
            words = line.strip("()").lower().split()
            steps.append((words[0], tuple(words[1:])))
    return tuple(steps)
