"""Test-wide settings: headless plotting, single-threaded torch (the suite runs 2 workers)."""

import os

os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import pytest  # noqa: E402


@pytest.fixture(scope="session")
def library():
    """The shipped skill library (push and pull), loaded once per test session."""
    from vslsp.skills.library import SkillLibrary, default_library_path

    return SkillLibrary.load(default_library_path())
