"""A studio root in tmp_path with the shipped PDDL and the grounding example pair."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

pytest.importorskip("nicegui", reason="the studio extra is not installed (pip install 'vslsp[studio]')")


@pytest.fixture
def studio_root(tmp_path: Path) -> Path:
    """A root with pddl/ (the shipped domain and problems) and examples/grounding/."""
    root = tmp_path / "root"
    shutil.copytree(REPO / "pddl", root / "pddl", ignore=shutil.ignore_patterns("*.py", "__pycache__"))
    shutil.copytree(
        REPO / "examples" / "grounding",
        root / "examples" / "grounding",
        ignore=shutil.ignore_patterns("test_*", "__pycache__"),
    )
    return root
