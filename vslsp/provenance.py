"""Where a result came from: what a report records so that a figure can be traced back and re-made
(the vslsp version and commit, Python, the platform, the command line)."""

from __future__ import annotations

import platform
import shlex
import subprocess
import sys
from functools import lru_cache
from importlib import metadata
from pathlib import Path
from typing import Any


@lru_cache(maxsize=1)
def _commit() -> dict[str, Any] | None:
    """The git commit of the checkout vslsp runs from (and whether it had changes), None for an installed
    wheel or where git is not there."""
    checkout = Path(__file__).resolve().parents[1]
    if not (checkout / ".git").exists():
        return None
    try:
        head = subprocess.run(
            ["git", "-C", str(checkout), "rev-parse", "HEAD"], capture_output=True, text=True, timeout=10
        )
        changed = subprocess.run(
            # --no-optional-locks: a status that is read only; a run killed meanwhile (or this timeout)
            # must not leave the checkout's index.lock behind, which blocks the user's next commit.
            ["git", "--no-optional-locks", "-C", str(checkout), "status", "--porcelain", "--untracked-files=no"],
            capture_output=True,
            text=True,
            timeout=10,
        )
    except (OSError, subprocess.SubprocessError):
        return None
    if head.returncode != 0:
        return None
    return {"commit": head.stdout.strip(), "changed": bool(changed.stdout.strip())}


def provenance() -> dict[str, Any]:
    """``{"vslsp", "commit", "changed" (uncommitted changes), "python", "platform", "command"}`` (a report adds
    ``seeds``: its first and last)."""
    try:
        version = metadata.version("vslsp")
    except metadata.PackageNotFoundError:
        version = "unknown"
    found = _commit() or {"commit": None, "changed": None}
    return {
        "vslsp": version,
        **found,
        "python": platform.python_version(),
        "platform": platform.platform(),
        "command": shlex.join(["vslsp", *sys.argv[1:]])
        if Path(sys.argv[0]).name in ("vslsp", "__main__.py")
        else shlex.join(sys.argv),
    }
