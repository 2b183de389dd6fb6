"""Reading PDDL files within a budget: regular files of at most :data:`MAX_PDDL_BYTES` bytes of UTF-8
text (shared with the planner path, :mod:`vslsp.symbolic.pddl`)."""

from __future__ import annotations

import os
from pathlib import Path

from vslsp.errors import InputError
from vslsp.files import decode_text, read_bytes, regular_file, shown
from vslsp.symbolic.budget import phase

#: The largest PDDL file read (the planner path's reader slows down more than linearly with size).
MAX_PDDL_BYTES = 1_000_000


def read_text(path: str | Path, what: str = "PDDL file") -> str:
    """The text of a regular UTF-8 file of at most :data:`MAX_PDDL_BYTES` bytes, or InputError saying what
    is wrong. A FIFO or a device is refused by its ``stat``, never opened; the limit holds while reading
    (:mod:`vslsp.files`)."""
    try:
        os.stat(path)
    except OSError as error:
        raise InputError(f"{shown(path)}: cannot read the file ({error.strerror})") from None
    size = regular_file(path, what).st_size
    if size > MAX_PDDL_BYTES:
        raise InputError(
            f"{shown(path)}: the {what} has {size / 1e6:.1f} MB; vslsp reads at most "
            f"{MAX_PDDL_BYTES / 1e6:.0f} MB (split the problem or plan with Fast Downward directly)"
        )
    return decode_text(read_bytes(path, what, MAX_PDDL_BYTES), path, what)


def check_files(domain_path: str | Path, problem_path: str | Path | None = None):  # type: ignore[no-untyped-def]
    """:func:`~vslsp.symbolic.language.analyse` on files read with :func:`read_text` (names as given), within
    the checking phase's budget (:func:`vslsp.symbolic.budget.phase`)."""
    from vslsp.symbolic.language.analysis import analyse

    domain_text = read_text(domain_path)
    problem_text = read_text(problem_path) if problem_path is not None else None
    with phase("checking", str(problem_path if problem_path is not None else domain_path)):
        return analyse(
            domain_text, str(domain_path), problem_text, str(problem_path) if problem_path is not None else ""
        )
