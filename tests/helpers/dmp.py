"""Demonstrations shared by the DMP tests: smooth reaches and drawn loops."""

import numpy as np

LIFT = np.array([0.05, 0.0, 0.1])  # the lift's peak offset (m): sideways in x, up in z


def reach(start=(0.0, 0.0, 0.0), goal=(0.3, -0.2, 0.0), duration=1.0, samples=101):
    """A demonstration (t (T,), y (T, 3)): minimum-jerk start → goal with a lift on the way."""
    t = np.linspace(0.0, duration, samples)
    u = t / duration
    progress = 10 * u**3 - 15 * u**4 + 6 * u**5
    start, goal = np.asarray(start, dtype=float), np.asarray(goal, dtype=float)
    lift = np.sin(np.pi * u) ** 2
    return t, start + progress[:, None] * (goal - start) + lift[:, None] * LIFT * np.linalg.norm(goal - start) / 0.36


def loop(gap=0.0, radius=20.0, samples=400, duration=2.0):
    """A hand-drawn loop (t (T,), y (T, 2)) in mm: a circle from its start back to ``gap`` mm of it."""
    t = np.linspace(0.0, duration, samples)
    u = t / duration
    angle = 2 * np.pi * (10 * u**3 - 15 * u**4 + 6 * u**5)
    y = radius * np.column_stack([np.sin(angle), 1.0 - np.cos(angle)])
    y += np.outer(u, [gap, 0.0])  # open the loop by ``gap`` at its end
    return t, y


def rmse(a, b):
    return float(np.sqrt(np.mean(np.sum((a - b) ** 2, axis=-1))))
