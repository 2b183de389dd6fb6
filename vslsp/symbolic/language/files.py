"""Reading PDDL files within a budget: regular files of UTF-8 text of at most ``max_bytes`` bytes
(:data:`MAX_PDDL_BYTES` unless the user's ``--max-size`` says otherwise), shared with the planner path
(:mod:`vslsp.symbolic.io.pddl`), the shell and the language server: the one place the limit is defined.

The language engine reads in time and memory linear in the size (benchmarks/bench_pddl_size.py: about
0.7 s of CPU and 70 MB of memory per MB of PDDL), so the limit is what bounds a file's memory."""

from __future__ import annotations

import os
from pathlib import Path

from vslsp.errors import InputError
from vslsp.files import decode_text, read_bytes, regular_file, shown
from vslsp.symbolic.budget import phase

#: The largest PDDL file read by default, in bytes: above IPC's largest problems (tens of MB), and at about
#: 70 bytes of memory per byte read, within a few GB (``--max-size MB`` changes it).
MAX_PDDL_BYTES = 100_000_000
#: The option that changes the limit, named in the message of a file over it.
MAX_SIZE_OPTION = "--max-size"


def read_text(path: str | Path, what: str = "PDDL file", max_bytes: int = MAX_PDDL_BYTES) -> str:
    """The text of a regular UTF-8 file of at most ``max_bytes`` bytes, or InputError saying what is
    wrong. A FIFO or a device is refused by its ``stat``, never opened; the limit holds while reading
    (:mod:`vslsp.files`)."""
    try:
        os.stat(path)
    except OSError as error:
        raise InputError(f"{shown(path)}: cannot read the file ({error.strerror})") from None
    size = regular_file(path, what).st_size
    if size > max_bytes:
        raise InputError(
            f"{shown(path)}: the {what} has {megabytes(size)} MB, over the limit of {megabytes(max_bytes)} MB; "
            f"raise it with {MAX_SIZE_OPTION} MB (or split the problem)"
        )
    return decode_text(read_bytes(path, what, max_bytes), path, what)


def megabytes(size: int) -> str:
    """``size`` bytes in MB as a user reads it: ``1.4``, ``100``, ``0.001``."""
    shown_size = f"{size / 1e6:.1f}"
    return shown_size if shown_size != "0.0" else f"{size / 1e6:.3g}"


def check_files(  # type: ignore[no-untyped-def]
    domain_path: str | Path, problem_path: str | Path | None = None, max_bytes: int = MAX_PDDL_BYTES
):
    """:func:`~vslsp.symbolic.language.analyse` on files read with :func:`read_text` (names as given, each of
    at most ``max_bytes``), within the checking phase's budget (:func:`vslsp.symbolic.budget.phase`)."""
    from vslsp.symbolic.language.analysis import analyse

    domain_text = read_text(domain_path, max_bytes=max_bytes)
    problem_text = read_text(problem_path, max_bytes=max_bytes) if problem_path is not None else None
    with phase("checking", str(problem_path if problem_path is not None else domain_path)):
        return analyse(
            domain_text, str(domain_path), problem_text, str(problem_path) if problem_path is not None else ""
        )
