"""Running a vslsp command as a separate program and waiting on events (a file appears, a
process ends), for the interrupt and output tests."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

from vslsp.symbolic.fast_downward import descendants

HERE = Path(__file__).resolve().parents[1] / "cli"
REPO = HERE.parents[1]
PATIENCE_S = 300  # a safety net against a hang, never a measure of speed


def command(args: list[object], tmp_path: Path) -> tuple[list[str], dict[str, str]]:
    """The program line of ``vslsp ARGS`` (with tests/cli/interrupt_tasks registered) and its
    environment: temporary folders under ``tmp_path/tmp``, markers under ``tmp_path/markers``."""
    for name in ("tmp", "markers"):
        (tmp_path / name).mkdir(exist_ok=True)
    env = {
        **os.environ,
        "TMPDIR": str(tmp_path / "tmp"),
        "VSLSP_TEST_MARKERS": str(tmp_path / "markers"),
        "PYTHONPATH": os.pathsep.join([str(HERE), str(REPO), os.environ.get("PYTHONPATH", "")]),
    }
    program = (
        "import signal, sys\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"  # a background job may have it ignored
        "import interrupt_tasks\nfrom vslsp.cli import main\nmain(sys.argv[1:])"
    )
    return [sys.executable, "-c", program, *map(str, args)], env


def start(args: list[object], tmp_path: Path, prefix: tuple[str, ...] = (), **popen) -> subprocess.Popen:
    """Start ``vslsp ARGS`` as a program (see :func:`command`), after ``prefix`` (e.g. ``timeout 600``)."""
    line, env = command(args, tmp_path)
    popen.setdefault("stdout", subprocess.PIPE)
    popen.setdefault("stderr", subprocess.PIPE)
    return subprocess.Popen([*prefix, *line], env=env, text=True, cwd=tmp_path, **popen)


def wait_until(condition: Callable[[], bool], process: subprocess.Popen | None = None) -> bool:
    """Wait until ``condition()`` holds (False if ``process`` ended first, or after PATIENCE_S)."""
    deadline = time.monotonic() + PATIENCE_S
    while time.monotonic() < deadline:
        if condition():
            return True
        if process is not None and process.poll() is not None:
            return condition()
        time.sleep(0.05)
    return False


def alive(pid: int) -> bool:
    """Whether ``pid`` is a running process (a zombie waiting for its parent counts as gone)."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as stat:
            return stat.read().rsplit(b")", 1)[1].split()[0] != b"Z"
    except OSError:
        return False


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
