"""Running a vslsp command as a separate program (with the tasks of
:mod:`helpers.interrupt_tasks` registered), for the interrupt and output tests; the waiting is
:mod:`helpers.events`'s."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from helpers.events import experiment_program
from vslsp.symbolic.engines.fast_downward import descendants

TESTS = Path(__file__).resolve().parents[1]
REPO = TESTS.parent


def command(args: list[object], tmp_path: Path) -> tuple[list[str], dict[str, str]]:
    """The program line of ``vslsp ARGS`` (with :mod:`helpers.interrupt_tasks` registered, each
    trial's result in the driver marked '<seed>.reported': :func:`helpers.events.experiment_program`)
    and its environment: temporary folders under ``tmp_path/tmp``, markers under ``tmp_path/markers``."""
    for name in ("tmp", "markers"):
        (tmp_path / name).mkdir(exist_ok=True)
    env = {
        **os.environ,
        "TMPDIR": str(tmp_path / "tmp"),
        "VSLSP_TEST_MARKERS": str(tmp_path / "markers"),
        "PYTHONPATH": os.pathsep.join([str(TESTS), str(REPO), os.environ.get("PYTHONPATH", "")]),
    }
    return [sys.executable, "-c", experiment_program("import helpers.interrupt_tasks"), *map(str, args)], env


def start(args: list[object], tmp_path: Path, prefix: tuple[str, ...] = (), **popen) -> subprocess.Popen:
    """Start ``vslsp ARGS`` as a program (see :func:`command`), after ``prefix`` (e.g. ``timeout 600``)."""
    line, env = command(args, tmp_path)
    popen.setdefault("stdout", subprocess.PIPE)
    popen.setdefault("stderr", subprocess.PIPE)
    return subprocess.Popen([*prefix, *line], env=env, text=True, cwd=tmp_path, **popen)


def planner_processes(pid: int) -> list[int]:
    """The Fast Downward processes below ``pid`` (its driver, translator or search)."""
    found = []
    for child in descendants(pid):
        try:
            command = Path(f"/proc/{child}/cmdline").read_bytes()
        except OSError:
            continue
        if b"fast-downward.py" in command or b"fast_downward.translate" in command or b"downward" in command:
            found.append(child)
    return found
