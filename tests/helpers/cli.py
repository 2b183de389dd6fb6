"""Running the CLI in tests, one way each: ``vslsp(capsys, ...)`` in this process (fast: exit
code and streams), ``vslsp_process(...)`` as a program (what a user's shell sees: no traceback,
standard input, the installed entry point's behaviour)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from vslsp.cli import main

REPO = Path(__file__).resolve().parents[2]


def vslsp(capsys: pytest.CaptureFixture[str], *args: object) -> tuple[int, str, str]:
    """Run ``vslsp ARGS`` in this process; (exit code, stdout, stderr)."""
    with pytest.raises(SystemExit) as done:
        main([str(a) for a in args])
    out, err = capsys.readouterr()
    code = done.value.code
    return (code if isinstance(code, int) else 1), out, err


def vslsp_process(
    *args: object, cwd: Path | None = None, input: str | None = None, timeout: float = 600
) -> subprocess.CompletedProcess[str]:
    """Run ``python -m vslsp ARGS`` as a subprocess (this checkout first on the path), with
    ``input`` on its standard input."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")])}
    return subprocess.run(
        [sys.executable, "-m", "vslsp", *map(str, args)],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=env,
        input=input,
        timeout=timeout,
    )


def unwritable_folder(tmp_path: Path) -> Path:
    """A folder nobody can write into: a read-only folder, or (as root, who ignores permissions)
    a folder under sysfs, which refuses new files."""
    if os.geteuid() != 0:
        folder = tmp_path / "read-only"
        folder.mkdir()
        folder.chmod(0o555)
        return folder
    return Path("/sys/vslsp-not-writable")
