"""Writing outputs so that nothing is lost, mixed or overwritten by mistake (docs/bad-input.md).

Every file vslsp writes (reports, figures, plans, scene views, skill libraries) goes through
:func:`atomic_file`: the bytes go to a temporary file in the same folder, which replaces the
target in one ``os.replace`` once complete. A full disk or an interrupt therefore leaves the
previous file whole (a skill library keeps its working skill) and never a truncated one. The
rules every writer shares:

- never write through a symbolic link: an output path that is a link is refused
  (:func:`refuse_link`), whatever it points to, and so is a link among the folders inside an
  output folder (:func:`output_subfolder`, :func:`refuse_places`);
- never write over a device, a FIFO or a socket (:func:`refuse_special`): the rename would
  replace the node with a regular file;
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
import json
import os
import socket
import stat
import sys
import tempfile
import time
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


def _kind(mode: int) -> str:
    for test, name in (
        (stat.S_ISFIFO, "a FIFO (named pipe)"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISSOCK, "a socket"),
    ):
        if test(mode):
            return name
    return "not a regular file"


def refuse_special(path: str | os.PathLike[str], option: str | None = None) -> None:
    """Raise InputError when ``path`` is a device, a FIFO or a socket: the atomic rename would
    replace the node itself with a regular file (``/dev/full`` with a plan), so vslsp writes
    only regular files (a missing one is created)."""
    try:
        mode = os.lstat(path).st_mode
    except OSError:
        return
    if stat.S_ISREG(mode) or stat.S_ISDIR(mode) or stat.S_ISLNK(mode):
        return
    where = f"{option}: " if option else ""
    raise InputError(
        f"{where}{path} is {_kind(mode)}, not a regular file; vslsp writes only regular files: choose another output"
    )


def refuse_places(
    folder: str | os.PathLike[str],
    files: tuple[str, ...] = (),
    folders: tuple[str, ...] = (),
    option: str = "--out",
) -> None:
    """Check, before any work, the places a command will write in its output ``folder``: each of
    ``files`` must be a regular file or missing, each of ``folders`` (``images``, ``images/raw``)
    a real folder or missing (never a link, never a file) holding no link and no node among its
    files; InputError (exit 2) naming the place."""
    for name in files:
        refuse_link(Path(folder) / name, option)
        refuse_special(Path(folder) / name, option)
        if (Path(folder) / name).is_dir():
            raise InputError(
                f"{option}: {Path(folder) / name} is a folder, where vslsp writes a file: remove it or "
                "choose another output folder"
            )
    for name in folders:
        place = Path(folder)
        for part in Path(name).parts:
            place = place / part
            _refuse_non_folder(place, option)
        if place.is_dir():  # the files vslsp writes there (pictures, videos): none a link or a node
            with os.scandir(place) as entries:
                for entry in entries:
                    if not entry.is_dir(follow_symlinks=False):
                        refuse_link(entry.path, option)
                        refuse_special(entry.path, option)


def _refuse_non_folder(place: Path, option: str | None) -> None:
    refuse_link(place, option)
    try:
        mode = os.lstat(place).st_mode
    except FileNotFoundError:
        return
    if not stat.S_ISDIR(mode):
        what = "a file" if stat.S_ISREG(mode) else _kind(mode)
        where = f"{option}: " if option else ""
        raise InputError(
            f"{where}{place} is {what}, where vslsp writes a folder: remove it or choose another output folder"
        )


def output_subfolder(folder: str | os.PathLike[str], *parts: str) -> Path:
    """``folder/parts...`` created (each part a real folder, never through a link); returns it.
    InputError when a part is a link or not a folder."""
    place = Path(folder)
    for part in parts:
        place = place / part
        _refuse_non_folder(place, None)
        try:
            place.mkdir(exist_ok=True)
        except OSError as error:
            raise write_error(place, error) from None
        _refuse_non_folder(place, None)  # again: a link made meanwhile
    return place


@contextmanager
def atomic_file(path: str | os.PathLike[str], mode: str = "wb") -> Iterator[IO[Any]]:
    """A file object whose content replaces ``path`` only once the block ends without error.

    ``mode``: ``"wb"`` or ``"w"`` (UTF-8 text). The target's folder must exist. On any error
    (or an interrupt) the temporary file is removed and ``path`` is left as it was.
    """
    target = Path(path)
    refuse_link(target)
    refuse_special(target)
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
        refuse_link(target)  # again: a link (or a node) made while the file was being written
        refuse_special(target)
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
    holder ends, however it ends; the file names the holder (pid, host, start time, command
    line). A lock file left by a run that was killed (SIGKILL, a crash: its lock is released but
    the file stays) is taken over, with one line on stderr naming the run that left it.
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
            holder = _holder(handle) or "another process"
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
    stale = _holder(handle)
    if stale:  # its run ended without removing the file (killed): its lock is ours now
        print(
            f"note: {option}: taking over {lock}, left by a vslsp run that ended without releasing it ({stale})",
            file=sys.stderr,
        )
    command = " ".join(["vslsp", *sys.argv[1:]]) if sys.argv else "python"
    record = {
        "pid": os.getpid(),
        "host": socket.gethostname(),
        "started": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "command": command,
    }
    with suppress(OSError):  # the record is for people; the lock holds without it
        os.ftruncate(handle, 0)
        os.pwrite(handle, (json.dumps(record) + "\n").encode("utf-8", "surrogateescape"), 0)
    _HELD[key] = handle
    atexit.register(_release, key, lock)


def _holder(handle: int) -> str:
    """Who the lock file open at ``handle`` names: ``pid 1234: vslsp experiment ... (on HOST since
    2026-12-03T16:20:00Z)``, or its first line as written by an older vslsp, or '' when empty."""
    try:
        text = os.pread(handle, 4096, 0).decode("utf-8", "replace").strip()
    except OSError:
        return ""
    try:
        record = json.loads(text)
        return f"pid {int(record['pid'])}: {record['command']} (on {record['host']} since {record['started']})"
    except (ValueError, TypeError, KeyError):
        return text.splitlines()[0][:300] if text else ""


def _release(key: str, lock: Path) -> None:
    handle = _HELD.pop(key, None)
    if handle is None:
        return
    with suppress(OSError):
        os.unlink(lock)  # while still holding it: a waiting run then locks a fresh file
    with suppress(OSError):
        os.close(handle)
