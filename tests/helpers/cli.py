"""Running the CLI in tests, one way each: ``vslsp(capsys, ...)`` in this process (fast: exit
code and streams), ``vslsp_process(...)`` as a program (what a user's shell sees: no traceback,
standard input, the installed entry point's behaviour)."""

from __future__ import annotations

import hashlib
import json
import os
import shutil
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


def refused(capsys: pytest.CaptureFixture[str], *args: object) -> str:
    """``vslsp ARGS --json`` that must be bad input: exit 2, a JSON error on stdout, one line on
    stderr and no traceback; returns stderr."""
    code, out, err = vslsp(capsys, *args, "--json")
    assert code == 2, err
    assert "error" in json.loads(out)
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    return err


def vslsp_process(
    *args: object,
    cwd: Path | None = None,
    input: str | None = None,
    timeout: float = 600,
    checkout: Path = REPO,
) -> subprocess.CompletedProcess[str]:
    """Run ``python -m vslsp ARGS`` as a subprocess (``checkout``, this one by default, first on
    the path), with ``input`` on its standard input."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(checkout), os.environ.get("PYTHONPATH", "")])}
    return subprocess.run(
        [sys.executable, "-m", "vslsp", *map(str, args)],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=env,
        input=input,
        timeout=timeout,
    )


def checkout_copy(folder: Path) -> Path:
    """A copy of this source checkout in ``folder`` (the package, the shipped skills/ and pddl/,
    pyproject.toml): for tests of what vslsp does to its own folders, which must never touch
    the real ones. Give it to :func:`vslsp_process` as ``checkout``."""
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc")
    for name in ("vslsp", "skills", "pddl"):
        shutil.copytree(REPO / name, folder / name, ignore=ignore)
    shutil.copy2(REPO / "pyproject.toml", folder / "pyproject.toml")
    return folder


def tree_digest(folder: Path) -> dict[str, str]:
    """Every file under ``folder`` (relative path) with the SHA-256 of its bytes."""
    return {
        str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(folder.rglob("*"))
        if p.is_file() and "__pycache__" not in p.parts
    }


def unwritable_folder(tmp_path: Path) -> Path:
    """A folder nobody can write into: a read-only folder, or (as root, who ignores permissions)
    a folder under sysfs, which refuses new files."""
    if os.geteuid() != 0:
        folder = tmp_path / "read-only"
        folder.mkdir()
        folder.chmod(0o555)
        return folder
    return Path("/sys/vslsp-not-writable")


def read_only_folder(tmp_path: Path) -> Path:
    """An existing folder nobody can add a file to: a folder made read-only, or (as root, who
    ignores permissions, as CI runs) a sysfs folder, where the kernel refuses new files."""
    if os.geteuid() != 0:
        return unwritable_folder(tmp_path)
    folder = Path("/sys/kernel")
    if not folder.is_dir():
        pytest.skip("as root, a read-only folder needs sysfs (/sys/kernel)")
    return folder
