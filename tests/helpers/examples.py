"""Running an example script of examples/ as a user runs it (``python SCRIPT ARGS``), in this
process: its ``__main__`` block with ``sys.argv`` set, what it printed returned."""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import pytest


def run_example(script: Path, args: list[str], capsys: pytest.CaptureFixture, monkeypatch: pytest.MonkeyPatch) -> str:
    """Run ``script`` with ``args``; returns its standard output."""
    monkeypatch.setattr(sys, "argv", [str(script), *args])
    runpy.run_path(str(script), run_name="__main__")
    return capsys.readouterr().out
