"""Tasks from a user's Python file (``vslsp experiment --tasks FILE.py NAME``), and the rule that
keeps a user's runner script from being run again by every worker.

A tasks file is Python and runs with the user's rights, like ``--predicates FILE.py``: the
classes it ``@register``\\ s become experiments. Trials run in spawned worker processes, which
receive the task by reference (its module and class name), so each file is imported under a
name made from its path (``vslsp_tasks_file_<digest>``) and the files' paths travel to the
workers in :data:`ENV`; a finder on ``sys.meta_path`` (installed when :mod:`vslsp.tasks` is
imported) imports such a module from its file in any process. A Ray worker may run on another
machine, so there the module travels by value (cloudpickle).

**The main guard.** A spawned worker imports the main script of the process that started it
(as ``__mp_main__``) before it runs a trial; a script that calls vslsp's runner at its top
level, outside ``if __name__ == "__main__":``, would run the whole command again in every
worker. :func:`check_main_guard` refuses that call in the parent, before any work, naming the
script's line.
"""

from __future__ import annotations

import ast
import hashlib
import importlib.abc
import importlib.machinery
import importlib.util
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from types import FrameType, ModuleType

from vslsp.errors import InputError
from vslsp.files import regular_file, shown

ENV = "VSLSP_TASK_FILES"  # the tasks files of the run (os.pathsep-separated absolute paths)
PREFIX = "vslsp_tasks_file_"
MAX_FILE_BYTES = 1_000_000


def module_name(path: Path) -> str:
    """The module name a tasks file is imported under (the same in every process)."""
    return PREFIX + hashlib.sha1(os.fsencode(path.resolve())).hexdigest()[:12]


def load_files(
    paths: Sequence[str | Path], registered_names: Callable[[], frozenset[str]], known_module: Callable[[str], bool]
) -> list[ModuleType]:
    """Import each tasks file (its ``@register``\\ ed tasks join the registry) and name them in
    :data:`ENV` for the worker processes. A file that is missing, not a ``.py`` file, raises
    while loading or registers nothing is an InputError naming it (and its line).
    ``registered_names()``: the registry's task names; ``known_module(name)``: whether a registered
    task comes from module ``name`` (the registry's, given by :func:`vslsp.tasks.registry.load_task_files`)."""
    modules = []
    for given in paths:
        path = Path(given).resolve()
        check_tasks_file(Path(given))
        before = registered_names()
        modules.append(_import(path, shown(given)))
        if registered_names() == before and not known_module(modules[-1].__name__):
            raise InputError(
                f"tasks file {shown(given)} registers no task; decorate a Task subclass with @register "
                "from vslsp.tasks (docs/tasks.md)"
            )
        known = [p for p in os.environ.get(ENV, "").split(os.pathsep) if p]
        if str(path) not in known:
            os.environ[ENV] = os.pathsep.join([*known, str(path)])
    return modules


def check_tasks_file(path: Path) -> None:
    """An InputError unless ``path`` is a regular ``.py`` file of at most :data:`MAX_FILE_BYTES`."""
    if path.suffix != ".py":
        raise InputError(f"tasks file {shown(path)} must be a Python file ending in .py")
    if regular_file(path, "tasks file").st_size > MAX_FILE_BYTES:
        raise InputError(f"tasks file {shown(path)} is over {MAX_FILE_BYTES // 1000} kB")


def _import(path: Path, name: str) -> ModuleType:
    from vslsp.grounding.loader import error_line
    from vslsp.grounding.user_code import describe, passes_through, quiet_stdout

    module_id = module_name(path)
    if module_id in sys.modules:
        return sys.modules[module_id]
    spec = importlib.util.spec_from_file_location(module_id, path)
    if spec is None or spec.loader is None:
        raise InputError(f"cannot load tasks file {name} as Python")
    module = importlib.util.module_from_spec(spec)
    sys.modules[module_id] = module
    try:
        with quiet_stdout():
            spec.loader.exec_module(module)
    except InputError as error:
        sys.modules.pop(module_id, None)
        raise InputError(f"tasks file {name}: {error}") from None
    except BaseException as error:  # the user's code: whatever it raises (SystemExit too) is theirs
        sys.modules.pop(module_id, None)
        if passes_through(error):
            raise
        raise InputError(f"cannot load tasks file {name}{error_line(error, path)}: {describe(error)}") from None
    return module


class _TasksFileFinder(importlib.abc.MetaPathFinder):
    """Imports ``vslsp_tasks_file_<digest>`` from the file of :data:`ENV` it was made from (a
    worker unpickling a task of such a file)."""

    def find_spec(
        self, fullname: str, path: object = None, target: object = None
    ) -> importlib.machinery.ModuleSpec | None:
        if not fullname.startswith(PREFIX):
            return None
        for file in os.environ.get(ENV, "").split(os.pathsep):
            if file and module_name(Path(file)) == fullname:
                return importlib.util.spec_from_file_location(fullname, file)
        return None


def install_finder() -> None:
    """Put the tasks files' finder on ``sys.meta_path`` (once)."""
    if not any(isinstance(finder, _TasksFileFinder) for finder in sys.meta_path):
        sys.meta_path.append(_TasksFileFinder())


def by_value_for_ray(task: object) -> None:
    """Let a task of a tasks file travel to Ray workers by value (they may not have the file)."""
    module = sys.modules.get(type(task).__module__)
    if module is not None and module.__name__.startswith(PREFIX):
        from ray import cloudpickle

        cloudpickle.register_pickle_by_value(module)


def check_main_guard(workers: int) -> None:
    """An InputError when trials are about to run in ``workers`` > 1 spawned processes and the
    call comes from the top level of a main script outside ``if __name__ == "__main__":``
    (every worker would import the script and run it again)."""
    if workers < 2:
        return
    main = sys.modules.get("__main__")
    script = getattr(main, "__file__", None)
    if main is None or script is None or getattr(getattr(main, "__spec__", None), "name", None):
        return  # python -m MODULE, an interactive session, vslsp's own command: nothing re-run
    frame: FrameType | None = sys._getframe(1)
    while frame is not None and not (frame.f_code.co_name == "<module>" and frame.f_globals is main.__dict__):
        frame = frame.f_back
    if frame is None or _guarded(Path(script), frame.f_lineno):
        return
    raise InputError(
        f"{shown(script)}, line {frame.f_lineno}: trials in {workers} worker processes are started from the "
        "top level of this script; each worker imports the script and would run it again: put the call "
        'under `if __name__ == "__main__":` (or use --workers 1)'
    )


def _guarded(script: Path, line: int) -> bool:
    """Whether ``line`` of ``script`` lies in an ``if __name__ == "__main__":`` block at its top
    level (unreadable source: assumed guarded, nothing refused on a guess)."""
    try:
        tree = ast.parse(script.read_text(encoding="utf-8"))
    except (OSError, SyntaxError, UnicodeDecodeError, ValueError):
        return True
    for statement in tree.body:
        end = getattr(statement, "end_lineno", statement.lineno) or statement.lineno
        if statement.lineno <= line <= end:
            return isinstance(statement, ast.If) and _is_main_test(statement.test)
    return True


def _is_main_test(test: ast.expr) -> bool:
    """``__name__ == "__main__"`` (either way round)."""
    if not (isinstance(test, ast.Compare) and len(test.ops) == 1 and isinstance(test.ops[0], ast.Eq)):
        return False
    sides = [test.left, test.comparators[0]]
    names = [s for s in sides if isinstance(s, ast.Name) and s.id == "__name__"]
    values = [s for s in sides if isinstance(s, ast.Constant) and s.value == "__main__"]
    return len(names) == 1 and len(values) == 1
