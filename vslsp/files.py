"""The user's files, read and named within bounds: the one edge every reader goes through.

Every file a user names (PDDL, plans, scenes, skill libraries, DMPs, images, predicates) is
read here, so that one rule holds for all of them:

* **regular files only**, checked by ``stat`` before opening: a FIFO, a device
  (``/dev/zero``), a socket or a folder is refused, never read (reading one can block for
  ever or never end);
* **bounded**: at most ``limit`` bytes are read, and the limit is applied while reading (a file
  that grows, or one ``stat`` misreports, is cut at ``limit + 1`` bytes and refused);
* **any path**: paths are handed to the operating system as Python paths (bytes-safe with
  ``surrogateescape``), never to a C library that must encode them (OpenCV crashes on a path
  that is not UTF-8), and shown in messages with the bytes that are not UTF-8 escaped
  (``pre\\xff.png``);
* **names the file system can hold**: each component at most :data:`NAME_MAX` bytes, checked
  before any work (an over-long ``--out`` would otherwise fail after the whole run);
* **npz headers first**: an ``.npz`` member's declared shape and type are read from its header
  and its size checked before anything is allocated (a 584-byte file can declare 7 TiB), and an
  object array (a pickle) is refused, never loaded.

Every refusal is an :class:`~vslsp.errors.InputError` (exit 2) that names the file.
"""

from __future__ import annotations

import atexit
import io
import json
import os
import shutil
import stat
import tempfile
import zipfile
from pathlib import Path
from typing import Any, BinaryIO

from vslsp.errors import InputError

#: The longest name of one path component, in bytes (Linux, macOS and Windows file systems).
NAME_MAX = 255
#: The longest path, in bytes (Linux's PATH_MAX).
PATH_MAX = 4096
#: The most digits of an integer in a JSON file (a 64-bit integer has 20).
MAX_JSON_DIGITS = 40
#: The deepest nesting of a JSON file (scenes and libraries nest 4 deep).
MAX_JSON_DEPTH = 64

PathLike = str | bytes | os.PathLike[str] | os.PathLike[bytes]


def shown(path: PathLike) -> str:
    """``path`` as text for a message: bytes that are not UTF-8 escaped (``pre\\xff.png``)."""
    return os.fsencode(path).decode("utf-8", "backslashreplace")


def check_name(path: PathLike, what: str = "path") -> None:
    """An InputError when ``path`` or one of its components is longer than the file system allows."""
    raw = os.fsencode(path)
    if len(raw) > PATH_MAX:
        raise InputError(f"{what}: the path is {len(raw)} bytes long; paths have at most {PATH_MAX} bytes")
    for part in raw.split(b"/"):
        if len(part) > NAME_MAX:
            start = part[:24].decode("utf-8", "backslashreplace")
            raise InputError(
                f"{what}: the name {start}... is {len(part)} bytes long; a file or folder name has at most "
                f"{NAME_MAX} bytes; choose a shorter name"
            )


def _kind(mode: int) -> str:
    for test, name in (
        (stat.S_ISDIR, "a folder"),
        (stat.S_ISFIFO, "a FIFO (named pipe)"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISSOCK, "a socket"),
    ):
        if test(mode):
            return name
    return "not a regular file"


def regular_file(path: PathLike, what: str = "file") -> os.stat_result:
    """The ``stat`` of ``path``, which must be a regular file (symbolic links followed), else an InputError."""
    check_name(path, f"{what} {shown(path)}")
    try:
        status = os.stat(path)
    except FileNotFoundError:
        raise InputError(f"cannot read {what} {shown(path)}: no such file") from None
    except OSError as error:
        raise InputError(f"cannot read {what} {shown(path)}: {error.strerror}") from None
    if not stat.S_ISREG(status.st_mode):
        raise InputError(
            f"cannot read {what} {shown(path)}: it is {_kind(status.st_mode)}, not a regular file; give a file"
        )
    return status


def too_large(path: PathLike, what: str, limit: int) -> InputError:
    """The error for a file over ``limit`` bytes."""
    return InputError(
        f"{what} {shown(path)} is larger than {_size(limit)}; vslsp reads at most {_size(limit)} from such a file"
    )


def _size(count: int) -> str:
    """``count`` bytes in the largest unit that keeps a number of at least 1 (bytes, kB, MB, GB, TB; powers of 1000)."""
    for unit, scale in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6)):
        if count >= scale:
            return f"{count / scale:.3g} {unit}"
    return f"{count / 1e3:.3g} kB" if count >= 1000 else f"{count} bytes"


def read_bytes(path: PathLike, what: str, limit: int) -> bytes:
    """The bytes of the regular file ``path``, at most ``limit`` of them (more is an InputError)."""
    status = regular_file(path, what)
    if status.st_size > limit:
        raise too_large(path, what, limit)
    try:
        with open(path, "rb") as file:
            if not stat.S_ISREG(os.fstat(file.fileno()).st_mode):  # replaced between stat and open
                raise InputError(f"cannot read {what} {shown(path)}: it is not a regular file; give a file")
            data = _read_within(file, os.fstat(file.fileno()).st_size, limit)
    except OSError as error:
        raise InputError(f"cannot read {what} {shown(path)}: {error.strerror}") from None
    if len(data) > limit:
        raise too_large(path, what, limit)
    return data


def _read_within(file: BinaryIO, size: int, limit: int) -> bytes:
    """At most ``limit + 1`` bytes of ``file``, whose size on disk is ``size``. ``read(n)`` reserves ``n``
    bytes before it reads, so the file is read by its own size (a small file under a large limit takes
    no more memory than itself), then in chunks while it still grows."""
    chunks = [file.read(min(size, limit) + 1)]
    total = len(chunks[0])
    while chunks[-1] and total <= limit:
        chunks.append(file.read(min(1 << 20, limit + 1 - total)))
        total += len(chunks[-1])
    return b"".join(chunks)


def decode_text(data: bytes, path: PathLike, what: str) -> str:
    """UTF-8 text (a byte-order mark allowed), or an InputError with the line and column of the first bad byte."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        line = data.count(b"\n", 0, error.start) + 1
        column = error.start - (data.rfind(b"\n", 0, error.start) + 1) + 1
        raise InputError(
            f"{shown(path)}:{line}:{column}: the {what} is not UTF-8 text (byte 0x{data[error.start]:02x}); "
            "save it as UTF-8 (plain ASCII is fine)"
        ) from None


def read_text(path: PathLike, what: str, limit: int) -> str:
    """The UTF-8 text of the regular file ``path`` of at most ``limit`` bytes."""
    return decode_text(read_bytes(path, what, limit), path, what)


def _integer(text: str) -> int:
    if len(text.lstrip("-")) > MAX_JSON_DIGITS:
        raise ValueError(f"an integer of {len(text.lstrip('-'))} digits (at most {MAX_JSON_DIGITS})")
    return int(text)


def _depth(text: str) -> int:
    """The deepest ``[``/``{`` nesting of JSON ``text`` (strings skipped)."""
    depth = deepest = 0
    in_string = escaped = False
    for char in text:
        if in_string:
            escaped, in_string = (False, True) if escaped else (char == "\\", char != '"')
        elif char == '"':
            in_string = True
        elif char in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif char in "]}":
            depth -= 1
    return deepest


def read_json(path: PathLike, what: str, limit: int) -> Any:
    """The JSON value of the regular file ``path`` (at most ``limit`` bytes, :data:`MAX_JSON_DEPTH` deep,
    integers of at most :data:`MAX_JSON_DIGITS` digits), or an InputError naming the file."""
    text = read_text(path, what, limit)
    if _depth(text) > MAX_JSON_DEPTH:
        raise InputError(f"cannot read {what} {shown(path)}: it nests deeper than {MAX_JSON_DEPTH} levels")
    try:
        return json.loads(text, parse_int=_integer)
    except ValueError as error:  # JSONDecodeError is a ValueError
        raise InputError(f"cannot read {what} {shown(path)}: {error}") from None


def load_npz(path: PathLike, what: str, limit: int, file_limit: int | None = None) -> dict[str, Any]:
    """The arrays of the ``.npz`` file ``path``, whose members together decode to at most ``limit`` bytes.

    Each member's header (shape and type) is read and checked before the member is loaded;
    an object array (a pickle) is refused. The file itself may have at most ``file_limit``
    bytes (default ``limit``). Errors are InputErrors whose message starts with the file's name.
    """
    import numpy as np
    from numpy.lib import format as npy

    name = shown(Path(os.fsdecode(path)).name)
    data = read_bytes(path, what, file_limit or limit)
    if data[:2] != b"PK":
        kind = (
            "holds one bare array, not an .npz archive"
            if data[:6] == b"\x93NUMPY"
            else "holds pickled Python objects; vslsp never reads pickles (loading one can run any code)"
            if data[:1] == b"\x80"
            else "is not an .npz file (not a zip archive of arrays)"
        )
        raise InputError(f"{name} {kind}; it should be the {what}")
    try:
        archive = zipfile.ZipFile(io.BytesIO(data))
        total = 0
        for member in archive.infolist():
            if not member.filename.endswith(".npy"):
                raise InputError(f"{name}: {member.filename!r} is not an array; it should be the {what}")
            with archive.open(member) as stream:
                version = npy.read_magic(stream)
                shape, _, dtype = (
                    npy.read_array_header_1_0(stream) if version == (1, 0) else npy.read_array_header_2_0(stream)
                )
            if dtype.hasobject:
                raise InputError(
                    f"{name} holds pickled Python objects, not the {what}; vslsp never reads pickles "
                    "(loading one can run any code)"
                )
            total += int(np.prod(shape, dtype=object)) * dtype.itemsize
            if total > limit:
                raise InputError(
                    f"{name}: its arrays declare {_size(total)}, more than the {what} can hold "
                    f"(at most {_size(limit)}); nothing was loaded"
                )
        with np.load(io.BytesIO(data), allow_pickle=False) as arrays:
            return {key: arrays[key] for key in arrays.files}
    except InputError:
        raise
    except (ValueError, OSError, EOFError, KeyError, zipfile.BadZipFile, RuntimeError) as error:
        raise InputError(f"{name} is not a readable .npz file of the {what} ({error})") from None


_private_cache: list[str] = []


def cache_folder() -> Path:
    """Where vslsp keeps files it makes once and reuses (the simulator's textures, reduced robot
    models): ``$VSLSP_CACHE``, else ``$XDG_CACHE_HOME/vslsp``, else ``~/.cache/vslsp``; never the
    temporary folder, which must hold nothing of a run once it ends. When none of them can be
    made, a private temporary folder, removed when this process exits."""
    xdg = os.environ.get("XDG_CACHE_HOME", "")
    for place in (
        os.environ.get("VSLSP_CACHE", ""),
        os.path.join(xdg, "vslsp") if os.path.isabs(xdg) else "",  # the spec: a relative one is ignored
        os.path.join(os.path.expanduser("~"), ".cache", "vslsp"),
    ):
        if not place:
            continue
        try:
            os.makedirs(place, exist_ok=True)
        except OSError:
            continue
        if os.access(place, os.W_OK | os.X_OK):
            return Path(place)
    if not _private_cache:
        _private_cache.append(tempfile.mkdtemp(prefix="vslsp-cache-"))
        atexit.register(shutil.rmtree, _private_cache[0], True)
    return Path(_private_cache[0])
