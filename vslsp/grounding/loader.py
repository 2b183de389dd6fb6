"""Loading a user's predicates file (``--predicates FILE.py``).

The file is Python and runs with the user's rights, like a pytest ``conftest.py``: every
function it decorates with :func:`~vslsp.grounding.predicate` (or passes to
:func:`~vslsp.grounding.register`) is a predicate to ground, alongside the built-in ``far``.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import sys
import traceback
from collections.abc import Sequence
from pathlib import Path

from vslsp.errors import InputError
from vslsp.files import regular_file, shown
from vslsp.grounding.predicates import Predicate, collecting
from vslsp.grounding.relations import BUILTINS
from vslsp.grounding.user_code import (
    LOAD_TIME_LIMIT_S,
    TimeLimitExceeded,
    describe,
    passes_through,
    quiet_stdout,
    time_limit,
)

MAX_FILE_BYTES = 1_000_000


def load_predicates(path: str | Path) -> tuple[Predicate, ...]:
    """The predicates a Python file registers (in order), after the built-ins it may not redefine.

    A file that is missing, not a regular ``.py`` file, that raises (anything, ``sys.exit`` too)
    or runs past :data:`LOAD_TIME_LIMIT_S` while loading, or that registers nothing is an
    InputError naming the file (and the line where loading failed).
    """
    path = Path(path)
    name = shown(path)
    check_predicates_file(path)
    digest = hashlib.sha1(os.fsencode(path.resolve())).hexdigest()[:12]
    module_name = f"vslsp_user_predicates_{digest}"
    spec = importlib.util.spec_from_file_location(module_name, path)
    if spec is None or spec.loader is None:
        raise InputError(f"cannot load predicates file {name} as Python")
    module = importlib.util.module_from_spec(spec)
    sys.modules[module_name] = module
    with collecting() as registry:
        try:
            with time_limit(LOAD_TIME_LIMIT_S), quiet_stdout():
                spec.loader.exec_module(module)
        except InputError as error:
            sys.modules.pop(module_name, None)
            raise InputError(f"predicates file {name}: {error}") from None
        except TimeLimitExceeded:
            sys.modules.pop(module_name, None)
            raise InputError(
                f"predicates file {name} ran longer than {LOAD_TIME_LIMIT_S:g} s while loading and was stopped; "
                "define the predicates at its top level, without long work"
            ) from None
        except BaseException as error:  # the user's code: whatever it raises (SystemExit too) is theirs
            if passes_through(error):
                raise
            sys.modules.pop(module_name, None)
            raise InputError(
                f"cannot load predicates file {name}{error_line(error, path)}: {describe(error)}"
            ) from None
    predicates = registry.predicates()
    if not predicates:
        raise InputError(
            f"predicates file {name} registers no predicate; decorate functions with "
            '@predicate("name") from vslsp.grounding'
        )
    return tuple(p for p in with_builtins(predicates) if p not in BUILTINS)


def check_predicates_file(path: Path) -> None:
    """An InputError unless ``path`` is a regular ``.py`` file of at most :data:`MAX_FILE_BYTES`."""
    name = shown(path)
    if path.suffix != ".py":
        raise InputError(f"predicates file {name} must be a Python file ending in .py")
    if regular_file(path, "predicates file").st_size > MAX_FILE_BYTES:
        raise InputError(f"predicates file {name} is over {MAX_FILE_BYTES // 1000} kB; keep predicates in a small file")


def check_unique(predicates: Sequence[Predicate]) -> tuple[Predicate, ...]:
    """The predicates, checked to have distinct names."""
    seen: dict[str, Predicate] = {}
    for made in predicates:
        if made.name in seen and seen[made.name] is not made:
            raise InputError(
                f"predicate {made.name} is defined twice (the built-in {made.name} is always grounded); "
                "give yours another name"
            )
        seen[made.name] = made
    return tuple(seen.values())


def error_line(error: BaseException, path: Path) -> str:
    """``", line N"``: where in the user's file ``path`` loading it raised ``error`` ("" when not in it)."""
    if isinstance(error, SyntaxError) and error.lineno:
        return f", line {error.lineno}"
    frames = [f for f in traceback.extract_tb(error.__traceback__) if Path(f.filename) == path]
    return f", line {frames[-1].lineno}" if frames else ""


def with_builtins(predicates: Sequence[Predicate] = ()) -> tuple[Predicate, ...]:
    """The built-in predicates followed by ``predicates`` (names checked to be distinct)."""
    return check_unique(tuple(BUILTINS) + tuple(p for p in predicates if p not in BUILTINS))
