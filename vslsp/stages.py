"""Where a trial's wall time goes: perception, planning and execution (the rest is "other").

The paper's systems all run the same loop (observe, decide, act; Algorithm 1 part II and the
VSL-SP closed loop), so a trial's time splits into three stages: *perception* (camera images,
features, match finding, grounding), *planning* (the PDDL planner, grasp planning) and
*execution* (the robot's motions). Code marks its stage with :func:`stage` (a context manager
or a decorator); stages nest, and the innermost one is charged (a camera image taken during a
motion is perception, not execution). The totals are per process: the trial runner resets
them before a trial and reads them after it (:func:`split`).
"""

from __future__ import annotations

import functools
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any, TypeVar

STAGES = ("perception", "planning", "execution")

_totals: dict[str, float] = dict.fromkeys(STAGES, 0.0)
_children: list[float] = []  # per open stage: the time its nested stages took

F = TypeVar("F", bound=Callable[..., Any])


@contextmanager
def stage(name: str) -> Iterator[None]:
    """Charge the wall time of the block to stage ``name`` (less any nested stage's time)."""
    if name not in _totals:
        raise ValueError(f"unknown stage {name!r}; one of {', '.join(STAGES)}")
    start = time.perf_counter()
    _children.append(0.0)
    try:
        yield
    finally:
        elapsed = time.perf_counter() - start
        _totals[name] += elapsed - _children.pop()
        if _children:
            _children[-1] += elapsed


def in_stage(name: str) -> Callable[[F], F]:
    """Decorator: every call of the function is charged to stage ``name``."""

    def decorate(function: F) -> F:
        @functools.wraps(function)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            with stage(name):
                return function(*args, **kwargs)

        return wrapper  # type: ignore[return-value]

    return decorate


def reset() -> None:
    """Start counting afresh (before a trial)."""
    for name in STAGES:
        _totals[name] = 0.0


def split(time_s: float) -> dict[str, float]:
    """The stages' wall seconds since :func:`reset` and ``other`` (the rest of ``time_s``),
    rounded to ms so that the four add up to ``time_s`` as the trial's record rounds it."""
    parts = {name: round(min(_totals[name], time_s), 3) for name in STAGES}
    parts["other"] = round(max(round(time_s, 3) - sum(parts.values()), 0.0), 3)
    return parts
