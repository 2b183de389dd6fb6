"""Typed outcomes of the symbolic layer: how constraints were compiled, and internal failures.

Paper: "Implementation" (planning with PDDL 3.0 constraints). Exit codes of the command line:
0 done, 1 no plan / invalid plan (:class:`~vslsp.errors.TaskFailed`), 2 bad input
(:class:`~vslsp.errors.InputError`), 3 a planner or compiler failed inside (:class:`InternalError`).
"""

from __future__ import annotations

from enum import StrEnum

from vslsp.errors import TaskFailed, VslspError


class Compilation(StrEnum):
    """How a problem's trajectory constraints reached the planner."""

    NONE = "none"  # the problem has no trajectory constraints
    LIFTED = "lifted"  # monitors compiled into the action schemas (vslsp.symbolic.lifted)
    GROUND = "ground"  # unified-planning's TrajectoryConstraintsRemover on the grounded problem


class InternalError(VslspError):
    """A planner or compiler failed inside (not the user's input, not "no plan"): exit code 3.

    The original exception is the ``__cause__``; the CLI shows its traceback with ``--debug``.
    """

    exit_code = 3


class Unsolvable(TaskFailed):
    """No plan exists, and the planner proved it (not a timeout or an incomplete search giving up):
    exit code 1, like every "no plan". :mod:`vslsp.symbolic.conflict` explains only these."""
