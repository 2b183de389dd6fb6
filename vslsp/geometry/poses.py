"""Planar poses (x, y, yaw): composition, relative pose and angle wrapping.

A pose ``(x, y, theta)`` places a frame in another (image pixels or table metres; radians).
These are the rigid motions of the plane, SE(2): ``compose(a, b)`` is a ∘ b, ``relative(a, b)``
is a⁻¹ ∘ b.
"""

from __future__ import annotations

import numpy as np

Pose2 = tuple[float, float, float]  # x, y; angle in radians


def compose(a: Pose2, b: Pose2) -> Pose2:
    """a ∘ b: pose ``b`` given in the frame of ``a``, expressed in ``a``'s parent frame."""
    c, s = np.cos(a[2]), np.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2])


def relative(a: Pose2, b: Pose2) -> Pose2:
    """a⁻¹ ∘ b: pose ``b`` in the frame of ``a``."""
    c, s = np.cos(a[2]), np.sin(a[2])
    dx, dy = b[0] - a[0], b[1] - a[1]
    return (c * dx + s * dy, -s * dx + c * dy, wrap(b[2] - a[2]))


def wrap(angle: float) -> float:
    """``angle`` (rad) in [−π, π)."""
    return float((angle + np.pi) % (2.0 * np.pi) - np.pi)
