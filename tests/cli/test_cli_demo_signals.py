"""Ctrl-C and SIGTERM during ``vslsp demo``, in the simulation and while it plans: the command
ends with 130 / 143 (docs/bad-input.md) and one line saying so, no traceback, and leaves no
process (the simulator, Fast Downward) nor temporary folder behind. The interrupts of ``plan``
and ``experiment``: tests/cli/test_bad_input_interrupts.py, tests/tasks/test_framework.py."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
from pathlib import Path

import pytest
from helpers.cli import REPO
from helpers.events import HANG_S, wait_until

pytestmark = pytest.mark.slow

EXIT = {"SIGINT": 130, "SIGTERM": 143}  # 128 + the signal's number
STAGES = {
    "simulation": "watching the tutor's demonstration",
    "planning": "learning the task and its order; planning",
}


def session_processes(session: int) -> list[int]:
    """The processes of the session ``session`` (the command and everything it started)."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[-1].split()
        except OSError:
            continue
        if int(fields[3]) == session and fields[0] not in ("Z", "X"):  # fields: state, ppid, pgrp, session
            found.append(int(stat.parent.name))
    return found


@pytest.mark.parametrize("stage", list(STAGES))
@pytest.mark.parametrize("name", list(EXIT))
def test_an_interrupt_during_demo_ends_it_cleanly(tmp_path, name, stage):
    temporary = tmp_path / "tmp"
    temporary.mkdir()
    program = "import signal, sys\nsignal.signal(signal.SIGINT, signal.default_int_handler)\n"
    program += "from vslsp.cli import main\nmain(sys.argv[1:])"
    env = {
        **os.environ,
        "TMPDIR": str(temporary),
        "HOME": str(tmp_path),
        "COLUMNS": "200",  # a stage's line unbroken on stderr
        "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
    }
    process = subprocess.Popen(
        [sys.executable, "-c", program, "demo", "--out", str(tmp_path / "report")],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    lines: list[str] = []
    assert process.stderr is not None
    reader = threading.Thread(target=lambda: lines.extend(process.stderr), daemon=True)  # type: ignore[arg-type]
    reader.start()
    try:
        wait_until(lambda: any(STAGES[stage] in line for line in lines) or process.poll() is not None, stage)
        assert process.poll() is None, "".join(lines)
        if name == "SIGINT":
            os.killpg(process.pid, signal.SIGINT)  # Ctrl-C: the terminal signals the whole group
        else:
            process.send_signal(signal.SIGTERM)
        process.wait(timeout=HANG_S)
        reader.join(timeout=HANG_S)
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
    stderr = "".join(lines)
    assert process.returncode == EXIT[name], stderr
    assert "Traceback" not in stderr, stderr
    last = stderr.strip().splitlines()[-1]
    assert name in last or (name == "SIGINT" and last == "aborted"), stderr  # one line says so
    wait_until(lambda: not session_processes(process.pid), "every process the demo started to end")
    assert not list(temporary.iterdir())  # the planner's folders removed; the cache is not kept there
