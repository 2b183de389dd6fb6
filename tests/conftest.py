"""Test-wide settings: headless plotting, single-threaded torch (the suite runs 2 workers), and
matplotlib's configuration and font cache in a temporary folder, for this process and the
programs it starts (matplotlib writes them into ~/.config and ~/.cache on first use: no test
writes outside its temporary folders); so is the XDG cache, where fontconfig puts its own font
cache when matplotlib lists the system's fonts with ``fc-list`` (~/.cache/fontconfig)."""

import atexit
import os
import shutil
import tempfile

os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ["MPLCONFIGDIR"] = tempfile.mkdtemp(prefix="vslsp-tests-matplotlib-")
atexit.register(shutil.rmtree, os.environ["MPLCONFIGDIR"], ignore_errors=True)
os.environ["XDG_CACHE_HOME"] = tempfile.mkdtemp(prefix="vslsp-tests-cache-")
atexit.register(shutil.rmtree, os.environ["XDG_CACHE_HOME"], ignore_errors=True)

import pytest  # noqa: E402


@pytest.fixture(scope="session")
def library():
    """The shipped skill library (push and pull), loaded once per test session."""
    from vslsp.skills.library import SkillLibrary, default_library_path

    return SkillLibrary.load(default_library_path())
