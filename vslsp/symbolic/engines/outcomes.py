"""Typed outcomes of the symbolic layer: how a planner run ended, how constraints were compiled,
and the failures a planner run raises.

Paper: "Implementation" (planning with PDDL 3.0 constraints). Exit codes of the command line:
0 done, 1 no plan / invalid plan (:class:`NoPlan`, a :class:`~vslsp.errors.TaskFailed`), 2 bad
input (:class:`~vslsp.errors.InputError`), 3 a planner or compiler failed inside (:class:`InternalError`).
"""

from __future__ import annotations

from enum import StrEnum

from vslsp.errors import TaskFailed, VslspError


class PlanStatus(StrEnum):
    """How a planner run ended, after unified-planning's ``PlanGenerationResultStatus``: from Fast
    Downward's exit code (:mod:`vslsp.symbolic.engines.fast_downward`) or a unified-planning engine's
    result, carried by every "no plan" (:class:`NoPlan`) up to the VSL-SP loop, which keeps
    the demonstrated order when the planner only ran out of time or memory."""

    SOLVED = "solved"
    UNSOLVABLE_PROVEN = "unsolvable_proven"  # the translator or a complete search proved there is no plan
    UNSOLVABLE_INCOMPLETELY = "unsolvable_incompletely"  # an incomplete search gave up without a plan
    TIMEOUT = "timeout"  # the time limit was reached
    MEMOUT = "memout"  # the memory limit was reached
    UNSUPPORTED_PROBLEM = "unsupported_problem"  # the planner cannot take the problem
    INTERNAL_ERROR = "internal_error"  # the planner (translator, search) or a compiler failed inside

    @property
    def limit_reached(self) -> bool:
        """Whether the run stopped at a resource limit (time, memory): nothing is known about the plan."""
        return self in (PlanStatus.TIMEOUT, PlanStatus.MEMOUT)


class Compilation(StrEnum):
    """How a problem's trajectory constraints reached the planner."""

    NONE = "none"  # the problem has no trajectory constraints
    LIFTED = "lifted"  # monitors compiled into the action schemas (vslsp.symbolic.engines.lifted)
    GROUND = "ground"  # unified-planning's TrajectoryConstraintsRemover on the grounded problem


class InternalError(VslspError):
    """A planner or compiler failed inside (not the user's input, not "no plan"): exit code 3.

    The original exception is the ``__cause__``; the CLI shows its traceback with ``--debug``.
    """

    exit_code = 3


class NoPlan(TaskFailed):
    """The planner returned no plan: ``"no plan: REASON"``, exit code 1, with the run's
    ``status`` (:class:`PlanStatus`). The failure's ``cause`` (what a report tallies) is "no plan",
    or the limit's name when the planner ran out of time or memory."""

    def __init__(self, reason: str, status: PlanStatus) -> None:
        causes = {PlanStatus.TIMEOUT: "planner time limit", PlanStatus.MEMOUT: "planner memory limit"}
        super().__init__(f"no plan: {reason}", cause=causes.get(status, "no plan"))
        self.reason = reason
        self.status = status


class Unsolvable(NoPlan):
    """No plan exists, and the planner proved it (not a timeout or an incomplete search giving up):
    exit code 1, like every "no plan". :mod:`vslsp.symbolic.validation.conflict` explains only these."""

    def __init__(self, reason: str) -> None:
        super().__init__(reason, PlanStatus.UNSOLVABLE_PROVEN)
