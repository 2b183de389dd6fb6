"""Typed outcomes shared by the layers: match finding that found nothing (:class:`NoMatch`,
2-D and 3-D alike), and how an operation of a reproduction ended, the judge's diagnosis (paper,
"Real-world Experiments": the repeatability test counts the failed operations and why they failed).

One vocabulary for every world: the robot's pick-and-place (:mod:`vslsp.sim.pick_place`) says
GRASP_FAILED, OBJECT_SLIPPED or UNREACHABLE; VSL's reproductions (:mod:`vslsp.vsl`) add what
match finding and the judge saw. A :class:`Diagnosis` is a ``str``, so records and reports write
the same strings as before ("ok", "no match", ...).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum


@dataclass(frozen=True)
class NoMatch:
    """Match finding found nothing: why (a typed outcome, not an exception). False in a test.

    Returned by 2-D match finding (:func:`vslsp.vision.matching.find_best_match`) and 3-D
    (:func:`vslsp.vsl3d.matching.find_best_match`, :func:`vslsp.vsl3d.alignment.align`)."""

    reason: str

    def __bool__(self) -> bool:
        return False


class Diagnosis(StrEnum):
    """The verdict on one operation: OK, or why it failed."""

    OK = "ok"
    NO_MATCH = "no match"  # match finding found nothing for the pick or the place
    AMBIGUOUS_MATCH = "ambiguous match"  # executed as planned, on a match that had a close rival
    WRONG_OBJECT = "wrong object"  # the robot moved another object than the demonstrated one
    MISPLACED = "misplaced"  # the right object, off its demonstrated place
    WRONG_PLACE = "wrong place"  # house-roof: a house that has its roof already, or no slot at all
    GRASP_FAILED = "grasp failed"  # the fingers closed on nothing
    OBJECT_SLIPPED = "object slipped"  # the object left the fingers on the way
    UNREACHABLE = "unreachable"  # no arm motion reaches the pick or the place
