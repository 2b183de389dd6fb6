"""The report's statistics: a success rate's confidence interval, pose-error summaries and the
trials' time by stage (see :mod:`vslsp.stages`)."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from vslsp.stages import STAGES

Z95 = 1.959964  # the standard normal's 97.5 % quantile


def wilson_interval(successes: int, trials: int, z: float = Z95) -> list[float]:
    """The Wilson score interval [lo, hi] of a success rate (95 % by default): unlike the
    normal approximation it stays inside [0, 1] and is not empty at 0/n or n/n."""
    if trials == 0:
        return [0.0, 1.0]
    p = successes / trials
    centre = (p + z * z / (2 * trials)) / (1 + z * z / trials)
    half = z * math.sqrt(p * (1 - p) / trials + z * z / (4 * trials * trials)) / (1 + z * z / trials)
    return [round(max(0.0, centre - half), 4), round(min(1.0, centre + half), 4)]


def describe(values: Sequence[float]) -> dict[str, float]:
    """Mean, sample standard deviation (0 for one value), median and 95th percentile."""
    array = np.asarray(values, dtype=float)
    return {
        "mean": round(float(array.mean()), 3),
        "sd": round(float(array.std(ddof=1)) if len(array) > 1 else 0.0, 3),
        "median": round(float(np.median(array)), 3),
        "p95": round(float(np.percentile(array, 95)), 3),
    }


def pose_error(errors: Sequence[tuple[float, float]]) -> dict | None:
    """``{"mm": {...}, "deg": {...}, "operations": n}`` over (mm, deg) pairs; None without any."""
    if not errors:
        return None
    return {
        "mm": describe([mm for mm, _ in errors]),
        "deg": describe([deg for _, deg in errors]),
        "operations": len(errors),
    }


def total_stages(records: Sequence[dict | None]) -> dict[str, float] | None:
    """The trials' stage times summed (None when no trial has them)."""
    timed = [r for r in records if r]
    if not timed:
        return None
    return {name: round(sum(r.get(name, 0.0) for r in timed), 3) for name in (*STAGES, "other")}
