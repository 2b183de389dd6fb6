"""Reading PDDL files within a budget: regular files of at most :data:`MAX_PDDL_BYTES` bytes of UTF-8
text (shared with the planner path, :mod:`vslsp.symbolic.pddl`)."""

from __future__ import annotations

import stat
from pathlib import Path

from vslsp.errors import InputError

#: The largest PDDL file read (the planner path's reader slows down more than linearly with size).
MAX_PDDL_BYTES = 1_000_000


def read_text(path: str | Path, what: str = "PDDL file") -> str:
    """The text of a regular UTF-8 file of at most :data:`MAX_PDDL_BYTES` bytes, or InputError saying what is wrong."""
    path = Path(path)
    try:
        status = path.stat()
        if not stat.S_ISREG(status.st_mode):
            raise InputError(f"{path}: not a regular file; give the path of a {what}")
        if status.st_size > MAX_PDDL_BYTES:
            raise InputError(
                f"{path}: the {what} has {status.st_size / 1e6:.1f} MB; vslsp reads at most "
                f"{MAX_PDDL_BYTES / 1e6:.0f} MB (split the problem or plan with Fast Downward directly)"
            )
        data = path.read_bytes()
    except OSError as error:
        raise InputError(f"{path}: cannot read the file ({error.strerror})") from None
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        line = data.count(b"\n", 0, error.start) + 1
        column = error.start - (data.rfind(b"\n", 0, error.start) + 1) + 1
        raise InputError(
            f"{path}:{line}:{column}: the {what} is not UTF-8 text (byte 0x{data[error.start]:02x}); "
            "save it as UTF-8 (plain ASCII is fine)"
        ) from None


def check_files(domain_path: str | Path, problem_path: str | Path | None = None):  # type: ignore[no-untyped-def]
    """:func:`~vslsp.symbolic.language.analyse` on files read with :func:`read_text` (names as given)."""
    from vslsp.symbolic.language.analysis import analyse

    domain_text = read_text(domain_path)
    problem_text = read_text(problem_path) if problem_path is not None else None
    return analyse(domain_text, str(domain_path), problem_text, str(problem_path) if problem_path is not None else "")
