"""Writing outputs so that nothing is lost, mixed or overwritten by mistake (docs/bad-input.md).

Every file vslsp writes (reports, figures, plans, scene views, skill libraries) goes through
:func:`atomic_file`: the bytes go to a temporary file in the same folder, which replaces the
target in one ``os.replace`` once complete. A full disk or an interrupt therefore leaves the
previous file whole (a skill library keeps its working skill) and never a truncated one. The
rules every writer shares:

- never write through a symbolic link: an output path that is a link is refused
  (:func:`refuse_link`), whatever it points to;
- an output folder is used by one run at a time (:func:`lock_folder`): a second run into the
  same folder is refused, naming the first run's process and command;
- an output is never one of the command's inputs (:func:`refuse_input`);
- a write that fails for lack of space (or quota, or file-size limit) is
  :class:`OutputFailed` (exit 1: the task ran, its output could not be kept); any other
  failure to write is an :class:`~vslsp.errors.InputError` naming the path (exit 2).
"""

from __future__ import annotations

import atexit
import errno
import fcntl
import os
import sys
import tempfile
from collections.abc import Iterator, Mapping
from contextlib import contextmanager, suppress
from pathlib import Path
from typing import IO, Any

from vslsp.errors import InputError, VslspError

#: The errors that mean "no room": a full disk, a full quota, a file-size limit (ulimit -f).
NO_SPACE = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EFBIG})
#: The file in an output folder that says which run is using it.
LOCK_NAME = ".vslsp.lock"
_PART_PREFIX = ".vslsp-part-"


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


_FILE_MODE = 0o666 & ~_umask()  # what open() would give a new file


class OutputFailed(VslspError):
    """An output could not be written while the task ran (a full disk): the task's result is lost."""

    exit_code = 1


def write_error(path: str | os.PathLike[str], error: OSError) -> VslspError:
    """The user-facing error for ``error`` raised while writing ``path``."""
    reason = error.strerror or str(error)
    if error.errno in NO_SPACE:
        return OutputFailed(
            f"cannot write {path}: {reason} (the disk, your quota or the file-size limit is full); "
            "free some space and run again"
        )
    return InputError(f"cannot write {path} ({reason}); choose a writable place")


def refuse_link(path: str | os.PathLike[str], option: str | None = None) -> None:
    """Raise InputError when ``path`` is a symbolic link: vslsp never writes through one."""
    if os.path.islink(path):
        try:
            target = os.readlink(path)
        except OSError:
            target = "?"
        where = f"{option}: " if option else ""
        raise InputError(
            f"{where}{path} is a symbolic link (to {target}); vslsp never writes through a link: "
            "remove the link or choose another output"
        )


@contextmanager
def atomic_file(path: str | os.PathLike[str], mode: str = "wb") -> Iterator[IO[Any]]:
    """A file object whose content replaces ``path`` only once the block ends without error.

    ``mode``: ``"wb"`` or ``"w"`` (UTF-8 text). The target's folder must exist. On any error
    (or an interrupt) the temporary file is removed and ``path`` is left as it was.
    """
    target = Path(path)
    refuse_link(target)
    folder = target.parent
    try:
        handle, temporary = tempfile.mkstemp(prefix=_PART_PREFIX, dir=folder)
    except OSError as error:
        raise write_error(target, error) from None
    try:
        # Text keeps a file name that is not UTF-8 as the bytes it was given (surrogateescape).
        text = "b" not in mode
        with os.fdopen(
            handle, mode, encoding="utf-8" if text else None, errors="surrogateescape" if text else None
        ) as stream:
            yield stream
            stream.flush()
            os.fsync(stream.fileno())
        os.chmod(temporary, _FILE_MODE)
        refuse_link(target)  # again: a link made while the file was being written
        os.replace(temporary, target)
    except OSError as error:
        raise write_error(target, error) from None
    finally:
        with suppress(FileNotFoundError):
            os.unlink(temporary)


def write_bytes(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically; returns the path."""
    with atomic_file(path, "wb") as stream:
        stream.write(data)
    return Path(path)


def write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically; returns the path."""
    with atomic_file(path, "w") as stream:
        stream.write(text)
    return Path(path)


def refuse_input(
    output: str | os.PathLike[str], inputs: Mapping[str, str | os.PathLike[str] | None], option: str
) -> None:
    """Raise InputError when the output file ``output`` is one of ``inputs`` (what -> path)."""
    for what, given in inputs.items():
        if given is None:
            continue
        try:
            same = os.path.samefile(output, given)
        except OSError:  # one of them does not exist (yet): not the same file
            same = False
        if same:
            raise InputError(
                f"{option} {output} is the {what} {given}: writing there would destroy the input; choose another file"
            )


_HELD: dict[str, int] = {}  # realpath of a locked folder -> the lock file's descriptor


def lock_folder(folder: str | os.PathLike[str], option: str = "--out") -> None:
    """Take ``folder`` for this process until it exits; InputError (exit 2) naming the process
    that holds it otherwise.

    The lock is an ``flock`` on ``folder/.vslsp.lock``, so the system releases it when the
    holder ends, however it ends; the file records the holder's pid and command line.
    """
    key = os.path.realpath(folder)
    if key in _HELD:
        return
    lock = Path(folder) / LOCK_NAME
    refuse_link(lock, option)
    while True:
        try:
            handle = os.open(lock, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW, _FILE_MODE)
        except OSError as error:
            raise InputError(f"{option}: cannot lock the folder {folder} ({error.strerror})") from None
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            holder = os.read(handle, 4096).decode("utf-8", "replace").strip() or "another process"
            os.close(handle)
            raise InputError(
                f"{option}: {folder} is in use by another vslsp run ({holder}); wait for it to end or "
                "choose another output folder"
            ) from None
        try:  # the holder before us may have removed the file we opened: lock the one in place
            if os.stat(lock, follow_symlinks=False).st_ino == os.fstat(handle).st_ino:
                break
        except FileNotFoundError:
            pass
        os.close(handle)
    command = " ".join(["vslsp", *sys.argv[1:]]) if sys.argv else "python"
    with suppress(OSError):  # the record is for people; the lock holds without it
        os.ftruncate(handle, 0)
        os.write(handle, f"pid {os.getpid()}: {command}\n".encode("utf-8", "surrogateescape"))
    _HELD[key] = handle
    atexit.register(_release, key, lock)


def _release(key: str, lock: Path) -> None:
    handle = _HELD.pop(key, None)
    if handle is None:
        return
    with suppress(OSError):
        os.unlink(lock)  # while still holding it: a waiting run then locks a fresh file
    with suppress(OSError):
        os.close(handle)
