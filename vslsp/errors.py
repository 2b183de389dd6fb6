"""The one exception family users see.

Every error a user can cause (bad input files, unreachable targets, unsolvable problems)
is a :class:`VslspError` whose message says what was wrong and what to do. The CLI turns
it into a one-line message and an exit code, never a traceback.
"""

from __future__ import annotations


class VslspError(Exception):
    """Base class of user-facing errors. ``exit_code`` is what the CLI returns."""

    exit_code: int = 2


class InputError(VslspError):
    """Bad input: a malformed file, an invalid argument, an image pair that cannot be read."""

    exit_code = 2


class TaskFailed(VslspError):
    """The input was fine but the task itself failed (no plan, grounding failed, a skill missed)."""

    exit_code = 1


class UnreachableError(VslspError):
    """A Cartesian target the arm cannot reach."""

    exit_code = 1
