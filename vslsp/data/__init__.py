"""The shipped data: the learned push/pull skill library and the PDDL examples.

They live at the top of the source tree (``skills/``, ``pddl/``) and are mapped into the package
at build time as ``vslsp.data.skills`` and ``vslsp.data.pddl`` (``package-dir`` in
``pyproject.toml``), so a wheel carries them as package data and an editable install maps them
to the source folders. Both are found through :mod:`importlib.resources`; a plain source
checkout on ``PYTHONPATH`` (no install, or an editable install made before the mapping
existed) falls back to the folders beside the package.
"""

from __future__ import annotations

import importlib.resources
from pathlib import Path

# A file each shipped folder must hold (to tell it from an empty namespace folder).
MARKERS = {"skills": "library.json", "pddl": "domain.pddl"}


def shipped_folder(kind: str) -> Path:
    """The folder of shipped ``kind`` data (``"skills"`` or ``"pddl"``) as a file-system path."""
    if kind not in MARKERS:
        raise ValueError(f"no shipped data {kind!r}; there are {sorted(MARKERS)}")
    marker = MARKERS[kind]
    source = Path(__file__).resolve().parents[2] / kind  # a source checkout: <repo>/vslsp/data
    if (source / marker).is_file():  # the checkout's own data (one of several worktrees on PYTHONPATH)
        return source
    try:
        resource = importlib.resources.files(f"{__name__}.{kind}") / marker
        if resource.is_file():
            with importlib.resources.as_file(resource) as path:
                return Path(path).parent
    except ModuleNotFoundError:
        pass
    raise FileNotFoundError(
        f"the shipped {kind} folder is missing from this installation of vslsp "
        f"(no {marker} in the package data nor in {source}); reinstall vslsp"
    )


def skills_folder() -> Path:
    """The shipped skill library folder (``library.json`` and the skills' ``.npz`` files)."""
    return shipped_folder("skills")


def pddl_folder() -> Path:
    """The shipped PDDL examples: ``domain.pddl`` and the problems of the paper's tasks."""
    return shipped_folder("pddl")
