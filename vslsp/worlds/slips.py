"""The tutor's slips: while demonstrating one operation, the tutor also disturbs another object
(the paper's own limit, "Results" of VSL: "if the tutor accidentally moves one object while
operating another, the algorithm may fail").

:class:`TutorSlips` draws, per demonstrated operation, whether the tutor slips (probability
``probability``) and, if so, which other object is nudged and by how much: 1 to 4 cm in a
random direction and up to 20 deg about the vertical. The draws come from a stream of their own
(the trial's seed and :data:`STREAM`), made for every operation whether or not it slips, so
that a trial's scenes, demonstrations and plans are the same as without slips up to the first
slip, and ``--tutor-slips 0`` gives exactly the runs without the option.

Each world applies a :class:`Slip` in its own units (metres and radians on the tables, pixels
on the house-roof board) with its tutor's hand; the slip is ground truth, recorded for the
report (``slip`` of the operation) and never read by perception.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

STREAM = 0x511D5  # the slips' own random stream of a trial: default_rng([seed, STREAM])
NUDGE_M = (0.01, 0.04)  # how far the disturbed object moves (m)
MAX_TURN_DEG = 20.0  # how far it turns about the vertical, either way (deg)


@dataclass(frozen=True)
class Slip:
    """The tutor's slip in one operation: object ``name`` moved by (``dx_m``, ``dy_m``) on the
    table and turned by ``dyaw_deg`` about the vertical."""

    operation: int
    name: str
    dx_m: float
    dy_m: float
    dyaw_deg: float

    def both_ways(self) -> tuple[Slip, Slip]:
        """This slip and the one the other way (a world tries the second when the first is not
        free)."""
        ahead = Slip(self.operation, self.name, float(self.dx_m), float(self.dy_m), float(self.dyaw_deg))
        return ahead, Slip(self.operation, self.name, -ahead.dx_m, -ahead.dy_m, -ahead.dyaw_deg)

    @property
    def distance_m(self) -> float:
        return math.hypot(self.dx_m, self.dy_m)

    def to_dict(self) -> dict:
        """The slip's JSON record (``slip`` of the operation in report.json): ground truth."""
        return {
            "object": self.name,
            "dx_mm": round(1000 * self.dx_m, 1),
            "dy_mm": round(1000 * self.dy_m, 1),
            "dyaw_deg": round(self.dyaw_deg, 1),
        }


class TutorSlips:
    """The slips of one trial's demonstration: :meth:`draw` once per demonstrated operation."""

    def __init__(self, probability: float, seed: int) -> None:
        if not 0.0 <= probability <= 1.0:
            raise ValueError(f"a slip probability is from 0 to 1, not {probability}")
        self.probability = probability
        self.rng = np.random.default_rng([seed, STREAM])
        self.drawn: list[Slip] = []

    def draw(self, operation: int, others: Sequence[str]) -> Slip | None:
        """Whether the tutor slips in ``operation`` and onto which of ``others`` (the objects the
        operation is not about, in a fixed order), or None. Every call takes the same number of
        draws, slip or not."""
        slips, pick, distance, direction, turn = self.rng.random(5)
        if not others or slips >= self.probability:
            return None
        low, high = NUDGE_M
        radius = low + (high - low) * distance
        angle = 2 * math.pi * direction
        slip = Slip(
            operation=operation,
            name=others[min(int(pick * len(others)), len(others) - 1)],
            dx_m=radius * math.cos(angle),
            dy_m=radius * math.sin(angle),
            dyaw_deg=MAX_TURN_DEG * (2 * turn - 1),
        )
        self.drawn.append(slip)
        return slip
