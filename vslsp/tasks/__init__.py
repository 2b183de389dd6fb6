"""Tasks: every experiment of the paper behind one interface, one registry, one trial runner and
one report (``vslsp experiment NAME``; ``vslsp experiment --list``).

Public API: :class:`Task` (subclass it), :func:`register` (class decorator), :class:`TrialResult`
(what a trial returns, how it ended: its :class:`TrialStatus`), :class:`System`, :class:`Option`,
:func:`get_task`, :func:`list_tasks`, :func:`run_trials`, :func:`write_report`, :func:`load_task_files`
(``--tasks FILE.py``). See ``docs/tasks.md`` for a task written from scratch.
"""

from vslsp.tasks.base import Option, System, Task, TrialResult, TrialStatus
from vslsp.tasks.registry import get_task, list_tasks, load_task_files, register, task_class
from vslsp.tasks.report import summary, write_report
from vslsp.tasks.runner import Run, run_trials
from vslsp.tasks.task_files import install_finder
from vslsp.tasks.trial import run_one

install_finder()  # a worker process imports the tasks of a user's file by name (task_files)

__all__ = [
    "Option",
    "Run",
    "System",
    "Task",
    "TrialResult",
    "TrialStatus",
    "get_task",
    "list_tasks",
    "load_task_files",
    "register",
    "run_one",
    "run_trials",
    "summary",
    "task_class",
    "write_report",
]
