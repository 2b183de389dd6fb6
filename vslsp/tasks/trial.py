"""One trial, run so that nothing it raises is lost: the unit every backend executes."""

from __future__ import annotations

import traceback

from vslsp.errors import Interrupted
from vslsp.tasks.base import Task, TrialResult, TrialStatus, timed

__all__ = ["Interrupted", "run_one"]


def run_one(task: Task, seed: int, keep: bool = False) -> TrialResult:
    """One trial; anything it raises becomes a failed trial that says what went wrong, except an
    interrupt (:class:`~vslsp.errors.Interrupted`, KeyboardInterrupt: BaseExceptions), which
    stops the run."""
    try:
        result = timed(task, seed, keep)
    except Exception as error:  # noqa: BLE001  (a trial that raises is recorded, never lost)
        where = traceback.extract_tb(error.__traceback__)[-1]
        return TrialResult(
            task.name,
            seed,
            False,
            f"{type(error).__name__}: {error} (at {where.filename.split('/')[-1]}:{where.lineno})",
            failure_cause=type(error).__name__,
            status=TrialStatus.RAISED,
        )
    return result if keep else result.without_artefacts()
