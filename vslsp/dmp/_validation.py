"""Checks of what a user hands the DMP: demonstrations, starts and goals, times, files.

Every problem is an :class:`~vslsp.errors.InputError` that names the demonstration (or the
argument) and says what is wrong with it.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from vslsp.errors import InputError

MIN_SAMPLES = 5


def _non_finite(name: str, values: np.ndarray) -> str | None:
    bad = ~np.isfinite(values)
    if not bad.any():
        return None
    first = np.argwhere(bad)[0]
    where = f"sample {first[0]}" + (f", dimension {first[1]}" if len(first) > 1 else "")
    return f"{name} has {int(bad.sum())} value(s) that are not finite (NaN or inf), the first at {where}"


def _as_array(value: Any, what: str) -> np.ndarray:
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise InputError(f"{what} is not an array of numbers ({error})") from error


def _looks_like(value: Any, ndim: int) -> bool:
    """Whether ``value`` is a numeric array of ``ndim`` dimensions (a time base or a path, not a demonstration)."""
    try:
        return np.asarray(value, dtype=np.float64).ndim == ndim
    except (TypeError, ValueError):  # a (t, y) pair, ragged
        return False


def check_demonstrations(demos: Any, n_dims: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """The demonstrations as ``[(t - t[0] (T,), y (T, D)), ...]``, or an InputError saying which is bad.

    Parameters
    ----------
    demos : list of (t, y)
        Times t, shape (T,), strictly increasing, and positions y, shape (T, n_dims), all finite.
    n_dims : int
        The DMP's number of dimensions.
    """
    if isinstance(demos, np.ndarray):
        raise InputError(
            "fit takes a list of demonstrations [(t, y), ...], not an array; pass [(t, y)] for a single demonstration"
        )
    if isinstance(demos, tuple) and len(demos) == 2 and _looks_like(demos[0], 1) and _looks_like(demos[1], 2):
        raise InputError(
            "fit takes a list of demonstrations [(t, y), ...], got a single (t, y) pair; "
            "pass [(t, y)] for one demonstration"
        )
    if not isinstance(demos, Sequence) or isinstance(demos, str):
        raise InputError(f"fit takes a list of demonstrations [(t, y), ...], got {type(demos).__name__}")
    if len(demos) == 0:
        raise InputError("fit needs at least one demonstration [(t, y), ...], got an empty list")
    checked = []
    for k, demo in enumerate(demos):
        name = f"demonstration {k}"
        if not isinstance(demo, Sequence) or isinstance(demo, str) or len(demo) != 2:
            raise InputError(f"{name} is not a pair (t, y) of times (T,) and positions (T, {n_dims})")
        t, y = _as_array(demo[0], f"{name}: t"), _as_array(demo[1], f"{name}: y")
        if t.ndim != 1 or y.ndim != 2 or y.shape[1] != n_dims or len(t) != len(y):
            raise InputError(f"{name}: expected t (T,) and y (T, {n_dims}), got t {t.shape} and y {y.shape}")
        if len(t) < MIN_SAMPLES:
            raise InputError(f"{name} has {len(t)} samples; a DMP needs at least {MIN_SAMPLES}")
        for label, values in (("t", t), ("y", y)):
            problem = _non_finite(label, values)
            if problem:
                raise InputError(f"{name}: {problem}")
        steps = np.diff(t)
        if np.any(steps <= 0):
            i = int(np.argmax(steps <= 0))
            raise InputError(
                f"{name}: the time base t must increase strictly, but t[{i + 1}] = {t[i + 1]:g} "
                f"does not come after t[{i}] = {t[i]:g}"
            )
        if np.all(y == y[0]):
            raise InputError(f"{name} never moves: all its {len(y)} positions are equal")
        checked.append((t - t[0], y))
    return checked


def check_points(y0: Any, goal: Any, n_dims: int) -> tuple[np.ndarray, np.ndarray, bool]:
    """Starts and goals broadcast to (B, n_dims) each, and whether the call was batched."""
    y0, goal = _as_array(y0, "the start y0"), _as_array(goal, "the goal")
    for name, value in (("the start y0", y0), ("the goal", goal)):
        if value.ndim not in (1, 2) or value.shape[-1] != n_dims:
            raise InputError(
                f"{name} must have shape ({n_dims},) or (B, {n_dims}) for {n_dims} dimensions, got {value.shape}"
            )
        problem = _non_finite(name, np.atleast_2d(value))
        if problem:
            raise InputError(problem.replace("sample", "movement"))
    batched = y0.ndim == 2 or goal.ndim == 2
    try:
        y0, goal = np.broadcast_arrays(np.atleast_2d(y0), np.atleast_2d(goal))
    except ValueError as error:
        raise InputError(
            f"{y0.shape[0]} starts and {goal.shape[0]} goals: give one of each per movement, "
            "or a single start or goal for all"
        ) from error
    return y0, goal, batched


def check_times(tau: Any, dt: float, duration: float | None, movements: int) -> tuple[np.ndarray, float, float]:
    """τ per movement (B,), dt and the rollout's duration (default 1.3 times the longest τ)."""
    taus = _as_array(tau, "tau")
    if taus.ndim > 1 or (taus.ndim == 1 and len(taus) not in (1, movements)):
        raise InputError(f"tau must be a number or one per movement ({movements},), got shape {taus.shape}")
    if not np.all(np.isfinite(taus)) or np.any(taus <= 0):
        raise InputError(f"tau must be positive and finite, got {taus if taus.ndim else float(taus)}")
    if not np.isfinite(dt) or dt <= 0:
        raise InputError(f"the sample period dt must be positive and finite, got {dt}")
    taus = np.broadcast_to(taus, (movements,)).copy()
    duration = 1.3 * float(taus.max()) if duration is None else float(duration)
    if not np.isfinite(duration) or duration < 0:
        raise InputError(f"the rollout's duration must be positive and finite, got {duration}")
    if duration < dt:
        raise InputError(f"a rollout of {duration} s is shorter than one sample period dt = {dt} s")
    return taus, float(dt), duration
