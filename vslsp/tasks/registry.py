"""The registry of tasks: ``@register`` a :class:`~vslsp.tasks.base.Task` subclass, find it by
name with :func:`get_task`, list all with :func:`list_tasks`.

Tasks are declared in the ``vslsp.tasks`` entry-point group, the paper's experiments in vslsp's
own ``pyproject.toml`` as another package's are in its own: ``NAME = "module:Class"``, a lazy
entry whose module is imported only when task NAME is first looked up (as unified-planning's
``DEFAULT_ENGINES`` name their engines), so that naming one experiment imports only its module
and ``vslsp --help`` none. An entry that names a module alone (``my_tasks = "my_package.tasks"``)
is imported at the first look-up, and the tasks it registers (``@register``) join; so do the
files of ``--tasks FILE.py``.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from importlib.metadata import EntryPoint, entry_points
from pathlib import Path
from types import ModuleType
from typing import TypeVar

from vslsp.errors import InputError, VslspError
from vslsp.tasks.base import Option, Task
from vslsp.tasks.task_files import ENV, load_files

GROUP = "vslsp.tasks"  # the entry-point group of tasks (docs/tasks.md)
BUILTIN = "vslsp.experiments"  # the package of the paper's experiments (declared in vslsp's own entry points)

_TASKS: dict[str, type[Task]] = {}
_entries: dict[str, EntryPoint] | None = None  # lazy "module:Class" entries by task name, not loaded yet
_loaded = False

T = TypeVar("T", bound=type[Task])


def register(cls: T) -> T:
    """Class decorator: make ``cls`` runnable as ``vslsp experiment cls.name``."""
    for attribute in ("name", "system", "paper_section"):
        if not hasattr(cls, attribute):
            raise TypeError(f"task class {cls.__qualname__} must set {attribute!r}")
    entry = _lazy().get(cls.name)
    declared = f"{entry.module}.{entry.attr}" if entry is not None else None
    existing = _TASKS.get(cls.name)
    if existing is not None and existing.__qualname__ != cls.__qualname__:
        raise ValueError(f"two tasks are named {cls.name!r}: {existing.__qualname__} and {cls.__qualname__}")
    if declared is not None and declared != f"{cls.__module__}.{cls.__qualname__}":
        raise ValueError(f"two tasks are named {cls.name!r}: {declared} (an entry point) and {cls.__qualname__}")
    _TASKS[cls.name] = cls
    return cls


def _lazy() -> dict[str, EntryPoint]:
    """The ``module:Class`` entries of :data:`GROUP` by task name; an entry naming a module alone is
    imported by :func:`_load` instead."""
    global _entries
    if _entries is None:
        found = {entry.name: entry for entry in entry_points(group=GROUP) if entry.attr}
        if not any(entry.module.startswith(BUILTIN + ".") for entry in found.values()):
            raise VslspError(
                "vslsp's installed metadata declares none of the paper's experiments (an install older than "
                f"its pyproject.toml's {GROUP} entry points): install vslsp again (pip install -e .)"
            )
        _entries = found
    return _entries


def _loaded_entry(name: str) -> type[Task]:
    """The class of the lazy entry ``name``, imported and registered (its name checked)."""
    cls = _lazy()[name].load()
    if not (isinstance(cls, type) and issubclass(cls, Task)) or getattr(cls, "name", None) != name:
        raise TypeError(f"the {GROUP} entry point {name!r} names {cls!r}, not a Task subclass named {name!r}")
    return register(cls)


def _load() -> None:
    """Import the entries that name a module alone and the files of a run's ``--tasks`` (the lazy
    entries wait until they are looked up, or listed)."""
    global _loaded
    if _loaded:
        return
    _loaded = True
    for entry in entry_points(group=GROUP):
        if not entry.attr:
            entry.load()
    given = [path for path in os.environ.get(ENV, "").split(os.pathsep) if path]
    if given:  # a process started for a run given --tasks (a worker, a studio job): the same tasks
        load_task_files(given)


def _load_all() -> None:
    _load()
    for name in _lazy():
        if name not in _TASKS:
            _loaded_entry(name)


def task_class(name: str) -> type[Task]:
    """The registered task class ``name`` (an :class:`InputError` naming the choices otherwise)."""
    _load()
    if name in _TASKS:
        return _TASKS[name]
    if name in _lazy():
        return _loaded_entry(name)
    raise InputError(
        f"unknown experiment {name!r}; choose one of {', '.join(sorted(registered_names()))} (vslsp experiment --list)"
    )


def get_task(name: str, **options: object) -> Task:
    """An instance of task ``name`` with ``options`` (checked before any work): an option the
    task does not take, or a bad value, is an :class:`InputError`."""
    cls = task_class(name)
    # a flag left off (``faults=False``) is not given; ``slip_detection=False`` is (detection off)
    given = {k for k, v in options.items() if v is not None and (v is not False or k == Option.SLIP_DETECTION)}
    unknown = given - {o.value for o in cls.options}
    if unknown:
        option = sorted(unknown)[0]
        raise InputError(
            f"--{option.replace('_', '-')} applies to {_taking(option)}; {name} takes "
            f"{', '.join(o.flag for o in sorted(cls.options)) or 'no task options'}"
        )
    task = cls(**options)
    task.check()
    return task


def _taking(option: str) -> str:
    """The experiments that take ``option``: "the VSL-SP experiments" when every one of the paper's
    experiments of those systems takes it, else their names."""
    taking = [c for c in list_tasks() if option in {o.value for o in c.options}]
    systems = dict.fromkeys(c.system for c in taking)
    papers = [c for c in list_tasks() if c.__module__.startswith(BUILTIN + ".") and c.system in systems]
    if not taking:
        return "no experiment"
    if all(c in taking for c in papers):
        return f"the {' and '.join(systems)} experiments"
    return " and ".join(c.name for c in taking)


def registered_names() -> frozenset[str]:
    """The names of every registered task, the lazy entries' too (none of them imported)."""
    _load()
    return frozenset(_TASKS) | frozenset(_lazy())


def task_classes() -> list[type[Task]]:
    """Every registered task class (the lazy entries imported), in the order registered."""
    _load_all()
    return list(_TASKS.values())


def load_task_files(paths: Sequence[str | Path]) -> list[ModuleType]:
    """The tasks files of ``--tasks FILE.py`` imported, their tasks registered here and in every worker
    (:mod:`vslsp.tasks.task_files`)."""
    return load_files(paths, registered_names, lambda module: any(c.__module__ == module for c in _TASKS.values()))


def list_tasks() -> list[type[Task]]:
    """Every registered task class (the lazy entries imported), by system (VSL, VSL-3D, VSL-SP): the
    paper's first, by module in the order each module defines them (the paper's), then the others."""
    _load_all()
    order = {"VSL": 0, "VSL-3D": 1, "VSL-SP": 2}
    return sorted(
        _TASKS.values(),
        key=lambda cls: (order.get(cls.system.value, 3), not cls.__module__.startswith(BUILTIN + "."), *_defined(cls)),
    )


def _defined(cls: type[Task]) -> tuple[str, int]:
    """Where ``cls`` is defined: its module, and its place among the module's names (definition order)."""
    names = list(vars(sys.modules[cls.__module__])) if cls.__module__ in sys.modules else []
    return cls.__module__, names.index(cls.__name__) if cls.__name__ in names else len(names)
