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
    """The input was fine but the task itself failed (no plan, grounding failed, a skill missed).

    ``cause``: the failure's short name, what a report tallies failed trials by ("no plan",
    "exploring push on green"); the whole message when not given (a failure that names no
    shorter cause is its own cause).
    """

    exit_code = 1

    def __init__(self, message: str, *, cause: str | None = None) -> None:
        super().__init__(message)
        self.cause: str = message if cause is None else cause

    def __reduce__(self) -> tuple:
        # Rebuilt from its state, whatever a subclass's constructor takes (crossing processes).
        return (_restored, (type(self), self.args, self.__dict__))


class GroundingFailed(TaskFailed, InputError):
    """Usable images in which the grounding found no answer: nothing moved, no landmark line, the
    moved object out of view, several objects moved. A failed task (exit 1, docs/bad-input.md);
    also an :class:`InputError`, so that code which treats an observation it cannot use as bad
    input (a recorder, a trial) goes on doing so."""

    exit_code = 1


def _restored(kind: type[TaskFailed], args: tuple, state: dict) -> TaskFailed:
    error = kind.__new__(kind)
    error.args = args
    error.__dict__.update(state)
    return error


class UnreachableError(VslspError):
    """A Cartesian target the arm cannot reach."""

    exit_code = 1


class Interrupted(BaseException):
    """SIGINT (Ctrl-C), SIGTERM, SIGHUP or SIGQUIT arrived: the run stops, keeping what finished.

    A BaseException, like KeyboardInterrupt, so that ``except Exception`` (a trial recorded as
    failed) never swallows it; ``finally`` blocks still end child processes and remove
    temporary folders on the way out. ``exit_code``: 128 + the signal's number (130, 143, 129, 131).
    """

    def __init__(self, signal_name: str = "SIGTERM") -> None:
        super().__init__(signal_name)
        self.signal_name = signal_name

    @property
    def exit_code(self) -> int:
        import signal

        try:
            return 128 + int(signal.Signals[self.signal_name])
        except KeyError:
            return 143
