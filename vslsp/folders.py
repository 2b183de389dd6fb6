"""A user's recording folder (docs/recordings.md): the numbered files of a demonstration's
operations, read and checked before any work, for every reader of such a folder (VSL's
pictures, :mod:`vslsp.vsl.recordings`; VSL-3D's clouds, :mod:`vslsp.vsl3d.recordings`; VSL-SP's
image pairs, :mod:`vslsp.loop.picture_domain`).

Per operation i (numbered 1, 2, ... without gaps, any number of digits up to four) one file a
role (``i-pre.png``, ``i-post.ply``, ...); the folder's :class:`Form` says which roles, which
endings and which roles an operation after the first may leave out. Beside them a side file
such as ``names.json`` (a list of the objects' names, one an operation: :func:`read_names`) or
``calibration.json`` (:func:`read_parsed`). Every refusal is an InputError (exit 2) naming the
file and saying what to do.
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

from vslsp.errors import InputError
from vslsp.files import read_json, shown
from vslsp.outputs import atomic_file, write_text

#: The largest side file read (names.json, heights.json, calibration.json).
MAX_SIDE_FILE_BYTES = 1_000_000

T = TypeVar("T")


@dataclass(frozen=True)
class Form:
    """How a folder's operation files are named. ``pattern`` matches a file's name: group 1 its
    number, group 2 its role, group 3 the ending after the role; ``suffixes``: the files looked
    at (a file of another ending is passed over); ``needs``: each role, in the order they are
    checked, and what a missing one is (``"pre-pick picture"``); ``later_optional``: the roles
    an operation after the first may leave out; ``spelled``: the names of the form, for the
    message of a file named otherwise (``"NN-pre or NN-post (.png or .jpg)"``); ``kind``: what
    a file of the folder is (``"picture"``); ``example``: the first operation's files
    (``"01-pre.png, 01-post.png"``); ``holds``: what the folder holds (``"the demonstration's
    pictures"``)."""

    pattern: re.Pattern[str]
    suffixes: tuple[str, ...]
    needs: Mapping[str, str]
    later_optional: tuple[str, ...]
    spelled: str
    kind: str
    example: str
    holds: str


def operation_files(folder: str | Path, form: Form) -> dict[int, dict[str, Path]]:
    """The operations' files of ``folder`` by number (1..N) and role. Raises InputError naming
    the file: ``folder`` is not a folder, a file named out of the form, a role given twice, no
    operation, numbers with gaps, a role an operation needs missing."""
    folder = Path(folder)
    if not folder.is_dir():
        raise InputError(f"{shown(folder)} is not a folder; give the folder of {form.holds}")
    found: dict[int, dict[str, Path]] = {}
    for path in sorted(folder.iterdir()):
        if not path.name.lower().endswith(form.suffixes):
            continue
        match = form.pattern.match(path.name)
        if match is None:
            raise InputError(
                f"{shown(path)}: a {form.kind} whose name is not {form.spelled}; "
                "rename it or move it out of the folder (docs/recordings.md)"
            )
        number, role = int(match.group(1)), match.group(2).lower()
        if role in found.setdefault(number, {}):
            raise InputError(
                f"{shown(path)} and {shown(found[number][role])} are both operation {number}'s {role} "
                f"{form.kind}; keep one"
            )
        found[number][role] = path
    if not found:
        raise InputError(f"{shown(folder)} holds no {form.kind}s named {form.example} ... (docs/recordings.md)")
    for expected, number in enumerate(sorted(found), start=1):
        some = next(iter(found[number].values()))
        if number != expected:
            raise InputError(
                f"{shown(some)}: operation {number} follows operation {expected - 1}; number the operations "
                f"1, 2, 3 ... without gaps (operation {expected} is missing)"
            )
        for role, what in form.needs.items():
            if role not in found[number] and (number == 1 or role not in form.later_optional):
                match = form.pattern.match(some.name)
                assert match is not None
                missing = folder / f"{match.group(1)}-{role}{match.group(3)}"
                raise InputError(
                    f"{shown(missing)} is missing: operation {number} needs its {what} (docs/recordings.md)"
                )
    return found


def spelled_number(path: Path) -> str:
    """An operation file's number as its name spells it (``"01"`` of ``01-pre.png``)."""
    return path.name.split("-")[0]


def read_names(path: Path, count: int) -> tuple[str, ...]:
    """The objects' names of ``names.json`` (a list, one an operation); ``object 1``, ``object
    2``, ... without the file."""
    if not path.exists():
        return tuple(f"object {k}" for k in range(1, count + 1))
    names = read_json(path, "names", MAX_SIDE_FILE_BYTES)
    if not isinstance(names, list) or len(names) != count or not all(isinstance(n, str) and n for n in names):
        raise InputError(f"{shown(path)}: give a list of {count} names, one for each operation's object")
    return tuple(names)


def read_parsed(path: Path, what: str, parse: Callable[[Any], T]) -> T:
    """``parse`` of the JSON side file ``path``; an InputError of ``parse`` (a message without a
    file's name) comes out naming the file."""
    data = read_json(path, what, MAX_SIDE_FILE_BYTES)
    try:
        return parse(data)
    except InputError as error:
        raise InputError(f"{shown(path)}: {error}") from None


def read_record(folder: str | Path, record: str, form: str, what: str, command: str, limit: int) -> tuple[Path, Any]:
    """The path and the parsed JSON of the record ``record`` that a learning command writes
    into ``folder``. Raises InputError naming the folder when it has no record (make one with
    ``command``) or naming the file when it does not parse or is not of format ``form``."""
    path = Path(folder) / record
    if not path.is_file():
        raise InputError(f"{shown(folder)} is not a {what} (no {record}); make one with `{command} FOLDER --out DEMO`")
    data = read_json(path, what, limit)
    if not isinstance(data, dict) or data.get("format") != form:
        raise InputError(unreadable(path, f"its format is not {form!r}", command))
    return path, data


def unreadable(path: Path, reason: object, command: str) -> InputError:
    """The error for a learned record that does not hold what its learning command writes."""
    return InputError(
        f"{shown(path)} is not a readable learned demonstration ({reason}); learn it again with `{command}`"
    )


def write_learned(
    folder: str | Path, record: str, data: dict, arrays_file: str, arrays: dict, compressed: bool = False
) -> Path:
    """Write a learned demonstration into ``folder``: its ``arrays`` (an ``.npz``, no pickle)
    and then its record ``data`` (JSON), each atomically; returns the record's path."""
    import numpy as np

    with atomic_file(Path(folder) / arrays_file) as stream:
        (np.savez_compressed if compressed else np.savez)(stream, **arrays)
    return write_text(Path(folder) / record, json.dumps(data, indent=2) + "\n")
