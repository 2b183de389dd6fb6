"""Shared click parameter types: every command checks its options here, before any work.

A bad value is a usage error (exit 2, one line naming the option, no traceback). The API:

``SEED`` (type) / :func:`seed_option` (decorator)
    A seed: an integer in ``0 .. MAX_SEED``. ``--seed -1`` -> ``Invalid value for '--seed': -1 is
    negative; a seed is an integer from 0 to 4294967295``. Every seed feeds
    ``numpy.random.default_rng``, so the same seed gives the same run.
``OUTPUT_FOLDER`` (type) / :func:`prepare_output_folder` (function)
    A folder the command writes into. Converting the option creates the folder (and its parents)
    and probes that a file can be written there, so a read-only folder or a path under a file is
    reported up front, naming the path, instead of as an ``OSError`` after the whole run; it
    also locks the folder for this run (a second run into it is refused, naming the first). Use the
    function for a folder known only later (a default computed from another argument); it raises
    :class:`vslsp.errors.InputError` (exit 2).
``OUTPUT_FILE`` (type) / :func:`prepare_output_file` (function)
    A file the command will write: its folder is created and probed the same way; an existing
    folder or symbolic link at that path is refused.
:func:`count` (type factory)
    A positive integer with an upper bound: ``count(4096)`` for ``--width``, ``count(10000)``
    for ``--trials``. ``0`` and negatives -> ``0 is not in the range 1<=x<=4096``.
:func:`positive_float` (type factory)
    A finite float > 0 (optionally <= a bound): NaN, inf, 0 and negatives are refused
    (click's own ``FloatRange`` lets NaN through). :func:`non_negative_float`: the same with 0 allowed.
``PROBABILITY`` (type)
    A finite float from 0 to 1 (``--tutor-slips 0.5``); ``1.5`` -> ``1.5 is not a probability
    from 0 to 1``.

Example::

    @click.command()
    @seed_option()
    @click.option("--out", type=OUTPUT_FOLDER, default="out/scene", show_default=True)
    @click.option("--width", type=count(4096), default=640)
    def scene(seed: int, out: Path, width: int) -> None: ...
"""

from __future__ import annotations

import math
import os
import re
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import click

from vslsp.errors import InputError
from vslsp.outputs import lock_folder, refuse_link, refuse_special

MAX_SEED = 2**32 - 1
#: A number on the command line is written in the ASCII digits: Python's int() and float() also
#: read other scripts' digits ('٣', '１') and underscores ('1_000'), which a user never means.
_ASCII_INTEGER = re.compile(r"[+-]?[0-9]+")
_ASCII_FLOAT = re.compile(
    r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|[+-]?(?:nan|inf|infinity)", re.IGNORECASE
)
F = TypeVar("F", bound=Callable[..., Any])


class Seed(click.ParamType):
    """An integer seed in ``0 .. MAX_SEED``."""

    name = "seed"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> int:
        if isinstance(value, bool):
            self.fail(f"{value!r} is not an integer seed", param, ctx)
        if isinstance(value, int):
            seed = value
        else:
            text = str(value).strip()
            if not _ASCII_INTEGER.fullmatch(text):  # int() also takes '٣', '１' and '1_0'
                self.fail(
                    f"{value!r} is not an integer in the digits 0-9; a seed is an integer from 0 to {MAX_SEED}",
                    param,
                    ctx,
                )
            seed = int(text, 10)
        if seed < 0:
            self.fail(f"{seed} is negative; a seed is an integer from 0 to {MAX_SEED}", param, ctx)
        if seed > MAX_SEED:
            self.fail(f"{seed} is too large; a seed is an integer from 0 to {MAX_SEED}", param, ctx)
        return seed


SEED = Seed()


def seed_option(
    help: str = "Seed of the run (0 to 4294967295): the same seed, the same result.",  # noqa: A002
    default: int = 0,
) -> Callable[[F], F]:
    """The ``--seed`` option every seeded command shares."""
    return click.option("--seed", type=SEED, default=default, show_default=True, help=help)


def _probe(folder: Path) -> None:
    """Write and remove a small file in ``folder``; raise OSError when that is impossible."""
    handle, name = tempfile.mkstemp(prefix=".vslsp-write-probe-", dir=folder)
    try:
        os.write(handle, b"ok")
    finally:
        os.close(handle)
        os.unlink(name)


def _blocking_file(path: Path) -> Path | None:
    """The first existing non-folder along ``path`` (itself or a parent), if any."""
    for candidate in [*reversed(path.parents), path]:
        if candidate.exists() and not candidate.is_dir():
            return candidate
    return None


def name_problem(path: Path) -> str | None:
    """Why the file system cannot hold ``path`` (a name over 255 bytes, a path over 4096), or None.

    Checked before any work, so that an over-long ``--out`` is a usage error up front, not an
    ``OSError`` after the run."""
    from vslsp.files import check_name

    try:
        check_name(path, "")
    except InputError as error:
        return str(error).lstrip(": ")
    return None


def _folder_problem(path: Path) -> str | None:
    """Create ``path`` as a folder and probe it; a sentence saying what is wrong, or None."""
    too_long = name_problem(path)
    if too_long is not None:
        return too_long
    blocker = _blocking_file(path)
    if blocker is not None:
        return f"{blocker} is a file, so the folder {path} cannot be created there; choose another output folder"
    try:
        path.mkdir(parents=True, exist_ok=True)
        _probe(path)
    except OSError as error:
        reason = error.strerror or str(error)
        return f"cannot write into the folder {path} ({reason}); choose a writable output folder"
    return None


def protected_folder(folder: Path) -> str | None:
    """Why ``folder`` belongs to vslsp itself (the shipped data, the package or the source tree), or None."""
    import vslsp
    from vslsp.data import shipped_folder

    package = Path(vslsp.__file__).resolve().parent
    places = {"the installed package vslsp": package}
    for kind in ("skills", "pddl"):
        try:
            places[f"the shipped {kind} folder"] = shipped_folder(kind).resolve()
        except FileNotFoundError:
            pass
    if (package.parent / "pyproject.toml").is_file():  # a source checkout
        places["the vslsp source tree"] = package.parent
    target = folder.resolve()
    for what, place in places.items():
        inside = target == place or place in target.parents
        if what == "the vslsp source tree":  # its top level only: out/ and the like are the user's
            inside = target == place
        if inside:
            return f"{folder} is {what} ({place})" if target == place else f"{folder} is inside {what} ({place})"
    return None


def prepare_output_folder(path: str | os.PathLike[str], option: str = "--out", vslsp_own: bool = False) -> Path:
    """Create the output folder ``path`` and check that it is writable; return it.

    Raises :class:`InputError` (exit 2) naming ``option`` and the path otherwise: an empty path,
    one of vslsp's own folders (the shipped ``skills/`` and ``pddl/``, the package, the source
    tree's top; allowed with ``vslsp_own``: ``teach --force``), and when another vslsp run is
    writing into the folder (:func:`vslsp.outputs.lock_folder`: the folder is this process's
    until it exits).
    """
    if str(path) == "":
        raise InputError(f"{option}: an empty path is not a folder; give a folder name")
    folder = Path(path)
    protected = None if vslsp_own else protected_folder(folder)
    if protected is not None:
        raise InputError(f"{option}: {protected}; vslsp writes its outputs elsewhere: choose another output folder")
    problem = _folder_problem(folder)
    if problem is not None:
        raise InputError(f"{option}: {problem}")
    lock_folder(folder, option)
    return folder


def prepare_output_file(path: str | os.PathLike[str], option: str = "--out") -> Path:
    """Check that the file ``path`` can be written (its folder is created and probed); return it.

    Raises :class:`InputError` (exit 2) naming ``option`` and the path otherwise.
    """
    if str(path) == "":
        raise InputError(f"{option}: an empty path is not a file name; give a file name")
    target = Path(path)
    too_long = name_problem(target)
    if too_long is not None:
        raise InputError(f"{option}: {too_long}")
    if target.is_dir():
        raise InputError(f"{option}: {target} is a folder; give a file name")
    refuse_link(target, option)
    refuse_special(target, option)
    problem = _folder_problem(target.parent)
    if problem is None and target.exists() and not os.access(target, os.W_OK):
        problem = f"the file {target} is read-only; choose another file"
    if problem is not None:
        raise InputError(f"{option}: {problem}")
    return target


class OutputFolder(click.ParamType):
    """A folder created and probed for writing when the option is read (value: a ``Path``)."""

    name = "folder"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Path:
        if value is None or value == "":
            self.fail("an empty path is not a folder", param, ctx)
        try:
            return prepare_output_folder(value, param.opts[0] if param is not None and param.opts else "--out")
        except InputError as error:
            self.fail(str(error).split(": ", 1)[1], param, ctx)


class OutputFile(click.ParamType):
    """A file path whose folder is created and probed when the option is read (value: a ``Path``)."""

    name = "file"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Path:
        if value is None or value == "":
            self.fail("an empty path is not a file name", param, ctx)
        try:
            return prepare_output_file(value)
        except InputError as error:
            self.fail(str(error).split(": ", 1)[1], param, ctx)


OUTPUT_FOLDER = OutputFolder()
OUTPUT_FILE = OutputFile()


class AsciiIntRange(click.IntRange):
    """click's IntRange, written in the digits 0-9 only."""

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        if isinstance(value, str) and not _ASCII_INTEGER.fullmatch(value.strip()):
            self.fail(f"{value!r} is not an integer in the digits 0-9", param, ctx)
        return super().convert(value, param, ctx)


class AsciiFloatRange(click.FloatRange):
    """click's FloatRange, written in ASCII only (digits 0-9, a point, an exponent)."""

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        if isinstance(value, str) and not _ASCII_FLOAT.fullmatch(value.strip()):
            self.fail(f"{value!r} is not a number in the digits 0-9", param, ctx)
        return super().convert(value, param, ctx)


def int_range(minimum: int, maximum: int) -> AsciiIntRange:
    """An integer ``minimum .. maximum`` in the digits 0-9 (``--port``, ``--memory``, ``--views``)."""
    return AsciiIntRange(minimum, maximum)


def float_range(minimum: float) -> AsciiFloatRange:
    """A float of at least ``minimum``, in ASCII (``--conflict-budget``)."""
    return AsciiFloatRange(min=minimum)


def count(maximum: int) -> click.IntRange:
    """A positive integer ``1 .. maximum`` (sizes, numbers of trials, workers, demonstrations)."""
    return AsciiIntRange(1, maximum)


class PositiveFloat(click.ParamType):
    """A finite float > 0 (>= 0 with ``zero``), at most ``maximum`` when given."""

    name = "float"

    def __init__(self, maximum: float | None = None, zero: bool = False) -> None:
        self.maximum = maximum
        self.zero = zero

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> float:
        if isinstance(value, str) and not _ASCII_FLOAT.fullmatch(value.strip()):
            self.fail(f"{value!r} is not a number in the digits 0-9", param, ctx)
        try:
            number = float(value)
        except (TypeError, ValueError):
            self.fail(f"{value!r} is not a number", param, ctx)
        if not math.isfinite(number):
            self.fail(f"{value} is not a finite number", param, ctx)
        if number < 0 and self.zero:
            self.fail(f"{value} is negative; give a number >= 0", param, ctx)
        if number <= 0 and not self.zero:
            self.fail(f"{value} is not positive; give a number > 0", param, ctx)
        if self.maximum is not None and number > self.maximum:
            self.fail(f"{value} is larger than {self.maximum}", param, ctx)
        return number


def positive_float(maximum: float | None = None) -> PositiveFloat:
    """A finite float > 0 (and <= ``maximum`` when given)."""
    return PositiveFloat(maximum)


def millions_option(option: str, dest: str, default: int, unit: str, maximum: float, help: str) -> Callable[[F], F]:
    """An input limit given in millions of ``unit`` (``--max-size 100`` MB, ``--max-pixels 300``
    MP: a finite float > 0, at most ``maximum``), handed to the command as the whole count
    ``dest`` (at least 1); ``default`` is the count."""
    return click.option(
        option,
        dest,
        type=positive_float(maximum),
        default=default / 1e6,
        show_default=True,
        metavar=unit,
        callback=lambda _ctx, _param, value: max(1, int(value * 1e6)),
        help=help,
    )


def non_negative_float(maximum: float | None = None) -> PositiveFloat:
    """A finite float >= 0 (and <= ``maximum`` when given): a budget where 0 means "none"."""
    return PositiveFloat(maximum, zero=True)


class Pixels(click.ParamType):
    """A finite number of pixels >= 0 (``--min-move 8``)."""

    name = "px"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> float:
        try:
            number = float(value)
        except (TypeError, ValueError):
            self.fail(f"{value!r} is not a number of pixels; give e.g. 8", param, ctx)
        if not math.isfinite(number) or number < 0:
            self.fail(f"{value} is not a number of pixels from 0 up; give e.g. 8", param, ctx)
        return number


PIXELS = Pixels()


class Probability(click.ParamType):
    """A finite float from 0 to 1."""

    name = "probability"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> float:
        if isinstance(value, str) and not _ASCII_FLOAT.fullmatch(value.strip()):
            self.fail(f"{value!r} is not a number in the digits 0-9; give a probability from 0 to 1", param, ctx)
        try:
            number = float(value)
        except (TypeError, ValueError):
            self.fail(f"{value!r} is not a number; give a probability from 0 to 1", param, ctx)
        if not 0.0 <= number <= 1.0:  # NaN fails this too
            self.fail(f"{value} is not a probability from 0 to 1", param, ctx)
        return number


PROBABILITY = Probability()


def check_display(gui: bool) -> None:
    """With ``--gui``, an InputError (exit 2) before any work when there is no display to open the
    window on (pybullet's GUI would hang or end the process without a word)."""
    if not gui or not sys.platform.startswith("linux"):
        return
    display = os.environ.get("DISPLAY", "")
    if not display and not os.environ.get("WAYLAND_DISPLAY"):
        raise InputError(
            "--gui: there is no display to open the pybullet window on (DISPLAY is not set); "
            "run without --gui, or under a virtual display (xvfb-run vslsp ...)"
        )
    local = re.fullmatch(r"(?:unix)?:(\d+)(?:\.\d+)?", display)
    if local and not os.environ.get("WAYLAND_DISPLAY") and not os.path.exists(f"/tmp/.X11-unix/X{local.group(1)}"):
        raise InputError(
            f"--gui: no X server listens on DISPLAY={display} (no /tmp/.X11-unix/X{local.group(1)}); "
            "start it, or run without --gui, or under a virtual display (xvfb-run vslsp ...)"
        )
