"""The registry of tasks: ``@register`` a :class:`~vslsp.tasks.base.Task` subclass, find it by
name with :func:`get_task`, list all with :func:`list_tasks`.

The paper's experiments register themselves in the modules of the package :data:`BUILTIN`
(:mod:`vslsp.experiments`, its ``MODULES``), imported on first use by name, as an entry point
is (they import the simulator and OpenCV only inside their trials, so listing is cheap).
Other packages add tasks through the ``vslsp.tasks`` entry-point group (each entry point
names a module that registers its tasks when imported).
"""

from __future__ import annotations

import importlib
import os
from importlib.metadata import entry_points
from typing import TypeVar

from vslsp.errors import InputError
from vslsp.tasks.base import Option, Task

BUILTIN = "vslsp.experiments"  # the package of the paper's experiments (above this layer: loaded by name)

_TASKS: dict[str, type[Task]] = {}
_loaded = False

T = TypeVar("T", bound=type[Task])


def register(cls: T) -> T:
    """Class decorator: make ``cls`` runnable as ``vslsp experiment cls.name``."""
    for attribute in ("name", "system", "paper_section"):
        if not hasattr(cls, attribute):
            raise TypeError(f"task class {cls.__qualname__} must set {attribute!r}")
    existing = _TASKS.get(cls.name)
    if existing is not None and existing.__qualname__ != cls.__qualname__:
        raise ValueError(f"two tasks are named {cls.name!r}: {existing.__qualname__} and {cls.__qualname__}")
    _TASKS[cls.name] = cls
    return cls


def _load() -> None:
    global _loaded
    if _loaded:
        return
    _loaded = True
    for module in importlib.import_module(BUILTIN).MODULES:
        importlib.import_module(module)
    for entry in entry_points(group="vslsp.tasks"):
        entry.load()
    from vslsp.tasks.task_files import ENV, load_task_files

    given = [path for path in os.environ.get(ENV, "").split(os.pathsep) if path]
    if given:  # a process started for a run given --tasks (a worker, a studio job): the same tasks
        load_task_files(given)


def task_class(name: str) -> type[Task]:
    """The registered task class ``name`` (an :class:`InputError` naming the choices otherwise)."""
    _load()
    if name not in _TASKS:
        raise InputError(
            f"unknown experiment {name!r}; choose one of {', '.join(sorted(_TASKS))} (vslsp experiment --list)"
        )
    return _TASKS[name]


def get_task(name: str, **options: object) -> Task:
    """An instance of task ``name`` with ``options`` (checked before any work): an option the
    task does not take, or a bad value, is an :class:`InputError`."""
    cls = task_class(name)
    # a flag left off (``faults=False``) is not given; ``slip_detection=False`` is (detection off)
    given = {k for k, v in options.items() if v is not None and (v is not False or k == Option.SLIP_DETECTION)}
    unknown = given - {o.value for o in cls.options}
    if unknown:
        option = sorted(unknown)[0]
        systems = dict.fromkeys(c.system.value for c in list_tasks() if option in {o.value for o in c.options})
        raise InputError(
            f"--{option.replace('_', '-')} applies to the {' and '.join(systems) or 'no'} experiments; {name} takes "
            f"{', '.join(o.flag for o in sorted(cls.options)) or 'no task options'}"
        )
    task = cls(**options)
    task.check()
    return task


def registered_names() -> frozenset[str]:
    """The names of every registered task (the built-ins loaded first)."""
    _load()
    return frozenset(_TASKS)


def task_classes() -> list[type[Task]]:
    """Every registered task class, in the order registered."""
    _load()
    return list(_TASKS.values())


def list_tasks() -> list[type[Task]]:
    """Every registered task class, by system (VSL, VSL-3D, VSL-SP) in the order registered."""
    _load()
    order = {"VSL": 0, "VSL-3D": 1, "VSL-SP": 2}
    return sorted(_TASKS.values(), key=lambda cls: order.get(cls.system.value, 3))
