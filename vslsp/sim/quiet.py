"""Keep pybullet's C-level prints off the user's terminal.

pybullet writes warnings (for example while loading the iCub URDF: missing inertias,
unknown tags) straight to file descriptors 1 and 2 from C, so ``contextlib.redirect_stdout``
cannot catch them. :func:`quiet` points both descriptors at ``/dev/null`` for the duration.
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading
from collections.abc import Iterator

_lock = threading.RLock()


@contextlib.contextmanager
def quiet() -> Iterator[None]:
    """Silence everything written to stdout/stderr (Python and C) inside the block."""
    with _lock:
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (AttributeError, ValueError):
                pass
        saved: list[tuple[int, int]] = []
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
        except OSError:  # pragma: no cover - no /dev/null
            yield
            return
        try:
            for fd in (1, 2):
                try:
                    saved.append((fd, os.dup(fd)))
                    os.dup2(devnull, fd)
                except OSError:
                    pass
            yield
        finally:
            for fd, copy in saved:
                os.dup2(copy, fd)
                os.close(copy)
            os.close(devnull)
